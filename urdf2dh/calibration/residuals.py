"""Measurement residuals of an :class:`~.chart.Estimate` and their analytic Jacobian.

Residuals, per measurement (model minus measured, both in the device frame):

* position ``x(q) - x_meas`` of the tool origin (poses) or of marker ``k``, ``x = P_n(q) c_k``
  (positions), divided by the position noise ``sigma_p``;
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
* the home pose ``M exp(zeta)``: ``d = Ad(T) zeta``; a marker ``c + dc``: ``dx = R_(P_n) dc``.

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
from .chart import Estimate, normal_bases, sizes, tool_screws

__all__ = ["Data", "evaluate", "model_poses", "prefix_products"]

Mat = NDArray[np.float64]

SLOTS = ("turn1", "turn2", "shift1", "shift2", "pitch", "offset", "scale")


@dataclass(frozen=True, slots=True)
class Data:
    """What the model is compared with.

    Attributes
    ----------
    q
        ``(N, n)`` joint positions.
    points
        ``(N, 3)`` measured tool points in the device frame.
    rotations
        ``(N, 3, 3)`` measured tool orientations (pose measurements), else ``None``.
    marker_rows
        ``(N,)`` for position measurements, the row of :attr:`Estimate.markers` each
        measurement saw, else ``None``.
    """

    q: Mat
    points: Mat
    rotations: Mat | None = None
    marker_rows: NDArray[np.int64] | None = None

    def __post_init__(self) -> None:
        n = len(self.q)
        if self.points.shape != (n, 3):
            raise ValueError(f"points must be ({n}, 3), not {self.points.shape}")
        if self.rotations is not None and self.rotations.shape != (n, 3, 3):
            raise ValueError(f"rotations must be ({n}, 3, 3), not {self.rotations.shape}")
        if (self.rotations is None) == (self.marker_rows is None):
            raise ValueError("data holds rotations (poses) or marker rows (positions)")

    def part(self, rows: slice) -> Data:
        """The measurements in ``rows``."""
        return Data(
            self.q[rows],
            self.points[rows],
            None if self.rotations is None else self.rotations[rows],
            None if self.marker_rows is None else self.marker_rows[rows],
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
    """``(N, 4, 4)`` the tool poses ``P_n(q) M`` (pose estimates only)."""
    assert est.home is not None
    return prefix_products(est, q)[-1] @ est.home


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


def _space_columns(
    est: Estimate, js: _Joints, q: Mat, rots: Mat, trans: Mat, tool: Mat | None
) -> Mat:
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
    if tool is not None:
        basis = tool_screws(est) if est.keep_tool_axis else np.eye(6)
        blocks.append(ad_apply(tool, basis[:, tool_free]))
    else:
        blocks.append(np.zeros((count, 6, int(np.sum(tool_free)))))
    return np.concatenate(blocks, axis=2)


CHUNK = 4096  # measurements evaluated at once: memory stays ~ rows x parameters, not 3 x that


def evaluate(
    est: Estimate, data: Data, sigma_pos: float, sigma_rot: float, jacobian: bool = True
) -> tuple[Mat, Mat | None]:
    """Weighted residuals ``(N * rows,)`` and, if asked, their Jacobian ``(N * rows, p)`` with
    respect to the free coordinates of ``est`` (rows: position x, y, z then, for poses,
    rotation x, y, z of each measurement in turn). Evaluated :data:`CHUNK` measurements at a
    time, into one array."""
    res = np.empty((len(data), data.rows))
    jac = np.empty((len(data), data.rows, sum(sizes(est)))) if jacobian else None
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
    if jac is None:
        return res.ravel(), None
    return res.ravel(), jac.reshape(len(data) * data.rows, -1)


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
    last_r, last_t = rots[-1], trans[-1]
    tool = None
    if est.home is not None:
        tool = np.zeros((len(data), 4, 4))
        tool[:, :3, :3] = last_r @ est.home[:3, :3]
        tool[:, :3, 3] = last_r @ est.home[:3, 3] + last_t
        tool[:, 3, 3] = 1.0
        x = tool[:, :3, 3]
    else:
        assert est.markers is not None and data.marker_rows is not None
        c = est.markers[data.marker_rows]
        x = np.einsum("nij,nj->ni", last_r, c) + last_t
    res[:, :3] = (x - data.points) / sigma_pos
    phi = None
    if data.rotations is not None:
        assert tool is not None
        phi = log_so3(tool[:, :3, :3] @ np.swapaxes(data.rotations, 1, 2))
        res[:, 3:] = phi / sigma_rot
    if jac is None:
        return
    cols = _space_columns(est, js, data.q, rots, trans, tool)
    jac[:, :3] = (cols[:, 3:] + cross_columns(cols[:, :3], x[:, :, None])) / sigma_pos
    if phi is not None:
        jac[:, 3:] = left_jacobian_inverse(phi) @ cols[:, :3] / sigma_rot
        return
    assert est.markers is not None and data.marker_rows is not None
    total = 3 * len(est.markers)
    free = np.ones(total, dtype=bool) if est.free is None else est.free[-total:]
    first = jac.shape[2] - int(np.sum(free))
    column = first
    for k in range(len(est.markers)):
        rows = data.marker_rows == k
        for axis in range(3):
            if free[3 * k + axis]:
                jac[rows, :3, column] = last_r[rows, :, axis] / sigma_pos
                column += 1
