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
measurements at once, ``N`` configurations as ``(N, ...)`` stacks. The Jacobian's columns are
the level's free twists (the base's, each joint's candidates, the tool's, of which
:func:`_layout` picks the level's) under the adjoints of the frames ``P_0 .. P_n`` and ``T``;
each adjoint is taken about the point the measurement saw (the translation ``t - x``), so that
its ``v`` is that point's motion ``dv + dw x x`` at once, and the twists of each frame meet all
its configurations' adjoints in one matrix product.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from ..geometry.lie import CROSS_NEXT, CROSS_PREV, cross_rows, left_jacobian_inverse, log_so3
from .chart import FRAME, Estimate, normal_bases, sizes, tool_screws
from .levels import Level

__all__ = [
    "Data",
    "Evaluation",
    "errors",
    "evaluate",
    "measurement_errors",
    "model_poses",
    "modelled_points",
    "observed",
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

    def part(self, rows: slice | NDArray[np.int64]) -> Data:
        """The measurements in ``rows`` (a slice, or their indices)."""
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


_EYE4 = np.eye(4)
_EYE6 = np.eye(6)


def _exp_basis(est: Estimate) -> Mat:
    """``(n, 4, 16)``: each joint's ``exp([xi] s)`` (a ``4 x 4`` transform, flattened) is
    ``c B`` with ``c = [1, sin t, 1 - cos t, s]`` and ``t = s`` for turning joints, ``0`` for
    sliding ones (Rodrigues: ``R = I + sin t [u] + (1 - cos t) [u]^2`` and the translation
    ``(I - R) p + h s u``, with ``h`` the lead: the pitch, or 1 for a sliding joint)."""
    chain = est.chain
    n = len(chain)
    turning = chain.turning
    out = np.zeros((n, 4, 16))
    out[:, 0] = _EYE4.ravel()
    out[:, 1, _SKEW_PLUS] = chain.axis  # [u], written in place
    out[:, 1, _SKEW_MINUS] = -chain.axis
    blocks = out.reshape(n, 4, 4, 4)
    k = blocks[:, 1, :3, :3]
    np.matmul(k, k, out=blocks[:, 2, :3, :3])
    point = chain.point * turning[:, None]
    blocks[:, 1:3, :3, 3] = -np.matmul(blocks[:, 1:3, :3, :3], point[:, None, :, None])[..., 0]
    blocks[:, 3, :3, 3] = np.where(turning, chain.pitch, 1.0)[:, None] * chain.axis
    return out


# where u_0, u_1, u_2 sit in a flattened 4 x 4 block's [u], and where -u_0, -u_1, -u_2 do
_SKEW_PLUS = np.array([9, 2, 4])
_SKEW_MINUS = np.array([6, 8, 1])


def _frames(est: Estimate, q: Mat) -> tuple[Mat, Mat, Mat]:
    """``(n + 2, N, 4, 4)`` the frames ``P_0 = I, P_1, ..., P_n`` and the tool's ``T = P_n M``;
    ``(n, N)`` each joint's ``q + o`` and its motion ``s (q + o)`` (read-only: the first may be
    a view of ``q``).

    Each joint's ``exp([xi] s)`` at every configuration is one product with
    :func:`_exp_basis` (``1 - cos t`` as ``2 sin^2(t/2)``); their running products one joint
    at a time."""
    chain = est.chain
    count, n = q.shape
    moved = q.T if est.offsets is None else q.T + est.offsets[:, None]
    coef = np.empty((n, 4, count))  # rows 1, sin t, 1 - cos t, s
    coef[:, 0] = 1.0
    s = np.multiply(moved, chain.scale[:, None], out=coef[:, 3])
    angle = s * chain.turning[:, None] if "prismatic" in chain.kinds else s
    np.sin(angle, out=coef[:, 1])
    half = np.sin(0.5 * angle)
    np.multiply(half, half, out=coef[:, 2])
    coef[:, 2] *= 2.0
    e = np.matmul(coef.transpose(0, 2, 1), _exp_basis(est)).reshape(n, count, 4, 4)
    out = np.empty((n + 2, count, 4, 4))
    out[0] = _EYE4
    if n:
        out[1] = e[0]
    for i in range(1, n):
        np.matmul(out[i], e[i], out=out[i + 1])
    np.matmul(out[n].reshape(-1, 4), est.home, out=out[n + 1].reshape(-1, 4))  # one product
    return out, moved, s


def model_poses(est: Estimate, q: Mat) -> Mat:
    """``(N, 4, 4)`` the tool poses ``T(q) = P_n(q) M``."""
    out: Mat = _frames(est, q)[0][-1]
    return out


def _points(est: Estimate, tool: Mat, markers: NDArray[np.int64]) -> Mat:
    """``(N, 3)`` the points ``T c_k`` the measurements saw (``markers``: each one's ``k``) on
    the tool's poses ``tool`` ``(N, 4, 4)``."""
    if not est.markers.any():  # the tool's origin
        return tool[:, :3, 3].copy()
    seen = est.markers[markers][:, :, None]
    out: Mat = np.matmul(tool[:, :3, :3], seen)[..., 0] + tool[:, :3, 3]
    return out


def modelled_points(est: Estimate, data: Data) -> Mat:
    """``(N, 3)`` the points of ``est``'s tool each measurement of ``data`` saw."""
    return _points(est, _frames(est, data.q)[0][-1], data.markers)


def observed(est: Estimate, q: Mat) -> Data:
    """What a device would measure of ``est`` at ``q`` ``(N, n)``, without noise: the tool's
    poses (a tool frame), or each marker's position at each configuration (markers; rows
    configuration by configuration, each marker in turn)."""
    k = len(est.markers)
    qs = np.repeat(q, k, axis=0) if k > 1 else q
    rows = np.tile(np.arange(k, dtype=np.int64), len(q))
    tool = _frames(est, qs)[0][-1]
    points = _points(est, tool, rows)
    return Data(qs, points, rows, tool[:, :3, :3].copy() if est.tool == FRAME else None)


def rms(values: Mat) -> float:
    """The root of the mean square of ``values`` (errors, residuals)."""
    return float(np.sqrt(np.mean(np.square(values))))


def errors(est: Estimate, data: Data) -> Mat:
    """``(N, 1 or 2)`` each measurement's position error (the distance between the modelled and
    the measured point) and, for poses, its rotation error (the angle of ``R R_meas^T``): the
    one formula every residual statistic is made of (offsets absorbed or not alike)."""
    return measurement_errors(residuals(est, data, 1.0, 1.0), data.rows)


def measurement_errors(res: Mat, rows: int) -> Mat:
    """:func:`errors` from the residuals at unit noise levels ``res`` (``rows`` per
    measurement): the norm of each measurement's position and rotation residuals."""
    parts = res.reshape(-1, rows // 3, 3)
    out: Mat = np.sqrt(np.add.reduce(parts * parts, axis=2))
    return out


@dataclass(frozen=True, slots=True)
class _Layout:
    """Where each free coordinate's Jacobian column comes from (module docstring).

    The frames are ``P_0 .. P_n`` and ``T`` (:func:`_frames`); those of them the columns use,
    ``used`` (``None``: all), hold ``width`` twists each, rows of :func:`_twists` (``place``
    ``(len(used), width)``), the last of them the zero row (read-only, as every array here).
    Column ``c`` is used frame ``frame[c]``'s twist ``slot[c]`` under that frame's adjoint,
    minus used frame ``after_frame[c]``'s twist ``after_slot[c]`` (for a joint line's
    coordinates the same twist under the next frame; for the others the zero row), times the
    factor ``factor[c]`` of :func:`_factors` (``None``: all 1)."""

    used: NDArray[np.int64] | None
    place: NDArray[np.int64]
    frame: NDArray[np.int64]
    slot: NDArray[np.int64]
    after_frame: NDArray[np.int64]
    after_slot: NDArray[np.int64]
    factor: NDArray[np.int64] | None


def _layout(est: Estimate) -> _Layout:
    """The :class:`_Layout` of ``est``'s level and free coordinates."""
    free = None if est.free is None else est.free.tobytes()
    markers = len(est.markers) if est.tool != FRAME else 0
    return _level_layout(est.level, est.chain.kinds, est.keep_tool_axis, markers, free)


@lru_cache(maxsize=256)
def _level_layout(
    level: Level, kinds: tuple[str, ...], keep_tool_axis: bool, markers: int, free: bytes | None
) -> _Layout:
    """:func:`_layout` of a level for joints of ``kinds``, the tool measured by ``markers``
    markers (0: its frame) and ``free`` the level's free coordinates (``None``: all)."""
    n = len(kinds)
    tool_row = 6 + 7 * n
    # each coordinate: (frame, twist row of _twists, factor of _factors, after frame or -1)
    every = [(0, j, 0, -1) for j in range(6 if level.base else 0)]
    for i, kind in enumerate(kinds):
        slots: list[int] = []  # of SLOTS
        if level.lines:
            slots += [0, 1] if kind == "prismatic" else [0, 1, 2, 3]
            if kind == "helical":
                slots.append(4)
        if level.offsets:
            slots.append(5)
        if level.scales:
            slots.append(6)
        for k in slots:
            factor = 1 + i if k == 4 else 1 + n + i if k == 6 else 0
            after = i + 1 if k < 4 and not (keep_tool_axis and i == n - 1) else -1
            every.append((i, 6 + 7 * i + k, factor, after))
    if markers:  # a marker's home moved by dc in the device frame: dx = R_(P_n) dc
        every += [
            (n, tool_row + 3 + a, 1 + 2 * n + m, -1) for m in range(markers) for a in range(3)
        ]
    else:
        tool = range(2) if keep_tool_axis else range(6)
        every += [(n + 1, tool_row + j, 0, -1) for j in tool]
    if free is not None:
        mask = np.frombuffer(free, dtype=bool)
        every = [c for c, f in zip(every, mask, strict=True) if f]
    held: list[list[int]] = [[] for _ in range(n + 2)]

    def slot_of(frame: int, row: int) -> int:
        if row not in held[frame]:
            held[frame].append(row)
        return held[frame].index(row)

    slot = [slot_of(c[0], c[1]) for c in every]
    after_slot = [slot_of(c[3], c[1]) if c[3] >= 0 else -1 for c in every]
    used = [f for f, rows in enumerate(held) if rows] or [0]
    at = {f: k for k, f in enumerate(used)}
    width = max(len(h) for h in held)
    # every frame's rows padded with the zero row to width + 1: the columns without a
    # second term take that of the zero row
    place = [held[f] + [tool_row + 6] * (width + 1 - len(held[f])) for f in used]
    factors = [c[2] for c in every]

    def ints(values: list[int]) -> NDArray[np.int64]:
        out = np.array(values, dtype=np.int64).reshape(-1)
        out.setflags(write=False)
        return out

    return _Layout(
        None if len(used) == n + 2 else ints(used),
        ints([row for rows in place for row in rows]).reshape(len(used), width + 1),
        ints([at[c[0]] for c in every]),
        ints(slot),
        ints([at[c[3] if c[3] >= 0 else c[0]] for c in every]),
        ints([a if a >= 0 else width for a in after_slot]),
        ints(factors) if any(factors) else None,
    )


def _twists(est: Estimate) -> Mat:
    """``(6 + 7 n + 7, 6)`` the twists the Jacobian's columns are made of, before the motion
    factors (module docstring): the base's six unit twists; each joint's seven candidates,
    turns ``[e, p x e]`` (``[e, 0]`` when sliding), shifts ``[0, e]``, the pitch's ``[0, u]``,
    the offset's ``s xi_hat`` and the scale's ``xi_hat``; the tool's six unit twists (or, with
    ``keep_tool_axis``, its two screws :func:`.chart.tool_screws`; for markers, the three
    ``[0, e_a]`` that shift a point); a zero row."""
    chain = est.chain
    n = len(chain)
    out = np.zeros((6 + 7 * n + 7, 6))
    out[:6] = _EYE6
    cand = out[6 : 6 + 7 * n].reshape(n, 7, 6)
    u = chain.axis
    sliding = "prismatic" in chain.kinds
    turning = chain.turning
    p = chain.point * turning[:, None] if sliding else chain.point
    e1, e2 = normal_bases(u)
    cand[:, 0, :3], cand[:, 1, :3] = e1, e2
    cand[:, 2, 3:], cand[:, 3, 3:] = e1, e2
    cand[:, 4, 3:] = u
    moments = cross_rows(p[:, None, :], cand[:, 2:5, 3:])  # p x e1, e2, u
    cand[:, :2, 3:] = moments[:, :2]
    cand[:, 6, :3] = turning[:, None] * u if sliding else u
    lead = np.where(turning, chain.pitch, 1.0) if sliding else chain.pitch
    cand[:, 6, 3:] = moments[:, 2] + lead[:, None] * u  # p = 0 for sliding joints
    cand[:, 5] = cand[:, 6] * chain.scale[:, None]
    tool = out[6 + 7 * n : 6 + 7 * n + 6]
    if est.keep_tool_axis:
        tool[:2] = tool_screws(est).T
    else:
        tool[:] = _EYE6
    return out


def _factors(est: Estimate, data: Data, moved: Mat, s: Mat, which: NDArray[np.int64]) -> Mat:
    """``(p, N)`` each column's factor per measurement: 1; a pitch's ``s (q + o)``; a scale's
    ``q + o``; for a marker's coordinates, whether the measurement saw that marker."""
    n, count = moved.shape
    k = len(est.markers)
    out = np.empty((1 + 2 * n + k, count))
    out[0] = 1.0
    out[1 : 1 + n] = s
    out[1 + n : 1 + 2 * n] = moved
    out[1 + 2 * n :] = data.markers == np.arange(k)[:, None]
    picked: Mat = out[which]
    return picked


# measurements evaluated at once: memory stays ~ rows x parameters, and each pass in cache
CHUNK = 1024


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
    if len(data) <= CHUNK:
        _evaluate_into(est, data, sigma_pos, sigma_rot, res, jac)
    else:
        for start in range(0, len(data), CHUNK):
            rows = slice(start, start + CHUNK)
            part = None if jac is None else jac[rows]
            _evaluate_into(est, data.part(rows), sigma_pos, sigma_rot, res[rows], part)
    out: Mat = res.ravel()
    return out


def _evaluate_into(
    est: Estimate,
    data: Data,
    sigma_pos: float,
    sigma_rot: float,
    res: Mat,
    jac: Mat | None,
) -> None:
    state = _model(est, data, sigma_pos, sigma_rot, res)
    if jac is not None:
        _jacobian_into(est, data, state, sigma_pos, sigma_rot, jac)


@dataclass(frozen=True, slots=True)
class _State:
    """What the Jacobian is made of: :func:`_frames`' frames and motions, the points seen
    ``x`` and, for poses, the rotation residuals ``phi``."""

    frames: Mat
    moved: Mat
    s: Mat
    x: Mat
    phi: Mat | None


def _model(est: Estimate, data: Data, sigma_pos: float, sigma_rot: float, res: Mat) -> _State:
    """The residuals into ``res`` ``(N, rows)``, and the state their Jacobian is made of."""
    frames, moved, s = _frames(est, data.q)
    tool = frames[-1]
    x = _points(est, tool, data.markers)
    np.subtract(x, data.points, out=res[:, :3])
    if sigma_pos != 1.0:
        res[:, :3] /= sigma_pos
    phi = None
    if data.rotations is not None:
        phi = log_so3(np.matmul(tool[:, :3, :3], np.swapaxes(data.rotations, 1, 2)))
        res[:, 3:] = phi / sigma_rot
    return _State(frames, moved, s, x, phi)


def _jacobian_into(
    est: Estimate, data: Data, state: _State, sigma_pos: float, sigma_rot: float, jac: Mat
) -> None:
    """The Jacobian ``(N, rows, p)`` into ``jac`` from ``state`` (module docstring)."""
    if not jac.shape[2]:
        return
    # the columns as space-frame twists moved to the point seen (the translation t - x):
    # Ad(P) [w, v] = [R w, R v + (t - x) x R w], whose v is the point's motion (dv + dw x x)
    lay = _layout(est)
    frames = state.frames if lay.used is None else state.frames[lay.used]
    used, count = frames.shape[:2]
    ad = np.empty((used, count, 6, 6))
    rot = frames[:, :, :3, :3]
    ad[:, :, :3, :3] = rot
    ad[:, :, :3, 3:] = 0.0
    ad[:, :, 3:, 3:] = rot
    # [t - x] R, formed from (3, 4, used, N) planes of the frames (long rows for numpy's loops)
    planes = np.ascontiguousarray(frames[:, :, :3].transpose(2, 3, 0, 1))
    lever = planes[:, 3] - state.x.T[:, None, :]
    rows = planes[:, :3]
    cross = lever[CROSS_NEXT, None] * rows[CROSS_PREV]  # lever x rows, components first
    cross -= lever[CROSS_PREV, None] * rows[CROSS_NEXT]
    ad[:, :, 3:, :3] = cross.transpose(2, 3, 0, 1)
    twists = _twists(est)[lay.place].transpose(0, 2, 1)  # (used, 6, width)
    moves = np.matmul(ad.reshape(used, count * 6, 6), twists)
    del ad  # (the arrays here are large: each freed as soon as done with)
    # (N, 6, used, width): a (frame, slot) pair per column gives (N, 6, p), the Jacobian's order
    by_point = moves.reshape(used, count, 6, -1).transpose(1, 2, 0, 3)
    cols = by_point[:, :, lay.frame, lay.slot]
    cols -= by_point[:, :, lay.after_frame, lay.after_slot]
    del moves, by_point
    if lay.factor is not None:
        cols *= _factors(est, data, state.moved, state.s, lay.factor).T[:, None, :]
    if sigma_pos != 1.0:
        np.divide(cols[:, 3:], sigma_pos, out=jac[:, :3])
    else:
        jac[:, :3] = cols[:, 3:]
    if state.phi is not None:
        np.matmul(left_jacobian_inverse(state.phi), cols[:, :3], out=jac[:, 3:])
        if sigma_rot != 1.0:
            jac[:, 3:] /= sigma_rot


@dataclass(frozen=True, slots=True)
class Evaluation:
    """The model of an estimate evaluated for measurements at unit noise levels: the residuals
    at once, their Jacobian when asked, from the same frames (a step the solver refuses costs
    no Jacobian).

    Attributes
    ----------
    estimate, data
        Where, and for what.
    residuals
        ``(N * rows,)`` (:func:`evaluate` at unit noise levels).
    """

    estimate: Estimate
    data: Data
    residuals: Mat
    made: _State | Mat  # the frames (one chunk), or the Jacobian made with the residuals

    @classmethod
    def at(cls, est: Estimate, data: Data) -> Evaluation:
        """The residuals of ``data`` at ``est`` (beyond one chunk, and the Jacobian: the frames
        are not kept, and making them twice would cost more than a Jacobian not asked for)."""
        if len(data) > CHUNK:
            jac = np.empty((len(data), data.rows, sum(sizes(est))))
            return cls(est, data, _evaluated(est, data, 1.0, 1.0, jac), jac)
        res = np.empty((len(data), data.rows))
        return cls(est, data, res.ravel(), _model(est, data, 1.0, 1.0, res))

    def jacobian(self) -> Mat:
        """``(N * rows, p)`` the residuals' Jacobian (:func:`evaluate` at unit noise levels)."""
        est, data, jac = self.estimate, self.data, self.made
        if isinstance(jac, _State):
            state, jac = jac, np.empty((len(data), data.rows, sum(sizes(est))))
            _jacobian_into(est, data, state, 1.0, 1.0, jac)
        return jac.reshape(len(data) * data.rows, -1)
