"""The small Lie-group kit everything else uses: elementary transforms, exp, adjoint, errors.

Conventions (they bite, so they are stated here once):

* Homogeneous transforms are ``(4, 4)`` float64 arrays ``[[R, t], [0, 1]]``.
* Twists are ordered ``[w, v]`` (angular first), as in Wu 2019 eq. (1) and Sumenkov eq. (5),
  with ``v = p x w + h w`` for a screw through point ``p`` with pitch ``h``. Pinocchio's motion
  vectors are ``[v, w]``; convert at that boundary only (``verify.py``).
* Batched functions take ``(N,)`` joint values and return ``(N, 4, 4)`` stacks.
* The chain walks (URDF -> POE -> tables) handle one 3-vector or frame at a time, where a numpy
  call costs far more than its arithmetic; they use the plain-float :data:`Frame` helpers at the
  end of this module, which do the same IEEE arithmetic without the calls.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "IDENTITY",
    "Frame",
    "Vec3",
    "adjoint",
    "as_configurations",
    "between",
    "compose",
    "dir_into",
    "fk_of_stack",
    "frame_of",
    "from_rpy",
    "inv",
    "matrix_of",
    "point_into",
    "pose_errors",
    "rot_axis",
    "rot_x",
    "rot_y",
    "rot_z",
    "rotate",
    "rpy",
    "skew",
    "trans",
    "twist_exp",
    "unit",
]

Mat = NDArray[np.float64]

EPS = float(np.finfo(float).eps)


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
    ``R = Rz(yaw) Ry(pitch) Rx(roll)``, with pitch in ``[-pi/2, pi/2]``.

    At pitch = +-pi/2 only ``yaw -+ roll`` is defined; roll is then 0.
    """
    r = np.asarray(r, dtype=float)[:3, :3]
    cos_pitch = math.hypot(r[0, 0], r[1, 0])
    pitch = math.atan2(-r[2, 0], cos_pitch)
    if cos_pitch > 16.0 * EPS:
        roll = math.atan2(r[2, 1], r[2, 2])
        yaw = math.atan2(r[1, 0], r[0, 0])
    else:
        roll = 0.0
        yaw = math.atan2(-r[0, 1], r[1, 1])
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
    """``exp([xi] q)`` for a twist ``xi = [w, v]`` of any scale (Wu 2019 eq. 2)."""
    w = np.asarray(xi[:3], dtype=float) * q
    v = np.asarray(xi[3:], dtype=float) * q
    theta = float(np.linalg.norm(w))
    out = np.eye(4)
    if theta == 0.0:
        out[:3, 3] = v
        return out
    k = skew(w / theta)
    k2 = k @ k
    out[:3, :3] = np.eye(3) + math.sin(theta) * k + (1.0 - math.cos(theta)) * k2
    g = np.eye(3) * theta + (1.0 - math.cos(theta)) * k + (theta - math.sin(theta)) * k2
    out[:3, 3] = g @ (v / theta)
    return out


def pose_errors(a: NDArray[np.float64], b: NDArray[np.float64]) -> tuple[float, float]:
    """Worst position and rotation error between two ``(N, 4, 4)`` stacks of poses.

    Position: Euclidean distance of the origins. Rotation: the angle of ``Ra^T Rb`` in radians,
    computed as ``2 asin(|Ra - Rb|_F / (2 sqrt 2))``, which stays accurate for tiny angles.
    Non-finite poses give non-finite errors.
    """
    a = np.asarray(a, dtype=float).reshape(-1, 4, 4)
    b = np.asarray(b, dtype=float).reshape(-1, 4, 4)
    if a.shape[0] == 0:
        return 0.0, 0.0
    d = (a - b).reshape(-1, 16)
    d *= d
    # per pose, the two sums of squares (one product); both measures grow with them, so the
    # worst is taken first and the root after. (0 x inf in the product is nan: no warning.)
    with np.errstate(invalid="ignore"):
        pos2, rot2 = (d @ _ERROR_SUMS).max(axis=0)
    return errors_of_squares(float(pos2), float(rot2))


def errors_of_squares(pos2: float, rot2: float) -> tuple[float, float]:
    """Position and rotation error from the worst sums of squared differences of the
    position entries and of the rotation entries (see :func:`pose_errors`)."""
    r = math.sqrt(rot2) / (2.0 * math.sqrt(2.0))
    return math.sqrt(pos2), (r if math.isnan(r) else 2.0 * math.asin(min(r, 1.0)))


_ERROR_SUMS = np.zeros((16, 2))  # picks, of a flattened 4x4, the position and rotation entries
_ERROR_SUMS[[3, 7, 11], 0] = 1.0
_ERROR_SUMS[[0, 1, 2, 4, 5, 6, 8, 9, 10], 1] = 1.0


# --------------------------------------------------------------------------- plain-float frames

Vec3 = tuple[float, float, float]
Frame = tuple[tuple[float, float, float, float], ...]
"""The top three rows ``[R | t]`` of a homogeneous transform, as plain floats, row by row."""

IDENTITY: Frame = ((1.0, 0.0, 0.0, 0.0), (0.0, 1.0, 0.0, 0.0), (0.0, 0.0, 1.0, 0.0))


def frame_of(t: Mat) -> Frame:
    """The :data:`Frame` of a ``(4, 4)`` transform."""
    r0, r1, r2, _ = t.tolist()
    return (tuple(r0), tuple(r1), tuple(r2))


def matrix_of(f: Frame) -> Mat:
    """The ``(4, 4)`` transform of a :data:`Frame`."""
    return np.array([*f, (0.0, 0.0, 0.0, 1.0)])


def stack(frames: list[Frame]) -> Mat:
    """Frames as a ``(k, 4, 4)`` array."""
    flat = [x for f in frames for row in (*f, (0.0, 0.0, 0.0, 1.0)) for x in row]
    return np.fromiter(flat, float, len(flat)).reshape(-1, 4, 4)


def compose(a: Frame, b: Frame) -> Frame:
    """``a @ b`` (written out: this runs once per joint and row of every conversion)."""
    (b00, b01, b02, b03), (b10, b11, b12, b13), (b20, b21, b22, b23) = b
    (x0, y0, z0, w0), (x1, y1, z1, w1), (x2, y2, z2, w2) = a
    return (
        (x0 * b00 + y0 * b10 + z0 * b20, x0 * b01 + y0 * b11 + z0 * b21,
         x0 * b02 + y0 * b12 + z0 * b22, x0 * b03 + y0 * b13 + z0 * b23 + w0),
        (x1 * b00 + y1 * b10 + z1 * b20, x1 * b01 + y1 * b11 + z1 * b21,
         x1 * b02 + y1 * b12 + z1 * b22, x1 * b03 + y1 * b13 + z1 * b23 + w1),
        (x2 * b00 + y2 * b10 + z2 * b20, x2 * b01 + y2 * b11 + z2 * b21,
         x2 * b02 + y2 * b12 + z2 * b22, x2 * b03 + y2 * b13 + z2 * b23 + w2),
    )


def rotate(f: Frame, v: Vec3) -> Vec3:
    """A direction given in the coordinates of ``f``, in the outer frame: ``R v``."""
    (a, b, c, _), (d, e, g, _), (h, i, k, _) = f
    x, y, z = v
    return (a * x + b * y + c * z, d * x + e * y + g * z, h * x + i * y + k * z)


def dir_into(f: Frame, v: Vec3) -> Vec3:
    """A direction given in the outer frame, in the coordinates of ``f``: ``R^T v``."""
    (a, b, c, _), (d, e, g, _), (h, i, k, _) = f
    x, y, z = v
    return (a * x + d * y + h * z, b * x + e * y + i * z, c * x + g * y + k * z)


def point_into(f: Frame, p: Vec3) -> Vec3:
    """A point given in the outer frame, in the coordinates of ``f``: ``R^T (p - t)``."""
    (a, b, c, tx), (d, e, g, ty), (h, i, k, tz) = f
    x, y, z = p[0] - tx, p[1] - ty, p[2] - tz
    return (a * x + d * y + h * z, b * x + e * y + i * z, c * x + g * y + k * z)


def between(a: Frame, b: Frame) -> Frame:
    """``a^-1 @ b``: the frame ``b`` in the coordinates of ``a`` (``R_a^T [R_b | t_b - t_a]``,
    written out as :func:`compose` is)."""
    (a00, a01, a02, a03), (a10, a11, a12, a13), (a20, a21, a22, a23) = a
    (b00, b01, b02, b03), (b10, b11, b12, b13), (b20, b21, b22, b23) = b
    x, y, z = b03 - a03, b13 - a13, b23 - a23
    return (
        (a00 * b00 + a10 * b10 + a20 * b20, a00 * b01 + a10 * b11 + a20 * b21,
         a00 * b02 + a10 * b12 + a20 * b22, a00 * x + a10 * y + a20 * z),
        (a01 * b00 + a11 * b10 + a21 * b20, a01 * b01 + a11 * b11 + a21 * b21,
         a01 * b02 + a11 * b12 + a21 * b22, a01 * x + a11 * y + a21 * z),
        (a02 * b00 + a12 * b10 + a22 * b20, a02 * b01 + a12 * b11 + a22 * b21,
         a02 * b02 + a12 * b12 + a22 * b22, a02 * x + a12 * y + a22 * z),
    )


def axis_frame(u: Vec3, p: Vec3) -> Frame:
    """A frame whose z axis is the unit direction ``u`` through the point ``p`` (its x axis:
    the basis vector least aligned with ``u``, made perpendicular to it)."""
    ux, uy, uz = u
    ax, ay, az = abs(ux), abs(uy), abs(uz)
    if ax <= ay and ax <= az:
        x = (1.0 - ux * ux, -ux * uy, -ux * uz)
    elif ay <= az:
        x = (-uy * ux, 1.0 - uy * uy, -uy * uz)
    else:
        x = (-uz * ux, -uz * uy, 1.0 - uz * uz)
    k = 1.0 / math.sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2])
    xx, xy, xz = x[0] * k, x[1] * k, x[2] * k
    yx, yy, yz = uy * xz - uz * xy, uz * xx - ux * xz, ux * xy - uy * xx
    return ((xx, yx, ux, p[0]), (xy, yy, uy, p[1]), (xz, yz, uz, p[2]))


def unit(v: Vec3) -> Vec3:
    """``v / |v|`` (``v`` non-zero)."""
    x, y, z = v
    n = math.hypot(x, y, z)
    return (x / n, y / n, z / n)
