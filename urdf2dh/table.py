"""The Table data type shared by every convention: rows, base and tool, its forward kinematics,
its POE model, and its JSON / YAML tree (SPEC §2).

Whatever the convention, a table's forward kinematics has the shape::

    T(q) = B . prod_i [A_i . Q_i(s_i) . C_i] . T,  Q_i(s) = Rz(j_i s) Tz(k_i s),  s_i = scale_i q_i

with ``(A_i, C_i)`` the constant matrices of row ``i`` (``dh``: ``A = I``, ``C = Rz Tz Rx Tx``;
``mdh``: ``A = Rx Tx``, ``C = Rz Tz``; ``cpc``: ``A = I``, ``C = V``). The table folds them into
``n + 1`` constant links ``G_0 Q_1 G_1 ... Q_n G_n`` once, and evaluates that.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import chainfk, se3
from .screws import Joint, JointKind, JointMotion, PoeModel

__all__ = ["CONVENTIONS", "SCHEMA", "Check", "Row", "Table", "convention_module"]

SCHEMA = "urdf2dh/1"
CONVENTIONS = ("dh", "mdh", "cpc")

Mat = NDArray[np.float64]


def convention_module(name: str) -> ModuleType:
    """The module that owns a convention's parameters (``urdf2dh.dh``, ``.mdh``, ``.cpc``)."""
    return importlib.import_module(f"urdf2dh.{name}")


@dataclass(frozen=True, init=False)
class Row(JointMotion):
    """One movable joint's row: its motion (kind, pitch, scale) and its constant parameters."""

    name: str
    kind: JointKind
    params: Mapping[str, Any]
    pitch: float = 0.0
    scale: float = 1.0
    lower: float | None = None
    upper: float | None = None

    def __init__(
        self,
        name: str,
        kind: JointKind,
        params: Mapping[str, Any],
        pitch: float = 0.0,
        scale: float = 1.0,
        lower: float | None = None,
        upper: float | None = None,
    ) -> None:
        # one update of the instance's dict, as screws.Joint does (a row per joint per table)
        vars(self).update(name=name, kind=kind, params=params, pitch=pitch, scale=scale,
                          lower=lower, upper=upper)


@dataclass(frozen=True)
class Check:
    """The conversion's own self-check: table FK against the source's POE FK."""

    samples: int
    max_position_error: float
    max_rotation_error: float


@dataclass(frozen=True, init=False)
class Table:
    """A kinematic parameter table in one convention (``dh``, ``mdh`` or ``cpc``)."""

    convention: str
    base: Mapping[str, Any]
    rows: tuple[Row, ...]
    tool: Mapping[str, Any]
    robot: str = ""
    source: str = ""
    base_link: str = ""
    tip_link: str = ""
    length_unit: str = "m"
    check: Check | None = None
    warnings: tuple[str, ...] = field(default=())

    def __init__(
        self,
        convention: str,
        base: Mapping[str, Any],
        rows: tuple[Row, ...],
        tool: Mapping[str, Any],
        robot: str = "",
        source: str = "",
        base_link: str = "",
        tip_link: str = "",
        length_unit: str = "m",
        check: Check | None = None,
        warnings: tuple[str, ...] = (),
    ) -> None:
        vars(self).update(  # in one update, as Row's fields are
            convention=convention, base=base, rows=tuple(rows), tool=tool, robot=robot,
            source=source, base_link=base_link, tip_link=tip_link, length_unit=length_unit,
            check=check, warnings=tuple(warnings),
        )

    @property
    def n(self) -> int:
        """Number of movable joints."""
        return len(self.rows)

    @cached_property
    def base_matrix(self) -> Mat:
        """``(4, 4)`` base transform ``B`` built from ``base`` params."""
        return se3.matrix_of(convention_module(self.convention).base_frame(self.base))

    @cached_property
    def tool_matrix(self) -> Mat:
        """``(4, 4)`` tool transform ``T`` built from ``tool`` params."""
        return se3.matrix_of(convention_module(self.convention).tool_frame(self.tool))

    @cached_property
    def links(self) -> Mat:
        """``(n + 1, 4, 4)``: the constant transforms ``G_0 .. G_n`` between the joint motions."""
        return se3.stack(self.link_form()[0])

    def link_form(self) -> tuple[list[se3.Frame], list[tuple[float, float]]]:
        """The FK as ``n + 1`` constant links ``G_0 .. G_n`` (plain-float frames) and, per
        joint, the rotation and translation of ``Q_i`` per unit of ``q``:
        ``T(q) = G_0 Q_1 G_1 ... Q_n G_n``."""
        mod = convention_module(self.convention)
        out: list[se3.Frame] = []
        g = mod.base_frame(self.base)
        for row in self.rows:
            pre, post = mod.row_frames(row.params)
            out.append(g if pre is None else se3.compose(g, pre))
            g = post
        out.append(se3.compose(g, mod.tool_frame(self.tool)))
        motions = [(r.rotation * r.scale, r.translation * r.scale) for r in self.rows]
        return out, motions

    @cached_property
    def _program(self) -> chainfk.Program:
        """The FK as elementary motions (see :mod:`urdf2dh.chainfk`): each joint's offsets
        joined to its motion, the rest as ``Rx``, ``Tx``, ``Rz``, ``Tz`` or a dense ``V``."""
        joints: list[tuple[float, float, float, float, float]] = []
        between: list[tuple[list[tuple[int, Any]], list[tuple[int, Any]]]] = []
        for r in self.rows:
            rot, lin = r.rotation, r.translation
            p = r.params
            if self.convention == "cpc":
                joints.append((rot, lin, r.scale, 0.0, 0.0))
                v = se3.matrix_of(convention_module("cpc").v_frame(p["b"], p["l"], p["beta"]))
                between.append(([], [(chainfk.MATRIX, v)]))
                continue
            joints.append((rot, lin, r.scale, p["theta"], p["d"]))
            link = chainfk.rx(p["alpha"]) + chainfk.translate(chainfk.TX, p["a"])
            between.append(([], link) if self.convention == "dh" else (link, []))
        t = self.tool
        tool = [] if self.convention == "cpc" else (
            chainfk.rz(t["theta"]) + chainfk.translate(chainfk.TZ, t["d"]))
        if self.convention == "mdh":
            tool = chainfk.rx(t["alpha"]) + chainfk.translate(chainfk.TX, t["a"]) + tool
        if self.convention == "cpc":
            return chainfk.Program.build(self.base_matrix, joints, between, tool)
        b = self.base  # B = Rz Tz (mdh), Rz Tz Rx Tx (dh): elementary operations too
        base = chainfk.rz(b["theta"]) + chainfk.translate(chainfk.TZ, b["d"])
        if self.convention == "dh":
            base += chainfk.rx(b["alpha"]) + chainfk.translate(chainfk.TX, b["a"])
        return chainfk.Program.build(base, joints, between, tool)

    def fk(self, q: NDArray[np.float64]) -> Mat:
        """Pose ``(4, 4)`` of the tool for a configuration ``q`` of shape ``(n,)``; for a stack
        of shape ``(..., n)``, poses ``(..., 4, 4)`` (computed by :meth:`fk_batch`)."""
        return se3.fk_of_stack(self.fk_batch, q, self.n)

    def fk_batch(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Poses ``(N, 4, 4)`` of the tool for configurations ``q`` of shape ``(N, n)``,
        vectorised over N (:func:`urdf2dh.chainfk.run`; threads for large N)."""
        return chainfk.run(self._program, se3.as_configurations(q, self.n))

    def frames(self) -> list[Mat]:
        """Home-pose frames: ``[B.A_1, ..]`` where each joint's z axis is, then the tool."""
        out, f = [], np.eye(4)
        for g in self.links[:-1]:
            f = f @ g
            out.append(f)
        out.append(f @ self.links[-1])
        return out

    def to_poe(self) -> PoeModel:
        """The equivalent POE model: joint ``i`` moves about the z axis of the frame just before
        ``Q_i``, and ``M`` is the home pose (Sumenkov §III-B; Wu 2019 §II)."""
        frames = self.frames()
        joints = []
        for row, f in zip(self.rows, frames[:-1], strict=True):
            joints.append(
                Joint(
                    row.name, row.kind, f[:3, 2].copy(), f[:3, 3].copy(),
                    row.pitch, row.scale, row.lower, row.upper,
                )
            )
        return PoeModel(
            tuple(joints), frames[-1], self.robot, self.source, self.base_link,
            self.tip_link, self.length_unit,
        )

    # ------------------------------------------------------------------ serialisation

    def to_dict(self) -> dict[str, Any]:
        """The SPEC §2 tree (what ``--format json`` and ``--format yaml`` write)."""

        def clean(p: Mapping[str, Any]) -> dict[str, Any]:
            return {k: (list(map(float, v)) if isinstance(v, list | tuple | np.ndarray)
                        else float(v)) for k, v in p.items()}

        joints = []
        for r in self.rows:
            entry: dict[str, Any] = {
                "name": r.name, "type": r.kind, "pitch": float(r.pitch),
                "scale": float(r.scale), "params": clean(r.params),
            }
            if r.lower is not None and r.upper is not None:
                entry["limits"] = [float(r.lower), float(r.upper)]
            joints.append(entry)
        return {
            "schema": SCHEMA,
            "convention": self.convention,
            "robot": self.robot,
            "source": self.source,
            "base_link": self.base_link,
            "tip_link": self.tip_link,
            "units": {"length": self.length_unit, "angle": "rad"},
            "base": {"params": clean(self.base), "matrix": self.base_matrix.tolist()},
            "joints": joints,
            "tool": {"params": clean(self.tool), "matrix": self.tool_matrix.tolist()},
            "check": None if self.check is None else {
                "samples": self.check.samples,
                "max_position_error": self.check.max_position_error,
                "max_rotation_error": self.check.max_rotation_error,
            },
            "warnings": list(self.warnings),
        }


def wrap(a: float) -> float:
    """An angle in ``(-pi, pi]``."""
    out = math.remainder(a, 2.0 * math.pi)
    return math.pi if out == -math.pi else out + 0.0
