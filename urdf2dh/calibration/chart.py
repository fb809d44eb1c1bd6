"""The parameters calibration identifies: nested levels of a POE model and their local charts.

The model (Brockett 1984; Wu 2019 eq. 5) in the measuring device's frame::

    T(q) = exp([xi_1] s_1 (q_1 + o_1)) ... exp([xi_n] s_n (q_n + o_n)) M,
    xi_i = [u_i, p_i x u_i + h_i u_i]

with joint offsets ``o`` and scales ``s``. What is identified is a :class:`Level`, from the
least to the most:

* ``base-tool``: the nominal joints, placed in the device frame by a base motion (6), and the
  tool (6 for poses; 3 per marker for positions). What an unknown base and tool alone explain:
  the fair "before" of every calibration.
* ``offsets``: and each joint's offset ``o_i`` (those the base and tool do not already carry:
  the first joint's turn is the base's, the last's the tool's).
* ``geometry``: every joint's line (Wu 2019 eq. 23 without the scales): a base needs no
  parameters of its own (``B exp([xi] q) = exp([Ad_B xi] q) B``, Wu 2019 eq. 3) and offsets are
  absorbed by the later lines and ``M`` (Wu 2019 §V-A).
* ``full``: and every joint's scale ``s_i`` (Wu's q_bar, §II).

Every quantity is updated by a *local* chart centred on the current estimate (re-centred after
each step, a retraction), so no parameter is singular anywhere, parallel axes included:

* base: ``exp(beta)`` moves every joint line, the tool and the markers: a space-frame twist, 6
  (``base.rx .. base.z``).
* joint line (revolute, 4): moved rigidly by ``G = exp(eta)``,
  ``eta = a [e1, p x e1] + b [e2, p x e2] + c [0, e1] + d [0, e2]`` (turns about two axes
  through the foot ``p`` of the perpendicular from the device origin, normal to the line, and
  shifts along them; ``e1, e2`` an orthonormal basis normal to ``u``); helical, 5: and the
  pitch ``h' = h + dh``; prismatic, 2: the direction turned, ``u' = exp(a e1 + b e2) u``.
* offset ``o' = o + do`` and scale ``s' = s + ds``: 1 each.
* the tool: what is measured decides (:attr:`Estimate.tool`). Every measurement sees a point
  ``T(q) c_k`` of the tool, ``c_k`` in the tool frame (the origin, ``c = 0``, for poses), and,
  for poses, the tool's orientation too:

  * ``frame`` (poses): the tool frame ``M' = M exp(zeta)``, 6. With ``keep_tool_axis`` the tool
    keeps the nominal's placement relative to the last joint's line: it moves with that line
    and only screws about and along it, 2;
  * ``markers`` (positions): the tool frame is not observed and stays as placed; each marker's
    home position in the device frame ``M c_k`` moves by ``dc``, 3 each (the frame is completed
    afterwards from the marker layout; see :mod:`.identify`).

For ``full`` this is Wu 2019 eq. (23) for poses, ``5h + 4r + 2t + n + 6`` coordinates, and
``5h + 4r + 2t + n + 3K`` for positions of K markers. The lines' variations are the adjoint
error model of Li, Wu, Löwe & Li (IEEE T-RO 32(5), 2016) with Wu 2019's pitch and scale.

A coordinate may be held *fixed* (at its value in the estimate): a named parameter the user
fixes, or one the level's other coordinates already carry (:func:`redundant`). ``free`` says
which coordinates of the level are identified; :func:`count`, :func:`names` and
:func:`retract` see only those.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..geometry.lie import (
    cross3,
    cross_rows,
    exp_so3_left_jacobian,
    left_jacobian,
    log_se3,
    skew_batch,
    turn_coefficients,
)
from ..geometry.se3 import twist_exp
from ..model.identifiability import LINE_PARAMETERS
from ..model.poe import Joint
from .levels import FULL, Level

__all__ = [
    "FRAME",
    "MARKERS",
    "TOOLS",
    "Chain",
    "Estimate",
    "LineCoordinates",
    "absorbed",
    "all_names",
    "count",
    "joint_columns",
    "line_coordinates",
    "local_coordinates",
    "names",
    "normal_basis",
    "retract",
    "sizes",
]

Mat = NDArray[np.float64]


def normal_basis(u: Mat) -> tuple[Mat, Mat]:
    """Orthonormal ``e1, e2`` normal to the unit ``u``: ``e1`` from the basis vector least
    aligned with ``u`` (a smooth choice near any ``u``), ``e2 = u x e1``."""
    k = int(np.argmin(np.abs(u)))
    e1 = -u[k] * u
    e1[k] += 1.0
    e1 /= np.linalg.norm(e1)
    return e1, cross3(u, e1)


def normal_bases(u: Mat) -> tuple[Mat, Mat]:
    """:func:`normal_basis` of each row of ``u`` ``(n, 3)``: ``(n, 3)`` and ``(n, 3)``
    (read-only: the bases of the last axes asked for are kept, the charts of one estimate ask
    for them several times)."""
    return _normal_bases(u.tobytes(), len(u))


@lru_cache(maxsize=64)
def _normal_bases(axes: bytes, n: int) -> tuple[Mat, Mat]:
    u = np.frombuffer(axes, dtype=np.float64).reshape(n, 3)
    flat = np.arange(n) * 3 + np.argmin(np.abs(u), axis=1)
    e1 = u * -u.ravel()[flat, None]
    e1.ravel()[flat] += 1.0
    e1 /= np.sqrt(np.add.reduce(e1 * e1, axis=1, keepdims=True))
    e2 = cross_rows(u, e1)
    e1.setflags(write=False)
    e2.setflags(write=False)
    return e1, e2


def line_point(u: Mat, p: Mat) -> Mat:
    """The foot of the perpendicular from the origin on the line through ``p`` along unit ``u``
    (rows of ``(n, 3)`` arrays, or one line)."""
    foot: Mat = p - np.add.reduce(p * u, axis=-1, keepdims=True) * u
    return foot


@dataclass(frozen=True, slots=True)
class Chain:
    """A chain's joints as arrays, the form the identification moves them in.

    Attributes
    ----------
    names, kinds
        Each joint's name and kind (``revolute``, ``helical``, ``prismatic``).
    axis
        ``(n, 3)`` unit directions.
    point
        ``(n, 3)`` for revolute and helical joints the foot of the perpendicular from the
        origin on the line; for prismatic ones a point of the line, or zeros.
    pitch, scale
        ``(n,)`` pitches (helical joints) and scales.
    located
        Whether each joint has a point (a prismatic joint of a POE file may not).
    lower, upper
        The joints' limits (carried into the output model).
    """

    names: tuple[str, ...]
    kinds: tuple[str, ...]
    axis: Mat
    point: Mat
    pitch: Mat
    scale: Mat
    located: tuple[bool, ...]
    lower: tuple[float | None, ...]
    upper: tuple[float | None, ...]

    @classmethod
    def of(cls, joints: tuple[Joint, ...]) -> Chain:
        """The chain of ``joints`` (turning joints' points as feet of perpendiculars)."""
        n = len(joints)
        axis, point = np.zeros((n, 3)), np.zeros((n, 3))
        for i, j in enumerate(joints):
            axis[i] = j.axis
            if j.point is not None:
                point[i] = j.point if j.kind == "prismatic" else line_point(j.axis, j.point)
        return cls(
            tuple(j.name for j in joints),
            tuple(j.kind for j in joints),
            axis,
            point,
            np.array([j.pitch for j in joints], dtype=float),
            np.array([j.scale for j in joints], dtype=float),
            tuple(j.point is not None for j in joints),
            tuple(j.lower for j in joints),
            tuple(j.upper for j in joints),
        )

    def __len__(self) -> int:
        return len(self.names)

    @property
    def turning(self) -> NDArray[np.bool_]:
        """``(n,)`` which joints turn (revolute and helical); read-only."""
        return _turning(self.kinds)

    def joints(self) -> tuple[Joint, ...]:
        """The chain as :class:`~urdf2dh.model.poe.Joint` objects."""
        return tuple(
            Joint(
                self.names[i],
                self.kinds[i],  # type: ignore[arg-type]
                self.axis[i].copy(),
                self.point[i].copy() if self.located[i] else None,
                float(self.pitch[i]),
                float(self.scale[i]),
                self.lower[i],
                self.upper[i],
            )
            for i in range(len(self))
        )

    def moved(self, g: Mat) -> Chain:
        """Every line moved by the rigid motion ``g``."""
        axis = self.axis @ g[:3, :3].T
        point = self.point @ g[:3, :3].T + g[:3, 3]
        return self.placed(axis, point)

    def scaled(self, scale: Mat) -> Chain:
        """The same joints with the scales ``scale``."""
        return Chain(
            self.names, self.kinds, self.axis, self.point, self.pitch, scale, self.located,
            self.lower, self.upper,
        )  # fmt: skip

    def placed(self, axis: Mat, point: Mat, pitch: Mat | None = None) -> Chain:
        """The same joints along ``axis`` through ``point`` (turning joints' points taken to
        the feet of the perpendiculars), with ``pitch`` when given."""
        if "prismatic" in self.kinds:
            point = np.where(self.turning[:, None], line_point(axis, point), point)
        else:
            point = line_point(axis, point)
        pitch = self.pitch if pitch is None else pitch
        return Chain(
            self.names, self.kinds, axis, point, pitch, self.scale, self.located, self.lower,
            self.upper,
        )  # fmt: skip


@lru_cache(maxsize=64)
def _turning(kinds: tuple[str, ...]) -> NDArray[np.bool_]:
    out = np.array([k != "prismatic" for k in kinds], dtype=bool)
    out.setflags(write=False)
    return out


FRAME = "frame"  # poses: the tool frame is measured (module docstring)
MARKERS = "markers"  # positions: points on the tool are
TOOLS = (FRAME, MARKERS)


@dataclass(frozen=True, slots=True)
class Estimate:
    """A POE model being identified, in the device frame.

    Attributes
    ----------
    chain
        The joints (``helical`` ones have their pitch identified; revolute ones keep pitch 0).
    home
        ``(4, 4)`` the tool's home pose ``M``.
    markers
        ``(K, 3)`` the points measured on the tool, in the tool frame (the origin for poses).
    tool
        What is measured (:data:`TOOLS`): the tool's ``frame`` (poses), or its ``markers``
        (positions); it decides the tool's coordinates (module docstring).
    level
        What is identified (:data:`.levels.LEVELS`).
    keep_tool_axis
        Whether the tool keeps its placement relative to the last joint's line.
    offsets
        ``(n,)`` the joint offsets ``o`` (added to the joint positions), or ``None`` for zeros.
    base
        ``(4, 4)`` the base motion applied so far (levels with a base), or ``None``.
    free
        Which of the level's coordinates (:func:`all_names`) are identified; ``None``: all.
    """

    chain: Chain
    home: Mat
    markers: Mat
    tool: str = FRAME
    level: Level = FULL
    keep_tool_axis: bool = False
    offsets: Mat | None = None
    base: Mat | None = None
    free: NDArray[np.bool_] | None = None

    def __post_init__(self) -> None:
        if self.tool not in TOOLS or self.markers.ndim != 2 or not len(self.markers):
            raise ValueError(f"an estimate measures a tool frame or markers, not {self.tool}")
        if self.keep_tool_axis and (
            self.tool != FRAME or not len(self.chain) or self.chain.kinds[-1] == "prismatic"
        ):
            raise InputError(
                "keeping the tool on the last joint's axis needs pose measurements "
                "and a revolute or helical last joint"
            )
        if self.free is not None and len(self.free) != sum(sizes(self, every=True)):
            raise ValueError("free must have one entry per coordinate of the level")

    @classmethod
    def of(
        cls, joints: tuple[Joint, ...], home: Mat, markers: Mat | None = None, **kw: object
    ) -> Estimate:
        """An estimate of ``joints`` with the tool at ``home``: its frame measured, or, with
        ``markers`` ``(K, 3)`` (tool frame), those points (the other fields as keywords)."""
        if markers is None:
            return cls(Chain.of(joints), home, np.zeros((1, 3)), FRAME, **kw)  # type: ignore[arg-type]
        return cls(Chain.of(joints), home, markers, MARKERS, **kw)  # type: ignore[arg-type]

    def device_markers(self) -> Mat:
        """``(K, 3)`` the markers' home positions in the device frame, ``M c_k``."""
        out: Mat = self.markers @ self.home[:3, :3].T + self.home[:3, 3]
        return out

    @property
    def n(self) -> int:
        return len(self.chain)

    @property
    def joints(self) -> tuple[Joint, ...]:
        """The joints as :class:`~urdf2dh.model.poe.Joint` objects (offsets not absorbed)."""
        return self.chain.joints()

    @property
    def scales(self) -> bool:
        """Whether the joints' scales are identified."""
        return self.level.scales

    def joint_offsets(self) -> Mat:
        """``(n,)`` the offsets (zeros when there are none)."""
        return np.zeros(self.n) if self.offsets is None else self.offsets

    def base_motion(self) -> Mat:
        """``(4, 4)`` the base motion applied so far (the identity without one)."""
        return np.eye(4) if self.base is None else self.base

    def with_level(self, level: Level, free: NDArray[np.bool_] | None = None) -> Estimate:
        """The same model, identified at ``level`` (offsets absorbed by the lines when the new
        level has no offsets of its own)."""
        est = self
        if not level.offsets and self.offsets is not None and self.offsets.any():
            est = absorbed(self)
        return Estimate(
            est.chain, est.home, est.markers, est.tool, level, est.keep_tool_axis, est.offsets,
            est.base, free,
        )  # fmt: skip

    def with_parts(
        self, chain: Chain, home: Mat, markers: Mat, offsets: Mat | None, base: Mat | None
    ) -> Estimate:
        """The same level, tool and free coordinates with the joints ``chain``, the tool at
        ``home``, ``markers``, ``offsets`` and the ``base`` motion (one constructor call, not
        :func:`dataclasses.replace`'s field by field copy: the solver makes one a step)."""
        return Estimate(
            chain, home, markers, self.tool, self.level, self.keep_tool_axis, offsets, base,
            self.free,
        )  # fmt: skip


def _joint_size(kind: str, level: Level) -> int:
    lines = LINE_PARAMETERS[kind] if level.lines else 0
    return lines + int(level.offsets) + int(level.scales)


def sizes(est: Estimate, every: bool = False) -> list[int]:
    """Coordinates per block: the base (0 or 6), one per joint, then the tool (or the markers).
    Counted over the level (``every``) or only the free ones."""
    tool = (2 if est.keep_tool_axis else 6) if est.tool == FRAME else 3 * len(est.markers)
    free = None if every or est.free is None else est.free.tobytes()
    return list(_sizes(est.level, est.chain.kinds, tool, free))


@lru_cache(maxsize=512)
def _sizes(level: Level, kinds: tuple[str, ...], tool: int, free: bytes | None) -> tuple[int, ...]:
    out = [6 if level.base else 0, *(_joint_size(k, level) for k in kinds), tool]
    if free is None:
        return tuple(out)
    mask = np.frombuffer(free, dtype=bool)
    edges = np.cumsum([0, *out])
    return tuple(int(np.sum(mask[a:b])) for a, b in itertools.pairwise(edges))


def count(est: Estimate) -> int:
    """Number of identified coordinates."""
    return sum(sizes(est))


def all_names(est: Estimate, marker_ids: list[int] | None = None) -> list[str]:
    """A name per coordinate of the level, e.g. ``base.rx``, ``j1.turn1``, ``j1.shift2``,
    ``j1.pitch``, ``j1.offset``, ``j1.scale``, ``tool.rx`` ... ``tool.z`` (body frame),
    ``marker0.x`` (device frame)."""
    out: list[str] = []
    if est.level.base:
        out += [f"base.{k}" for k in ("rx", "ry", "rz", "x", "y", "z")]
    for name, kind in zip(est.chain.names, est.chain.kinds, strict=True):
        if est.level.lines:
            if kind == "prismatic":
                out += [f"{name}.turn1", f"{name}.turn2"]
            else:
                out += [f"{name}.{k}" for k in ("turn1", "turn2", "shift1", "shift2")]
                if kind == "helical":
                    out.append(f"{name}.pitch")
        if est.level.offsets:
            out.append(f"{name}.offset")
        if est.level.scales:
            out.append(f"{name}.scale")
    if est.tool == FRAME:
        out += (
            ["tool.turn", "tool.slide"]
            if est.keep_tool_axis
            else [f"tool.{k}" for k in ("rx", "ry", "rz", "x", "y", "z")]
        )
    else:
        ids = marker_ids if marker_ids is not None else list(range(len(est.markers)))
        out += [f"marker{m}.{c}" for m in ids for c in "xyz"]
    return out


def names(est: Estimate, marker_ids: list[int] | None = None) -> list[str]:
    """The names of the identified coordinates (:func:`all_names`, the free ones)."""
    every = all_names(est, marker_ids)
    if est.free is None:
        return every
    return [n for n, f in zip(every, est.free, strict=True) if f]


def expand(est: Estimate, delta: Mat) -> Mat:
    """The free coordinates ``delta`` as the level's (zeros at the fixed ones)."""
    delta = np.asarray(delta, dtype=float)
    if est.free is None:
        return delta
    out = np.zeros(len(est.free))
    out[est.free] = delta
    return out


def line_motion(u: Mat, p: Mat, a: float, b: float, c: float, d: float) -> Mat:
    """``eta`` of the line chart (module docstring) of the line along ``u`` through ``p`` as a
    twist ``(6,)``."""
    e1, e2 = normal_basis(u)
    rho, tau = a * e1 + b * e2, c * e1 + d * e2
    return np.concatenate([rho, cross3(p, rho) + tau])


def tool_screws(est: Estimate) -> Mat:
    """``(6, 2)``: with ``keep_tool_axis`` (a tool frame), the last line's screws (turn about
    it, slide along it) in the tool's body frame: ``Ad(M^-1) [u, p x u]`` and
    ``Ad(M^-1) [0, u]``."""
    return _screws(est.chain, est.home)


def _screws(chain: Chain, home: Mat) -> Mat:
    """:func:`tool_screws` of the last line of ``chain`` with the tool at ``home``."""
    u, p = chain.axis[-1], chain.point[-1]
    twists = np.array([np.concatenate([u, cross3(p, u)]), np.concatenate([np.zeros(3), u])]).T
    r, t = home[:3, :3], home[:3, 3]
    w = r.T @ twists[:3]
    v = r.T @ (twists[3:] - np.cross(t[:, None], twists[:3], axis=0))
    return np.vstack([w, v])


def joint_columns(est: Estimate) -> tuple[NDArray[np.int64], ...]:
    """Where each joint coordinate sits in the level's coordinates: ``(line (n, 5), offset,
    scale)`` indices, -1 where a joint has none (line: turn1, turn2, shift1, shift2, pitch)."""
    return _columns_of(est.level, est.chain.kinds)


@lru_cache(maxsize=256)
def _columns_of(level: Level, kinds: tuple[str, ...]) -> tuple[NDArray[np.int64], ...]:
    n = len(kinds)
    line = np.full((n, 5), -1, dtype=np.int64)
    offset = np.full(n, -1, dtype=np.int64)
    scale = np.full(n, -1, dtype=np.int64)
    k = 6 if level.base else 0
    for i, kind in enumerate(kinds):
        if level.lines:
            width = 2 if kind == "prismatic" else 4
            line[i, :width] = np.arange(k, k + width)
            k += width
            if kind == "helical":
                line[i, 4] = k
                k += 1
        if level.offsets:
            offset[i] = k
            k += 1
        if level.scales:
            scale[i] = k
            k += 1
    for a in (line, offset, scale):
        a.setflags(write=False)
    return line, offset, scale


def retract(est: Estimate, delta: Mat) -> Estimate:
    """The estimate moved by the free coordinates ``delta`` (``(count,)``), re-centred."""
    x_all = expand(est, delta)
    level = est.level
    chain, home, base = est.chain, est.home, est.base
    if level.base:  # everything moves: the lines, the tool frame (and the markers with it)
        g = twist_exp(x_all[:6])
        chain, home, base = chain.moved(g), g @ home, g @ est.base_motion()
    before = chain  # the lines as the base left them
    line_at, offset_at, scale_at = joint_columns(est)
    padded = np.append(x_all, 0.0)  # indexed by joint_columns' -1: 0
    if level.scales:
        chain = chain.scaled(chain.scale + padded[scale_at])
    offsets = est.offsets
    if level.offsets:
        offsets = est.joint_offsets() + padded[offset_at]
    last_motion = None
    if level.lines:
        x = padded[line_at]  # (n, 5)
        e1, e2 = normal_bases(chain.axis)
        rho = x[:, :1] * e1 + x[:, 1:2] * e2
        rot, jac = exp_so3_left_jacobian(rho)  # (n, 3, 3) each
        axis = np.einsum("nij,nj->ni", rot, chain.axis)
        axis /= np.sqrt(np.add.reduce(axis * axis, axis=1, keepdims=True))
        tau = x[:, 2:3] * e1 + x[:, 3:4] * e2
        v = cross_rows(chain.point, rho) + tau
        shift = np.einsum("nij,nj->ni", jac, v)
        point = np.einsum("nij,nj->ni", rot, chain.point) + shift
        if est.keep_tool_axis:  # the tool moves with the last line
            last_motion = np.eye(4)
            last_motion[:3, :3] = rot[-1]
            last_motion[:3, 3] = shift[-1]
        if "prismatic" in chain.kinds:  # a sliding joint's point stays (its turn moves the
            point = np.where(chain.turning[:, None], point, chain.point)  # direction alone)
        chain = chain.placed(axis, point, chain.pitch + x[:, 4])
    k = sum(sizes(est, every=True)[:-1])
    markers = est.markers
    if est.tool == FRAME:
        if est.keep_tool_axis:
            zeta = _screws(before, home) @ x_all[k : k + 2]
            moved = home if last_motion is None else last_motion @ home
            home = moved @ twist_exp(zeta)
        else:
            home = home @ twist_exp(x_all[k : k + 6])
    else:  # device-frame moves of the markers' home positions
        markers = markers + x_all[k:].reshape(-1, 3) @ home[:3, :3]
    return est.with_parts(chain, home, markers, offsets, base)


_FIRST, _SECOND = np.array([0, 0, 1]), np.array([0, 1, 1])  # the products c1 c1, c1 c2, c2 c2


def line_coordinates(axis: Mat, point: Mat, other_axis: Mat, other_point: Mat) -> Mat:
    """``(n, 4)``: each line chart's coordinates (turn1, turn2, shift1, shift2) from the line
    ``(axis[i], point[i])`` to ``(other_axis[i], other_point[i])``, all lines at once (the turns
    alone are meaningful for a prismatic joint's direction): :attr:`LineCoordinates.values`."""
    return LineCoordinates.of(axis, point, other_axis, other_point).values


@dataclass(frozen=True, slots=True)
class LineCoordinates:
    """Lines' chart coordinates seen from reference lines, and what their derivatives by the
    lines' own charts are made of (:meth:`tangent`).

    The turn is the rotation vector ``rho`` taking ``u`` to ``u'`` about their common normal;
    the shifts ``tau`` make ``exp(eta) p = p + J(rho) tau`` (:func:`.lie.left_jacobian`) a point
    of the other line (least squares in the plane normal to it, closed form: two unknowns).

    Attributes
    ----------
    values
        ``(n, 4)`` turn1, turn2, shift1, shift2 of each line.
    axis, other_axis, other_point, point
        The reference lines' directions, the lines' directions and points, the reference
        lines' points ``(n, 3)``.
    basis
        ``(n, 3, 2)`` the reference charts' ``e1, e2`` (:func:`normal_bases`).
    cross, angle, ratio
        ``u x u'`` ``(n, 3)``, the angle between them and ``angle / sin(angle)`` ``(n,)``.
    rho, jacobian
        The turns as rotation vectors ``(n, 3)`` and ``J(rho)`` ``(n, 3, 3)``.
    cols
        ``(n, 3, 2)`` ``J(rho) e1, J(rho) e2`` with their parts along ``u'`` removed.
    normal
        ``(4, n)``: the normal equations' ``a, b, d`` (``[[a, b], [b, d]]``) and determinant.
    """

    values: Mat
    axis: Mat
    other_axis: Mat
    other_point: Mat
    point: Mat
    basis: Mat
    cross: Mat
    angle: Mat
    ratio: Mat
    rho: Mat
    jacobian: Mat
    cols: Mat
    normal: Mat

    @classmethod
    def of(cls, axis: Mat, point: Mat, other_axis: Mat, other_point: Mat) -> LineCoordinates:
        """The coordinates of the lines ``(other_axis[i], other_point[i])`` in the charts of
        ``(axis[i], point[i])`` (class docstring)."""
        e1, e2 = normal_bases(axis)
        cross = cross_rows(axis, other_axis)
        sin = np.sqrt(np.add.reduce(cross * cross, axis=1))
        angle = np.arctan2(sin, np.add.reduce(axis * other_axis, axis=1))
        ratio = np.divide(angle, sin, out=np.ones_like(sin), where=sin > 0.0)
        rho = cross * ratio[:, None]
        out = np.empty((len(axis), 4))
        basis = np.empty((len(axis), 3, 2))
        basis[:, :, 0], basis[:, :, 1] = e1, e2
        out[:, :2] = np.add.reduce(rho[:, :, None] * basis, axis=1)
        # the columns J(rho) e1, J(rho) e2 and the gap, each with its part along u' removed
        jacobian = left_jacobian(rho)
        cols = np.matmul(jacobian, basis)
        cols -= np.matmul(other_axis[:, None, :], cols) * other_axis[:, :, None]
        gap = other_point - point
        gap -= np.add.reduce(other_axis * gap, axis=1)[:, None] * other_axis
        # the normal equations' 2 x 2 system, by Cramer's rule
        normal = np.empty((4, len(axis)))
        normal[:3] = np.add.reduce(cols[:, :, _FIRST] * cols[:, :, _SECOND], axis=1).T
        a, b, d = normal[:3]
        g1, g2 = np.add.reduce(cols * gap[:, :, None], axis=1).T
        det = normal[3] = a * d - b * b
        if (det == 0.0).any():  # as LAPACK's solve: a singular system is an error, NaN flows on
            raise np.linalg.LinAlgError("Singular matrix")
        out[:, 2] = (d * g1 - b * g2) / det
        out[:, 3] = (a * g2 - b * g1) / det
        return cls(
            out, axis, other_axis, other_point, point, basis, cross, angle, ratio, rho,
            jacobian, cols, normal,
        )  # fmt: skip

    def tangent(self) -> Mat:
        """``(n, 4, 4)``: the derivatives of each line's :attr:`values` (rows) by its own chart
        coordinates at it (columns; :func:`retract`'s turn1, turn2, shift1, shift2 about its
        point ``p'``), the reference lines held.

        A turn along ``f`` (``f1, f2``: the line's :func:`normal_bases`) moves ``u'`` by
        ``du = f x u'`` about ``p'``; a shift moves ``p'`` by ``dp = f``. With ``w = u x u'``
        and ``t`` the angle, the turns' ``rho = (t / sin t) w`` move by
        ``drho = (t / sin t) (u x du) - h(t) (u . du) w``, ``h = (sin t - t cos t) / sin^3 t``
        (``u' . du = 0``). The shifts solve ``C tau = g`` with ``C = P J(rho) [e1 e2]``,
        ``g = P (p' - p)`` and ``P = I - u' u'^T``, exactly (both in the plane normal to
        ``u'``); differentiated and multiplied by ``C^T`` (``C^T u' = 0``):
        ``C^T C dtau = C^T (dp - (u' . (p' - q)) du - dJ[drho] v)`` with ``v = [e1 e2] tau``,
        ``q = p + J(rho) v`` the reference point moved onto the line, and, ``J = I + b S +
        c S^2`` (``S = [rho]``, ``V = [v]``), ``dJ[drho] v = -(b V + c (2 S V - V S)) drho +
        (rho . drho) S (b' v + c' S v) / t``.
        """
        n = len(self.axis)
        f1, f2 = normal_bases(self.other_axis)
        moves = np.empty((n, 3, 4))  # each chart direction's du (turns) or dp (shifts)
        moves[:, :, 0], moves[:, :, 1], moves[:, :, 2], moves[:, :, 3] = -f2, f1, f1, f2
        du = moves[:, :, :2]
        v = np.matmul(self.basis, self.values[:, 2:, None])  # (n, 3, 1)
        skews = skew_batch(np.concatenate((self.axis, self.rho, v[:, :, 0])))
        su, s, sv = skews[:n], skews[n : 2 * n], skews[2 * n :]
        h, db, dc, b, c = turn_coefficients(self.angle)[..., None, None].transpose(1, 0, 2, 3)
        drho = self.ratio[:, None, None] * su - h * self.cross[:, :, None] * self.axis[:, None]
        drho = drho @ du  # (n, 3, 2)
        ssv = s @ sv
        rv = s @ v
        dj = (db * rv + dc * (s @ rv)) @ self.rho[:, None] - b * sv - c * (ssv + ssv - sv @ s)
        moved = self.point[:, :, None] + self.jacobian @ v  # q
        slide = self.other_axis[:, None] @ (self.other_point[:, :, None] - moved)  # (n, 1, 1)
        moves[:, :, :2] = -slide * du - dj @ drho
        adjugate = self.normal[_ADJUGATE].T * (_ADJUGATE_SIGNS / self.normal[3, :, None])
        inverse = adjugate.reshape(n, 2, 2)  # of the normal equations' [[a, b], [b, d]]
        out = np.zeros((n, 4, 4))
        out[:, :2, :2] = self.basis.transpose(0, 2, 1) @ drho
        out[:, 2:] = inverse @ (self.cols.transpose(0, 2, 1) @ moves)
        return out


_ADJUGATE, _ADJUGATE_SIGNS = [2, 1, 1, 0], np.array([1.0, -1.0, -1.0, 1.0])  # d, -b, -b, a


def local_coordinates(est: Estimate, other: Estimate) -> Mat:
    """The free coordinates ``delta`` around ``est`` with ``retract(est, delta)`` equal to
    ``other`` (``other`` near ``est``, at the same level; to compare an identified model with the
    truth, or with the nominal)."""
    level = est.level
    full = np.zeros(sum(sizes(est, every=True)))
    base = np.eye(4)
    if level.base:
        base = other.base_motion() @ np.linalg.inv(est.base_motion())
        full[:6] = log_se3(base)
    a, b = est.chain, other.chain
    line_at, offset_at, scale_at = joint_columns(est)
    motion = np.eye(4)
    if level.lines and len(a):
        lines = line_coordinates(a.axis, a.point, b.axis, b.point)
        turning = a.turning
        width = np.where(turning, 4, 2)
        for k in range(4):
            rows = width > k
            full[line_at[rows, k]] = lines[rows, k]
        helical = line_at[:, 4] >= 0
        full[line_at[helical, 4]] = b.pitch[helical] - a.pitch[helical]
        if turning[-1]:
            motion = twist_exp(line_motion(a.axis[-1], a.point[-1], *lines[-1]))
    if level.offsets:
        full[offset_at] = other.joint_offsets() - est.joint_offsets()
    if level.scales:
        full[scale_at] = b.scale - a.scale
    k = sum(sizes(est, every=True)[:-1])
    if est.tool == FRAME:
        start = base @ est.home
        if est.keep_tool_axis:
            zeta = log_se3(np.linalg.inv(start) @ np.linalg.inv(motion) @ other.home)
            full[k:] = np.linalg.lstsq(tool_screws(est), zeta, rcond=None)[0]
        else:
            full[k:] = log_se3(np.linalg.inv(start) @ other.home)
    else:
        start_markers = est.device_markers() @ base[:3, :3].T + base[:3, 3]
        full[k:] = (other.device_markers() - start_markers).ravel()
    return full if est.free is None else full[est.free]


def absorbed(est: Estimate) -> Estimate:
    """The same motion with the joint offsets absorbed by the lines and the tool (offsets 0).

    With ``E_i = exp([xi_i] s_i o_i)`` and ``C_i = E_1 ... E_i``, ``exp([xi] s (q + o)) =
    exp([xi] s q) E`` and ``C exp([xi] q) = exp([Ad_C xi] q) C``: joint ``i + 1``'s line moves
    by ``C_i``, and ``M`` (or the markers) by ``C_n``.
    """
    offsets = est.joint_offsets()
    chain = est.chain
    n = len(chain)
    turning = chain.turning[:, None]
    u, p = chain.axis, chain.point
    angular = np.where(turning, u, 0.0)
    linear = np.where(turning, cross_rows(p, u) + chain.pitch[:, None] * u, u)
    motion = (chain.scale * offsets)[:, None]
    rot, jac = exp_so3_left_jacobian(angular * motion)
    each = np.zeros((n, 4, 4))  # E_i
    each[:, :3, :3] = rot
    each[:, :3, 3] = np.einsum("nij,nj->ni", jac, linear * motion)
    each[:, 3, 3] = 1.0
    before = np.empty((n + 1, 4, 4))  # C_0 = I, C_1, ..., C_n
    before[0] = np.eye(4)
    for i in range(n):
        np.matmul(before[i], each[i], out=before[i + 1])
    axis = np.einsum("nij,nj->ni", before[:-1, :3, :3], u)
    point = np.einsum("nij,nj->ni", before[:-1, :3, :3], p) + before[:-1, :3, 3]
    return est.with_parts(
        chain.placed(axis, point), before[-1] @ est.home, est.markers, None, est.base
    )
