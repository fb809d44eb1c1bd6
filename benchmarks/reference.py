"""Forward kinematics of a URDF chain in extended precision, straight from the text's numbers.

The reference that float64 results (ours and Pinocchio's) are measured against in the chain-length
benchmark: Pinocchio's own ``Data`` needs O(n^3) memory (0.5 GB at 200 joints), so it cannot be the
oracle for chains of thousands of joints. numpy's ``longdouble`` (x87 extended precision on x86-64,
eps 1.1e-19) is 2,000 times finer than float64; every step, from parsing the decimal strings to
the trigonometry, is done in it. Only serial chains of revolute, continuous, prismatic and fixed
joints (what ``tests/chains.py`` writes) are handled.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
from numpy.typing import NDArray

__all__ = ["EPS", "chain_fk"]

X = np.longdouble
EPS = float(np.finfo(X).eps)


def _numbers(text: str | None, default: str) -> NDArray[np.longdouble]:
    return np.array([X(v) for v in (text or default).split()], dtype=X)


def _rotation(axis: NDArray[np.longdouble], angle: NDArray[np.longdouble]) -> NDArray:
    """``(N, 4, 4)`` rotations by ``angle`` about the unit ``axis`` (Rodrigues)."""
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]], dtype=X)
    out = np.zeros((angle.shape[0], 4, 4), dtype=X)
    out[:, :3, :3] = (
        np.eye(3, dtype=X)
        + np.sin(angle)[:, None, None] * k
        + (1 - np.cos(angle))[:, None, None] * (k @ k)
    )
    out[:, 3, 3] = 1
    return out


def _origin(xyz: NDArray[np.longdouble], rpy: NDArray[np.longdouble]) -> NDArray:
    """URDF's origin: ``Tr(xyz) Rz(yaw) Ry(pitch) Rx(roll)``."""
    (cr, cp, cy), (sr, sp, sy) = np.cos(rpy), np.sin(rpy)
    out = np.eye(4, dtype=X)
    out[:3, :3] = [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
    out[:3, 3] = xyz
    return out


def chain_fk(text: str, base: str, tip: str, q: NDArray[np.float64]) -> NDArray[np.longdouble]:
    """Poses ``(N, 4, 4)`` of ``tip`` in ``base`` for joint positions ``q`` ``(N, n)`` (the
    movable joints from base to tip, in order), in extended precision."""
    joints = {j.find("child").get("link"): j for j in ET.fromstring(text).findall("joint")}
    path, link = [], tip
    while link != base:
        path.append(joints[link])
        link = path[-1].find("parent").get("link")
    out = np.broadcast_to(np.eye(4, dtype=X), (q.shape[0], 4, 4))
    k = 0
    for joint in reversed(path):
        origin = joint.find("origin")
        attrs = {} if origin is None else origin.attrib
        out = out @ _origin(
            _numbers(attrs.get("xyz"), "0 0 0"), _numbers(attrs.get("rpy"), "0 0 0")
        )
        kind = joint.get("type")
        if kind == "fixed":
            continue
        axis = joint.find("axis")
        u = _numbers(None if axis is None else axis.get("xyz"), "1 0 0")
        u = u / np.sqrt(u @ u)
        value = q[:, k].astype(X)
        k += 1
        if kind == "prismatic":
            out = out.copy()
            out[:, :3, 3] += value[:, None] * (out[:, :3, :3] @ u)
        else:
            out = out @ _rotation(u, value)
    return out
