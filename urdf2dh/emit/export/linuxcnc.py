"""LinuxCNC ``genserkins``: HAL lines for its six Craig-convention links and the joint zeros.

The consumer (LinuxCNC's genserkins, ``genserfuncs.c``): six revolute links; link ``i`` is
``go_dh_pose_convert`` of ``(A-i, ALPHA-i, D-i, theta = joint i)``, which is Craig's
``Rx(ALPHA-i) Tx(A-i) Rz(joint i) Tz(D-i)``, and the tool pose is their product: no base or tool
transform, no theta offsets and no joint directions. Joint positions are in degrees, ``A`` and
``D`` in the machine's length unit, ``ALPHA`` in radians.

From a modified D-H (``mdh``) table ``Rz(theta_B) Tz(d_B) . prod_i [Rx(alpha_i) Tx(a_i) Q_i
Rz(theta_i) Tz(d_i)] . Rx(alpha_T) Tx(a_T) Rz(theta_T) Tz(d_T)``, genserkins' joint ``i`` is the
angle ``sign_i q_i + offset_i`` of the arm's joint position ``q_i`` (:class:`Joint`):

* ``offset_i = theta_i``;
* the base joins link 0 when joint 1's axis lies on the base's z line (``a_1 = 0``): with
  ``alpha_1 = 0`` its ``Rz Tz`` commutes with joint 1, so ``theta_B`` adds to joint 1's offset and
  ``d_B`` to ``D-0``; with ``alpha_1 = pi``, ``Rz(t) Tz(d) Rx(pi) = Rx(pi) Rz(-t) Tz(-d)``, so
  both are subtracted. Otherwise genserkins' world frame is the frame its link 0 starts from,
  ``Rz(theta_B) Tz(d_B)`` in the base link (:class:`World`), and the file says so;
* the tool joins the last link when the tip's z lies on the last axis (``a_T = 0``): with
  ``alpha_T = 0``, ``theta_T`` adds to that joint's offset and ``d_T`` to its ``D``; with
  ``alpha_T = pi`` (the tip's z against the axis, as KUKA and FANUC flanges are),
  ``Rz(u) Tz(d) Rx(pi) = Rx(pi) Rz(-u) Tz(-d)`` turns the last link into ``Rx(alpha + pi)
  Tx(a) Rz(theta_T - u) Tz(d_T - d)``: that joint turns against genserkins' (``sign = -1``).
  A tip tilted from the axis with its origin on it keeps LinuxCNC's position exact, and the
  file gives the turn ``Rx(alpha_T) Rz(theta_T)`` from the orientation LinuxCNC reports; a tip
  whose origin is off the axis cannot be held (LinuxCNC would move another point);
* fewer than six joints leave the last links zero (their joints held at 0).

The chain is named in comments that urdf2dh reads back (:mod:`urdf2dh.io.halfile`): a JSON line
``urdf2dh chain: {...}`` (robot, base and tip links, length unit, world frame, tool turn) and a
line ``urdf2dh joint i: "name"`` per joint.

A joint whose sign is not 1 or whose offset is not 0 gets two HAL ``scale`` components
(``out = in * gain + offset``) between motion's joint position (genserkins' angle) and the
drive's (the arm's ``q``): ``urdf2dh-fb-i`` for the feedback, ``q -> sign q + offset``, and
``urdf2dh-cmd-i`` for the command, ``theta -> sign theta - sign offset``. LinuxCNC's ``offset``
component adds an offset but cannot turn a joint around; ``scale`` does both.

Values whose effect is below the exactness a table promises (``check_rotation`` rad,
``check_position`` x size) count as zero where genserkins has no place for them (a tool tilted
by a rounded pi); offsets are written as they are.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ... import units
from ...conventions.base import written_angle
from ...conventions.table import Row, Table
from ...errors import ExportError, shown, visible
from ...escape import hal_comment
from ...geometry.frames import wrap_angle
from ...geometry.se3 import dh_matrix, rot_x
from .common import (
    ExportOptions,
    Numbers,
    close_to,
    floats,
    header,
    num,
    require,
    require_convention,
)

__all__ = ["JOINTS", "UNITS", "Genser", "Joint", "Link", "genser", "render"]

JOINTS = 6  # genserkins' GENSER_MAX_JOINTS: it always evaluates six links
UNITS = {"mm": "mm", "inch": "inch", "in": "inch"}
THREAD = "servo-thread"  # the thread motmod creates; LinuxCNC's sample configurations use it


@dataclass(frozen=True, slots=True)
class Link:
    """One genserkins link ``Rx(alpha) Tx(a) Rz(joint) Tz(d)``, lengths in the table's unit."""

    a: float
    alpha: float
    d: float


@dataclass(frozen=True, slots=True)
class Joint:
    """genserkins' joint angle as a function of the arm's joint position ``q``:
    ``sign * q + offset`` (radians)."""

    sign: int = 1
    offset: float = 0.0


@dataclass(frozen=True, slots=True)
class Genser:
    """What genserkins holds of a table: its links, how each joint's angle follows the arm's
    joint position, and what is left of the base and tool where they cannot join the links:
    ``world = (theta, d)``, genserkins' world frame ``Rz(theta) Tz(d)`` in the base link, and
    ``tool_turn = (alpha, theta)``, the tip ``Rx(alpha) Rz(theta)`` in genserkins' last frame
    (same origin); ``None`` where nothing is left."""

    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    world: tuple[float, float] | None = None
    tool_turn: tuple[float, float] | None = None


def _refuse(why: str) -> ExportError:
    return ExportError(f"linuxcnc: genserkins {why}; this chain cannot be written for it")


def _flips(table: Table, alpha: float, a: float, opts: ExportOptions) -> bool | None:
    """Whether ``Rx(alpha) Tx(a)`` is the identity (False) or a half turn about x (True),
    within the table's exactness; ``None`` when it is neither."""
    m = dh_matrix(0.0, 0.0, alpha, a)
    if close_to(table, m, np.eye(4), opts.tol):
        return False
    if close_to(table, m, rot_x(math.pi), opts.tol):
        return True
    return None


def genser(table: Table, opts: ExportOptions) -> Genser:
    """genserkins' view of an ``mdh`` table (see the module docstring), or the reason it
    cannot hold the chain."""
    rows = [floats(r.params) for r in table.rows]
    links = [Link(p["a"], p["alpha"], p["d"]) for p in rows]
    joints = [Joint(1, p["theta"]) for p in rows]
    base, tool = floats(table.base), floats(table.tool)

    world = None
    if not close_to(table, table.base_matrix, np.eye(4), opts.tol):
        first = links[0]
        flip = _flips(table, first.alpha, first.a, opts)
        if flip is None:
            world = (base["theta"], base["d"])
        else:
            sign = -1 if flip else 1
            links[0] = Link(first.a, first.alpha, first.d + sign * base["d"])
            joints[0] = Joint(1, joints[0].offset + sign * base["theta"])

    last, joint = links[-1], joints[-1]
    flip = _flips(table, tool["alpha"], tool["a"], opts)
    if flip is True:
        links[-1] = Link(last.a, wrap_angle(last.alpha + math.pi), tool["d"] - last.d)
        joints[-1] = Joint(-joint.sign, tool["theta"] - joint.offset)
        return Genser(tuple(links), tuple(joints), world)
    if flip is False:
        links[-1] = Link(last.a, last.alpha, last.d + tool["d"])
        joints[-1] = Joint(joint.sign, joint.offset + tool["theta"])
        return Genser(tuple(links), tuple(joints), world)
    # the tip's origin in the last frame: Rx(alpha) Tx(a) Rz(theta) Tz(d) . 0
    origin = (tool["a"], -tool["d"] * math.sin(tool["alpha"]), tool["d"] * math.cos(tool["alpha"]))
    if math.hypot(origin[0], origin[1]) > opts.tol.check_position * table.size:
        raise _refuse(
            f"has no tool transform, and the tip {shown(table.tip_link)} lies "
            f"{math.hypot(origin[0], origin[1]):.6g} {visible(table.length_unit)} off the last "
            "joint's axis, where LinuxCNC's Cartesian position would be another point; choose "
            "a tip link on the last joint's axis (the flange)"
        )
    return Genser(tuple(links), tuple(joints), world, (tool["alpha"], tool["theta"]))


def _degrees(angle: float) -> str:
    """An angle's text in degrees (genserkins' joint unit), 15 significant digits."""
    return num(float(f"{math.degrees(angle):.15g}"))


def _mapping(joint: Joint) -> str:
    q = "q" if joint.sign > 0 else "-q"
    if joint.offset == 0.0:
        return q
    return f"{q} {'+' if joint.offset > 0 else '-'} {_degrees(abs(joint.offset))}"


def _note(i: int, row: Row, joint: Joint) -> str:
    """The comment naming genserkins' joint ``i``: the arm's joint, how its angle follows the
    joint's position ``q``, and its limits in genserkins' angles (LinuxCNC's joint limits)."""
    mapped = joint != Joint()
    text = f"joint {i}: {row.name}"
    if mapped:
        text += f", genserkins angle {_mapping(joint)} deg"
    if row.lower is not None and row.upper is not None:
        ends = sorted(joint.sign * x + joint.offset for x in (row.lower, row.upper))
        text += f", limits {math.degrees(ends[0]):.6g} .. {math.degrees(ends[1]):.6g} deg"
        if mapped:
            text += f" (q: {math.degrees(row.lower):.6g} .. {math.degrees(row.upper):.6g})"
    return text


def _scales(maps: dict[int, Joint]) -> list[str]:
    """The ``scale`` components that turn drive positions into genserkins' angles and back."""
    if not maps:
        return []
    names = [f"urdf2dh-{way}-{i}" for i in maps for way in ("fb", "cmd")]
    notes = [
        "Joint zeros and directions. genserkins has neither: LinuxCNC's joint positions",
        "(motion's, the [JOINT_i] limits, homing) are genserkins' angles, which for the joints",
        "marked above differ from the arm's joint positions q (degrees, the source's zero and",
        "direction). Two scale components (out = in * gain + offset) per such joint i convert:",
        "urdf2dh-fb-i the drive's position feedback q to genserkins' angle, urdf2dh-cmd-i",
        "motion's command back to q. Connect them to your drives' pins, e.g.:",
        "  net ji-cmd joint.i.motor-pos-cmd => urdf2dh-cmd-i.in",
        "  net ji-drive-cmd urdf2dh-cmd-i.out => <the drive's position command>",
        "  net ji-drive-fb <the drive's position feedback> => urdf2dh-fb-i.in",
        "  net ji-fb urdf2dh-fb-i.out => joint.i.motor-pos-fb",
        f"Their functions are added at the end of {THREAD} here; to spare a servo period of",
        "delay, put urdf2dh-fb-i after the drives' read and before motion-command-handler,",
        "urdf2dh-cmd-i after motion-controller and before the drives' write (addf's position",
        "argument). If your configuration loads scale already, add these names to its names=.",
    ]
    out = [line for note in notes for line in hal_comment(note)]
    out.append(f"loadrt scale names={','.join(names)}")
    out += [f"addf {name} {THREAD}" for name in names]
    for i, joint in maps.items():
        gain = f"{float(joint.sign)!r}"
        out.append(f"setp urdf2dh-fb-{i}.gain {gain}")
        out.append(f"setp urdf2dh-fb-{i}.offset {_degrees(joint.offset)}")
        out.append(f"setp urdf2dh-cmd-{i}.gain {gain}")
        out.append(f"setp urdf2dh-cmd-{i}.offset {_degrees(-joint.sign * joint.offset)}")
    return out


def _frame_notes(table: Table, g: Genser, numbers: Numbers, unit: str) -> list[str]:
    """What the poses LinuxCNC reports are, where genserkins cannot hold the base or the tool."""
    base, tip = visible(table.base_link or "the base"), visible(table.tip_link or "the tip")
    notes = []
    if g.world is not None:
        theta, d = g.world
        notes.append(
            f"World frame: genserkins has no base transform, and joint 1's axis is off the z "
            f"line of {base}, so LinuxCNC's poses are in the frame link 0 starts from, {base} "
            f"turned about and moved along its z: pose in {base} = Rz({_degrees(theta)} deg) "
            f"Tz({numbers.lin(d)} {unit}) . pose LinuxCNC reports."
        )
    if g.tool_turn is not None:
        alpha, theta = g.tool_turn
        notes.append(
            f"Tool frame: genserkins has no tool transform, and {tip} is tilted from the last "
            f"joint's axis (its origin on it), so LinuxCNC's position is {tip}'s and its "
            f"orientation that of the last link: pose of {tip} = pose LinuxCNC reports . "
            f"Rx({_degrees(alpha)} deg) Rz({_degrees(theta)} deg)."
        )
    return notes


def _chain_notes(table: Table, g: Genser, numbers: Numbers, unit: str) -> list[str]:
    """The chain as urdf2dh reads the file back (:mod:`urdf2dh.io.halfile`): one JSON line with
    the robot, its links, the length unit, the world frame and the tool's turn, and a line per
    joint with its name (JSON strings, ASCII: the names whatever they hold)."""
    import json

    from ...io.chaincomment import encoded

    world = None if g.world is None else [g.world[0], numbers.length(g.world[1])]
    chain = {"robot": table.robot, "base_link": table.base_link, "tip_link": table.tip_link,
             "unit": unit, "world": world,
             "tool_turn": None if g.tool_turn is None else list(g.tool_turn)}  # fmt: skip
    lines = [encoded(chain)]
    lines += [f"urdf2dh joint {i}: " + json.dumps(r.name) for i, r in enumerate(table.rows)]
    return lines


def render(table: Table, opts: ExportOptions) -> str:
    """HAL lines for genserkins and the joint zeros (see the module docstring)."""
    require_convention(table, "linuxcnc", ("mdh",))
    if table.n > JOINTS:
        raise _refuse(f"evaluates {JOINTS} joints, and this chain has {table.n}")
    require(table, "linuxcnc", ("mdh",), ("revolute",))
    unit = UNITS.get(opts.units or "mm")
    if unit is None:
        raise ExportError(f"linuxcnc: the length unit must be mm or inch, not '{opts.units}'")
    g = genser(table, opts)
    numbers = Numbers.of(table, opts.tol, units.factor(table.length_unit, unit))
    joints = [
        Joint(j.sign, written_angle(wrap_angle(j.offset), opts.tol.written)) for j in g.joints
    ]
    maps = {i: j for i, j in enumerate(joints) if j != Joint()}
    notes = header(table, "LinuxCNC genserkins parameters", unit)
    notes.append(
        f"genserkins link i = Rx(ALPHA-i) Tx(A-i) Rz(joint i) Tz(D-i) (Craig); A and D "
        f"in {unit}, ALPHA in radians,"
    )
    notes.append(
        "joint positions in degrees. The base height is in D-0, the tool length in "
        f"D-{len(g.links) - 1}."
    )
    for i, (row, joint) in enumerate(zip(table.rows, joints, strict=True)):
        notes.append(_note(i, row, joint))
    for i in range(table.n, JOINTS):
        notes.append(f"joint {i}: none (a zero link; hold this joint at 0)")
    notes += _frame_notes(table, g, numbers, unit)
    notes += _chain_notes(table, g, numbers, unit)
    out = [line for note in notes for line in hal_comment(note)]
    links = list(g.links) + [Link(0.0, 0.0, 0.0)] * (JOINTS - len(g.links))
    for i, link in enumerate(links):
        out.append(f"setp genserkins.A-{i} {numbers.lin(link.a)}")
        out.append(f"setp genserkins.ALPHA-{i} {numbers.ang(link.alpha)}")
        out.append(f"setp genserkins.D-{i} {numbers.lin(link.d)}")
    out += _scales(maps)
    return "\n".join(out) + "\n"
