"""Rigid fits that place models and tools: the start, the nominal base, the tool of markers.

* :func:`fit_rigid` -- the rigid transform ``G`` minimising ``sum |G a_k - b_k|^2`` (Kabsch 1976 /
  Horn 1987, by SVD of the cross-covariance with the determinant fixed). When the points do not
  fix the rotation (one point, or all on one line) the rotation closest to a reference is
  taken: the reference itself, or the smallest turn of it that aligns the line.
* :func:`pose_points` -- a pose as four points (origin and the tips of its axes at a given
  length), so that orientations take part in a point fit.
* :func:`tool_on_last_axis` -- the identified tool placed on the last joint's line exactly as
  the nominal's was, turned about and slid along it as identified: it removes the round-off the
  iterations left in a relation that ``keep_tool_axis`` holds (so that a tool z on the last
  axis stays on it to float precision, as D-H's Lemma 4 and UR's flange need).
* :func:`anchor_base` -- the device -> nominal base transform that puts the identified first
  joint's line exactly on the nominal's (what defines a robot's base frame: controllers such as
  UR's put frame 0 on joint 1's axis) and fits the two motions that leave a line in place,
  the turn about it and the slide along it, to the nominal's tool points in closed form. For a
  prismatic first joint only its direction is anchored and the translation is fitted too.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..geometry.frames import axis_frame
from ..geometry.se3 import inv, matrix_of
from ..model.poe import Joint
from ..tolerances import RANK_RELATIVE

__all__ = ["anchor_base", "fit_rigid", "misfit", "pose_points", "spread", "tool_on_last_axis"]

Mat = NDArray[np.float64]


def spread(points: Mat) -> float:
    """The RMS distance of ``points`` ``(N, 3)`` from their centroid: how far a point set
    reaches, the scale its misfits are judged against."""
    return float(np.sqrt(np.mean(np.sum((points - points.mean(axis=0)) ** 2, axis=1))))


def _align(a: Mat, b: Mat) -> Mat:
    """The smallest rotation (3x3) taking unit ``a`` to unit ``b``."""
    axis = np.cross(a, b)
    sin, cos = float(np.linalg.norm(axis)), float(a @ b)
    if sin == 0.0:
        if cos > 0.0:
            return np.eye(3)
        pick = int(np.argmin(np.abs(a)))  # half a turn about any axis normal to a
        n = np.cross(a, np.eye(3)[pick])
        n /= np.linalg.norm(n)
        return 2.0 * np.outer(n, n) - np.eye(3)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]]) / sin
    angle = math.atan2(sin, cos)
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


def fit_rigid(a: Mat, b: Mat, reference: Mat | None = None) -> Mat:
    """``(4, 4)`` rigid ``G`` with ``G a_k ~ b_k`` in least squares (``a, b``: ``(k, 3)``).

    ``reference`` (3x3, default identity) decides the rotation where the points leave it free.
    """
    ref = np.eye(3) if reference is None else reference
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    da, db = a - ca, b - cb
    h = db.T @ da  # sum b a^T: maximise tr(R^T h)
    u, s, vt = np.linalg.svd(h)
    spread = max(float(np.abs(da).max(initial=0.0)), float(np.abs(db).max(initial=0.0)))
    tiny = RANK_RELATIVE * spread * spread * len(a)
    rank = int(np.sum(s > tiny))
    if rank >= 2:
        d = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt)) or 1.0])
        r = u @ d @ vt
    elif rank == 1:  # collinear: align the line, keep the rest of the reference
        r = _align(ref @ vt[0], u[:, 0]) @ ref
    else:
        r = ref
    out = np.eye(4)
    out[:3, :3] = r
    out[:3, 3] = cb - r @ ca
    return out


def misfit(a: Mat, b: Mat) -> float:
    """The RMS distance between ``b``'s points and ``a``'s (both ``(k, 3)``) after the best rigid
    fit of ``a`` onto ``b`` (:func:`fit_rigid`): what no placement of one set explains."""
    g = fit_rigid(a, b)
    moved = a @ g[:3, :3].T + g[:3, 3]
    return float(np.sqrt(np.mean(np.sum((moved - b) ** 2, axis=1))))


def pose_points(poses: Mat, length: float) -> Mat:
    """``(4 N, 3)``: each pose's origin and its origin plus ``length`` times each axis."""
    origin = poses[:, :3, 3]
    tips = origin[:, None, :] + length * np.swapaxes(poses[:, :3, :3], 1, 2)
    return np.concatenate([origin[:, None, :], tips], axis=1).reshape(-1, 3)


def _line_frame(j: Joint) -> Mat:
    point = (0.0, 0.0, 0.0) if j.point is None else tuple(j.point.tolist())
    return matrix_of(axis_frame(tuple(j.axis.tolist()), point))


def anchor_base(first: Joint, nominal_first: Joint, points: Mat, nominal_points: Mat) -> Mat:
    """The transform ``B`` (device -> nominal base) with ``B`` taking the identified first line
    onto the nominal's exactly and ``B points ~ nominal_points`` otherwise (module docstring).

    ``points``, ``nominal_points``: ``(k, 3)`` the identified and the nominal tool points at the
    same configurations.
    """
    c_nom = _line_frame(nominal_first)
    to_id, to_nom = inv(_line_frame(first)), inv(c_nom)  # into each first line's frame
    a = points @ to_id[:3, :3].T + to_id[:3, 3]
    b = nominal_points @ to_nom[:3, :3].T + to_nom[:3, 3]
    move = np.eye(4)
    if first.kind == "prismatic":  # turn about z (direction anchored) and any translation
        a2, b2 = a - a.mean(axis=0), b - b.mean(axis=0)
        phi = math.atan2(
            float(np.sum(a2[:, 0] * b2[:, 1] - a2[:, 1] * b2[:, 0])),
            float(np.sum(a2[:, 0] * b2[:, 0] + a2[:, 1] * b2[:, 1])),
        )
        c, s = math.cos(phi), math.sin(phi)
        move[:3, :3] = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
        move[:3, 3] = b.mean(axis=0) - move[:3, :3] @ a.mean(axis=0)
    else:  # turn about the line (z) and slide along it
        phi = math.atan2(
            float(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])),
            float(np.sum(a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1])),
        )
        c, s = math.cos(phi), math.sin(phi)
        move[:3, :3] = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
        move[2, 3] = float(np.mean(b[:, 2] - a[:, 2]))
    return c_nom @ move @ to_id


def tool_on_last_axis(
    start_last: Joint, start_home: Mat, last: Joint, home: Mat, angle: float, distance: float
) -> tuple[Mat, float]:
    """The tool pose on ``last``'s line with the relation ``start_home`` had to ``start_last``
    (module docstring): ``C Rz(phi) Tz(t) K``, ``C`` a frame on the line, ``K`` the start's
    relation, ``phi, t`` read from ``home``.

    A start tool whose z lies within ``angle`` (rad) of the line and whose origin lies within
    ``distance`` of it (URDFs' rounded angles leave 1e-12 rad) is put on it exactly: what
    D-H's Lemma 4 and a flange on the last D-H frame (UR) read as "on the axis". Returns the
    pose and the angle that moved the tool z (0 if not).
    """
    rel = inv(_line_frame(start_last)) @ start_home
    z, origin = rel[:3, 2], rel[:3, 3]
    off = math.atan2(math.hypot(z[0], z[1]), abs(z[2]))
    moved = 0.0
    if 0.0 < off <= angle and math.hypot(origin[0], origin[1]) <= distance:
        rel[:3, :3] = _align(z, np.array([0.0, 0.0, math.copysign(1.0, z[2])])) @ rel[:3, :3]
        rel[:2, 3] = 0.0
        moved = off
    frame = _line_frame(last)
    x = inv(frame) @ home @ inv(rel)
    phi, t = math.atan2(x[1, 0], x[0, 0]), x[2, 3]
    c, s = math.cos(phi), math.sin(phi)
    screw = np.array([[c, -s, 0.0, 0.0], [s, c, 0.0, 0.0], [0.0, 0.0, 1.0, t], [0, 0, 0, 1.0]])
    return frame @ screw @ rel, moved
