"""The product-of-exponentials (POE) model shared by every other module.

A serial chain at its home pose is a list of screw axes in the base frame plus the home pose of
the tip (Brockett 1984; Wu 2019 eq. 5)::

    T(q) = exp([xi_1] q_1) ... exp([xi_n] q_n) M

Each joint is stored geometrically (unit direction, a point on the axis, pitch, scale), which is
what the conversions need and keeps full precision; :meth:`Joint.twist` gives the ``[w, v]``
twist (Wu's un-normalised ``xi = q_bar * xi_hat``).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from . import se3
from .trig import expi

__all__ = ["KINDS", "Joint", "JointKind", "JointMotion", "PoeModel", "joint_from_twist"]

JointKind = Literal["revolute", "prismatic", "helical"]
KINDS: tuple[str, ...] = ("revolute", "prismatic", "helical")

Vec = NDArray[np.float64]

FK_BLOCK = 8192  # configurations per block of the batched FK (two (16, 3, 8192) stacks, 6 MiB)
_ZERO_ROW = (0.0, 0.0, 0.0, 0.0)
_IDENTITY_ROWS = ((1.0, 0.0, 0.0, 0.0), (0.0, 1.0, 0.0, 0.0), (0.0, 0.0, 1.0, 0.0),
                  (0.0, 0.0, 0.0, 1.0))
_IDENTITY_T = np.eye(4)[:, :3, None]  # the identity pose as (F^T)[:, :3], for (4, 3, m) stacks


def _frozen(a: NDArray[np.float64] | None) -> NDArray[np.float64] | None:
    if a is None or (isinstance(a, np.ndarray) and a.dtype == np.float64
                     and not a.flags.writeable):
        return a  # None, or already immutable: shared as it is
    out = np.array(a, dtype=float)
    out.setflags(write=False)
    return out


class JointMotion:
    """What a joint's ``kind`` and ``pitch`` make of its motion ``Rz(rotation s) Tz(translation
    s)``: shared by a POE model's :class:`Joint` and a table's row."""

    kind: JointKind
    pitch: float

    @property
    def rotation(self) -> float:
        """Radians of rotation per unit of ``s`` (1 or 0)."""
        return 0.0 if self.kind == "prismatic" else 1.0

    @property
    def translation(self) -> float:
        """Length of translation along the axis per unit of ``s``."""
        return 1.0 if self.kind == "prismatic" else self.pitch


@dataclass(frozen=True, init=False)
class Joint(JointMotion):
    """One joint of the chain, at the home pose, in the base frame.

    Attributes
    ----------
    name
        Joint name (URDF joint name, or the POE file's).
    kind
        ``revolute`` (URDF ``revolute`` and ``continuous``), ``prismatic`` or ``helical``.
    axis
        ``(3,)`` unit direction of the joint's positive motion.
    point
        ``(3,)`` a point on the axis line. ``None`` only for a prismatic joint whose line
        location is free (POE sources): conversions then place it through the previous frame's
        origin (SPEC §3).
    pitch
        Helix pitch, length per radian of ``s`` (0 for revolute and prismatic joints).
    scale
        ``s = scale * q``: the motion variable per unit of the joint position ``q`` (Wu 2019's
        normalisation factor q_bar).
    lower, upper
        Joint position limits in ``q`` units, or ``None`` (continuous, or unknown).
    """

    name: str
    kind: JointKind
    axis: Vec
    point: Vec | None
    pitch: float = 0.0
    scale: float = 1.0
    lower: float | None = None
    upper: float | None = None

    def __init__(
        self,
        name: str,
        kind: JointKind,
        axis: Vec,
        point: Vec | None,
        pitch: float = 0.0,
        scale: float = 1.0,
        lower: float | None = None,
        upper: float | None = None,
    ) -> None:
        # the fields in one update of the instance's dict, where the generated __init__ of a
        # frozen dataclass calls object.__setattr__ once a field: a joint is made per joint of
        # every model, and this halves the time it takes
        vars(self).update(
            name=name, kind=kind, axis=_frozen(axis), point=_frozen(point), pitch=pitch,
            scale=scale, lower=lower, upper=upper,
        )

    def normalized_twist(self) -> Vec:
        """``xi_hat = [w, v]`` with ``|w| = 1`` (or ``w = 0, |v| = 1`` for prismatic)."""
        if self.kind == "prismatic":
            return np.concatenate([np.zeros(3), self.axis])
        assert self.point is not None  # revolute and helical joints always carry a point
        v = np.cross(self.point, self.axis) + self.pitch * self.axis
        return np.concatenate([self.axis, v])

    def twist(self) -> Vec:
        """The un-normalised twist ``xi = scale * xi_hat`` that multiplies ``q``."""
        return self.scale * self.normalized_twist()


def joint_from_twist(
    name: str,
    xi: NDArray[np.float64],
    noise: float,
    lower: float | None = None,
    upper: float | None = None,
) -> Joint:
    """Build a joint from a twist ``[w, v]`` of any scale (SPEC §4, Wu 2019 §II).

    For ``|w| > 0`` the scale is ``|w|`` and the pitch ``w.v / |w|^2``; the joint is revolute
    when the pitch is round-off (``|h| <= noise * |v| / |w|``), helical otherwise. For
    ``|w| <= noise`` the joint is prismatic with scale ``|v|``. Callers validate the twist
    (finite, not all zero) before calling.
    """
    xi = np.asarray(xi, dtype=float)
    w, v = xi[:3], xi[3:]
    nw, nv = float(np.linalg.norm(w)), float(np.linalg.norm(v))
    if nw <= noise:
        return Joint(name, "prismatic", v / nv, None, 0.0, nv, lower, upper)
    u = w / nw
    pitch = float(w @ v) / (nw * nw)
    point = np.cross(w, v) / (nw * nw)
    if abs(pitch) <= noise * nv / nw:
        return Joint(name, "revolute", u, point, 0.0, nw, lower, upper)
    return Joint(name, "helical", u, point, pitch, nw, lower, upper)


@dataclass(frozen=True, init=False)
class PoeModel:
    """A serial chain as screws at the home pose plus the tip's home pose.

    Attributes
    ----------
    joints
        The movable joints from base to tip.
    home
        ``(4, 4)`` pose of the tip frame in the base frame at ``q = 0`` (``M``).
    name, source, base_link, tip_link, length_unit
        Provenance, carried into every table made from the model.
    warnings
        Judgements made while building the model (ignored mimic relations, ...).
    """

    joints: tuple[Joint, ...]
    home: NDArray[np.float64]
    name: str = ""
    source: str = ""
    base_link: str = ""
    tip_link: str = ""
    length_unit: str = "m"
    warnings: tuple[str, ...] = field(default=())

    def __init__(
        self,
        joints: tuple[Joint, ...],
        home: NDArray[np.float64],
        name: str = "",
        source: str = "",
        base_link: str = "",
        tip_link: str = "",
        length_unit: str = "m",
        warnings: tuple[str, ...] = (),
    ) -> None:
        vars(self).update(  # in one update, as Joint's fields are
            joints=tuple(joints), home=_frozen(home), name=name, source=source,
            base_link=base_link, tip_link=tip_link, length_unit=length_unit,
            warnings=tuple(warnings),
        )

    @property
    def n(self) -> int:
        """Number of movable joints."""
        return len(self.joints)

    def twists(self) -> NDArray[np.float64]:
        """``(n, 6)`` un-normalised twists ``[w, v]``, one row per joint."""
        return np.array([j.twist() for j in self.joints]).reshape(-1, 6)

    def extent(self) -> float:
        """The robot's size: the largest distance from the base origin of any joint's axis
        point or of the tip at the home pose (0 for a chain that is all at the origin)."""
        return self._extent

    @cached_property
    def _extent(self) -> float:  # asked for several times per conversion
        return max(math.hypot(*p) for p in self._points[1:])

    def travel(self) -> float:
        """How far the joints can translate the tip along their axes: prismatic travel within
        the limits (within the extent where unknown) and helical advance over the rotation
        range (:meth:`limits`)."""
        lim = self._limits
        return float(sum(
            abs(j.translation * j.scale) * max(abs(lim[i][0]), abs(lim[i][1]))
            for i, j in enumerate(self.joints) if j.translation
        ))

    def size(self) -> float:
        """The length errors are measured against: the extent at home plus the travel of the
        sliding joints (or 1 for a chain that is all at the origin and cannot slide)."""
        return self._size

    @cached_property
    def _size(self) -> float:  # asked for several times per conversion
        e = self.extent() + self.travel()
        return e if e > 0.0 else 1.0

    def reach(self) -> float:
        """An upper bound on any point's distance from the base origin over all configurations
        within reach of the chain's geometry: the length of the polyline through the joint axis
        points and the tip (used to bound the effect of a tolerance judgement)."""
        return math.fsum(math.dist(a, b) for a, b in itertools.pairwise(self._points))

    @cached_property
    def _points(self) -> list[list[float]]:
        """The base origin, the joints' axis points and the tip's origin, as plain floats."""
        pts = [[0.0, 0.0, 0.0]]
        pts += [j.point.tolist() for j in self.joints if j.point is not None]
        pts.append(self.home[:3, 3].tolist())
        return pts

    def fk(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Pose ``(4, 4)`` of the tip for a configuration ``q`` of shape ``(n,)``; for a stack
        of shape ``(..., n)``, poses ``(..., 4, 4)`` (computed by :meth:`fk_batch`)."""
        return se3.fk_of_stack(self.fk_batch, q, self.n)

    @cached_property
    def _exponentials(self) -> tuple[NDArray[np.float64], list[tuple[slice, NDArray[np.float64]]]]:
        """Per joint ``(scale, rot, trans)``, ``(3, n)``; and per joint the terms its exponential
        uses (a slice of ``(sin, 1 - cos, trans s)``) with their transposed weights ``W^T``,
        ``(4, 4 + 4 k)``.

        ``X = [[u]x, p x u; 0, 0]`` is the 4x4 matrix of the joint's unit screw of zero pitch
        and ``E = [0, u; 0, 0]`` its translation along the axis; they commute (``X E = E X = 0``)
        and ``X^3 = -X``, so the exponential of a joint's motion is, in closed form (Rodrigues;
        Murray, Li & Sastry 1994, eq. 2.36)::

            exp(s) = I + sin(rot s) X + (1 - cos(rot s)) X^2 + (trans s) E

        ``W`` stacks ``I`` and the matrices of the terms used (``X``, ``X^2``, ``E``).
        """
        weights: list[float] = []  # flat: one array call for them all
        motion, uses = [], []
        for j in self.joints:
            rows = list(_IDENTITY_ROWS)
            if j.rotation:
                assert j.point is not None  # revolute and helical joints always carry a point
                (ux, uy, uz), (px, py, pz) = j.axis.tolist(), j.point.tolist()
                vx, vy, vz = py * uz - pz * uy, pz * ux - px * uz, px * uy - py * ux  # p x u
                wx, wy, wz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx  # u x v
                rows += [(0.0, -uz, uy, vx), (uz, 0.0, -ux, vy), (-uy, ux, 0.0, vz), _ZERO_ROW]
                rows += [  # X^2 = [[u u^T - |u|^2 I, u x v], [0, 0]]
                    (-(uy * uy + uz * uz), ux * uy, ux * uz, wx),
                    (uy * ux, -(ux * ux + uz * uz), uy * uz, wy),
                    (uz * ux, uz * uy, -(ux * ux + uy * uy), wz),
                    _ZERO_ROW,
                ]
            if j.translation:
                rows += [(0.0, 0.0, 0.0, c) for c in j.axis.tolist()] + [_ZERO_ROW]
            uses.append(slice(0 if j.rotation else 2, 3 if j.translation else 2))
            motion.append((j.scale, j.rotation, j.translation))
            rows += [_ZERO_ROW] * (16 - len(rows))
            weights.extend(itertools.chain.from_iterable(rows))
        stacked = np.fromiter(weights, float, len(weights)).reshape(-1, 16, 4).transpose(0, 2, 1)
        stacks = [(u, stacked[i, :, : 4 * (1 + u.stop - u.start)]) for i, u in enumerate(uses)]
        return np.array(motion, dtype=float).reshape(-1, 3).T, stacks  # W^T: F-ordered views

    def fk_batch(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Poses ``(N, 4, 4)`` of the tip for configurations ``q`` of shape ``(N, n)``.

        The screw exponentials in closed form (see ``_exponentials``), a block of ``m``
        configurations at a time, each pose held transposed and without its constant last row
        (``F^T[:, :3]``, shape ``(4, 3, m)``): a joint is one product of ``F`` with its terms,
        then one matrix product ``(F exp)^T = W^T @ [F; sin F; (1 - cos) F; t F]^T``.
        """
        q = se3.as_configurations(q, self.n)
        motion, stacks = self._exponentials
        count = q.shape[0]
        out = np.empty((count, 4, 4))
        buffers = np.empty((2, 16 * 3 * min(count, FK_BLOCK)))
        for lo in range(0, count, FK_BLOCK):
            m = min(lo + FK_BLOCK, count) - lo
            s = q[lo : lo + m].T * motion[0, :, None]  # (n, m)
            terms = np.empty((self.n, 3, m))  # per joint: sin, 1 - cos, trans s
            turns = np.empty((self.n, m), dtype=np.complex128)
            expi(s * motion[1, :, None], turns)  # cos + i sin
            terms[:, 0] = turns.imag
            np.subtract(1.0, turns.real, out=terms[:, 1])
            np.multiply(s, motion[2, :, None], out=terms[:, 2])
            # the stack [F; sin F; (1 - cos) F; t F]^T, as (4, 4, 3, m) and as (16, 3 m)
            (cur, cur2), (nxt, nxt2) = ((v.reshape(4, 4, 3, m), v.reshape(16, -1))
                                        for v in (buf[: 48 * m] for buf in buffers))
            cur[0] = _IDENTITY_T  # F^T of the identity
            for i, (used, w) in enumerate(stacks):
                k = used.stop - used.start
                np.multiply(cur[:1], terms[i, used, None, None, :], out=cur[1 : 1 + k])
                np.dot(w, cur2[: 4 + 4 * k], out=nxt2[:4])
                (cur, cur2), (nxt, nxt2) = (nxt, nxt2), (cur, cur2)
            f = self.home.T @ cur2[:4]
            out[lo : lo + m, :3] = f.reshape(4, 3, m).transpose(2, 1, 0)
            out[lo : lo + m, 3] = (0.0, 0.0, 0.0, 1.0)
        return out

    def link_form(self) -> tuple[list[se3.Frame], list[tuple[float, float]]]:
        """The same FK as ``n + 1`` constant links ``G`` and ``n`` joint motions (rotation,
        translation per unit of ``q``) with ``T(q) = G_0 Q_1(q_1) G_1 ... Q_n(q_n) G_n``,
        ``Q = Rz Tz``, as a table's FK is (:meth:`Table.link_form`).

        With ``C_i`` a frame whose z axis is joint ``i``'s axis line, ``exp(xi_i s) =
        C_i Rz(rot s) Tz(trans s) C_i^-1``, so ``G_0 = C_1``, ``G_i = C_i^-1 C_(i+1)`` and
        ``G_n = C_n^-1 M``. The self-check evaluates the model this way beside the table.
        """
        frames: list[se3.Frame] = []
        motions: list[tuple[float, float]] = []
        previous = se3.IDENTITY
        for j in self.joints:
            ux, uy, uz = j.axis.tolist()
            point = (0.0, 0.0, 0.0) if j.point is None else tuple(j.point.tolist())
            frame = se3.axis_frame((ux, uy, uz), point)
            frames.append(se3.between(previous, frame))
            motions.append((j.rotation * j.scale, j.translation * j.scale))
            previous = frame
        frames.append(se3.between(previous, se3.frame_of(self.home)))
        return frames, motions

    def scaled(self, factor: float, unit: str) -> PoeModel:
        """The same chain with lengths multiplied by ``factor`` and called ``unit`` (points,
        tip position, helix pitch; prismatic joints move ``factor`` times as far per ``q``)."""
        joints = tuple(
            Joint(j.name, j.kind, j.axis, None if j.point is None else factor * j.point,
                  factor * j.pitch, factor * j.scale if j.kind == "prismatic" else j.scale,
                  j.lower, j.upper)
            for j in self.joints
        )
        home = self.home.copy()
        home[:3, 3] *= factor
        return replace(self, joints=joints, home=home, length_unit=unit)

    def limits(self) -> NDArray[np.float64]:
        """``(n, 2)`` sampling ranges for ``q``: the joint limits where known, else
        ``[-pi, pi]`` for rotating joints and ``[-extent, extent]`` (in ``s``) for prismatic
        ones (``[-1, 1]`` for a chain that is all at the origin)."""
        return np.array(self._limits, dtype=float).reshape(-1, 2)

    @cached_property
    def _limits(self) -> list[tuple[float, float]]:  # asked for several times per conversion
        out = []
        size = self.extent() or 1.0
        for j in self.joints:
            if j.lower is not None and j.upper is not None and j.upper > j.lower:
                out.append((j.lower, j.upper))
            else:
                half = (size if j.kind == "prismatic" else math.pi) / abs(j.scale)
                out.append((-half, half))
        return out
