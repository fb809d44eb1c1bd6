"""Batched SO(3)/SE(3): exp, log, their Jacobians, quaternions (calibration's residuals and charts).

Twists are ``[w, v]`` (angular first), as everywhere in urdf2dh (Wu 2019 eq. 1). Stacks of
transforms are ``(N, 4, 4)``, of rotations ``(N, 3, 3)``, of rotation vectors ``(N, 3)``.
Quaternions are ``[x, y, z, w]`` (scalar last), as the measurement files hold them.

Formulas: Rodrigues' rotation and the SO(3) left Jacobian and its inverse (Barfoot, *State
Estimation for Robotics*, 2017, eqs. 7.37, 7.45); the logarithm as the rotation vector of the
skew part, with the symmetric part near pi (Murray, Li & Sastry 1994, §2.2).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TypeVar

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "CROSS_NEXT",
    "CROSS_PREV",
    "coefficients",
    "cross3",
    "cross_rows",
    "exp_so3",
    "exp_so3_left_jacobian",
    "left_jacobian",
    "left_jacobian_inverse",
    "log_se3",
    "log_so3",
    "quaternion_of",
    "rotation_of",
    "skew_batch",
    "turn_coefficients",
]

Mat = NDArray[np.float64]
T = TypeVar("T", float, Mat)

_EYE3 = np.eye(3)
_EYE3.setflags(write=False)
_SERIES = 0.1  # below this angle (rad) the coefficients that cancel are taken from their series
_NEAR_PI = 1e-3  # within this of pi the rotation axis comes from the symmetric part of R


def skew_batch(w: Mat) -> Mat:
    """``(..., 3) -> (..., 3, 3)``: the matrices ``[w]`` with ``[w] u = w x u``."""
    w = np.asarray(w, dtype=float)
    out = np.zeros((*w.shape[:-1], 9))
    out[..., _SKEW_PLUS] = w
    out[..., _SKEW_MINUS] = -w
    return out.reshape(*w.shape[:-1], 3, 3)


_SKEW_PLUS = np.array([7, 2, 3])  # where w_0, w_1, w_2 sit in the flattened [w]
_SKEW_MINUS = np.array([5, 6, 1])  # and where -w_0, -w_1, -w_2 do


def _norms(w: Mat) -> Mat:
    """``|w|`` along the last axis (numpy's ``norm`` without its dispatch)."""
    out: Mat = np.sqrt(np.add.reduce(w * w, axis=-1))
    return out


def _coefficients(theta: Mat) -> tuple[Mat, Mat, Mat]:
    """``sin t / t``, ``(1 - cos t) / t^2``, ``(t - sin t) / t^3``.

    The second as ``2 sin^2(t/2) / t^2`` (no cancellation); the third, which cancels, from its
    series below :data:`_SERIES` (truncation below 1e-16 relative there, and its rounding above
    costs at most one unit of 1e-16 once multiplied by the ``t^2`` of ``[w]^2``).
    """
    zero = theta == 0.0
    some_zero = bool(zero.any())
    t = np.where(zero, 1.0, theta) if some_zero else theta
    sin = np.sin(t)
    a = sin / t
    half = np.sin(0.5 * t) / t
    b = 2.0 * half * half
    if some_zero:
        a, b = np.where(zero, 1.0, a), np.where(zero, 0.5, b)
    c = _either(
        theta < _SERIES, lambda: _third_series(theta * theta), lambda: (t - sin) / (t * t * t)
    )
    return a, b, c


def coefficients(t2: float) -> tuple[float, float, float]:
    """:func:`_coefficients` of one angle ``t`` given as ``t^2``, in plain floats (one pose:
    numpy's per-call cost would be most of it)."""
    t = math.sqrt(t2)
    if t == 0.0:
        a, b = 1.0, 0.5
    else:
        half = math.sin(0.5 * t) / t
        a, b = math.sin(t) / t, 2.0 * half * half
    c = _third_series(t2) if t < _SERIES else (t - math.sin(t)) / (t2 * t)
    return a, b, c


def _third_series(t2: T) -> T:
    """``(t - sin t) / t^3`` near 0, from ``t^2``: its series to ``t^6``."""
    return 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0 - t2 * t2 * t2 / 362880.0


def turn_coefficients(angle: Mat) -> Mat:
    """``(n, 5)``: of each angle ``t`` ``(n,)``, ``h = (sin t - t cos t) / sin^3 t`` (the
    derivative of a line's turn coordinates, :meth:`.calibration.chart.LineCoordinates.tangent`),
    ``b'(t) / t``, ``c'(t) / t``, ``b`` and ``c`` with ``b, c`` the left Jacobian's
    (:func:`coefficients`: ``(1 - cos t) / t^2``, ``(t - sin t) / t^3``); below
    :data:`_SERIES` from their series to ``t^8`` (the first three cancel; each multiplies a
    ``t^2`` there, so the closed forms' rounding above costs a few units of 1e-16)."""
    t2 = angle * angle
    out: Mat = (t2[:, None] ** _POWERS) @ _SERIES_TERMS
    far = angle >= _SERIES
    if far.any():
        t = angle[far]
        tt, sin, cos = t * t, np.sin(t), np.cos(t)
        b, c = np.array([coefficients(x)[1:] for x in tt.tolist()]).T
        out[far] = np.stack(
            (
                (sin - t * cos) / (sin * sin * sin),
                (sin / t - 2.0 * b) / tt,
                (b - 3.0 * c) / tt,
                b,
                c,
            ),
            axis=1,
        )
    return out


_POWERS = np.arange(5)  # of t^2
_SERIES_TERMS = np.array(  # each power's term (rows) in h, b'/t, c'/t, b, c (columns)
    [
        [1 / 3, -1 / 12, -1 / 60, 1 / 2, 1 / 6],
        [2 / 15, 1 / 180, 1 / 1260, -1 / 24, -1 / 120],
        [2 / 63, -1 / 6720, -1 / 60480, 1 / 720, 1 / 5040],
        [4 / 675, 1 / 453600, 1 / 4989600, -1 / 40320, -1 / 362880],
        [2 / 2079, -1 / 47900160, -1 / 622702080, 1 / 3628800, 1 / 39916800],
    ]
)


def _either(near: NDArray[np.bool_], series: Callable[[], Mat], closed: Callable[[], Mat]) -> Mat:
    """``np.where(near, series(), closed())``, each formula evaluated only when some entry takes
    it (the closed forms are taken away from ``near`` entries, the series near them)."""
    if near.all():
        return series()
    if not near.any():
        return closed()
    out: Mat = np.where(near, series(), closed())
    return out


def exp_so3(w: Mat) -> Mat:
    """``(..., 3) -> (..., 3, 3)``: ``exp([w]) = I + a [w] + b [w]^2`` (Rodrigues)."""
    w = np.asarray(w, dtype=float)
    theta = _norms(w)
    a, b, _ = _coefficients(theta)
    k = skew_batch(w)
    return _EYE3 + a[..., None, None] * k + b[..., None, None] * (k @ k)


def left_jacobian(w: Mat) -> Mat:
    """``(..., 3) -> (..., 3, 3)``: SO(3)'s left Jacobian ``I + b [w] + c [w]^2``; the
    translation of ``exp([w, v])`` is ``J(w) v``."""
    w = np.asarray(w, dtype=float)
    theta = _norms(w)
    _, b, c = _coefficients(theta)
    k = skew_batch(w)
    return _EYE3 + b[..., None, None] * k + c[..., None, None] * (k @ k)


def exp_so3_left_jacobian(w: Mat) -> tuple[Mat, Mat]:
    """:func:`exp_so3` and :func:`left_jacobian` of ``w`` at once (the same arithmetic, the
    coefficients and ``[w]^2`` found once)."""
    w = np.asarray(w, dtype=float)
    theta = _norms(w)
    a, b, c = _coefficients(theta)
    k = skew_batch(w)
    k2 = k @ k
    rot = _EYE3 + a[..., None, None] * k + b[..., None, None] * k2
    return rot, _EYE3 + b[..., None, None] * k + c[..., None, None] * k2


def left_jacobian_inverse(w: Mat) -> Mat:
    """``(..., 3) -> (..., 3, 3)``: ``J(w)^-1 = I - [w]/2 + e [w]^2`` with
    ``e = 1/t^2 - (1 + cos t) / (2 t sin t)`` (``1/12`` at 0). With ``R = exp([w])``, a left
    perturbation ``exp([d]) R`` has the rotation vector ``w + J(w)^-1 d`` to first order."""
    w = np.asarray(w, dtype=float)
    theta = _norms(w)
    small = theta < _SERIES

    def series() -> Mat:
        t2 = theta * theta
        out: Mat = 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0 + t2 * t2 * t2 / 1209600.0
        return out

    def closed() -> Mat:
        t = np.where(small, 1.0, theta)
        out: Mat = 1.0 / (t * t) - (1.0 + np.cos(t)) / (2.0 * t * np.sin(t))
        return out

    e = _either(small, series, closed)
    k = skew_batch(w)
    return _EYE3 - 0.5 * k + e[..., None, None] * (k @ k)


def log_so3(r: Mat) -> Mat:
    """``(..., 3, 3) -> (..., 3)``: the rotation vector of ``R`` (angle in ``[0, pi]``)."""
    r = np.asarray(r, dtype=float)
    s = np.empty(r.shape[:-1])  # sin(t) * axis
    np.subtract(r[..., 2, 1], r[..., 1, 2], out=s[..., 0])
    np.subtract(r[..., 0, 2], r[..., 2, 0], out=s[..., 1])
    np.subtract(r[..., 1, 0], r[..., 0, 1], out=s[..., 2])
    s *= 0.5
    sin = _norms(s)
    cos = 0.5 * (r[..., 0, 0] + r[..., 1, 1] + r[..., 2, 2] - 1.0)
    theta = np.arctan2(sin, cos)
    zero = sin == 0.0
    if zero.any():
        factor = np.where(zero, 1.0, theta / np.where(zero, 1.0, sin))
    else:
        factor = theta / sin
    out = factor[..., None] * s
    near_pi = np.pi - theta < _NEAR_PI
    if near_pi.any():  # sin t is tiny there: take the axis from R + R^T = 2 (I + (1-c) a a^T)
        rp = r[near_pi]
        sym = 0.5 * (rp + np.swapaxes(rp, -1, -2)) - cos[near_pi][:, None, None] * np.eye(3)
        col = np.argmax(np.diagonal(sym, axis1=-2, axis2=-1), axis=-1)
        axis = sym[np.arange(len(rp)), :, col]
        axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
        sign = np.where(np.sum(axis * s[near_pi], axis=-1) < 0.0, -1.0, 1.0)
        out[near_pi] = (sign * theta[near_pi])[:, None] * axis
    return out


def log_se3(t: Mat) -> Mat:
    """``(..., 4, 4) -> (..., 6)``: the twist ``[w, v]`` with ``exp([w, v]) = T``."""
    t = np.asarray(t, dtype=float)
    w = log_so3(t[..., :3, :3])
    v = np.einsum("...ij,...j->...i", left_jacobian_inverse(w), t[..., :3, 3])
    return np.concatenate([w, v], axis=-1)


def rotation_of(quat: Mat) -> Mat:
    """``(..., 4) -> (..., 3, 3)``: the rotation of unit quaternions ``[x, y, z, w]``."""
    quat = np.asarray(quat, dtype=float)
    x, y, z, w = np.moveaxis(quat, -1, 0)
    xx, yy, zz, xy, xz, yz = x * x, y * y, z * z, x * y, x * z, y * z
    xw, yw, zw = x * w, y * w, z * w
    out = np.empty((*quat.shape[:-1], 3, 3))
    out[..., 0, 0] = 1 - 2 * (yy + zz)
    out[..., 0, 1] = 2 * (xy - zw)
    out[..., 0, 2] = 2 * (xz + yw)
    out[..., 1, 0] = 2 * (xy + zw)
    out[..., 1, 1] = 1 - 2 * (xx + zz)
    out[..., 1, 2] = 2 * (yz - xw)
    out[..., 2, 0] = 2 * (xz - yw)
    out[..., 2, 1] = 2 * (yz + xw)
    out[..., 2, 2] = 1 - 2 * (xx + yy)
    return out


def quaternion_of(r: Mat) -> Mat:
    """``(..., 3, 3) -> (..., 4)``: unit quaternions ``[x, y, z, w]`` with ``w >= 0``, from the
    largest of the four diagonal combinations (Shepperd 1978), so every rotation is accurate."""
    r = np.asarray(r, dtype=float)
    tr = np.trace(r, axis1=-2, axis2=-1)
    d = np.stack([r[..., 0, 0], r[..., 1, 1], r[..., 2, 2], tr], axis=-1)
    pick = np.argmax(d, axis=-1)
    q = np.empty((*r.shape[:-2], 4))
    # four candidate formulas, each exact where its pivot is the largest
    piv = (
        np.sqrt(
            np.maximum(1.0 + 2.0 * np.take_along_axis(d, pick[..., None], -1)[..., 0] - tr, 0.0)
        )
        / 2.0
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        k = 0.25 / piv
    r10, r01, r20, r02 = r[..., 1, 0], r[..., 0, 1], r[..., 2, 0], r[..., 0, 2]
    r21, r12 = r[..., 2, 1], r[..., 1, 2]
    cands = [
        np.stack([piv, (r01 + r10) * k, (r02 + r20) * k, (r21 - r12) * k], -1),
        np.stack([(r01 + r10) * k, piv, (r12 + r21) * k, (r02 - r20) * k], -1),
        np.stack([(r02 + r20) * k, (r12 + r21) * k, piv, (r10 - r01) * k], -1),
        np.stack([(r21 - r12) * k, (r02 - r20) * k, (r10 - r01) * k, piv], -1),
    ]
    for i, c in enumerate(cands):
        sel = pick == i
        q[sel] = c[sel]
    q *= np.where(q[..., 3:] < 0.0, -1.0, 1.0)
    return q


def cross3(a: Mat, b: Mat) -> Mat:
    """``a x b`` of two 3-vectors (numpy's ``cross`` costs ten times as much for one pair)."""
    a0, a1, a2 = float(a[0]), float(a[1]), float(a[2])
    b0, b1, b2 = float(b[0]), float(b[1]), float(b[2])
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def cross_rows(a: Mat, b: Mat) -> Mat:
    """``a x b`` row by row for ``(n, 3)`` arrays, or for any two that broadcast (without
    numpy's ``cross`` axis handling)."""
    if a.shape != b.shape:  # each operand's components gathered once, then broadcast
        out: Mat = a[..., CROSS_NEXT] * b[..., CROSS_PREV] - a[..., CROSS_PREV] * b[..., CROSS_NEXT]
        return out
    out = np.empty(a.shape)
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


# component i of a x b is a[CROSS_NEXT[i]] b[CROSS_PREV[i]] - a[CROSS_PREV[i]] b[CROSS_NEXT[i]]
CROSS_NEXT = np.array([1, 2, 0])
CROSS_PREV = np.array([2, 0, 1])
CROSS_NEXT.setflags(write=False)
CROSS_PREV.setflags(write=False)
