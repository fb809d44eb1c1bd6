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
    "base_matrix",
    "r_of_b",
    "reversals",
    "row_matrices",
    "shapes_from_poe",
    "tool_matrix",
    "v_matrix",
]

PARAMS = ("b", "l", "beta")
BASE_PARAMS = ("b", "l", "beta")
TOOL_PARAMS: tuple[str, ...] = ()

Mat = NDArray[np.float64]
Vec = NDArray[np.float64]


def r_of_b(b: Vec) -> Mat:
    """``R(b)`` of Sumenkov eq. (4) as a 3x3 rotation taking z to the unit vector ``b``.

    Evaluated with ``1/(1 + b_z) = (1 - b_z)/(b_x^2 + b_y^2)`` when ``b_z < 0``, which is the same
    number in exact arithmetic and keeps full precision near ``b = -z``.
    """
    bx, by, bz = float(b[0]), float(b[1]), float(b[2])
    rho2 = bx * bx + by * by
    if rho2 == 0.0:
        return np.eye(3) if bz > 0.0 else np.diag([-1.0, 1.0, -1.0])
    c = 1.0 / (1.0 + bz) if bz >= 0.0 else (1.0 - bz) / rho2
    return np.array(
        [
            [1.0 - c * bx * bx, -c * bx * by, bx],
            [-c * bx * by, 1.0 - c * by * by, by],
            [-bx, -by, bz],
        ]
    )


def v_matrix(b: Vec, l: Vec, beta: float) -> Mat:  # noqa: E741 - the paper's name
    """``V(b, l, beta) = R(b) Rz(beta) Tx(l_x) Ty(l_y) Tz(l_z)`` (Sumenkov eq. 3)."""
    out = np.eye(4)
    r = r_of_b(np.asarray(b, dtype=float)) @ se3.rot_z(beta)[:3, :3]
    out[:3, :3] = r
    out[:3, 3] = r @ np.asarray(l, dtype=float)
    return out


def base_matrix(p: dict[str, Any]) -> Mat:
    """``B = V_0``."""
    return v_matrix(p["b"], p["l"], p["beta"])


def row_matrices(p: dict[str, Any]) -> tuple[Mat | None, Mat]:
    """(before ``Q_i``, after ``Q_i``): ``None`` and ``V_i``."""
    return None, v_matrix(p["b"], p["l"], p["beta"])


def tool_matrix(p: dict[str, Any]) -> Mat:
    """The identity: the tool shape matrix lives in the last row (SPEC §2)."""
    return np.eye(4)


def reversals(model: PoeModel, tol: Tolerances) -> list[float]:
    """The sign (+1 or -1) of each joint's CPC frame z relative to its axis.

    Forward pass: reverse a frame whose axis points more than ``acos(reverse_below)`` away from
    the previous frame's z. Then the tool: if its z points that far from the last frame's z,
    reverse the shortest run of last frames whose first member may turn around safely.
    """
    reverse_below = tol.cpc_reverse_below
    signs: list[float] = []
    zs = [np.array([0.0, 0.0, 1.0])]
    for j in model.joints:
        s = -1.0 if float(zs[-1] @ j.axis) < reverse_below else 1.0
        signs.append(s)
        zs.append(s * j.axis)
    tool_z = model.home[:3, 2]
    if model.n and float(zs[-1] @ tool_z) < reverse_below:
        # Reverse a run of last frames, starting at joint `first` (1-based): the pair
        # (first - 1, first) then turns round. Prefer the shortest run whose turned pair stays
        # within the preference; else the one whose turned pair is farthest from singular.
        turned = {first: -float(zs[first - 1] @ zs[first]) for first in range(model.n, 0, -1)}
        ok = [f for f, v in turned.items() if v >= reverse_below]
        first = ok[0] if ok else max(turned, key=lambda f: turned[f])
        if turned[first] > -1.0 + tol.cpc_singular_margin:
            for k in range(first - 1, model.n):
                signs[k] = -signs[k]
    return signs


def _direction(v: Vec, noise: float) -> Vec:
    """A unit ``b``; within round-off of ``-z`` it is exactly ``-z``, so that ``R(b)`` there is
    the documented ``Ry(pi)`` and not a turn about whatever the round-off points to."""
    b = v / np.linalg.norm(v)
    if b[2] < 0.0 and math.hypot(float(b[0]), float(b[1])) <= noise:
        return np.array([0.0, 0.0, -1.0])
    return b


def _tool_shape(g: Mat, noise: float) -> dict[str, Any]:
    """Statement 1: ``b`` is the third column, ``beta`` from ``R(b)^T R``, ``l`` from ``t``."""
    b = _direction(g[:3, 2], noise)
    rz = r_of_b(b).T @ g[:3, :3]
    beta = angle(rz[1, 0], rz[0, 0])
    r = r_of_b(b) @ se3.rot_z(beta)[:3, :3]
    return {"b": b.tolist(), "l": (r.T @ g[:3, 3]).tolist(), "beta": beta}


def shapes_from_poe(
    model: PoeModel, tol: Tolerances
) -> tuple[list[dict[str, Any]], list[float], list[str]]:
    """Sumenkov's Algorithm 1: the shape parameters ``V_0 .. V_n``, the frame signs, and notes.

    Frames are accumulated from the parameters as they will be evaluated, so each row sees the
    previous rows' rounding.
    """
    signs = reversals(model, tol)
    f = np.eye(4)
    shapes: list[dict[str, Any]] = []
    notes: list[str] = []
    prev = "base z"
    for j, s in zip(model.joints, signs, strict=True):
        r, t = f[:3, :3], f[:3, 3]
        b = _direction(r.T @ (s * j.axis), tol.noise)
        p = np.zeros(3) if j.point is None else r.T @ (j.point - t)
        o = p - float(p @ b) * b  # foot of the perpendicular from the previous origin
        rb = r_of_b(b)
        if b[0] == 0.0 and b[1] == 0.0 and b[2] < 0.0:
            notes.append(_singular_note(prev, j.name))
        shape = {"b": b.tolist(), "l": [float(rb[:, 0] @ o), float(rb[:, 1] @ o), 0.0], "beta": 0.0}
        shapes.append(shape)
        f = f @ v_matrix(shape["b"], shape["l"], 0.0)
        prev = j.name
    g = se3.inv(f) @ model.home
    tool = _tool_shape(g, tol.noise)
    if tool["b"][0] == 0.0 and tool["b"][1] == 0.0 and tool["b"][2] < 0.0:
        notes.append(_singular_note(prev, "tool z"))
    shapes.append(tool)
    return shapes, signs, notes


def _singular_note(first: str, second: str) -> str:
    return (
        f"cpc: '{second}' points exactly against the z of the frame on '{first}' and no frame "
        "reversal can avoid it; R(b) at b = -z is taken as Ry(pi), its limit from +x "
        "(Sumenkov eq. 4 is 0/0 there)"
    )
