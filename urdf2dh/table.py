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

from . import se3
from .screws import Joint, JointKind, PoeModel

__all__ = ["CONVENTIONS", "SCHEMA", "Check", "Row", "Table", "convention_module"]

SCHEMA = "urdf2dh/1"
FK_BLOCK = 8192  # configurations per block of the batched FK (two (3, 8192, 4) buffers, 1.5 MiB)
CONVENTIONS = ("dh", "mdh", "cpc")

Mat = NDArray[np.float64]


def convention_module(name: str) -> ModuleType:
    """The module that owns a convention's parameters (``urdf2dh.dh``, ``.mdh``, ``.cpc``)."""
    return importlib.import_module(f"urdf2dh.{name}")


@dataclass(frozen=True)
class Row:
    """One movable joint's row: its motion (kind, pitch, scale) and its constant parameters."""

    name: str
    kind: JointKind
    params: Mapping[str, Any]
    pitch: float = 0.0
    scale: float = 1.0
    lower: float | None = None
    upper: float | None = None


@dataclass(frozen=True)
class Check:
    """The conversion's own self-check: table FK against the source's POE FK."""

    samples: int
    max_position_error: float
    max_rotation_error: float


@dataclass(frozen=True)
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
        mod = convention_module(self.convention)
        out: list[se3.Frame] = []
        g = mod.base_frame(self.base)
        for row in self.rows:
            pre, post = mod.row_frames(row.params)
            out.append(g if pre is None else se3.compose(g, pre))
            g = post
        out.append(se3.compose(g, mod.tool_frame(self.tool)))
        flat = [x for f in out for row in (*f, (0.0, 0.0, 0.0, 1.0)) for x in row]
        return np.fromiter(flat, float, len(flat)).reshape(-1, 4, 4)

    @cached_property
    def _motion(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Per joint: rotation and translation per unit of ``s``, and the scale; ``(n,)`` each."""
        rot, lin, scale = np.array(
            [(0.0, 1.0, r.scale) if r.kind == "prismatic" else (1.0, r.pitch, r.scale)
             for r in self.rows], dtype=float,
        ).reshape(-1, 3).T
        return rot, lin, scale

    def fk(self, q: NDArray[np.float64]) -> Mat:
        """Pose ``(4, 4)`` of the tool for a configuration ``q`` of shape ``(n,)``; for a stack
        of shape ``(..., n)``, poses ``(..., 4, 4)`` (computed by :meth:`fk_batch`)."""
        return se3.fk_of_stack(self.fk_batch, q, self.n)

    def fk_batch(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Poses ``(N, 4, 4)`` of the tool for configurations ``q`` of shape ``(N, n)``.

        Vectorised over N, a block of ``m`` configurations at a time (so that the work stays
        in cache), the poses held as their top three rows, row-major over the block
        (``(3, m, 4)``). Per joint, ``Rz(phi)`` turns the x and y columns, which is one complex
        product: with ``z = x + i y``, ``[x y] Rz(phi)`` is ``z e^{-i phi}``; ``Tz(t)`` adds ``t``
        times the z column to the position; then the constant link is a single
        ``(3 m, 4) @ (4, 4)`` matrix product.
        """
        q = se3.as_configurations(q, self.n)
        rot, lin, scale = self._motion
        links = self.links
        count = q.shape[0]
        out = np.empty((count, 4, 4))
        buffers = np.empty((2, 12 * min(count, FK_BLOCK)))
        for lo in range(0, count, FK_BLOCK):
            m = min(lo + FK_BLOCK, count) - lo
            s = (q[lo : lo + m] * scale).T  # (n, m)
            minus = s * -rot[:, None]  # -phi
            turn = np.empty(s.shape, dtype=complex)  # e^{-i phi}
            np.cos(minus, out=turn.real)
            np.sin(minus, out=turn.imag)
            # per buffer: the poses (3, m, 4), their x + i y columns, and the (3 m, 4) rows
            views = [(v, v[:, :, :2].view(complex)[:, :, 0], v.reshape(-1, 4))
                     for v in (b[: 12 * m].reshape(3, m, 4) for b in buffers)]
            views[0][0][...] = links[0, :3, None, :]
            for i in range(self.n):
                (f, xy, rows), nxt = views
                if rot[i]:
                    xy *= turn[i]
                if lin[i]:
                    f[:, :, 3] += (lin[i] * s[i]) * f[:, :, 2]
                np.dot(rows, links[i + 1], out=nxt[2])
                views = [nxt, views[0]]
            out[lo : lo + m, :3] = views[0][0].transpose(1, 0, 2)
            out[lo : lo + m, 3] = (0.0, 0.0, 0.0, 1.0)
        return out

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
