"""POE -> CPC, the complete and parametrically continuous model (Zhuang, Roth & Hamano 1990),
by Sumenkov's analytic conversion (Lemmas 1-3, Statement 1, Algorithm 1).

Forward kinematics of a ``cpc`` table (SPEC §2)::

    T(q) = V_0 . prod_i [ Q_i(s_i) . V_i ],   V(b, l, beta) = R(b) Rz(beta) Tx(l_x) Ty(l_y) Tz(l_z)

``V_0`` (the base) and ``V_1 .. V_{n-1}`` put each next frame's z on the next joint axis with
``beta = l_z = 0``: ``b`` is the axis direction and the origin is the foot of the perpendicular
from the previous origin (Lemmas 1-3). The last row's ``V_n`` is the whole tool transform
(Statement 1), so ``tool`` is the identity.

``R(b)`` (Sumenkov eq. 4) is singular at ``b = -z``. A frame whose axis direction would have
``b_z < cpc_reverse_below`` is reversed (its joint gets ``scale = -scale``, SPEC §2); where no
reversal can help (a chain of parallel axes whose far ends point opposite ways) and ``b`` is
exactly ``-z``, ``R(-z)`` is taken as ``Ry(pi)``, its limit from the ``+x`` side, and a warning
says so.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import se3
from .lines import angle
from .screws import PoeModel
from .tolerances import Tolerances

__all__ = [
    "BASE_PARAMS",
    "PARAMS",
    "TOOL_PARAMS",
    "base_frame",
    "r_of_b",
    "reversals",
    "row_frames",
    "shapes_from_poe",
    "tool_frame",
    "v_frame",
    "v_matrix",
]

PARAMS = ("b", "l", "beta")
BASE_PARAMS = ("b", "l", "beta")
TOOL_PARAMS: tuple[str, ...] = ()

Mat = NDArray[np.float64]
Rows = tuple[se3.Vec3, se3.Vec3, se3.Vec3]


def _r_rows(b: Sequence[float]) -> Rows:
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


def r_of_b(b: Sequence[float]) -> Mat:
    """``R(b)`` of Sumenkov eq. (4) as a 3x3 rotation taking z to the unit vector ``b``.

    Evaluated with ``1/(1 + b_z) = (1 - b_z)/(b_x^2 + b_y^2)`` when ``b_z < 0``, which is the same
    number in exact arithmetic and keeps full precision near ``b = -z``.
    """
    return np.array(_r_rows(b))


def v_frame(b: Sequence[float], l: Sequence[float], beta: float) -> se3.Frame:  # noqa: E741
    """``V(b, l, beta) = R(b) Rz(beta) Tx(l_x) Ty(l_y) Tz(l_z)`` (Sumenkov eq. 3), as a
    plain-float :data:`~urdf2dh.se3.Frame`."""
    cb, sb = math.cos(beta), math.sin(beta)
    lx, ly, lz = (float(c) for c in l)
    rows = []
    for r0, r1, r2 in _r_rows(b):
        x, y = r0 * cb + r1 * sb, r1 * cb - r0 * sb  # the row of R(b) Rz(beta)
        rows.append((x, y, r2, x * lx + y * ly + r2 * lz))
    return tuple(rows)


def v_matrix(b: Sequence[float], l: Sequence[float], beta: float) -> Mat:  # noqa: E741
    """``V(b, l, beta)`` as a 4x4 array."""
    return se3.matrix_of(v_frame(b, l, beta))


def base_frame(p: dict[str, Any]) -> se3.Frame:
    """``B = V_0``."""
    return v_frame(p["b"], p["l"], p["beta"])


def row_frames(p: dict[str, Any]) -> tuple[se3.Frame | None, se3.Frame]:
    """(before ``Q_i``, after ``Q_i``): ``None`` and ``V_i``."""
    return None, v_frame(p["b"], p["l"], p["beta"])


def tool_frame(p: dict[str, Any]) -> se3.Frame:
    """The identity: the tool shape matrix lives in the last row (SPEC §2)."""
    return se3.IDENTITY


def _dot(a: Sequence[float], b: Sequence[float]) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def reversals(model: PoeModel, tol: Tolerances) -> list[float]:
    """The sign (+1 or -1) of each joint's CPC frame z relative to its axis.

    Forward pass: reverse a frame whose axis points more than ``acos(reverse_below)`` away from
    the previous frame's z. Then the tool: if its z points that far from the last frame's z,
    reverse the shortest run of last frames whose first member may turn around safely.
    """
    reverse_below = tol.cpc_reverse_below
    signs: list[float] = []
    zs: list[se3.Vec3] = [(0.0, 0.0, 1.0)]
    for j in model.joints:
        x, y, z = j.axis.tolist()
        s = -1.0 if _dot(zs[-1], (x, y, z)) < reverse_below else 1.0
        signs.append(s)
        zs.append((s * x, s * y, s * z))
    tool_z = model.home[:3, 2].tolist()
    if model.n and _dot(zs[-1], tool_z) < reverse_below:
        # Reverse a run of last frames, starting at joint `first` (1-based): the pair
        # (first - 1, first) then turns round. Prefer the shortest run whose turned pair stays
        # within the preference; else the one whose turned pair is farthest from singular.
        turned = {first: -_dot(zs[first - 1], zs[first]) for first in range(model.n, 0, -1)}
        ok = [f for f, v in turned.items() if v >= reverse_below]
        first = ok[0] if ok else max(turned, key=lambda f: turned[f])
        if turned[first] > -1.0 + tol.cpc_singular_margin:
            for k in range(first - 1, model.n):
                signs[k] = -signs[k]
    return signs


def _direction(v: se3.Vec3, noise: float) -> se3.Vec3:
    """A unit ``b``; within round-off of ``-z`` it is exactly ``-z``, so that ``R(b)`` there is
    the documented ``Ry(pi)`` and not a turn about whatever the round-off points to."""
    b = se3.unit(v)
    if b[2] < 0.0 and math.hypot(b[0], b[1]) <= noise:
        return (0.0, 0.0, -1.0)
    return b


def _tool_shape(g: se3.Frame, noise: float) -> dict[str, Any]:
    """Statement 1: ``b`` is the third column, ``beta`` from ``R(b)^T R``, ``l`` from ``t``."""
    b = _direction((g[0][2], g[1][2], g[2][2]), noise)
    r = _r_rows(b)
    x = (g[0][0], g[1][0], g[2][0])  # R's first column; R(b)^T x gives beta
    beta = angle(_dot((r[0][1], r[1][1], r[2][1]), x), _dot((r[0][0], r[1][0], r[2][0]), x))
    l = se3.dir_into(v_frame(b, (0.0, 0.0, 0.0), beta), (g[0][3], g[1][3], g[2][3]))  # noqa: E741
    return {"b": list(b), "l": list(l), "beta": beta}


def shapes_from_poe(
    model: PoeModel, tol: Tolerances
) -> tuple[list[dict[str, Any]], list[float], list[str]]:
    """Sumenkov's Algorithm 1: the shape parameters ``V_0 .. V_n``, the frame signs, and notes.

    Frames are accumulated from the parameters as they will be evaluated, so each row sees the
    previous rows' rounding.
    """
    signs = reversals(model, tol)
    f = se3.IDENTITY
    shapes: list[dict[str, Any]] = []
    notes: list[str] = []
    prev = "base z"
    for j, s in zip(model.joints, signs, strict=True):
        x, y, z = j.axis.tolist()
        b = _direction(se3.dir_into(f, (s * x, s * y, s * z)), tol.noise)
        p = (0.0, 0.0, 0.0) if j.point is None else se3.point_into(f, _vec(j.point))
        pb = _dot(p, b)
        o = (p[0] - pb * b[0], p[1] - pb * b[1], p[2] - pb * b[2])  # foot of the perpendicular
        r = _r_rows(b)
        if b[0] == 0.0 and b[1] == 0.0 and b[2] < 0.0:
            notes.append(_singular_note(prev, j.name))
        offset = [_dot((r[0][0], r[1][0], r[2][0]), o), _dot((r[0][1], r[1][1], r[2][1]), o), 0.0]
        shapes.append({"b": list(b), "l": offset, "beta": 0.0})
        f = se3.compose(f, v_frame(b, offset, 0.0))
        prev = j.name
    tool = _tool_shape(se3.between(f, se3.frame_of(model.home)), tol.noise)
    if tool["b"][0] == 0.0 and tool["b"][1] == 0.0 and tool["b"][2] < 0.0:
        notes.append(_singular_note(prev, "tool z"))
    shapes.append(tool)
    return shapes, signs, notes


def _vec(a: Mat) -> se3.Vec3:
    x, y, z = a.tolist()
    return (x, y, z)


def _singular_note(first: str, second: str) -> str:
    return (
        f"cpc: '{second}' points exactly against the z of the frame on '{first}' and no frame "
        "reversal can avoid it; R(b) at b = -z is taken as Ry(pi), its limit from +x "
        "(Sumenkov eq. 4 is 0/0 there)"
    )
