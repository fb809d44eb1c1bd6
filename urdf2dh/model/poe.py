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
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any, Literal, TypeVar, cast

import numpy as np
from numpy.typing import NDArray

from ..checks import (
    check_array,
    check_configurations,
    check_count,
    check_instance,
    check_limit,
    check_real,
    check_seed,
)
from ..errors import InputError, shown, visible
from ..escape import markdown_table, markdown_text, text_table
from ..geometry import frames, se3
from ..tolerances import JOINT_POSITIONS, RIGID_INPUT, SMALLEST_SIZE
from ..units import DECIMALS, fixed
from . import _draw
from ._fastfk import chain_fk
from .mimic import Mimic, actuated, row_positions

__all__ = [
    "KINDS",
    "Joint",
    "JointKind",
    "JointMotion",
    "PoeModel",
    "check_motion",
    "joint_from_twist",
]

JointKind = Literal["revolute", "prismatic", "helical"]
KINDS: tuple[str, ...] = ("revolute", "prismatic", "helical")

Vec = NDArray[np.float64]
_T = TypeVar("_T")


def _frozen(a: object, shape: tuple[int, ...], where: str) -> NDArray[np.float64]:
    """``a`` as a read-only finite float64 array of ``shape`` (shared as it is if it already is
    one)."""
    if isinstance(a, np.ndarray) and a.dtype == np.float64 and not a.flags.writeable:
        return check_array(a, shape, where)
    out = np.array(check_array(a, shape, where))
    out.setflags(write=False)
    return out


def check_motion(joint: Any, where: str) -> None:
    """The fields a joint and a table row share, as their constructors take them: a name, a
    known kind, finite pitch and non-zero scale, finite limits, a :class:`Mimic`."""
    check_instance(joint.name, str, f"{where}: name")
    if joint.kind not in KINDS:
        raise ValueError(f"{where}: kind must be one of {', '.join(KINDS)}, not {joint.kind!r}")
    object.__setattr__(joint, "pitch", check_real(joint.pitch, f"{where}: pitch"))
    if not check_real(joint.scale, f"{where}: scale"):
        raise ValueError(f"{where}: scale must not be 0 (s = scale q)")
    object.__setattr__(joint, "scale", float(joint.scale))
    # limits out of order are kept as the source has them (sampling then ignores them)
    object.__setattr__(joint, "lower", check_limit(joint.lower, f"{where}: lower"))
    object.__setattr__(joint, "upper", check_limit(joint.upper, f"{where}: upper"))
    mimic = joint.mimic
    if mimic is not None:
        check_instance(mimic, Mimic, f"{where}: mimic", "urdf2dh.model.mimic.Mimic(joint, m, o)")


class JointMotion:
    """What a joint's ``kind`` and ``pitch`` make of its motion ``Rz(rotation s) Tz(translation
    s)``: shared by a POE model's :class:`Joint` and a table's row."""

    __slots__ = ()
    kind: JointKind
    pitch: float
    lower: float | None
    upper: float | None
    mimic: Mimic | None

    def file_fields(self) -> dict[str, Any]:
        """The joint's ``limits`` (when both are set) and ``mimic`` as table and POE model
        files write them."""
        out: dict[str, Any] = {}
        if self.lower is not None and self.upper is not None:
            out["limits"] = [float(self.lower), float(self.upper)]
        if self.mimic is not None:
            m = self.mimic
            out["mimic"] = {"joint": m.joint, "multiplier": m.multiplier, "offset": m.offset}
        return out

    @property
    def rotation(self) -> float:
        """Radians of rotation per unit of ``s`` (1 or 0)."""
        return 0.0 if self.kind == "prismatic" else 1.0

    @property
    def translation(self) -> float:
        """Length of translation along the axis per unit of ``s``."""
        return 1.0 if self.kind == "prismatic" else self.pitch


@dataclass(frozen=True, slots=True)
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
        origin (docs/conventions/dh.md).
    pitch
        Helix pitch, length per radian of ``s`` (0 for revolute and prismatic joints).
    scale
        ``s = scale * q``: the motion variable per unit of the joint position ``q`` (Wu 2019's
        normalisation factor q_bar).
    lower, upper
        Joint position limits in ``q`` units, or ``None`` (continuous, or unknown).
    mimic
        Whom the joint follows, if it is not actuated on its own.
    """

    name: str
    kind: JointKind
    axis: Vec
    point: Vec | None
    pitch: float = 0.0
    scale: float = 1.0
    lower: float | None = None
    upper: float | None = None
    mimic: Mimic | None = None

    def __post_init__(self) -> None:
        where = f"joint {shown(self.name)}" if isinstance(self.name, str) else "Joint"
        check_motion(self, where)
        axis = _frozen(self.axis, (3,), f"{where}: axis")
        norm = math.hypot(*axis.tolist())
        if abs(norm - 1.0) > RIGID_INPUT:
            raise ValueError(f"{where}: axis must be a unit vector, not of length {norm!r}")
        object.__setattr__(self, "axis", axis)
        if self.point is None and self.kind != "prismatic":
            raise ValueError(f"{where}: a {self.kind} joint needs a point")
        if self.point is not None:
            object.__setattr__(self, "point", _frozen(self.point, (3,), f"{where}: point"))

    def normalized_twist(self) -> Vec:
        """``xi_hat = [w, v]`` with ``|w| = 1`` (or ``w = 0, |v| = 1`` for prismatic)."""
        if self.point is None or self.kind == "prismatic":
            return np.concatenate([np.zeros(3), self.axis])
        v = np.cross(self.point, self.axis) + self.pitch * self.axis
        return np.concatenate([self.axis, v])

    def twist(self) -> Vec:
        """The un-normalised twist ``xi = scale * xi_hat`` that multiplies ``q``."""
        return self.scale * self.normalized_twist()


@dataclass(frozen=True, slots=True)
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
    warnings: tuple[str, ...] = ()
    # figures derived from the frozen fields, each computed once (size and limits are asked
    # for by every table made from the model, its check and every export)
    _derived: dict[str, object] = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "joints", tuple(self.joints))
        for i, j in enumerate(self.joints):
            check_instance(j, Joint, f"PoeModel: joints[{i}]")
        home = _frozen(self.home, (4, 4), "PoeModel: home")
        if home[3].tolist() != [0.0, 0.0, 0.0, 1.0] or not np.allclose(
            home[:3, :3].T @ home[:3, :3], np.eye(3), rtol=0.0, atol=RIGID_INPUT
        ):
            raise ValueError("PoeModel: home must be a rigid transform (R^T R = I, last row 0001)")
        object.__setattr__(self, "home", home)
        for name in ("name", "source", "base_link", "tip_link", "length_unit"):
            check_instance(getattr(self, name), str, f"PoeModel: {name}")
        object.__setattr__(self, "warnings", tuple(self.warnings))
        leaders = {j.name for j in self.joints if j.mimic is None}
        for j in self.joints:
            if j.mimic is not None and j.mimic.joint not in leaders:
                raise ValueError(
                    f"joint {shown(j.name)} mimics {shown(j.mimic.joint)}, not an actuated joint "
                    "of the chain"
                )

    def _repr_markdown_(self) -> str:
        """In a notebook: the joints as a table (axis, a point on it, pitch, scale, limits,
        whom a joint mimics) and the tip's home pose; names escaped."""
        title, head, body, after = self._layout(markdown_text)
        out = [f"**{title[0]}**{title[1]}", "", *markdown_table(head, body, 3), ""]
        return "\n".join([*out, *after[:1], *(f"- {w}" for w in after[1:])]) + "\n"

    def __str__(self) -> str:
        """The model as a person reads it: its joints as a table and the tip's home pose."""
        title, head, body, after = self._layout(visible)
        used = [i for i in range(len(head)) if i < 3 or any(row[i] for row in body)]
        head, body = [head[i] for i in used], [[row[i] for i in used] for row in body]
        out = ["".join(title), "", *text_table(head, body, 3), ""]
        return "\n".join([*out, *after[:1], *(f"warning: {w}" for w in after[1:])]) + "\n"

    def __repr__(self) -> str:
        chain = f" ({self.base_link} -> {self.tip_link})" if self.base_link else ""
        return f"<PoeModel {shown(self.name)}{visible(chain)}, {self.n} joints>"

    def _layout(
        self, text: Callable[[str], str]
    ) -> tuple[tuple[str, str], list[str], list[list[str]], list[str]]:
        """The title (name, the rest), the joints' table and the lines after it (the tip's
        home pose, then each warning) with names as ``text`` writes them."""
        unit = self.length_unit
        places = DECIMALS.get(unit, 6)

        def vector(v: NDArray[np.float64] | None, decimals: int) -> str:
            return "" if v is None else "(" + ", ".join(fixed(float(x), decimals) for x in v) + ")"

        head = ["", "joint", "type", "axis", f"point [{text(unit)}]", f"pitch [{text(unit)}/rad]",
                "scale", "limits", "mimics (q = m q_leader + o)"]  # fmt: skip
        body = []
        for i, j in enumerate(self.joints, 1):
            limits = "" if j.lower is None or j.upper is None else f"[{j.lower:.6g}, {j.upper:.6g}]"
            m = j.mimic
            follows = "" if m is None else f"{text(m.joint)} m={m.multiplier:g} o={m.offset:g}"
            body.append([str(i), text(j.name), j.kind, vector(j.axis, 6), vector(j.point, places),
                         f"{j.pitch:.6g}" if j.kind == "helical" else "", f"{j.scale:.8g}",
                         limits, follows])  # fmt: skip
        chain = f" {text(self.base_link)} -> {text(self.tip_link)}" if self.base_link else ""
        title = (text(self.name or "POE model"), f"{chain}: POE model, {self.n} joints")
        home = self.home
        after = [f"tip at home: origin {vector(home[:3, 3], places)} {text(unit)}, z axis "
                 f"{vector(home[:3, 2], 6)}", *(text(w) for w in self.warnings)]  # fmt: skip
        return title, head, body, after

    def _once(self, key: str, compute: Callable[[], _T]) -> _T:
        """``compute()``, computed once for this model (its fields are frozen)."""
        if key not in self._derived:
            self._derived[key] = compute()
        return cast(_T, self._derived[key])

    @property
    def n(self) -> int:
        """Number of movable joints (the mimicking ones included)."""
        return len(self.joints)

    @property
    def dof(self) -> int:
        """Number of actuated joints: the length of a configuration ``q``."""
        return len(actuated(self.joints))

    def twists(self) -> NDArray[np.float64]:
        """``(n, 6)`` un-normalised twists ``[w, v]``, one row per joint."""
        return np.array([j.twist() for j in self.joints]).reshape(-1, 6)

    def _points(self) -> list[list[float]]:
        """The base origin, the joints' axis points and the tip's origin, as plain floats."""
        pts = [[0.0, 0.0, 0.0]]
        pts += [j.point.tolist() for j in self.joints if j.point is not None]
        pts.append(self.home[:3, 3].tolist())
        return pts

    def extent(self) -> float:
        """The largest distance from the base origin of any joint's axis point or of the tip at
        the home pose (0 for a chain that is all at the origin)."""
        return self._once("extent", lambda: max(math.hypot(*p) for p in self._points()[1:]))

    def travel(self) -> float:
        """How far the joints can translate the tip along their axes: prismatic travel within
        the limits (within the extent where unknown) and helical advance over the rotation
        range (:meth:`limits`; a mimicking joint's range follows its leader's)."""
        lim = row_positions(self.joints, self.limits().T).T  # (n, 2): each joint's range ends
        return float(sum(
            abs(j.translation * j.scale) * max(abs(lim[i, 0]), abs(lim[i, 1]))
            for i, j in enumerate(self.joints) if j.translation
        ))  # fmt: skip

    def size(self) -> float:
        """The robot's size, which errors and the conversions' tolerances are measured against
        (docs/commands/index.md, "Robot size"): :meth:`own_size`, or the size the model was
        given by :meth:`sized` (a table's POE model: the size of the table's source)."""
        return self._once("size", self.own_size)

    def own_size(self) -> float:
        """The size of this model's geometry: the extent at home plus the travel of the sliding
        joints (1 for a chain that is all at the origin and cannot slide, within
        :data:`~urdf2dh.tolerances.SMALLEST_SIZE`)."""
        e = self.extent() + self.travel()
        return e if e >= SMALLEST_SIZE else 1.0

    def sized(self, size: float) -> PoeModel:
        """The same model with :meth:`size` ``size``: the size of the robot it describes where
        that is known apart from this model's geometry. :meth:`urdf2dh.Table.to_poe` gives its
        model the table's size (its source's): the model's axis points are the table's frame
        origins, elsewhere on the same axes than the source's, so :meth:`own_size` differs, and
        a conversion of it would decide the tolerances relative to size otherwise than the
        table's did. :meth:`named` keeps the size and :meth:`scaled` scales it; a model made
        from this one otherwise (``dataclasses.replace``) computes its own size again.

        Raises
        ------
        TypeError, ValueError
            ``size`` not a positive finite number.
        """
        if not check_real(size, "PoeModel.sized: size") > 0.0:
            raise ValueError(f"PoeModel.sized: size must be positive, not {size!r}")
        out = replace(self)
        out._derived["size"] = float(size)
        return out

    def named(self, name: str) -> PoeModel:
        """The same model called ``name``: what depends on its geometry (:meth:`size`, given
        by :meth:`sized` or not) kept.

        Raises
        ------
        TypeError
            ``name`` not a string.
        """
        check_instance(name, str, "PoeModel.named: name")
        out = replace(self, name=name)
        out._derived.update(self._derived)
        return out

    def reach(self) -> float:
        """An upper bound on any point's distance from the base origin over all configurations:
        the length of the polyline through the joint axis points and the tip (used to bound the
        effect of a tolerance judgement)."""
        return math.fsum(math.dist(a, b) for a, b in itertools.pairwise(self._points()))

    def limits(self) -> NDArray[np.float64]:
        """``(dof, 2)`` sampling ranges for ``q``, one row per actuated joint: the joint limits
        where known, else ``[-pi, pi]`` for rotating joints and ``[-extent, extent]`` (in ``s``)
        for prismatic ones (``[-1, 1]`` for a chain that is all at the origin); read-only."""
        return self._once("limits", self._limits)

    def sample(self, count: int, seed: int | tuple[int, ...] = 0) -> NDArray[np.float64]:
        """``(count, dof)`` actuated joint positions drawn uniformly within :meth:`limits`,
        seeded (``numpy.random.default_rng(seed)``; a tuple seed names a separate stream).

        Raises
        ------
        InputError
            More than :data:`~urdf2dh.tolerances.JOINT_POSITIONS` positions in all.
        TypeError, ValueError
            ``count`` not an integer from 1 to :data:`~urdf2dh.tolerances.MAX_SAMPLES`, or a
            ``seed`` that is not a non-negative integer (or a tuple of them).
        """
        check_count(count, "PoeModel.sample: count")
        for part in seed if isinstance(seed, tuple) else (seed,):
            check_seed(part, "PoeModel.sample: seed")
        if count * max(self.dof, 1) > JOINT_POSITIONS:
            raise InputError(
                f"{self.source or self.name}: {count:,} configurations of {self.dof:,} joints "
                f"are more than {JOINT_POSITIONS:,} joint positions, the most one run evaluates "
                f"(at most {JOINT_POSITIONS // max(self.dof, 1):,} configurations of this chain)"
            )
        lim = self.limits()
        return _draw.uniform(lim[:, 0], lim[:, 1], count, seed)

    def _limits(self) -> NDArray[np.float64]:
        drivers = [self.joints[i] for i in actuated(self.joints)]
        out = np.empty((len(drivers), 2))
        extent = self.extent() or 1.0
        for i, j in enumerate(drivers):
            if j.lower is not None and j.upper is not None and j.upper > j.lower:
                out[i] = (j.lower, j.upper)
            else:
                half = (extent if j.kind == "prismatic" else math.pi) / abs(j.scale)
                out[i] = (-half, half)
        out.setflags(write=False)
        return out

    def link_form(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The FK as links ``G_0 .. G_n`` ``(n + 1, 4, 4)`` and motions ``(n, 2)`` (rotation,
        translation per unit of ``q``): ``T(q) = G_0 Q_1(q_1) G_1 ... Q_n(q_n) G_n`` with
        ``Q = Rz Tz``, as a table's FK is (:mod:`urdf2dh.model.fk`).

        With ``C_i`` a frame whose z axis is joint ``i``'s axis line, ``exp(xi_i s) =
        C_i Rz(rot s) Tz(trans s) C_i^-1``, so ``G_0 = C_1``, ``G_i = C_i^-1 C_(i+1)`` and
        ``G_n = C_n^-1 M``.
        """
        links: list[frames.Frame] = []
        motions: list[tuple[float, float]] = []
        previous = frames.IDENTITY
        for j in self.joints:
            point = (0.0, 0.0, 0.0) if j.point is None else j.point.tolist()
            ux, uy, uz = j.axis.tolist()
            frame = frames.axis_frame((ux, uy, uz), point)
            links.append(frames.between(previous, frame))
            motions.append((j.rotation * j.scale, j.translation * j.scale))
            previous = frame
        links.append(frames.between(previous, frames.frame_of(self.home)))
        return se3.stack(links), np.array(motions, dtype=float).reshape(-1, 2)

    def positions(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Every joint's position ``(N, n)`` for configurations ``q`` ``(N, dof)`` (finite
        numbers; ``ValueError`` or ``TypeError`` otherwise)."""
        q = check_configurations(q, self.dof, "PoeModel.positions: q", batch=True)
        return row_positions(self.joints, se3.as_configurations(q, self.dof))

    def fk_batch(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Poses ``(N, 4, 4)`` of the tip for configurations ``q`` of shape ``(N, dof)`` (large
        batches by the fast path, :mod:`urdf2dh.model._fastfk`); finite numbers only."""
        q = check_configurations(q, self.dof, "PoeModel.fk_batch: q", batch=True)
        return self._fk_batch(q)

    def _fk_batch(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        positions = row_positions(self.joints, se3.as_configurations(q, self.dof))
        return chain_fk(*self.link_form(), positions)

    def fk(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Pose ``(4, 4)`` of the tip for a configuration ``q`` of shape ``(dof,)``; for a
        stack of shape ``(..., dof)``, poses ``(..., 4, 4)``; finite numbers only."""
        q = check_configurations(q, self.dof, "PoeModel.fk: q")
        return se3.fk_of_stack(self._fk_batch, q, self.dof)

    def scaled(self, factor: float, unit: str) -> PoeModel:
        """The same chain with lengths multiplied by ``factor`` and called ``unit`` (points,
        tip position, helix pitch, a size given by :meth:`sized`; prismatic joints move
        ``factor`` times as far per ``q``)."""
        if not check_real(factor, "PoeModel.scaled: factor") > 0.0:
            raise ValueError(f"PoeModel.scaled: factor must be positive, not {factor!r}")
        check_instance(unit, str, "PoeModel.scaled: unit")
        joints = tuple(
            replace(
                j,
                point=None if j.point is None else factor * j.point,
                pitch=factor * j.pitch,
                scale=factor * j.scale if j.kind == "prismatic" else j.scale,
            )
            for j in self.joints
        )
        home = self.home.copy()
        home[:3, 3] *= factor
        out = replace(self, joints=joints, home=home, length_unit=unit)
        given = self.size() != self.own_size()  # by :meth:`sized`: it scales with the lengths
        return out.sized(factor * self.size()) if given else out


def joint_from_twist(
    name: str,
    xi: NDArray[np.float64],
    noise: float,
    lower: float | None = None,
    upper: float | None = None,
) -> Joint:
    """Build a joint from a twist ``[w, v]`` of any scale (Wu 2019 §II).

    For ``|w| > 0`` the scale is ``|w|`` and the pitch ``w.v / |w|^2``; the joint is revolute
    when the pitch is round-off (``|h| <= noise * |v| / |w|``), helical otherwise. For
    ``|w| <= noise`` the joint is prismatic with scale ``|v|``. A scale within ``noise`` of 1 is
    1: a unit twist written with its direction's last bit of round-off reads back as itself (a
    unit scale is what most controllers require). Callers validate the twist (finite, not all
    zero) before calling.
    """
    xi = np.asarray(xi, dtype=float)
    w, v = xi[:3], xi[3:]
    nw, nv = float(np.linalg.norm(w)), float(np.linalg.norm(v))
    if nw <= noise:
        scale = 1.0 if abs(nv - 1.0) <= noise else nv
        return Joint(name, "prismatic", v / nv, None, 0.0, scale, lower, upper)
    u = w / nw
    pitch = float(w @ v) / (nw * nw)
    point = np.cross(w, v) / (nw * nw)
    scale = 1.0 if abs(nw - 1.0) <= noise else nw
    if abs(pitch) <= noise * nv / nw:
        return Joint(name, "revolute", u, point, 0.0, scale, lower, upper)
    return Joint(name, "helical", u, point, pitch, scale, lower, upper)
