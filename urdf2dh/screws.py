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
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from . import se3

__all__ = ["KINDS", "Joint", "JointKind", "PoeModel", "joint_from_twist"]

JointKind = Literal["revolute", "prismatic", "helical"]
KINDS: tuple[str, ...] = ("revolute", "prismatic", "helical")

Vec = NDArray[np.float64]


def _frozen(a: NDArray[np.float64] | None) -> NDArray[np.float64] | None:
    if a is None:
        return None
    out = np.array(a, dtype=float)
    out.setflags(write=False)
    return out


@dataclass(frozen=True)
class Joint:
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

    def __post_init__(self) -> None:
        object.__setattr__(self, "axis", _frozen(self.axis))
        object.__setattr__(self, "point", _frozen(self.point))

    @property
    def rotation(self) -> float:
        """Radians of rotation per unit of ``s`` (1 or 0)."""
        return 0.0 if self.kind == "prismatic" else 1.0

    @property
    def translation(self) -> float:
        """Length of translation along the axis per unit of ``s``."""
        return 1.0 if self.kind == "prismatic" else self.pitch

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


@dataclass(frozen=True)
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

    def __post_init__(self) -> None:
        object.__setattr__(self, "joints", tuple(self.joints))
        object.__setattr__(self, "home", _frozen(self.home))
        object.__setattr__(self, "warnings", tuple(self.warnings))

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
        pts = [j.point for j in self.joints if j.point is not None]
        pts.append(self.home[:3, 3])
        return float(max(np.linalg.norm(p) for p in pts))

    def travel(self) -> float:
        """How far the joints can translate the tip along their axes: prismatic travel within
        the limits (within the extent where unknown) and helical advance over the rotation
        range (:meth:`limits`)."""
        lim = self.limits()
        return float(sum(
            abs(j.translation * j.scale) * float(np.abs(lim[i]).max())
            for i, j in enumerate(self.joints) if j.translation
        ))

    def size(self) -> float:
        """The length errors are measured against: the extent at home plus the travel of the
        sliding joints (or 1 for a chain that is all at the origin and cannot slide)."""
        e = self.extent() + self.travel()
        return e if e > 0.0 else 1.0

    def reach(self) -> float:
        """An upper bound on any point's distance from the base origin over all configurations
        within reach of the chain's geometry: the length of the polyline through the joint axis
        points and the tip (used to bound the effect of a tolerance judgement)."""
        pts = [np.zeros(3)] + [j.point for j in self.joints if j.point is not None]
        pts.append(self.home[:3, 3])
        return float(sum(np.linalg.norm(b - a) for a, b in itertools.pairwise(pts)))

    def fk(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Pose of the tip for one configuration ``q`` of shape ``(n,)``."""
        return self.fk_batch(se3.as_configurations(q, self.n))[0]

    def fk_batch(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Poses ``(N, 4, 4)`` of the tip for configurations ``q`` of shape ``(N, n)``."""
        q = se3.as_configurations(q, self.n)
        out = np.broadcast_to(np.eye(4), (q.shape[0], 4, 4)).copy()
        zero = np.zeros(3)
        for i, j in enumerate(self.joints):
            point = zero if j.point is None else j.point
            g = se3.line_screw_batch(j.axis, point, j.rotation, j.translation, j.scale * q[:, i])
            out = out @ g
        return out @ self.home

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
        return PoeModel(joints, home, self.name, self.source, self.base_link, self.tip_link,
                        unit, self.warnings)

    def limits(self) -> NDArray[np.float64]:
        """``(n, 2)`` sampling ranges for ``q``: the joint limits where known, else
        ``[-pi, pi]`` for rotating joints and ``[-extent, extent]`` (in ``s``) for prismatic
        ones (``[-1, 1]`` for a chain that is all at the origin)."""
        out = np.empty((self.n, 2))
        size = self.extent() or 1.0
        for i, j in enumerate(self.joints):
            if j.lower is not None and j.upper is not None and j.upper > j.lower:
                out[i] = (j.lower, j.upper)
            elif j.kind == "prismatic":
                out[i] = (-size / abs(j.scale), size / abs(j.scale))
            else:
                out[i] = (-math.pi / abs(j.scale), math.pi / abs(j.scale))
        return out
