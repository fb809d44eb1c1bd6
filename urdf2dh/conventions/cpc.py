"""CPC, the complete and parametrically continuous model (Zhuang, Roth & Hamano 1990), from a
POE model by Sumenkov's analytic conversion (Lemmas 1-3, Statement 1, Algorithm 1).

Forward kinematics of a ``cpc`` table (docs/conventions/cpc.md)::

    T(q) = V_0 . prod_i [ Q_i(s_i) . V_i ],   V(b, l, beta) = R(b) Rz(beta) Tx(l_x) Ty(l_y) Tz(l_z)

``V_0`` (the base) and ``V_1 .. V_{n-1}`` put each next frame's z on the next joint axis with
``beta = l_z = 0``: ``b`` is the axis direction and the origin is the foot of the perpendicular
from the previous origin (Lemmas 1-3). The last row's ``V_n`` is the whole tool transform
(Statement 1), so the tool record is empty (the identity).

How a ``cpc`` table is evaluated, exactly (what another implementation needs; also
``docs/conventions/cpc.md``):

* ``b`` is written as a unit vector (its norm 1 to within a unit in the last place; a component
  within ``tol.written`` of 0 is written as exactly 0 and the rest normalised again). A reader
  may normalise it again; it must not change its direction.
* ``R(b)`` is Sumenkov's eq. (4), the rotation about ``(-b_y, b_x, 0)`` that takes z to ``b``::

      R(b) = [[1 - c b_x^2,   -c b_x b_y,   b_x],
              [ -c b_x b_y,  1 - c b_y^2,   b_y],
              [     -b_x,        -b_y,      b_z]],   c = 1 / (1 + b_z)

  evaluated with ``c = (1 - b_z) / (b_x^2 + b_y^2)`` when ``b_z < 0`` (the same number in exact
  arithmetic; ``1 + b_z`` would cancel to nothing near ``-z``).
* ``b = (0, 0, -1)`` exactly (``b_x = b_y = 0``, ``b_z < 0``) is the one direction eq. (4) leaves
  undefined (0/0). There ``R(b)`` is the fixed rotation ``Ry(pi) = diag(-1, 1, -1)``, the limit
  of eq. (4) as ``b`` tends to ``-z`` from the ``+x`` side, ``b = (sin e, 0, -cos e)``, ``e -> 0+``
  (``b = (0, 0, 1)`` gives the identity). A written table holds this ``b`` only where no frame
  reversal can avoid it (below), and says so in a warning.
* ``V(b, l, beta) = R(b) Rz(beta) Tx(l_x) Ty(l_y) Tz(l_z)``, and ``Q_i(s_i)`` turns (slides) about
  (along) z by ``s_i = scale_i q_i``.

``R(b)`` is singular at ``b = -z``. A frame whose axis direction would have
``b_z < cpc_reverse_below`` is reversed (its joint gets ``scale = -scale``, which leaves the
table's forward kinematics unchanged); where no
reversal can help (a chain of parallel axes whose far ends point opposite ways) and ``b`` is
``-z`` up to round-off, it is written as exactly ``-z``, evaluated as ``Ry(pi)`` above, and a
warning says so. Frames are built from ``b`` as written, so each row's ``l`` and the next row see
the direction a reader evaluates.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import shown
from ..geometry import frames
from ..geometry.frames import Frame, Vec3
from .base import Conversion, Params, Style, angle, direction, offset, unit_direction

if TYPE_CHECKING:
    from ..model.poe import PoeModel
    from ..tolerances import Tolerances

__all__ = ["CPC", "CpcConvention", "CpcShape", "CpcTool", "r_rows", "reversals", "v_frame"]

Rows = tuple[Vec3, Vec3, Vec3]


def r_rows(b: Sequence[float]) -> Rows:
    """``R(b)`` of Sumenkov eq. (4), the rotation taking z to the unit vector ``b``, row by row.

    Evaluated with ``1/(1 + b_z) = (1 - b_z)/(b_x^2 + b_y^2)`` when ``b_z < 0``, which is the same
    number in exact arithmetic and keeps full precision near ``b = -z``.
    """
    bx, by, bz = float(b[0]), float(b[1]), float(b[2])
    rho2 = bx * bx + by * by
    if rho2 == 0.0:
        if bz > 0.0:
            return (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
        return (-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0)
    c = 1.0 / (1.0 + bz) if bz >= 0.0 else (1.0 - bz) / rho2
    return (
        (1.0 - c * bx * bx, -c * bx * by, bx),
        (-c * bx * by, 1.0 - c * by * by, by),
        (-bx, -by, bz),
    )


def v_frame(b: Sequence[float], l: Sequence[float], beta: float) -> Frame:  # noqa: E741
    """``V(b, l, beta) = R(b) Rz(beta) Tx(l_x) Ty(l_y) Tz(l_z)`` (Sumenkov eq. 3)."""
    cb, sb = math.cos(beta), math.sin(beta)
    lx, ly, lz = (float(c) for c in l)
    rows = []
    for r0, r1, r2 in r_rows(b):
        x, y = r0 * cb + r1 * sb, r1 * cb - r0 * sb  # the row of R(b) Rz(beta)
        rows.append((x, y, r2, x * lx + y * ly + r2 * lz))
    return tuple(rows)


@dataclass(frozen=True, slots=True)
class CpcShape(Params):
    """A CPC shape matrix ``V(b, l, beta)`` (the base, and every row)."""

    b: tuple[float, float, float] = direction()
    l: tuple[float, float, float] = offset()  # noqa: E741
    beta: float = angle()

    def frame(self) -> Frame:
        return v_frame(self.b, self.l, self.beta)


@dataclass(frozen=True, slots=True)
class CpcTool(Params):
    """The identity: the tool shape matrix is the last row's (Statement 1)."""

    def frame(self) -> Frame:
        return frames.IDENTITY


class CpcConvention:
    """The ``cpc`` convention."""

    name = "cpc"
    label = "CPC"
    title = "CPC (Zhuang-Roth-Hamano): V_0 . prod[Q_i V(b, l, beta)], V = R(b) Rz(beta) Tx Ty Tz(l)"
    formula = (
        "T(q) = V_0 . prod_i [Rz(q_i) V(b_i, l_i, beta_i)],  V = R(b) Rz(beta) Tx Ty Tz(l)  (CPC)"
    )
    base_types: tuple[type[Params], ...] = (CpcShape,)
    row_types: tuple[type[Params], ...] = (CpcShape,)
    tool_types: tuple[type[Params], ...] = (CpcTool,)
    styles: tuple[str, ...] = ("wu",)
    guided = False

    def from_poe(self, model: PoeModel, tol: Tolerances, style: Style) -> Conversion:
        """Sumenkov's Algorithm 1. Frames are accumulated from the parameters as they will be
        evaluated, so each row sees the previous rows' rounding."""
        signs = reversals(model, tol)
        f = frames.IDENTITY
        shapes: list[CpcShape] = []
        notes: list[str] = []
        prev = "base z"
        for j, s in zip(model.joints, signs, strict=True):
            x, y, z = j.axis.tolist()
            b = _direction(frames.dir_into(f, (s * x, s * y, s * z)), tol.written)
            p = (0.0, 0.0, 0.0) if j.point is None else frames.point_into(f, j.point.tolist())
            pb = _dot(p, b)
            o = (p[0] - pb * b[0], p[1] - pb * b[1], p[2] - pb * b[2])  # foot of perpendicular
            r = r_rows(b)
            if b[0] == 0.0 and b[1] == 0.0 and b[2] < 0.0:
                notes.append(_singular_note(prev, j.name))
            l = (_dot(_col(r, 0), o), _dot(_col(r, 1), o), 0.0)  # noqa: E741
            shapes.append(CpcShape(b, l, 0.0))
            f = frames.compose(f, v_frame(b, l, 0.0))
            prev = j.name
        tool = _tool_shape(frames.between(f, frames.frame_of(model.home)), tol.written)
        if tool.b[0] == 0.0 and tool.b[1] == 0.0 and tool.b[2] < 0.0:
            notes.append(_singular_note(prev, "tool z"))
        shapes.append(tool)
        notes.extend(
            f"cpc: joint {shown(j.name)} points against the previous frame's z; its frame is "
            "reversed (scale = -scale) to avoid R(b)'s singularity at b = -z"
            for j, sign in zip(model.joints, signs, strict=True)
            if sign < 0
        )
        return Conversion(shapes[0], tuple(shapes[1:]), CpcTool(), tuple(signs), (), tuple(notes))


CPC = CpcConvention()


def _dot(a: Sequence[float], b: Sequence[float]) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _col(r: Sequence[Sequence[float]], k: int) -> Vec3:
    return (r[0][k], r[1][k], r[2][k])


def reversals(model: PoeModel, tol: Tolerances) -> list[float]:
    """The sign (+1 or -1) of each joint's CPC frame z relative to its axis.

    Forward pass: reverse a frame whose axis points more than ``acos(reverse_below)`` away from
    the previous frame's z. Then the tool: if its z points that far from the last frame's z,
    reverse the shortest run of last frames whose first member may turn around safely.
    """
    reverse_below = tol.cpc_reverse_below
    signs: list[float] = []
    zs: list[Vec3] = [(0.0, 0.0, 1.0)]
    for j in model.joints:
        x, y, z = j.axis.tolist()
        s = -1.0 if _dot(zs[-1], (x, y, z)) < reverse_below else 1.0
        signs.append(s)
        zs.append((s * x, s * y, s * z))
    tool_z = model.home[:3, 2].tolist()
    if model.n and _dot(zs[-1], tool_z) < reverse_below:
        # Reverse a run of last frames, starting at joint `first` (1-based): the pair
        # (first - 1, first) then turns round. Prefer the shortest run whose turned pair stays
        # within the preference; else the shortest of those whose turned pair is farthest from
        # singular, up to round-off (pairs at equal angles, such as an axis parallel to the base
        # z, would otherwise be told apart by round-off, differently when the table's POE model
        # is converted again).
        turned = {first: -_dot(zs[first - 1], zs[first]) for first in range(model.n, 0, -1)}
        ok = [f for f, v in turned.items() if v >= reverse_below]
        best = max(turned.values())
        first = ok[0] if ok else next(f for f, v in turned.items() if v >= best - tol.noise)
        if turned[first] > -1.0 + tol.cpc_singular_margin:
            for k in range(first - 1, model.n):
                signs[k] = -signs[k]
    return signs


def _direction(v: Vec3, clean: float) -> Vec3:
    """``b`` as the table writes it: a unit vector whose components within ``clean``
    (``tol.written``) of 0 are 0, normalised again (:func:`~.base.unit_direction`), so that the
    frames built from it are the ones a reader evaluates. Within round-off of ``-z`` it is
    exactly ``-z``, where ``R(b)`` is the fixed ``Ry(pi)`` of the module docstring and not a
    turn about whatever the round-off points to."""
    x, y, z = (0.0 if abs(c) <= clean else c for c in frames.unit(v))
    return unit_direction((x, y, z))


def _tool_shape(g: Frame, clean: float) -> CpcShape:
    """Statement 1: ``b`` is the third column, ``beta`` from ``R(b)^T R``, ``l`` from ``t``."""
    b = _direction(_col(g, 2), clean)
    r = r_rows(b)
    x = _col(g, 0)  # R's first column; R(b)^T x gives beta
    beta = frames.angle(_dot(_col(r, 1), x), _dot(_col(r, 0), x))
    l = frames.dir_into(v_frame(b, (0.0, 0.0, 0.0), beta), _col(g, 3))  # noqa: E741
    return CpcShape(b, l, beta)


def _singular_note(first: str, second: str) -> str:
    return (
        f"cpc: {shown(second)} points exactly against the z of the frame on {shown(first)} and "
        "no frame reversal can avoid it; R(b) at b = -z is taken as Ry(pi), its limit from +x "
        "(Sumenkov eq. 4 is 0/0 there)"
    )
