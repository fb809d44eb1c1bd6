"""OPW kinematics: the parameters of a 6R arm with an ortho-parallel base and a spherical wrist,
their forward kinematics, and how they are read off a chain's screws.

The model of Brandstötter, Angerer & Hofbaur ("An analytical solution of the inverse kinematics
problem of industrial serial manipulators with an ortho-parallel basis and a spherical wrist",
Austrian Robotics Workshop 2014), as ``opw_kinematics`` (MoveIt, Tesseract) and
``rs-opw-kinematics`` evaluate it, with OPW joint angles ``theta_i = sign_i q_i - offset_i``::

    F(theta) = Rz(t1) T(a1, 0, c1) Ry(t2) Tz(c2) Ry(t3) T(a2, b, c3) Rz(t4) Ry(t5) Rz(t6) Tz(c4)

At ``theta = 0`` the arm stands upright in OPW's base frame: axis 1 is its z axis; axes 2 and 3
point along y, ``a1`` in front of axis 1 at heights ``c1`` and ``c1 + c2``; axis 4 is vertical,
``a2`` in front of axis 3 and ``b`` beside axis 1; axes 4, 5 (along y) and 6 meet in the wrist
centre ``(a1 + a2, b, c1 + c2 + c3)``; the flange is ``c4`` above it, turned as the base.

:func:`opw_from_poe` reads the OPW arrangement off the axis lines at the home pose (the POE model's
screws), not from the URDF's text: axis 1 perpendicular to axis 2, axes 2 and 3 parallel (and
apart), axis 3 perpendicular to axis 4, and axes 4, 5, 6 meeting in one point at right angles, each
within the tolerances (``parallel_angle`` for the angles, ``intersect_distance`` for the meeting
point); the first that fails is named.

It then chooses the frames so that the parameters need the least of the two transforms OPW does
not hold, ``pose(q) = B . F(theta) . T``. OPW's base z is axis 1, pointing to the side of the
chain's base z, with its origin nearest the base origin and its x nearest the base x (so ``B``
is the identity when the base z lies on axis 1). Of the two mirror images, ``a1 >= 0`` (or, with
``a1 = 0``, the one with the least joint-1 offset); ``c2, c3 >= 0`` (each link points from one
axis to the next); ``c4 >= 0`` (the flange lies beyond the wrist centre); joint 4's zero is the
one with the least offset, and joint 6's offset absorbs the tip's turn about axis 6, so ``T`` is
the identity when the tip sits on axis 6 facing along it. Signs are +1 where the joint's own axis
points as OPW's; offsets map the source's zero to OPW's (``theta = sign q - offset``), in
``(-pi, pi]``. The result is checked against the source's forward kinematics.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from ..errors import ConversionError, ExportError, Remedy, shown
from ..geometry.frames import unit, wrap_angle
from ..geometry.se3 import pose_errors
from ..model.poe import PoeModel
from ..tolerances import DEFAULT, Tolerances

__all__ = [
    "GEOMETRY",
    "JOINT_NAMES",
    "OpwParameters",
    "opw_fk",
    "opw_from_poe",
    "opw_to_poe",
    "rotations_y",
    "rotations_z",
]

Mat = NDArray[np.float64]
CHECK_SAMPLES, JUDGED_SAMPLES = 100, 1000  # as the tables' self-check (convert.py)
GEOMETRY = ("a1", "a2", "b", "c1", "c2", "c3", "c4")


@dataclass(frozen=True, slots=True)
class OpwParameters:
    """An arm in OPW's terms: ``pose(q) = base . F(sign q - offsets) . tool`` (module doc).

    Lengths (``a1`` ... ``c4``, the translations of ``base`` and ``tool``) in the source's unit;
    ``offsets`` in radians; ``signs`` +1 or -1; ``base`` and ``tool`` are 4x4 transforms.
    ``check`` is ``(samples, worst position error, worst rotation error)`` of :func:`opw_fk`
    against the source; ``warnings`` the judgements made and the deviation they cost.
    """

    a1: float
    a2: float
    b: float
    c1: float
    c2: float
    c3: float
    c4: float
    offsets: tuple[float, ...]
    signs: tuple[int, ...]
    base: Mat
    tool: Mat
    check: tuple[int, float, float] = (0, 0.0, 0.0)
    warnings: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        if len(self.offsets) != 6 or len(self.signs) != 6:
            raise ValueError("OPW has six joint offsets and six sign corrections")
        if any(s not in (1, -1) for s in self.signs):
            raise ValueError(f"sign corrections must be 1 or -1, not {self.signs}")
        values = [*self.geometry().values(), *self.offsets]
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f"non-finite OPW parameter in {values}")
        for name in ("base", "tool"):
            m = np.array(getattr(self, name), dtype=float)
            if m.shape != (4, 4):
                raise ValueError(f"{name} must be a 4x4 transform, not shape {m.shape}")
            m.flags.writeable = False
            object.__setattr__(self, name, m)

    def geometry(self) -> dict[str, float]:
        """``{a1, a2, b, c1, c2, c3, c4}``."""
        return {k: getattr(self, k) for k in GEOMETRY}

    def fk_batch(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Poses ``(N, 4, 4)`` of the chain's tip for joint positions ``q`` ``(N, 6)``."""
        theta = np.asarray(q, dtype=float) * np.array(self.signs) - np.array(self.offsets)
        return self.base @ opw_fk(self, theta) @ self.tool


def rotations_z(t: Mat) -> Mat:
    """``Rz(t)`` ``(..., 3, 3)`` for angles ``t`` of any shape."""
    c, s, z, o = np.cos(t), np.sin(t), np.zeros_like(t), np.ones_like(t)
    return np.stack([c, -s, z, s, c, z, z, z, o], axis=-1).reshape(*t.shape, 3, 3)


def rotations_y(t: Mat) -> Mat:
    """``Ry(t)`` ``(..., 3, 3)`` for angles ``t`` of any shape."""
    c, s, z, o = np.cos(t), np.sin(t), np.zeros_like(t), np.ones_like(t)
    return np.stack([c, z, s, z, o, z, -s, z, c], axis=-1).reshape(*t.shape, 3, 3)


def opw_fk(p: OpwParameters, theta: NDArray[np.float64]) -> NDArray[np.float64]:
    """OPW's flange pose ``F(theta)`` ``(N, 4, 4)`` for OPW joint angles ``theta`` ``(N, 6)``,
    in OPW's base frame (the product in the module doc; no base, tool, signs or offsets)."""
    t = np.atleast_2d(np.asarray(theta, dtype=float))
    r1, r23 = rotations_z(t[:, 0]), rotations_y(t[:, 1] + t[:, 2])
    elbow = np.array([0.0, 0.0, p.c2]) + rotations_y(t[:, 2]) @ np.array([p.a2, p.b, p.c3])
    arm = np.array([p.a1, 0.0, p.c1]) + (rotations_y(t[:, 1]) @ elbow[..., None])[..., 0]
    centre = r1 @ arm[..., None]
    rot = r1 @ r23 @ rotations_z(t[:, 3]) @ rotations_y(t[:, 4]) @ rotations_z(t[:, 5])
    out = np.zeros((len(t), 4, 4))
    out[:, :3, :3] = rot
    out[:, :3, 3] = centre[..., 0] + p.c4 * rot[:, :, 2]
    out[:, 3, 3] = 1.0
    return out


JOINT_NAMES = ("joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6")


def opw_to_poe(
    p: OpwParameters,
    names: tuple[str, ...] = JOINT_NAMES,
    name: str = "",
    source: str = "",
    base_link: str = "",
    tip_link: str = "",
) -> PoeModel:
    """The chain ``base . F(sign q - offsets) . tool`` as a POE model (``q`` the source's joint
    positions): each joint's axis at ``q = 0`` (OPW's angles ``-offsets``), turning as ``sign``
    makes OPW's angle follow ``q``; the home pose ``base . F(-offsets) . tool``."""
    from ..model.poe import Joint

    t = -np.array(p.offsets, dtype=float)

    def rz(a: float) -> Mat:
        return _homogeneous(rotations_z(np.array(a)))

    def ry(a: float) -> Mat:
        return _homogeneous(rotations_y(np.array(a)))

    def move(x: float, y: float, z: float) -> Mat:
        out = np.eye(4)
        out[:3, 3] = (x, y, z)
        return out

    # each joint's local axis (z: 2, y: 1) and what follows it in F, in order
    steps = [
        (2, rz(float(t[0])) @ move(p.a1, 0.0, p.c1)),
        (1, ry(float(t[1])) @ move(0.0, 0.0, p.c2)),
        (1, ry(float(t[2])) @ move(p.a2, p.b, p.c3)),
        (2, rz(float(t[3]))),
        (1, ry(float(t[4]))),
        (2, rz(float(t[5])) @ move(0.0, 0.0, p.c4)),
    ]
    frame = p.base.copy()
    joints = []
    for i, (column, after) in enumerate(steps):
        axis = p.signs[i] * frame[:3, column]
        joints.append(Joint(names[i], "revolute", axis, frame[:3, 3].copy()))
        frame = frame @ after
    home = frame @ p.tool
    home[3] = (0.0, 0.0, 0.0, 1.0)
    return PoeModel(tuple(joints), home, name, source, base_link, tip_link, "m")


def _homogeneous(r: Mat) -> Mat:
    out = np.eye(4)
    out[:3, :3] = r
    return out


def _across(v: Mat, n: Mat) -> Mat:
    """The unit direction of ``v`` with its component along unit ``n`` removed."""
    across: Mat = np.array(unit((v - (v @ n) * n).tolist()), dtype=np.float64)
    return across


def _turn(a: Mat, b: Mat, axis: Mat) -> float:
    """The angle about ``axis`` from ``a`` to ``b`` (both perpendicular to it)."""
    return math.atan2(float(np.cross(a, b) @ axis), float(a @ b))


def _pick(value: float, fallback: float, limit: float) -> int:
    """+1 or -1: the sign of ``value`` beyond ``limit``, else of ``fallback`` (ties: +1)."""
    if abs(value) > limit:
        return 1 if value > 0 else -1
    return -1 if fallback < -limit else 1


class _Judge:
    """Decides OPW's right angles, parallels and meeting points within the tolerances; records
    each relation that held only within them (not exactly) for the report."""

    def __init__(self, model: PoeModel, tol: Tolerances) -> None:
        self.names = [j.name for j in model.joints]
        self.unit, self.tol = model.length_unit, tol
        self.angle = max(tol.parallel_angle, tol.noise)
        self.noise_length = tol.noise * model.size()
        self.distance = tol.distance(model.size())
        self.made: list[tuple[str, float, float]] = []  # (what, angle, gap) held within tol

    def axes(self, *i: int) -> str:
        return ", ".join(f"{k + 1} ({shown(self.names[k])})" for k in i)

    def relation(self, d: list[Mat], i: int, k: int, parallel: bool, what: str) -> None:
        """Axes ``i`` and ``k`` (0-based) parallel, or else perpendicular, within the angle."""
        dot = abs(float(d[i] @ d[k]))
        if parallel:
            off, ideal = math.atan2(float(np.linalg.norm(np.cross(d[i], d[k]))), dot), "parallel"
        else:
            off, ideal = math.asin(min(1.0, dot)), "perpendicular"
        if off > self.angle:
            raise ExportError(
                f"opw: {what}: axes {self.axes(i, k)} are not {ideal} ({math.degrees(off):.4g} "
                f"deg off; the parallel angle tolerance is {self.tol.parallel_angle:g} rad)",
                remedy=Remedy("tol.parallel_angle", " ({} allows more)", "RAD"),
            )
        if off > self.tol.noise:
            treated = f"opw: axes {self.axes(i, k)} are {off:.3g} rad off {ideal}; treated as such"
            self.made.append((treated, off, 0.0))

    def meet(self, gap: float, fault: Callable[[str], str], treated: str) -> None:
        """Lines ``gap`` apart from meeting: ``fault(gap text)`` beyond the distance (a function,
        not a format string: the text holds names from the file, braces and all)."""
        if gap > self.distance:
            raise ExportError(
                f"opw: {fault(f'{gap:.4g} {self.unit}')}; the intersect distance is "
                f"{self.distance:.3g}",
                remedy=Remedy("tol.intersect_distance", " ({} allows more)", "LENGTH"),
            )
        if gap > self.noise_length:
            self.made.append((f"opw: {treated} ({gap:.3g} {self.unit} off)", 0.0, gap))


def _meeting_point(points: list[Mat], dirs: list[Mat]) -> tuple[Mat, float]:
    """The point nearest to the lines (least squares) and its largest distance from them."""
    projectors = [np.eye(3) - np.outer(d, d) for d in dirs]
    pairs = list(zip(projectors, points, strict=True))
    centre = np.asarray(np.linalg.solve(sum(projectors), sum(m @ p for m, p in pairs)), float)
    return centre, max(float(np.linalg.norm(m @ (centre - p))) for m, p in pairs)


def _require_six_revolute(model: PoeModel) -> None:
    if model.n != 6:
        raise ExportError(f"opw: an OPW arm has 6 joints; this chain has {model.n}")
    bad = [f"{shown(j.name)} ({j.kind})" for j in model.joints if j.kind != "revolute"]
    if bad:
        raise ExportError(
            f"opw: joints {', '.join(bad)} cannot be written; opw has revolute joints only"
        )
    bad = [f"{shown(j.name)} (scale {j.scale:g})" for j in model.joints if abs(j.scale) != 1.0]
    if bad:
        raise ExportError(
            f"opw: joints {', '.join(bad)} move by a multiple of their position; "
            "opw has no joint scale"
        )


def opw_from_poe(
    model: PoeModel, tol: Tolerances = DEFAULT, samples: int | None = None, seed: int = 0
) -> OpwParameters:
    """The OPW parameters of ``model`` (module doc), checked against its forward kinematics at
    ``samples`` seeded configurations (100, or 1000 after a judgement).

    Raises
    ------
    ExportError
        If the chain is not an OPW arm; the message names the condition that failed.
    ConversionError
        If the parameters' FK deviates from the model's beyond the exactness promised without
        a judgement to account for it.
    """
    _require_six_revolute(model)
    judge = _Judge(model, tol)
    d = [j.scale * j.axis for j in model.joints]
    p = [np.zeros(3) if j.point is None else j.point for j in model.joints]
    judge.relation(d, 3, 4, False, "not an ortho wrist")
    judge.relation(d, 4, 5, False, "not an ortho wrist")
    centre, gap = _meeting_point(p[3:], d[3:])
    judge.meet(
        gap,
        lambda apart: (
            f"wrist axes do not intersect: offset wrist (axes {judge.axes(3, 4, 5)} "
            f"pass {apart} from one common point)"
        ),
        "wrist axes treated as meeting in one point",
    )
    judge.relation(d, 0, 1, False, "not an ortho-parallel base")
    judge.relation(d, 1, 2, True, "not an ortho-parallel base")
    judge.relation(d, 2, 3, False, "not an ortho-parallel base")

    # OPW's base frame: z on axis 1 (towards the base z), origin nearest the base origin
    z = _pick(d[0][2], 1.0, tol.noise) * d[0]
    origin = p[0] - (p[0] @ z) * z
    x0 = _across(np.eye(3)[0] if abs(z[0]) < 0.9 else np.eye(3)[1], z)
    frame = np.column_stack([x0, np.cross(z, x0), z])
    turn = math.atan2(frame[0, 1] - frame[1, 0], frame[0, 0] + frame[1, 1])  # max trace
    frame = frame @ rotations_z(np.array(turn))
    # the arm's plane at home: y along axis 2, a1 >= 0 (or the least joint-1 turn)
    y = _across(d[1], z)
    y *= _pick(
        float(np.cross(y, z) @ (p[1] - origin)), float(np.cross(y, z) @ frame[:, 0]), judge.distance
    )
    x = np.cross(y, z)
    between = p[2] - p[1] - ((p[2] - p[1]) @ y) * y
    c2 = float(np.linalg.norm(between))
    if c2 <= judge.distance:
        raise ExportError(
            f"opw: not an ortho-parallel base: axes {judge.axes(1, 2)} coincide ({c2:.4g} "
            f"{model.length_unit} apart, within the intersect distance {judge.distance:.3g})"
        )
    up = between / c2  # the upper arm at home: OPW's z at joint 2's zero
    w4 = _across(d[3], y)  # forearm: from the elbow towards the wrist centre (c3 >= 0)
    w4 *= _pick(float((centre - p[2]) @ w4), float(w4 @ up), judge.distance)
    e5 = _across(d[4], w4)  # joint 5's axis at OPW's zero of joint 4: the least turn
    e5 *= _pick(float(e5 @ y), 1.0, tol.noise)
    w6 = _across(d[5], e5)  # joint 6: outward, towards the tip (c4 >= 0)
    tip = model.home[:3, 3]
    w6 *= _pick(float((tip - centre) @ w6), float(w6 @ model.home[:3, 2]), judge.distance)
    theta2 = math.atan2(float(up @ x), float(up @ z))
    theta = [  # OPW's joint angles at the source's zero
        _turn(frame[:, 0], x, z),
        theta2,
        math.atan2(float(w4 @ x), float(w4 @ z)) - theta2,
        _turn(y, e5, w4),
        math.atan2(float(w6 @ np.cross(e5, w4)), float(w6 @ w4)),
        0.0,
    ]
    geometry = (  # a1, a2, b, c1, c2, c3, c4
        float(x @ (p[1] - origin)), float(np.cross(y, w4) @ (centre - p[2])),
        float(y @ (centre - origin)), float(z @ (p[1] - origin)), c2,
        float(w4 @ (centre - p[2])), float(w6 @ (tip - centre)),
    )  # fmt: skip
    signs = tuple(
        _pick(float(di @ e), 1.0, 0.0) for di, e in zip(d, [z, y, y, w4, e5, w6], strict=True)
    )
    base = np.eye(4)
    base[:3, :3], base[:3, 3] = frame, origin
    draft = OpwParameters(*geometry, (0.0,) * 6, (1,) * 6, base, np.eye(4))
    flange = base @ opw_fk(draft, np.array(theta))[0]
    m = flange[:3, :3].T @ model.home[:3, :3]
    theta[5] = math.atan2(m[1, 0] - m[0, 1], m[0, 0] + m[1, 1])  # the least tool rotation
    flange = base @ opw_fk(draft, np.array(theta))[0]
    tool = np.linalg.solve(flange, model.home)
    tool[3] = (0.0, 0.0, 0.0, 1.0)
    offsets = tuple(wrap_angle(-t) for t in theta)
    result = OpwParameters(*geometry, offsets, signs, base, tool)
    return _checked(model, result, judge, tol, samples, seed)


def _checked(
    model: PoeModel,
    p: OpwParameters,
    judge: _Judge,
    tol: Tolerances,
    samples: int | None,
    seed: int,
) -> OpwParameters:
    """``p`` with its check against the model; refused if it deviates unaccountably."""
    size, reach = model.size(), max(model.reach(), model.size())
    samples = samples or (JUDGED_SAMPLES if judge.made else CHECK_SAMPLES)
    q = model.sample(samples, seed)
    pos, rot = pose_errors(p.fk_batch(q), model.fk_batch(q))
    # as the tables' check (convert.to_table): each judgement may cost twice its angle over
    # the robot's reach plus its gap, and is reported once its effect exceeds tol.report
    allowed_pos = tol.check_position * size + 2.0 * sum(a * reach + g for _, a, g in judge.made)
    allowed_rot = tol.check_rotation + 2.0 * sum(a for _, a, _ in judge.made)
    if not (pos <= allowed_pos and rot <= allowed_rot):
        raise ConversionError(
            f"{model.source or model.name}: the OPW parameters' forward kinematics deviates from "
            f"the source by {pos:.3g} {model.length_unit} and {rot:.3g} rad (allowed "
            f"{allowed_pos:.3g} {model.length_unit}, {allowed_rot:.3g} rad); not written"
        )
    warnings = list(model.warnings)
    if judge.made and (pos > tol.report * size or rot > tol.report):
        warnings += [what for what, _, _ in judge.made]
        warnings.append(
            f"opw: FK deviation from the source caused by these judgements: "
            f"{pos:.3g} {model.length_unit}, {rot:.3g} rad (worst of {samples} "
            "configurations); OPW cannot hold the exact geometry"
        )
    return replace(p, check=(samples, pos, rot), warnings=tuple(warnings))
