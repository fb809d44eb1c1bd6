"""Joints that follow others (URDF ``<mimic>``, docs/trees-mimic.md): the relation, and the
positions of a chain's every joint from its actuated ones.

A chain's configuration ``q`` holds the positions of the joints that move on their own, in
order; a joint that mimics one of them moves to ``multiplier * q_leader + offset``. Both a POE
model's joints and a table's rows carry the relation (:class:`Followed`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from ..errors import shown

__all__ = ["Followed", "Mimic", "actuated", "row_positions"]


@dataclass(frozen=True, slots=True)
class Mimic:
    """A joint that follows another (URDF ``<mimic>``): its position is ``multiplier *
    q_joint + offset``, ``joint`` being an actuated joint of the same chain."""

    joint: str
    multiplier: float = 1.0
    offset: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.multiplier) and math.isfinite(self.offset)):
            raise ValueError(f"mimic of {shown(self.joint)}: multiplier and offset must be finite")


class Followed(Protocol):
    """A joint or a table row: its name, and whom it follows if it mimics."""

    @property
    def name(self) -> str: ...

    @property
    def mimic(self) -> Mimic | None: ...


def actuated(items: Sequence[Followed]) -> tuple[int, ...]:
    """The indices of the items that move on their own (no mimic): the positions ``q`` that
    drive a chain, in order."""
    return tuple(i for i, item in enumerate(items) if item.mimic is None)


def row_positions(items: Sequence[Followed], q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Every joint's position ``(N, n)`` from the actuated joints' ``q`` ``(N, n_actuated)``:
    a mimicking joint's is ``multiplier * q_leader + offset``."""
    driving = actuated(items)
    if len(driving) == len(items):
        return q
    column = {items[i].name: k for k, i in enumerate(driving)}
    out = np.empty((q.shape[0], len(items)))
    for i, item in enumerate(items):
        m = item.mimic
        out[:, i] = q[:, column[item.name]] if m is None else (
            m.multiplier * q[:, column[m.joint]] + m.offset)  # fmt: skip
    return out
