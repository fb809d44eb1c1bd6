"""The small Lie-group kit in numpy: elementary transforms, exp, adjoint, rpy, pose errors.

Conventions (they bite, so they are stated here once):

* Homogeneous transforms are ``(4, 4)`` float64 arrays ``[[R, t], [0, 1]]``.
* Twists are ordered ``[w, v]`` (angular first), as in Wu 2019 eq. (1) and Sumenkov eq. (5),
  with ``v = p x w + h w`` for a screw through point ``p`` with pitch ``h``. Pinocchio's motion
  vectors are ``[v, w]``; convert at that boundary only (``verify.py``).
* Batched functions take ``(N, n)`` joint values and return ``(N, 4, 4)`` stacks.
* Plain-float frames, for the chain walks, are in :mod:`urdf2dh.geometry.frames`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .frames import Frame, dh_frame
from .lie import coefficients

__all__ = [
    "adjoint",
    "as_configurations",
    "dh_matrix",
    "errors_from_squares",
    "fk_of_stack",
    "from_rpy",
    "inv",
    "matrix_of",
    "pose_errors",
    "rot_axis",
    "rot_x",
    "rot_y",
    "rot_z",
    "rpy",
    "skew",
    "stack",
    "trans",
    "twist_exp",
]

Mat = NDArray[np.float64]

EPS = float(np.finfo(float).eps)
GIMBAL = 1e-12  # cos(pitch) below this: at gimbal lock, where only yaw -+ roll is defined


def as_configurations(q: NDArray[np.float64], n: int) -> NDArray[np.float64]:
    """``q`` as an ``(N, n)`` float array: one configuration ``(n,)`` becomes ``(1, n)``; works
    for chains without movable joints (``n = 0``) too."""
    q = np.asarray(q, dtype=float)
    if q.ndim == 1:
        q = q[None, :]
    if q.ndim != 2 or q.shape[1] != n:
        raise ValueError(f"expected configurations of shape (N, {n}), got {q.shape}")
    return q


def fk_of_stack(
    batch: Callable[[NDArray[np.float64]], NDArray[np.float64]], q: Any, n: int
) -> NDArray[np.float64]:
    """A batched FK ``(N, n) -> (N, 4, 4)`` applied to one configuration ``(n,)`` (a ``(4, 4)``
    pose) or to a stack ``(..., n)`` (poses ``(..., 4, 4)``)."""
    q = np.asarray(q, dtype=float)
    if q.shape[-1:] != (n,):
        raise ValueError(f"q has shape {q.shape}; expected (..., {n})")
    lead = q.shape[:-1]
    return batch(q.reshape(math.prod(lead), n)).reshape(*lead, 4, 4)


def rot_x(a: float) -> Mat:
    """``Rx(a)`` as a 4x4 transform."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def rot_y(a: float) -> Mat:
    """``Ry(a)`` as a 4x4 transform."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s, 0], [0, 1.0, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]])


def rot_z(a: float) -> Mat:
    """``Rz(a)`` as a 4x4 transform."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1.0, 0], [0, 0, 0, 1]])


def trans(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> Mat:
    """Pure translation ``Tx(x) Ty(y) Tz(z)`` as a 4x4 transform."""
    out = np.eye(4)
    out[:3, 3] = (x, y, z)
    return out


def from_rpy(xyz: tuple[float, float, float], rpy_angles: tuple[float, float, float]) -> Mat:
    """A URDF ``<origin xyz rpy>``: ``T(xyz) Rz(yaw) Ry(pitch) Rx(roll)`` (fixed-axis roll,
    pitch, yaw about x, y, z, as the URDF specification defines it)."""
    roll, pitch, yaw = rpy_angles
    out = rot_z(yaw) @ rot_y(pitch) @ rot_x(roll)
    out[:3, 3] = xyz
    return out


def rpy(r: Mat) -> tuple[float, float, float]:
    """``(roll, pitch, yaw)`` of a rotation (3x3, or the rotation of a 4x4), URDF convention
    ``R = Rz(yaw) Ry(pitch) Rx(roll)`` (fixed axes x, y, z), pitch in ``[-pi/2, pi/2]``.

    Pitch comes from ``atan2`` (accurate near +-pi/2); yaw from the first column (0 at gimbal
    lock, where only ``yaw -+ roll`` is defined); roll from what remains,
    ``Rx(roll) = Ry(-pitch) Rz(-yaw) R``, so that the three angles rebuild ``R`` to round-off.
    """
    r = np.asarray(r, dtype=float)[:3, :3]
    cos_pitch = math.hypot(r[0, 0], r[1, 0])
    pitch = math.atan2(-r[2, 0], cos_pitch)
    yaw = math.atan2(r[1, 0], r[0, 0]) if cos_pitch > GIMBAL else 0.0
    rest = rot_y(-pitch)[:3, :3] @ rot_z(-yaw)[:3, :3] @ r
    roll = math.atan2(rest[2, 1], rest[1, 1])
    return roll + 0.0, pitch + 0.0, yaw + 0.0


def skew(w: NDArray[np.float64]) -> Mat:
    """The 3x3 matrix ``[w]`` with ``[w] u = w x u``."""
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def rot_axis(u: NDArray[np.float64], angle: float) -> Mat:
    """Rotation by ``angle`` about the unit vector ``u`` (Rodrigues), as a 3x3 matrix."""
    k = skew(u)
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


def inv(t: Mat) -> Mat:
    """Inverse of a homogeneous transform."""
    out = np.eye(4)
    rt = t[:3, :3].T
    out[:3, :3] = rt
    out[:3, 3] = -rt @ t[:3, 3]
    return out


def adjoint(t: Mat) -> Mat:
    """``Ad(T)`` acting on ``[w, v]`` twists (Wu 2019 eq. 4): ``[[R, 0], [[t] R, R]]``."""
    r, p = t[:3, :3], t[:3, 3]
    out = np.zeros((6, 6))
    out[:3, :3] = r
    out[3:, 3:] = r
    out[3:, :3] = skew(p) @ r
    return out


def twist_exp(xi: NDArray[np.float64], q: float = 1.0) -> Mat:
    """``exp([xi] q)`` for a twist ``xi = [w, v]`` of any scale (Wu 2019 eq. 2): with
    ``t = |w|``, ``R = I + a [w] + b [w]^2`` and the translation ``(I + b [w] + c [w]^2) v``,
    ``a = sin t / t``, ``b = (1 - cos t) / t^2`` (as ``2 sin^2(t/2) / t^2``) and
    ``c = (t - sin t) / t^3`` (:func:`.lie.coefficients`: plain floats, the series where it
    cancels)."""
    w0, w1, w2, v0, v1, v2 = (x * q for x in np.asarray(xi, dtype=float)[:6].tolist())
    a, b, c = coefficients(w0 * w0 + w1 * w1 + w2 * w2)
    # [w]^2 = w w^T - t^2 I; [w] v = w x v
    k00, k11, k22 = -(w1 * w1 + w2 * w2), -(w0 * w0 + w2 * w2), -(w0 * w0 + w1 * w1)
    k01, k02, k12 = w0 * w1, w0 * w2, w1 * w2
    c0, c1, c2 = w1 * v2 - w2 * v1, w2 * v0 - w0 * v2, w0 * v1 - w1 * v0  # w x v
    cc0, cc1, cc2 = w1 * c2 - w2 * c1, w2 * c0 - w0 * c2, w0 * c1 - w1 * c0  # w x (w x v)
    return np.array(
        [
            [1.0 + b * k00, -a * w2 + b * k01, a * w1 + b * k02, v0 + b * c0 + c * cc0],
            [a * w2 + b * k01, 1.0 + b * k11, -a * w0 + b * k12, v1 + b * c1 + c * cc1],
            [-a * w1 + b * k02, a * w0 + b * k12, 1.0 + b * k22, v2 + b * c2 + c * cc2],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


def pose_errors(a: NDArray[np.float64], b: NDArray[np.float64]) -> tuple[float, float]:
    """Worst position and rotation error between two stacks of poses ``(..., 4, 4)``.

    Position: the Euclidean distance of the origins. Rotation: the angle of ``Ra^T Rb`` in
    radians, computed as ``2 asin(|Ra - Rb|_F / (2 sqrt 2))``, which stays accurate for tiny
    angles. Non-finite poses give non-finite errors; an empty stack gives ``(0, 0)``.
    """
    a = np.asarray(a, dtype=float).reshape(-1, 4, 4)
    b = np.asarray(b, dtype=float).reshape(-1, 4, 4)
    if a.shape[0] == 0:
        return 0.0, 0.0
    with np.errstate(invalid="ignore", over="ignore"):  # non-finite poses: NaN, no warning
        d = a[:, :3] - b[:, :3]
        moved, turned = d[:, :, 3], d[:, :, :3]
        return errors_from_squares(
            float(np.einsum("ni,ni->n", moved, moved).max()),
            float(np.einsum("nij,nij->n", turned, turned).max()),
        )


def errors_from_squares(moved: float, turned: float) -> tuple[float, float]:
    """Position and rotation error (:func:`pose_errors`) from the largest squared distance of
    the origins and the largest squared Frobenius distance ``|Ra - Rb|_F^2`` of the rotations."""
    chord = math.sqrt(turned) / (2.0 * math.sqrt(2.0))
    rotation = chord if math.isnan(chord) else 2.0 * math.asin(min(chord, 1.0))
    return math.sqrt(moved), rotation


def matrix_of(f: Frame) -> Mat:
    """The ``(4, 4)`` transform of a :data:`~urdf2dh.geometry.frames.Frame`."""
    return np.array([*f, (0.0, 0.0, 0.0, 1.0)])


def stack(frames: list[Frame]) -> Mat:
    """Frames as a ``(k, 4, 4)`` array."""
    flat = [x for f in frames for row in (*f, (0.0, 0.0, 0.0, 1.0)) for x in row]
    return np.fromiter(flat, float, len(flat)).reshape(-1, 4, 4)


def dh_matrix(theta: float, d: float, alpha: float, a: float) -> Mat:
    """``Rz(theta) Tz(d) Rx(alpha) Tx(a)`` (Wu 2019 eq. 9) as a ``(4, 4)`` array."""
    return matrix_of(dh_frame(theta, d, alpha, a))
