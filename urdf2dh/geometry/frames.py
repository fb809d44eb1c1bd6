"""Rigid frames as plain floats: what the chain walks and conversions compose one at a time.

A conversion handles one 3-vector or frame at a time, where a numpy call costs far more than
its arithmetic, so these helpers do the same IEEE arithmetic on tuples. They import nothing
heavy: the convention modules, which the command line's ``--help`` lists, build on them.

A :data:`Frame` is the top three rows ``[R | t]`` of a homogeneous transform, row by row;
:mod:`urdf2dh.geometry.se3` turns frames into ``(4, 4)`` arrays and back.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

__all__ = [
    "IDENTITY",
    "Frame",
    "Vec3",
    "angle",
    "axis_frame",
    "between",
    "compose",
    "dh_frame",
    "dir_into",
    "frame_of",
    "point_into",
    "rotate",
    "rx_tx",
    "unit",
    "wrap_angle",
]

Vec3 = tuple[float, float, float]
Frame = tuple[tuple[float, float, float, float], ...]

IDENTITY: Frame = ((1.0, 0.0, 0.0, 0.0), (0.0, 1.0, 0.0, 0.0), (0.0, 0.0, 1.0, 0.0))


def frame_of(t: Any) -> Frame:
    """The :data:`Frame` of a ``(4, 4)`` array (anything with ``tolist``)."""
    r0, r1, r2, _ = t.tolist()
    return (tuple(r0), tuple(r1), tuple(r2))


def angle(y: float, x: float) -> float:
    """``atan2`` in ``(-pi, pi]`` without signed zeros, so tables print ``180`` not ``-180``."""
    out = math.atan2(y + 0.0, x + 0.0)
    return math.pi if out == -math.pi else out + 0.0


def dh_frame(theta: float, d: float, alpha: float, a: float) -> Frame:
    """``Rz(theta) Tz(d) Rx(alpha) Tx(a)`` in closed form (Wu 2019 eq. 9)."""
    ct, st = math.cos(theta), math.sin(theta)
    ca, sa = math.cos(alpha), math.sin(alpha)
    return (
        (ct, -st * ca, st * sa, a * ct),
        (st, ct * ca, -ct * sa, a * st),
        (0.0, sa, ca, d),
    )


def rx_tx(alpha: float, a: float) -> Frame:
    """``Rx(alpha) Tx(a)``."""
    c, s = math.cos(alpha), math.sin(alpha)
    return ((1.0, 0.0, 0.0, a), (0.0, c, -s, 0.0), (0.0, s, c, 0.0))


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
    )  # fmt: skip


def rotate(f: Frame, v: Sequence[float]) -> Vec3:
    """A direction given in the coordinates of ``f``, in the outer frame: ``R v``."""
    (a, b, c, _), (d, e, g, _), (h, i, k, _) = f
    x, y, z = v
    return (a * x + b * y + c * z, d * x + e * y + g * z, h * x + i * y + k * z)


def dir_into(f: Frame, v: Sequence[float]) -> Vec3:
    """A direction given in the outer frame, in the coordinates of ``f``: ``R^T v``."""
    (a, b, c, _), (d, e, g, _), (h, i, k, _) = f
    x, y, z = v
    return (a * x + d * y + h * z, b * x + e * y + i * z, c * x + g * y + k * z)


def point_into(f: Frame, p: Sequence[float]) -> Vec3:
    """A point given in the outer frame, in the coordinates of ``f``: ``R^T (p - t)``."""
    (a, b, c, tx), (d, e, g, ty), (h, i, k, tz) = f
    x, y, z = p[0] - tx, p[1] - ty, p[2] - tz
    return (a * x + d * y + h * z, b * x + e * y + i * z, c * x + g * y + k * z)


def between(a: Frame, b: Frame) -> Frame:
    """``a^-1 @ b``: the frame ``b`` in the coordinates of ``a``."""
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
    )  # fmt: skip


def axis_frame(u: Vec3, p: Sequence[float]) -> Frame:
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


def wrap_angle(a: float) -> float:
    """``a`` as the angle in ``(-pi, pi]`` that turns the same way (``pi`` for ``-pi``), never
    ``-0.0``."""
    out = math.remainder(a, 2.0 * math.pi)
    return math.pi if out == -math.pi else out + 0.0


def unit(v: Sequence[float]) -> Vec3:
    """``v / |v|`` (``v`` non-zero)."""
    x, y, z = v
    n = math.hypot(x, y, z)
    return (x / n, y / n, z / n)
