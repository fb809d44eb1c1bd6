"""Which coordinates of a level are identified: not fixed by name, and not already carried by
the level's other coordinates.

A level's coordinates (:mod:`.chart`) can overlap: in ``offsets``, the first joint's offset
turns the whole robot about its axis as the base does, and the last joint's turns the tool as
the tool's own coordinates do; a robot with special structure may have more such pairs. They
are found once per level, from the Jacobian of the level's model at seeded configurations
spread over the joint limits (what *any* measurement could see, not what these happened to):
columns are taken in order, the base's and the tool's first, then the joints' along the chain,
and one whose unit column lies within :data:`~urdf2dh.tolerances.RANK_RELATIVE` of the span of
those before (the diagonal of the QR factorisation in that order) is carried by them and held
fixed. What the measurements at hand leave undetermined
(a joint that never moved) is another matter, found at the solution (:mod:`.solver`).
"""

from __future__ import annotations

import fnmatch
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError, choices
from ..tolerances import BARELY_MOVED, RANK_RELATIVE
from .chart import Estimate, all_names, sizes
from .levels import Level
from .residuals import evaluate, observed

__all__ = [
    "barely_moved",
    "carried_at_levels",
    "check_patterns",
    "fixed_by_name",
    "free_coordinates",
    "redundant",
]

Mat = NDArray[np.float64]

_SAMPLES = 40  # configurations of the structural test (seeded; each gives 3 or 6 rows)


def fixed_by_name(
    est: Estimate, patterns: tuple[str, ...], marker_ids: list[int] | None = None
) -> NDArray[np.bool_]:
    """The level's coordinates that ``patterns`` (names or shell-style patterns such as
    ``*.scale``, ``arm_7_joint.*``) fix."""
    return _named(all_names(est, marker_ids), patterns)


def _named(names: list[str], patterns: tuple[str, ...]) -> NDArray[np.bool_]:
    """Which of ``names`` ``patterns`` match."""
    return np.array([any(fnmatch.fnmatchcase(n, p) for p in patterns) for n in names], dtype=bool)


def check_patterns(
    patterns: tuple[str, ...], estimates: list[Estimate], marker_ids: list[int] | None
) -> None:
    """Refuse a pattern that names no coordinate of any of ``estimates``' levels."""
    every = {n for est in estimates for n in all_names(est, marker_ids)}
    for p in patterns:
        if not any(fnmatch.fnmatchcase(n, p) for n in every):
            raise InputError(
                f"no parameter is named {p!r}; the parameters are {choices(every, limit=15)}"
            )


def _order(est: Estimate) -> NDArray[np.int64]:
    """Column order of the test: the base's, the tool's (or markers'), then the joints'."""
    blocks = sizes(est, every=True)
    base, joints = blocks[0], sum(blocks[1:-1])
    total = sum(blocks)
    order: NDArray[np.int64] = np.r_[
        np.arange(base), np.arange(base + joints, total), np.arange(base, base + joints)
    ].astype(np.int64)
    return order


def redundant(est: Estimate, limits: NDArray[np.float64], size: float) -> NDArray[np.bool_]:
    """The level's coordinates that the others already carry (module docstring).

    ``limits``: ``(n, 2)`` the joints' ranges to draw configurations from; ``size``: the
    robot's size (rotation rows count at that lever).
    """
    return carried_at_levels(est, (est.level,), limits, size)[est.level.name]


def carried_at_levels(
    est: Estimate, levels: tuple[Level, ...], limits: NDArray[np.float64], size: float
) -> dict[str, NDArray[np.bool_]]:
    """:func:`redundant` of ``est``'s model at each of ``levels``, by name: the configurations
    drawn once for all, and the levels tested on the same model (``est``'s, or with its offsets
    absorbed where a level has none: :meth:`.chart.Estimate.with_level`) observed once and
    tested on one Jacobian, the model's at every coordinate one of them has (:func:`_union`):
    each level's own columns are among that one's (the chart's formula is the same at every
    level)."""
    rng = np.random.default_rng((0, 6))
    q = rng.uniform(limits[:, 0], limits[:, 1], size=(_SAMPLES, est.n))
    probes = {level: _probe(est, level) for level in levels}
    on_model: dict[bool, list[Level]] = {}  # on est's own model, and on it absorbed
    for level, probe in probes.items():
        on_model.setdefault(probe.chain is est.chain, []).append(level)
    out: dict[str, NDArray[np.bool_]] = {}
    for group in on_model.values():
        every = _probe(est, _union(group))
        _, jac = evaluate(every, observed(every, q), size, 1.0)
        column = {n: k for k, n in enumerate(all_names(every))}
        for level in group:
            probe = probes[level]
            out[level.name] = _carried(probe, jac[:, [column[n] for n in all_names(probe)]])
    return {level.name: out[level.name] for level in levels}


def _probe(est: Estimate, level: Level) -> Estimate:
    """``est``'s model at ``level``, every coordinate of it free."""
    return replace(est, free=None) if level == est.level else est.with_level(level)


def _union(levels: list[Level]) -> Level:
    """The level with every coordinate one of ``levels`` has (the one level itself, alone)."""
    if len(levels) == 1:
        return levels[0]
    return Level(
        " + ".join(level.name for level in levels),
        base=any(level.base for level in levels),
        lines=any(level.lines for level in levels),
        offsets=any(level.offsets for level in levels),
        scales=any(level.scales for level in levels),
    )


def _carried(est: Estimate, jac: Mat) -> NDArray[np.bool_]:
    """The coordinates of ``est``'s level (all of them) whose columns of ``jac`` lie within
    :data:`~urdf2dh.tolerances.RANK_RELATIVE` of the span of those before them in the test's
    order (module docstring)."""
    norms = np.linalg.norm(jac, axis=0)
    order = _order(est)
    unit = jac[:, order] / np.where(norms[order] > 0.0, norms[order], 1.0)
    # QR in the test's order: a column's part outside the span of those before is |R_kk|
    outside = np.abs(np.diag(np.linalg.qr(unit, mode="r")))
    out = np.zeros(jac.shape[1], dtype=bool)
    seen = norms[order] <= RANK_RELATIVE * float(norms.max(initial=1.0))
    out[order] = seen | (outside <= RANK_RELATIVE)
    return out


def barely_moved(q: NDArray[np.float64], est: Estimate, size: float) -> tuple[str, ...]:
    """The joints whose positions ``q`` ``(N, n)`` span less than
    :data:`~urdf2dh.tolerances.BARELY_MOVED` (rad, or x ``size`` for sliding joints)."""
    span = np.ptp(q, axis=0) if len(q) else np.zeros(est.n)
    limit = np.where(est.chain.turning, BARELY_MOVED, BARELY_MOVED * size)
    return tuple(n for n, s, lim in zip(est.chain.names, span, limit, strict=True) if s < lim)


def free_coordinates(
    est: Estimate,
    patterns: tuple[str, ...],
    limits: NDArray[np.float64],
    size: float,
    marker_ids: list[int] | None = None,
    carried: NDArray[np.bool_] | None = None,
) -> tuple[NDArray[np.bool_], list[str]]:
    """The level's free coordinates: not fixed by ``patterns``, not carried by the others
    (``carried``, when the caller found them already for this level and chain). Also the names
    of the coordinates the others carry."""
    names = all_names(est, marker_ids)
    fixed = _named(names, patterns)
    if carried is None:
        carried = redundant(est, limits, size)
    return ~(fixed | carried), [
        n for n, c, f in zip(names, carried, fixed, strict=True) if c and not f
    ]
