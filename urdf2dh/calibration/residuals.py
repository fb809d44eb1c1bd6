"""Measurement residuals of an :class:`~.chart.Estimate` and their analytic Jacobian.

Residuals, per measurement (model minus measured, both in the device frame), with
``T(q) = P_n(q) M`` the tool's pose:

* position ``x(q) - x_meas`` of the point the measurement saw, ``x = T(q) c_k`` (marker ``k``
  in the tool frame; the tool origin for poses), divided by the position noise ``sigma_p``;
* for poses, rotation ``phi = log(R(q) R_meas^T)`` (a rotation vector in the device frame),
  divided by the rotation noise ``sigma_r``.

Jacobian. A change of the coordinates moves the tool by a small space-frame twist
``d = [dw, dv]`` (``T' = exp([d]) T``), so ``dx = dv + dw x x`` and
``dphi = J_l(phi)^-1 dw`` (left Jacobian of SO(3); exact, not just near ``phi = 0``). With
``P_i = exp([xi_1] q_1) ... exp([xi_i] q_i)`` and the charts of :mod:`.chart`:

* a joint's line moved by ``exp(eta)``: ``exp(eta) exp([xi] q) exp(-eta)`` gives
  ``d = Ad(P_(i-1)) eta - Ad(P_i) eta`` (when the tool moves with the last line, the second
  term cancels: ``d = Ad(P_(n-1)) eta``);
* its scale ``s + ds`` (``exp([xi_hat] s (q + o))``): ``d = Ad(P_(i-1)) xi_hat (q_i + o_i) ds``;
* its offset ``o + do``: ``d = Ad(P_(i-1)) xi_hat s do``;
* its pitch ``h + dh`` (``[0, u]`` commutes with ``xi_hat``):
  ``d = Ad(P_(i-1)) [0, u] s (q_i + o_i) dh``;
* the base ``exp(beta)`` applied to everything: ``d = beta``;
* the home pose ``M exp(zeta)``: ``d = Ad(T) zeta``; a marker's home position in the device
  frame moved by ``dc``: ``dx = R_(P_n) dc``.

``Ad([R, t]) [w, v] = [R w, R v + t x R w]`` (Wu 2019 eq. 4). Everything is evaluated for all
measurements and all joints at once: ``N`` configurations as ``(N, ...)`` stacks, each joint's
seven candidate columns (two turns, two shifts, pitch, offset, scale) as one ``(n, 6, 7)``
block, of which the level's coordinates are then picked (:func:`_picks`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from ..geometry.lie import ad_apply, cross_columns, cross_rows, left_jacobian_inverse, log_so3
from .chart import FRAME, Estimate, normal_bases, sizes, tool_screws

__all__ = [
    "Data",
    "errors",
    "evaluate",
    "model_poses",
    "modelled_points",
    "observed",
    "prefix_products",
    "residuals",
    "rms",
]

Mat = NDArray[np.float64]

SLOTS = ("turn1", "turn2", "shift1", "shift2", "pitch", "offset", "scale")


@dataclass(frozen=True, slots=True)
class Data:
    """What the model is compared with: measurements of poses and of positions alike.

    Attributes
    ----------
    q
        ``(N, n)`` joint positions.
    points
        ``(N, 3)`` measured tool points in the device frame.
    markers
        ``(N,)`` the row of :attr:`.chart.Estimate.markers` each measurement saw (0 for poses).
    rotations
        ``(N, 3, 3)`` measured tool orientations (pose measurements), or ``None``.
    """

    q: Mat
    points: Mat
    markers: NDArray[np.int64]
    rotations: Mat | None = None

    def __post_init__(self) -> None:
        n = len(self.q)
        if self.points.shape != (n, 3) or self.markers.shape != (n,):
            raise ValueError(f"points must be ({n}, 3) and markers ({n},)")
        if self.rotations is not None and self.rotations.shape != (n, 3, 3):
            raise ValueError(f"rotations must be ({n}, 3, 3), not {self.rotations.shape}")

    @classmethod
    def poses(cls, q: Mat, points: Mat, rotations: Mat) -> Data:
        """Pose measurements: tool origins and orientations."""
        return cls(q, points, np.zeros(len(q), dtype=np.int64), rotations)

    def part(self, rows: slice) -> Data:
        """The measurements in ``rows``."""
        return Data(
            self.q[rows],
            self.points[rows],
            self.markers[rows],
            None if self.rotations is None else self.rotations[rows],
        )

    @property
    def rows(self) -> int:
        """Residuals per measurement: 6 for poses, 3 for positions."""
        return 6 if self.rotations is not None else 3

    def __len__(self) -> int:
        return len(self.q)


@dataclass(frozen=True, slots=True)
class _Joints:
    """The joints of an estimate as arrays: directions, points, pitches, scales, offsets."""

    axis: Mat  # (n, 3)
    point: Mat  # (n, 3), zeros for sliding joints
    turning: Mat  # (n,) 1 for revolute and helical joints, 0 for prismatic ones
    lead: Mat  # (n,) translation per unit of s: the pitch, or 1 for prismatic joints
    scale: Mat  # (n,)
    offset: Mat  # (n,)


def _arrays(est: Estimate) -> _Joints:
    chain = est.chain
    turning = chain.turning.astype(float)
    return _Joints(
        chain.axis,
        chain.point * turning[:, None],
        turning,
        np.where(turning > 0.0, chain.pitch, 1.0),
        chain.scale,
        est.joint_offsets(),
    )


def _skews(u: Mat) -> Mat:
    """``(n, 3) -> (n, 3, 3)``: ``[u]``."""
    out = np.zeros((len(u), 3, 3))
    out[:, 0, 1], out[:, 0, 2] = -u[:, 2], u[:, 1]
    out[:, 1, 0], out[:, 1, 2] = u[:, 2], -u[:, 0]
    out[:, 2, 0], out[:, 2, 1] = -u[:, 1], u[:, 0]
    return out


def _prefix(js: _Joints, q: Mat) -> tuple[Mat, Mat]:
    """Rotations ``(n + 1, N, 3, 3)`` and translations ``(n + 1, N, 3)`` of ``P_0 .. P_n``.

    Each joint's ``exp([xi] s)`` by Rodrigues (``1 - cos = 2 sin^2(t/2)``), all at once, as
    ``(N, n, 4, 4)`` transforms; their running products one joint at a time."""
    s = js.scale * (q + js.offset)  # (N, n)
    k = _skews(js.axis)
    angle = s * js.turning
    half = np.sin(0.5 * angle)
    count, n = q.shape
    e = np.zeros((count, n, 4, 4))
    r = e[:, :, :3, :3]
    r[:] = np.eye(3)
    r += np.sin(angle)[:, :, None, None] * k
    r += (2.0 * half * half)[:, :, None, None] * (k @ k)
    e[:, :, :3, 3] = js.point - (r @ js.point[:, :, None])[..., 0]
    e[:, :, :3, 3] += (js.lead * s)[:, :, None] * js.axis
    e[:, :, 3, 3] = 1.0
    out = np.empty((n + 1, count, 4, 4))
    out[0] = np.eye(4)
    for i in range(n):
        np.matmul(out[i], e[:, i], out=out[i + 1])
    return out[:, :, :3, :3], out[:, :, :3, 3]


def prefix_products(est: Estimate, q: Mat) -> list[Mat]:
    """``[P_0 = I, P_1, ..., P_n]``, each ``(N, 4, 4)`` (joint offsets added to ``q``)."""
    rots, trans = _prefix(_arrays(est), q)
    out = np.zeros((len(rots), len(q), 4, 4))
    out[:, :, :3, :3] = rots
    out[:, :, :3, 3] = trans
    out[:, :, 3, 3] = 1.0
    return list(out)


def model_poses(est: Estimate, q: Mat) -> Mat:
    """``(N, 4, 4)`` the tool poses ``T(q) = P_n(q) M``."""
    return prefix_products(est, q)[-1] @ est.home


def _tool(est: Estimate, rots: Mat, trans: Mat, markers: NDArray[np.int64]) -> tuple[Mat, Mat]:
    """The tool's poses ``T = P_n M`` ``(N, 4, 4)`` from ``P_n`` (``rots``, ``trans``) and the
    points ``(N, 3)`` the measurements saw, ``T c_k`` (``markers``: each one's ``k``)."""
    tool = np.zeros((len(rots), 4, 4))
    tool[:, :3, :3] = rots @ est.home[:3, :3]
    tool[:, :3, 3] = rots @ est.home[:3, 3] + trans
    tool[:, 3, 3] = 1.0
    x: Mat = np.einsum("nij,nj->ni", tool[:, :3, :3], est.markers[markers]) + tool[:, :3, 3]
    return tool, x


def modelled_points(est: Estimate, data: Data) -> Mat:
    """``(N, 3)`` the points of ``est``'s tool each measurement of ``data`` saw."""
    rots, trans = _prefix(_arrays(est), data.q)
    return _tool(est, rots[-1], trans[-1], data.markers)[1]


def observed(est: Estimate, q: Mat) -> Data:
    """What a device would measure of ``est`` at ``q`` ``(N, n)``, without noise: the tool's
    poses (a tool frame), or each marker's position at each configuration (markers; rows
    configuration by configuration, each marker in turn)."""
    k = len(est.markers)
    qs = np.repeat(q, k, axis=0) if k > 1 else q
    rows = np.tile(np.arange(k, dtype=np.int64), len(q))
    rots, trans = _prefix(_arrays(est), qs)
    tool, points = _tool(est, rots[-1], trans[-1], rows)
    return Data(qs, points, rows, tool[:, :3, :3] if est.tool == FRAME else None)


def rms(values: Mat) -> float:
    """The root of the mean square of ``values`` (errors, residuals)."""
    return float(np.sqrt(np.mean(np.square(values))))


def errors(est: Estimate, data: Data) -> Mat:
    """``(N, 1 or 2)`` each measurement's position error (the distance between the modelled and
    the measured point) and, for poses, its rotation error (the angle of ``R R_meas^T``): the
    one formula every residual statistic is made of (offsets absorbed or not alike)."""
    rows = residuals(est, data, 1.0, 1.0).reshape(len(data), data.rows)
    out: Mat = np.linalg.norm(rows[:, :3], axis=1, keepdims=True)
    if data.rotations is not None:
        out = np.hstack([out, np.linalg.norm(rows[:, 3:], axis=1, keepdims=True)])
    return out


@lru_cache(maxsize=256)
def _picks_cached(
    joint_slots: tuple[tuple[int, ...], ...], base: bool, free: bytes | None
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    flat = [i * len(SLOTS) + k for i, slots in enumerate(joint_slots) for k in slots]
    every = [*([-1] * (6 if base else 0)), *flat]
    chosen = np.array(every, dtype=np.int64)
    if free is not None:
        mask = np.frombuffer(free, dtype=bool)[: len(every)]
        chosen = chosen[mask]
    base_cols = np.flatnonzero(chosen < 0)
    return base_cols, chosen[chosen >= 0]


def _picks(est: Estimate) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The base's free columns (of its 6) and, for the joints, the free candidate columns
    (``joint * 7 + slot``), in the level's order."""
    level = est.level
    joint_slots = []
    for kind in est.chain.kinds:
        slots: list[int] = []
        if level.lines:
            slots += [0, 1] if kind == "prismatic" else [0, 1, 2, 3]
            if kind == "helical":
                slots.append(4)
        if level.offsets:
            slots.append(5)
        if level.scales:
            slots.append(6)
        joint_slots.append(tuple(slots))
    free = None if est.free is None else est.free.tobytes()
    return _picks_cached(tuple(joint_slots), level.base, free)


def _candidates(js: _Joints) -> Mat:
    """``(n, 6, 7)`` each joint's candidate twists before the motion factors (module
    docstring): turns ``[e, p x e]`` (``[e, 0]`` when sliding), shifts ``[0, e]``, the pitch's
    ``[0, u]`` and the unit screw ``xi_hat`` for offset and scale."""
    n = len(js.axis)
    out = np.zeros((n, 6, 7))
    u, p = js.axis, js.point
    e1, e2 = normal_bases(u)
    out[:, :3, 0], out[:, 3:, 0] = e1, cross_rows(p, e1)
    out[:, :3, 1], out[:, 3:, 1] = e2, cross_rows(p, e2)
    out[:, 3:, 2], out[:, 3:, 3] = e1, e2
    out[:, 3:, 4] = u
    out[:, :3, 5] = js.turning[:, None] * u
    out[:, 3:, 5] = js.turning[:, None] * cross_rows(p, u) + js.lead[:, None] * u
    out[:, :, 6] = out[:, :, 5]
    return out


def _ad(rots: Mat, trans: Mat, x: Mat) -> Mat:
    """``Ad(P) X`` for ``P`` as ``rots (N, n, 3, 3)``, ``trans (N, n, 3)`` and ``X (n, 6, k)``:
    ``(N, n, 6, k)``."""
    out = np.empty((*rots.shape[:2], 6, x.shape[2]))
    w = np.matmul(rots, x[:, :3], out=out[:, :, :3])
    v = np.matmul(rots, x[:, 3:], out=out[:, :, 3:])
    t = trans[..., None]
    v[:, :, 0] += t[:, :, 1] * w[:, :, 2] - t[:, :, 2] * w[:, :, 1]
    v[:, :, 1] += t[:, :, 2] * w[:, :, 0] - t[:, :, 0] * w[:, :, 2]
    v[:, :, 2] += t[:, :, 0] * w[:, :, 1] - t[:, :, 1] * w[:, :, 0]
    return out


def _space_columns(est: Estimate, js: _Joints, q: Mat, rots: Mat, trans: Mat, tool: Mat) -> Mat:
    """``(N, 6, p)`` the tool's space-frame twist per free coordinate (module docstring); the
    marker coordinates of position estimates are left at zero (they move points, not the
    tool)."""
    count, n = q.shape
    base_cols, joint_cols = _picks(est)
    blocks = []
    if len(base_cols):
        blocks.append(np.broadcast_to(np.eye(6)[:, base_cols], (count, 6, len(base_cols))))
    if len(joint_cols):
        cand = _candidates(js)
        before_r = np.swapaxes(rots[:-1], 0, 1)  # (N, n, 3, 3): P_(i-1)
        before_t = np.swapaxes(trans[:-1], 0, 1)
        cols = _ad(before_r, before_t, cand)  # (N, n, 6, 7)
        if est.level.lines:
            after = _ad(np.swapaxes(rots[1:], 0, 1), np.swapaxes(trans[1:], 0, 1), cand[:, :, :4])
            if est.keep_tool_axis:
                after[:, n - 1] = 0.0  # the tool moves with the last line
            cols[:, :, :, :4] -= after
        s = js.scale * (q + js.offset)  # (N, n)
        cols[:, :, :, 4] *= s[:, :, None]
        cols[:, :, :, 5] *= js.scale[None, :, None]
        cols[:, :, :, 6] *= (q + js.offset)[:, :, None]
        flat = np.swapaxes(cols, 1, 2).reshape(count, 6, n * len(SLOTS))
        blocks.append(flat[:, :, joint_cols])
    total = sizes(est, every=True)[-1]
    tool_free = np.ones(total, dtype=bool) if est.free is None else est.free[-total:]
    if est.tool == FRAME:
        basis = tool_screws(est) if est.keep_tool_axis else np.eye(6)
        blocks.append(ad_apply(tool, basis[:, tool_free]))
    else:
        blocks.append(np.zeros((count, 6, int(np.sum(tool_free)))))
    return np.concatenate(blocks, axis=2)


CHUNK = 4096  # measurements evaluated at once: memory stays ~ rows x parameters, not 3 x that


def evaluate(est: Estimate, data: Data, sigma_pos: float, sigma_rot: float) -> tuple[Mat, Mat]:
    """Weighted residuals ``(N * rows,)`` and their Jacobian ``(N * rows, p)`` with respect to
    the free coordinates of ``est`` (rows: position x, y, z then, for poses, rotation x, y, z of
    each measurement in turn)."""
    jac = np.empty((len(data), data.rows, sum(sizes(est))))
    res = _evaluated(est, data, sigma_pos, sigma_rot, jac)
    return res, jac.reshape(len(data) * data.rows, -1)


def residuals(est: Estimate, data: Data, sigma_pos: float, sigma_rot: float) -> Mat:
    """The weighted residuals alone (:func:`evaluate`)."""
    return _evaluated(est, data, sigma_pos, sigma_rot, None)


def _evaluated(
    est: Estimate, data: Data, sigma_pos: float, sigma_rot: float, jac: Mat | None
) -> Mat:
    """The residuals ``(N * rows,)``, and the Jacobian into ``jac`` ``(N, rows, p)`` when
    given; :data:`CHUNK` measurements at a time."""
    res = np.empty((len(data), data.rows))
    js = _arrays(est)
    for start in range(0, len(data), CHUNK):
        rows = slice(start, start + CHUNK)
        _evaluate_into(
            est,
            js,
            data.part(rows),
            sigma_pos,
            sigma_rot,
            res[rows],
            None if jac is None else jac[rows],
        )
    out: Mat = res.ravel()
    return out


def _evaluate_into(
    est: Estimate,
    js: _Joints,
    data: Data,
    sigma_pos: float,
    sigma_rot: float,
    res: Mat,
    jac: Mat | None,
) -> None:
    rots, trans = _prefix(js, data.q)
    last_r = rots[-1]
    tool, x = _tool(est, last_r, trans[-1], data.markers)
    res[:, :3] = (x - data.points) / sigma_pos
    phi = None
    if data.rotations is not None:
        phi = log_so3(tool[:, :3, :3] @ np.swapaxes(data.rotations, 1, 2))
        res[:, 3:] = phi / sigma_rot
    if jac is None:
        return
    cols = _space_columns(est, js, data.q, rots, trans, tool)
    jac[:, :3] = (cols[:, 3:] + cross_columns(cols[:, :3], x[:, :, None])) / sigma_pos
    if phi is not None:
        jac[:, 3:] = left_jacobian_inverse(phi) @ cols[:, :3] / sigma_rot
    if est.tool == FRAME:
        return
    total = 3 * len(est.markers)
    free = np.ones(total, dtype=bool) if est.free is None else est.free[-total:]
    column = jac.shape[2] - int(np.sum(free))
    for k in range(len(est.markers)):
        rows = data.markers == k
        for axis in range(3):
            if free[3 * k + axis]:
                jac[rows, :3, column] = last_r[rows, :, axis] / sigma_pos
                column += 1
