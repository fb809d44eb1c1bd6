"""A model's kinematics written into a nominal URDF: ``--format urdf --like NOMINAL.urdf``
(docs/commands/convert.md).

The URDF written is NOMINAL's own document with only joint origins and axes changed, so that its
forward kinematics equals the model's while every link keeps its visual, collision and inertial
elements in its own frame: a calibrated (or vendor-read) URDF that can replace the vendor's.

Where each link goes. A URDF joint's axis passes through its child link's frame origin, so each
moving joint's child frame must lie on the model's axis line, its URDF axis along the model's
direction. Of those frames, the one nearest the nominal's: the nominal frame moved by the least
rotation that turns its axis onto the model's (the URDF axis is flipped instead where the model
turns the other way) and slid onto the model's line where it passes nearest; then turned about
that line as the link best carries the next joint's axis (the link moves as one body: a joint's
zero that changed turns its link with it). The last moving link keeps the nominal's turn (the
tool's transform is not the link's). Fixed joints keep their origins, so that everything fixed
to a link moves with it, except the first fixed joint after the last moving joint on the way to
the tip, which takes the tool: the tip lands on the model's. A tip that is itself the last
moving joint's child lands there too, when the model's tip lies on that joint's axis.

The written text is read back (the same reader as every SOURCE) and its forward kinematics
checked against the model before it is returned.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .._version import __version__
from ..conventions.table import Check
from ..errors import ConversionError, ExportError, InputError, shown, visible
from ..geometry import se3
from ..geometry.lie import log_so3
from ..model.poe import PoeModel
from ..tolerances import DEFAULT, Tolerances

if TYPE_CHECKING:
    from ..io.urdf.tree import UrdfJoint, UrdfTree
    from ..io.xacro import XacroOptions

__all__ = ["LinkMove", "UrdfLike", "urdf_like"]

Mat = NDArray[np.float64]
CHECK_SAMPLES = 200


@dataclass(frozen=True, slots=True)
class LinkMove:
    """How far a link's frame moved from the nominal's, at the home pose: ``distance`` (the
    model's length unit) and ``angle`` (rad); ``tool`` for a link the tool's transform carries
    (beyond the joint that took it)."""

    link: str
    distance: float
    angle: float
    tool: bool = False


@dataclass(frozen=True)
class UrdfLike:
    """The result of :func:`urdf_like`.

    Attributes
    ----------
    text
        The URDF: NOMINAL's document with the changed joints' origins and axes.
    nominal
        NOMINAL as given.
    base_link, tip_link
        The chain of NOMINAL the model was written into.
    joints
        The joints whose origin or axis changed, in chain order.
    tool_joint
        The fixed joint that took the tool's transform (``None`` where the tip is the last
        moving joint's child).
    moved
        Each link of the chain that moved at the home pose, and how far.
    check
        The written URDF's forward kinematics (read back) against the model.
    notes
        What the file's header comment says besides.
    """

    text: str
    nominal: str
    base_link: str
    tip_link: str
    joints: tuple[str, ...]
    tool_joint: str | None
    moved: tuple[LinkMove, ...]
    check: Check
    notes: tuple[str, ...] = field(default=())

    def summary(self) -> str:
        """One line: what changed, how far the links moved, who took the tool."""
        if not self.joints:
            return f"--like {self.nominal}: no joint changed (the model is the nominal's)"
        arm = [m for m in self.moved if not m.tool]
        far = max(arm, key=lambda m: m.distance, default=None)
        turned = max(arm, key=lambda m: m.angle, default=None)
        moved = (
            ""
            if far is None or turned is None
            else f"; the arm's links moved at most {far.distance:.3g} m ({visible(far.link)}) "
            f"and {math.degrees(turned.angle):.3g} deg ({visible(turned.link)})"
        )
        tool = f"; {visible(self.tool_joint)} takes the tool" if self.tool_joint else ""
        return (
            f"--like {self.nominal}: {len(self.joints)} joints changed "
            f"({', '.join(visible(j) for j in self.joints)}){moved}{tool}; FK as the model's "
            f"to {self.check.max_position_error:.2g}, {self.check.max_rotation_error:.2g} rad"
        )


def urdf_like(
    model: Any,
    nominal: str | os.PathLike[str],
    *,
    base: str | None = None,
    tip: str | None = None,
    tol: Tolerances = DEFAULT,
    samples: int = CHECK_SAMPLES,
    xacro: XacroOptions | None = None,
) -> UrdfLike:
    """NOMINAL's URDF with the joint origins and axes of ``model`` (module docstring).

    Parameters
    ----------
    model
        The kinematics to write: a :class:`~urdf2dh.PoeModel` (an identified one:
        ``Calibration.model``) or a :class:`~urdf2dh.Table` (its POE model).
    nominal
        The URDF (or xacro file, or bundled robot) whose links, meshes and inertials to keep.
    base, tip
        NOMINAL's chain: by default the model's base and tip links, else a bundled robot's own,
        else NOMINAL's root and its deepest leaf. Its moving joints are the model's, by name
        (else in order, said in the notes).
    tol, samples
        The check of the written URDF against the model.
    xacro
        How a ``.xacro`` NOMINAL is expanded.

    Returns
    -------
    UrdfLike
        The text and what changed.

    Raises
    ------
    InputError
        NOMINAL is not a URDF, has no such chain, or its moving joints are not the model's.
    ExportError
        The model cannot be written so (a joint scale other than 1, a helical or mimic joint, a
        tip off the last joint's axis with no fixed joint to hold it).
    ConversionError
        The written URDF's forward kinematics deviates from the model's (never written).
    """
    from ..checks import check_count, check_instance, check_optional_name, check_source
    from ..conventions.table import Table
    from ..io.sources import open_source

    if isinstance(model, Table):
        model = model.to_poe()
    check_instance(model, PoeModel, "urdf_like: model", "a PoeModel or a Table")
    nominal = check_source(nominal, "urdf_like: nominal")
    base = check_optional_name(base, "urdf_like: base")
    tip = check_optional_name(tip, "urdf_like: tip")
    check_count(samples, "urdf_like: samples")
    source = open_source(nominal, tol, xacro=xacro)
    nominal = source.display  # as messages and comments show it (one line, visible)
    if source.tree is None or source.document is None:
        raise InputError(
            f"{nominal}: --like takes a URDF (or xacro file), not a {source.kind} file"
        )
    tree, bundled = source.tree, source.bundled
    own_base, own_tip = (bundled.base, bundled.tip) if bundled else (None, None)
    base = base or (model.base_link if model.base_link in tree.links else own_base or tree.root)
    tip = tip or (
        model.tip_link if model.tip_link in tree.links else own_tip or tree.default_tip(base)
    )
    path = tree.chain(base, tip)
    moving = [j for j in path if j.type != "fixed"]
    notes = _joint_map(model, moving, nominal)
    _writable(model, moving, nominal)
    origins, axes, tool_joint = _placed(model, path, moving, tree, nominal, tol)
    text = _edited(source.document, origins, axes, model, nominal, notes)
    check = _checked(text, nominal, base, tip, model, tol, samples)
    changed = tuple(j.name for j in path if j.name in origins or j.name in axes)
    moved = _moves(path, origins, model.size(), tool_joint)
    return UrdfLike(text, nominal, base, tip, changed, tool_joint, moved, check, tuple(notes))


def _joint_map(model: PoeModel, moving: list[UrdfJoint], nominal: str) -> list[str]:
    """Check that NOMINAL's moving joints are the model's (by name, else in order)."""
    if len(moving) != model.n:
        raise InputError(
            f"{nominal}: its chain has {len(moving)} moving joints, the model {model.n} "
            f"({', '.join(shown(j.name) for j in model.joints)}); choose NOMINAL's chain with "
            "--base and --tip"
        )
    if [j.name for j in moving] == [j.name for j in model.joints]:
        return []
    return [
        "the model's joints are written into NOMINAL's in order: "
        + ", ".join(
            f"{visible(a.name)} as {visible(b.name)}"
            for a, b in zip(model.joints, moving, strict=True)
        )
    ]


def _writable(model: PoeModel, moving: list[UrdfJoint], nominal: str) -> None:
    for joint, urdf in zip(model.joints, moving, strict=True):
        kind = "prismatic" if urdf.type == "prismatic" else "revolute"
        if joint.kind != kind:
            raise ExportError(
                f"urdf --like: joint {shown(joint.name)} is {joint.kind} in the model and "
                f"{urdf.type} in {nominal}"
            )
        if urdf.mimic is not None or joint.mimic is not None:
            raise ExportError(
                f"urdf --like: joint {shown(urdf.name)} mimics another; a URDF like NOMINAL "
                "is written for independent joints only"
            )
        if abs(abs(joint.scale) - 1.0) > 1e-12:
            raise ExportError(
                f"urdf --like: joint {shown(joint.name)} moves by {joint.scale:.10g} q; a URDF "
                "joint has no scale (calibrate with --keep-scale, or write --format urdf "
                "without --like)"
            )


def _placed(
    model: PoeModel,
    path: list[UrdfJoint],
    moving: list[UrdfJoint],
    tree: UrdfTree,
    nominal: str,
    tol: Tolerances,
) -> tuple[dict[str, Mat], dict[str, Mat], str | None]:
    """New joint origins and axes (by joint name) and the joint that took the tool."""
    size = model.size()
    nominal_frames = _frames(path)  # each joint's child frame at home, in the base link
    index = {j.name: k for k, j in enumerate(moving)}
    last = path.index(moving[-1])
    after = path[last + 1 :]  # fixed joints from the last moving link to the tip
    placed: dict[str, Mat] = {}  # new child frames of the moving joints
    axes: dict[str, Mat] = {}
    for k, (urdf, joint) in enumerate(zip(moving, model.joints, strict=True)):
        frame = nominal_frames[urdf.name]
        direction = joint.scale * joint.axis  # the model's positive motion
        point = joint.point if joint.point is not None else frame[:3, 3]
        new, flip = _onto_line(frame, urdf.axis, direction, point)
        if k + 1 < len(moving):
            nxt = moving[k + 1]
            follower = model.joints[k + 1]
            new = _carrying(new, frame, nominal_frames[nxt.name], nxt.axis, follower,
                            _unit(direction), size)  # fmt: skip
        elif not after:
            new = _tip_on_axis(model, urdf, direction, point, nominal, tol)
        placed[urdf.name] = new
        axes[urdf.name] = flip * (new[:3, :3].T @ direction)
    origins: dict[str, Mat] = {}
    world = np.eye(4)
    for j in path:
        if j.name in index:
            origins[j.name] = se3.inv(world) @ placed[j.name]
            world = placed[j.name]
        elif after and j is after[0]:
            rest = np.eye(4)
            for fixed in after[1:]:
                rest = rest @ fixed.origin
            origins[j.name] = se3.inv(world) @ model.home @ se3.inv(rest)
            world = world @ origins[j.name]
        else:
            world = world @ j.origin
    # what round-off alone moved stays as NOMINAL writes it
    same = 4.0 * np.finfo(float).eps
    joints = {j.name: j for j in path}
    for name in list(origins):
        difference = np.abs(origins[name] - joints[name].origin)
        if difference[:3, :3].max() <= same and difference[:3, 3].max() <= same * size:
            del origins[name]
    for name in list(axes):
        if np.abs(axes[name] - joints[name].axis).max() <= same:
            del axes[name]
    return origins, axes, after[0].name if after else None


def _frames(path: list[UrdfJoint]) -> dict[str, Mat]:
    """Each joint's child frame at the home pose, in the chain's base frame."""
    out, world = {}, np.eye(4)
    for j in path:
        world = world @ j.origin
        out[j.name] = world
    return out


def _onto_line(frame: Mat, axis: Mat, direction: Mat, point: Mat) -> tuple[Mat, float]:
    """The nominal child frame moved by the least rotation that turns its axis onto
    ``direction`` (or against it, the URDF axis then flipped: ``flip`` -1) and slid onto the
    line through ``point`` where it passes nearest."""
    current = frame[:3, :3] @ axis
    flip = 1.0 if float(current @ direction) >= 0.0 else -1.0
    target = flip * direction
    turn = _least_rotation(current, target)
    out = np.eye(4)
    out[:3, :3] = turn @ frame[:3, :3]
    origin = frame[:3, 3]
    out[:3, 3] = point + float((origin - point) @ direction) * direction
    return out, flip


def _least_rotation(a: Mat, b: Mat) -> Mat:
    """The rotation by the least angle that turns unit ``a`` onto unit ``b``."""
    axis = np.cross(a, b)
    s, c = float(np.linalg.norm(axis)), float(a @ b)
    if s < 1e-15:
        return np.eye(3)  # parallel (anti-parallel never asked: the axis is flipped instead)
    return se3.rot_axis(axis / s, math.atan2(s, c))


def _carrying(
    new: Mat,
    frame: Mat,
    next_frame: Mat,
    next_axis: Mat,
    follower: Any,
    u: Mat,
    size: float,
) -> Mat:
    """``new`` turned about its joint's line (through its origin, along unit ``u``) so that the
    link, moved as one body from the nominal ``frame``, carries the next joint's axis nearest
    the model's ``follower``: the least squares of a point on that axis and of its direction
    (``size`` long)."""
    moved = new @ se3.inv(frame)  # the link's motion, before the turn
    centre = new[:3, 3]
    start = (moved @ np.append(next_frame[:3, 3], 1.0))[:3]
    along = moved[:3, :3] @ (next_frame[:3, :3] @ next_axis)
    target_dir = follower.scale * follower.axis
    if float(target_dir @ along) < 0.0:
        target_dir = -target_dir
    point = follower.point if follower.point is not None else start
    target = point + float((start - point) @ target_dir) * target_dir
    sin = cos = 0.0
    for a, b in ((start - centre, target - centre), (size * along, size * target_dir)):
        a_perp, b_perp = a - (a @ u) * u, b - (b @ u) * u
        sin += float(np.cross(a_perp, b_perp) @ u)
        cos += float(a_perp @ b_perp)
    if math.hypot(sin, cos) < 1e-15 * size * size:
        return new
    turn = np.eye(4)
    turn[:3, :3] = se3.rot_axis(u, math.atan2(sin, cos))
    turn[:3, 3] = centre - turn[:3, :3] @ centre
    out: Mat = turn @ new
    return out


def _unit(v: Mat) -> Mat:
    """``v`` made unit length."""
    out: Mat = v / np.linalg.norm(v)
    return out


def _tip_on_axis(
    model: PoeModel, urdf: UrdfJoint, direction: Mat, point: Mat, nominal: str, tol: Tolerances
) -> Mat:
    """The last moving joint's child as the tip: the model's tip frame, which must lie on the
    joint's axis."""
    home = model.home
    off = home[:3, 3] - point
    gap = float(np.linalg.norm(off - (off @ direction) * direction))
    if gap > tol.check_position * model.size():
        raise ExportError(
            f"urdf --like: the model's tip lies {gap:.6g} {visible(model.length_unit)} off the "
            f"axis of joint {shown(urdf.name)}, and {nominal}'s chain ends at its child "
            f"{shown(urdf.child)}, whose frame must lie on that axis; choose a tip beyond a fixed "
            "joint (--tip), which then takes the tool"
        )
    out: Mat = home.copy()
    return out


def _edited(
    document: bytes,
    origins: dict[str, Mat],
    axes: dict[str, Mat],
    model: PoeModel,
    nominal: str,
    notes: list[str],
) -> str:
    """NOMINAL's document with the new origins and axes, comments kept, a header comment
    added."""
    from lxml import etree

    from ..escape import xml_comment

    parser = etree.XMLParser(remove_comments=False, remove_pis=False, resolve_entities=False,
                             no_network=True)  # fmt: skip
    root = etree.fromstring(document, parser=parser)
    for joint in root.findall("joint"):  # the robot's own (not a transmission's references)
        name = joint.get("name")
        if name in origins:
            element = joint.find("origin")
            if element is None:
                element = etree.SubElement(joint, "origin")
            t = origins[name]
            element.set("xyz", " ".join(_num(v) for v in t[:3, 3]))
            element.set("rpy", " ".join(_num(v) for v in se3.rpy(t)))
        if name in axes:
            element = joint.find("axis")
            if element is None:
                element = etree.SubElement(joint, "axis")
            element.set("xyz", " ".join(_num(v) for v in _clean_axis(axes[name])))
    header = [
        f"Written by urdf2dh {__version__}: {nominal} with the joint origins and axes of "
        f"{model.source or model.name or 'the model'} ({visible(model.base_link)} -> "
        f"{visible(model.tip_link)}); links, meshes and inertials as in {nominal}.",
        *notes,
    ]
    indent = root.text if root.text and not root.text.strip() else "\n  "
    for text in reversed(header):
        comment = etree.fromstring(f"<r>{xml_comment(text)}</r>", parser=parser)[0]
        comment.tail = indent
        root.insert(0, comment)
    before = reversed(list(root.itersiblings(preceding=True)))  # comments before the root
    prolog = "".join(str(etree.tostring(node, encoding="unicode")).strip() + "\n"
                     for node in before)  # fmt: skip
    body = str(etree.tostring(root, encoding="unicode"))
    return '<?xml version="1.0"?>\n' + prolog + body + "\n"


def _clean_axis(a: Mat) -> Mat:
    """A URDF axis as written: components within round-off of 0 made 0, unit length."""
    out = np.where(np.abs(a) <= 4 * np.finfo(float).eps, 0.0, a)
    unit: Mat = out / np.linalg.norm(out)
    return unit + 0.0


def _num(x: float) -> str:
    return repr(float(x) + 0.0)


def _checked(
    text: str, nominal: str, base: str, tip: str, model: PoeModel, tol: Tolerances, samples: int
) -> Check:
    """The written URDF read back, its chain's forward kinematics against the model's."""
    from ..io.urdf import parse_tree, tree_to_poe

    tree = parse_tree(text.encode("utf-8"), f"{nominal} (as written)")
    written = tree_to_poe(tree, base, tip)
    q = model.sample(samples, 11)
    pos, rot = se3.pose_errors(written.fk_batch(q), model.fk_batch(q))
    size = model.size()
    if not (pos <= tol.check_position * size and rot <= tol.check_rotation):
        raise ConversionError(
            f"urdf --like: the written URDF's forward kinematics deviates from the model's by "
            f"{pos:.3g} {visible(model.length_unit)} and {rot:.3g} rad (allowed "
            f"{tol.check_position * size:.3g}, {tol.check_rotation:.3g}); not written"
        )
    return Check(samples, pos, rot)


def _moves(
    path: list[UrdfJoint], origins: dict[str, Mat], size: float, tool_joint: str | None
) -> tuple[LinkMove, ...]:
    """How far each link of the chain moved from the nominal at home."""
    out = []
    before = after = np.eye(4)
    tool = False
    for j in path:
        tool = tool or j.name == tool_joint
        before = before @ j.origin
        after = after @ origins.get(j.name, j.origin)
        distance = float(np.linalg.norm(after[:3, 3] - before[:3, 3]))
        m = before[:3, :3].T @ after[:3, :3]
        angle = float(np.linalg.norm(log_so3(m)))  # exact near 0, where acos(trace) is not
        if distance > 1e-12 * size or angle > 1e-12:
            out.append(LinkMove(j.child, distance, angle, tool))
    return tuple(out)
