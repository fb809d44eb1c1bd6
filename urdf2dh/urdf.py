"""URDF -> kinematic tree -> serial chain -> POE model. The only module that reads URDF XML.

The file is parsed by lxml once and checked element by element (so a bad value is reported
with the joint or link that carries it), then loaded with yourdfpy, which supplies the joint
origins, axes, limits and mimic relations. Meshes are never loaded: a URDF whose mesh files are
absent loads all the same.
"""

from __future__ import annotations

import io
import logging
import math
import re
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from . import frames, se3
from .errors import ChainError, InputError, choices
from .files import read_file
from .screws import Joint, JointKind, PoeModel

__all__ = ["UrdfJoint", "UrdfTree", "load_tree", "parse_tree", "tree_to_poe"]

MOVABLE: dict[str, JointKind] = {
    "revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic"
}
KNOWN_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
_IDENTITY = np.eye(4)  # a joint without <origin>, shared read-only
_IDENTITY.setflags(write=False)
_X_AXIS = np.array([1.0, 0.0, 0.0])  # URDF's default axis, shared read-only
_X_AXIS.setflags(write=False)


class UrdfJoint(NamedTuple):
    """A URDF joint as the chain walk needs it (origin is the 4x4 parent->child transform).

    A named tuple, not a dataclass: one is made per joint of every file read, and a frozen
    dataclass takes four times as long to make."""

    name: str
    type: str
    parent: str
    child: str
    origin: NDArray[np.float64]
    axis: NDArray[np.float64]
    lower: float | None
    upper: float | None
    mimic: str | None
    multiplier: float = 1.0
    offset: float = 0.0


@dataclass(frozen=True)
class UrdfTree:
    """The kinematic tree of one URDF file."""

    name: str
    path: str
    links: tuple[str, ...]
    joints: dict[str, UrdfJoint]
    parent_joint: dict[str, UrdfJoint]
    children: dict[str, tuple[UrdfJoint, ...]]
    root: str

    def depth(self, link: str) -> int:
        """Number of joints between the root and ``link``."""
        n = 0
        while link in self.parent_joint:
            link = self.parent_joint[link].parent
            n += 1
        return n

    def subtree(self, link: str) -> list[str]:
        """``link`` and every link below it."""
        out, stack, children = [], [link], self.children
        while stack:
            cur = stack.pop()
            out.append(cur)
            for j in children.get(cur, ()):
                stack.append(j.child)
        return out

    def leaves(self, below: str | None = None) -> list[str]:
        """Links without children, optionally only those in the subtree of ``below``."""
        return sorted(k for k in self.subtree(below or self.root) if k not in self.children)

    def default_tip(self, base: str) -> str:
        """The single deepest leaf below ``base`` (SPEC §1); ties are an error listing them."""
        leaves = self.leaves(base)
        depths = {leaf: self.depth(leaf) for leaf in leaves}
        deepest = max(depths.values())
        tied = [leaf for leaf, d in depths.items() if d == deepest]
        if len(tied) > 1:
            raise ChainError(
                f"{self.path}: several leaves tie as the deepest below '{base}': "
                f"{choices(tied)}; choose one with --tip"
            )
        return tied[0]

    def chain(self, base: str, tip: str) -> list[UrdfJoint]:
        """The joints from ``base`` down to ``tip`` (fixed ones included), base first."""
        for role, link in (("base", base), ("tip", tip)):
            if link not in self.children and link not in self.parent_joint and link != self.root:
                raise ChainError(
                    f"{self.path}: unknown {role} link '{link}'; links are {choices(self.links)}"
                )
        out: list[UrdfJoint] = []
        link = tip
        while link != base:
            if link not in self.parent_joint:
                raise ChainError(
                    f"{self.path}: tip link '{tip}' is not below base link '{base}' "
                    f"(links below '{base}' end in {choices(self.leaves(base))})"
                )
            joint = self.parent_joint[link]
            out.append(joint)
            link = joint.parent
        out.reverse()
        return out


# --------------------------------------------------------------------------- reading and checking


def _floats(text: str | None, count: int, what: str, where: str) -> list[float] | None:
    if text is None:
        return None
    try:
        values = list(map(float, text.split()))
    except ValueError as e:
        raise InputError(f"{where}: {what} '{text}' is not {count} numbers") from e
    if len(values) != count:
        raise InputError(f"{where}: {what} '{text}' is not {count} numbers")
    if not all(map(math.isfinite, values)):
        raise InputError(f"{where}: {what} '{text}' is not finite")
    return values


def _check_xml(root: Any, display: str) -> None:
    """Check every element the chain walk relies on, naming the joint or link at fault."""
    if root.tag != "robot":
        raise InputError(f"{display}: not a URDF robot (root element is <{root.tag}>)")
    if not root.get("name"):
        raise InputError(f"{display}: <robot> has no name attribute")
    links: set[str] = set()
    for el in root.iterchildren("link"):
        name = el.get("name")
        if not name:
            raise InputError(f"{display}: a <link> has no name attribute")
        if name in links:
            raise InputError(f"{display}: link '{name}' is declared twice")
        links.add(name)
    if not links:
        raise InputError(f"{display}: robot '{root.get('name')}' declares no links")
    joints: set[str] = set()
    for el in root.iterchildren("joint"):
        name = el.get("name")
        if not name:
            raise InputError(f"{display}: a <joint> has no name attribute")
        where = f"{display}: joint '{name}'"
        if name in joints:
            raise InputError(f"{where} is declared twice")
        joints.add(name)
        jtype = el.get("type")
        if jtype not in KNOWN_TYPES:
            raise InputError(f"{where} has unknown type '{jtype}'; valid: {choices(KNOWN_TYPES)}")
        sub: dict[Any, Any] = {}
        for child in el:  # one pass; the first of each tag counts, as with find()
            sub.setdefault(child.tag, child)
        for role in ("parent", "child"):
            link = sub[role].get("link") if role in sub else None
            if not link:
                raise InputError(f"{where} has no <{role} link=...>")
            if link not in links:
                raise InputError(f"{where} names undeclared link '{link}' as its {role}")
        if "origin" in sub:
            _floats(sub["origin"].get("xyz"), 3, "origin xyz", where)
            _floats(sub["origin"].get("rpy"), 3, "origin rpy", where)
        if "axis" in sub:
            xyz = _floats(sub["axis"].get("xyz"), 3, "axis xyz", where)
            if xyz is not None and jtype in MOVABLE and not any(xyz):
                raise InputError(f"{where} has a zero axis")
        if "limit" in sub:
            for attr in ("lower", "upper"):
                _floats(sub["limit"].get(attr), 1, f"limit {attr}", where)
        if "mimic" in sub and not sub["mimic"].get("joint"):
            raise InputError(f"{where} has a <mimic> without a joint attribute")


def parse_tree(data: bytes, display: str) -> UrdfTree:
    """Parse URDF text into a checked :class:`UrdfTree` (``display`` names it in messages).

    yourdfpy parses the text and :func:`_tree_from_robot` checks what it made; only when either
    fails does our own pass over the XML (:func:`_checked_name`) run, to name the joint or link
    at fault. A sound file is parsed once.
    """
    if not data.strip():
        raise InputError(f"{display}: empty file")
    if b"\x00" in data[:4096]:
        raise InputError(f"{display}: binary file, not URDF XML")
    robot = None
    if _root_tag(data) == b"robot":
        try:
            robot = _yourdfpy_robot(data, display)
        except InputError:
            robot = None
    return _tree_of(data, robot, display)


def _tree_of(data: bytes, robot: Any, display: str) -> UrdfTree:
    """Our part of :func:`parse_tree`, given yourdfpy's ``Robot`` of ``data`` (``None`` if it
    could not make one): check it and build the tree; on any doubt, our XML pass names the
    fault (and if it finds none, yourdfpy's own complaint stands)."""
    if robot is not None:
        try:
            return _tree_from_robot(robot, display, str(robot.name))
        except _Unsound:
            pass
    name = _checked_name(data, display)  # raises, naming the fault, if it finds one
    return _tree_from_robot(_yourdfpy_robot(data, display), display, name)


_ROOT = re.compile(
    rb"\s*(?:<\?.*?\?>\s*|<!--.*?-->\s*|<!DOCTYPE[^>]*>\s*)*<([A-Za-z_][\w:.-]*)", re.S
)


def _root_tag(data: bytes) -> bytes | None:
    """The root element's tag, read off the text (``None`` if it does not look like XML)."""
    m = _ROOT.match(data)
    return m.group(1) if m else None


def _checked_name(data: bytes, display: str) -> str:
    """Our own pass over the text (lxml, :func:`_check_xml`); returns the robot's name."""
    from lxml import etree

    if not data.strip():
        raise InputError(f"{display}: empty file")
    if b"\x00" in data[:4096]:
        raise InputError(f"{display}: binary file, not URDF XML")
    try:
        root = etree.fromstring(data, parser=etree.XMLParser(remove_comments=True))
    except etree.XMLSyntaxError as e:
        raise InputError(f"{display}: malformed XML ({e})") from e
    _check_xml(root, display)
    return str(root.get("name"))


def load_tree(path: str | Path, display: str | None = None) -> UrdfTree:
    """Read and check a URDF file."""
    path = Path(path)
    return parse_tree(read_file(path, display or str(path)), display or str(path))


class _Errors(logging.Handler):
    """Collects what yourdfpy logs as errors: it logs a failed strict parse, then recovers."""

    def __init__(self) -> None:
        super().__init__(logging.ERROR)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


def _yourdfpy_robot(data: bytes, display: str) -> Any:
    """yourdfpy's ``Robot`` of the text (joint origins, axes, limits, mimic; no meshes).

    yourdfpy parses strictly and, if that fails, logs the error and parses again recovering
    what it can; a recovered parse is malformed XML to us, and its log stays off the terminal.
    """
    import yourdfpy

    log = logging.getLogger("yourdfpy.urdf")
    errors, propagate = _Errors(), log.propagate
    log.addHandler(errors)
    log.propagate = False
    try:  # non-finite values make its matrix code warn; our checks report them instead
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            urdf = yourdfpy.URDF.load(
                io.BytesIO(data),
                build_scene_graph=False,
                build_collision_scene_graph=False,
                load_meshes=False,
                load_collision_meshes=False,
            )
    except Exception as e:  # yourdfpy raises many kinds
        raise InputError(f"{display}: yourdfpy cannot load it ({type(e).__name__}: {e})") from e
    finally:
        log.removeHandler(errors)
        log.propagate = propagate
    if errors.messages:
        raise InputError(f"{display}: malformed XML ({errors.messages[0]})")
    return urdf.robot


class _Unsound(InputError):
    """yourdfpy's objects break what :func:`_check_xml` guarantees (the XML pass says what)."""


def _tree_from_robot(robot: Any, display: str, name: str) -> UrdfTree:
    """The :class:`UrdfTree` of a yourdfpy ``Robot`` (its joints and links), checked in the same
    pass for what :func:`_check_xml` guarantees (cheap: no second parse). A failed check raises
    :class:`_Unsound`, which only says *that* something is wrong; the XML pass then says what.
    A tree that is not one (a loop, several roots) is reported once the checks pass."""
    problem = f"{display}: not a sound URDF"
    links = tuple(link.name for link in robot.links)
    declared = set(links)
    if not robot.name or not links or not all(links) or len(declared) != len(links):
        raise _Unsound(problem)
    joints: dict[str, UrdfJoint] = {}
    parent_joint: dict[str, UrdfJoint] = {}
    children: dict[str, list[UrdfJoint]] = {}
    origins: list[NDArray[np.float64]] = []
    loop: tuple[str, str, str] | None = None  # the first link with two parent joints
    for j in robot.joints:
        jname, jtype, parent, child, limit, mimic = (
            j.name, j.type, j.parent, j.child, j.limit, j.mimic
        )
        if (not jname or jname in joints or jtype not in KNOWN_TYPES or parent not in declared
                or child not in declared):
            raise _Unsound(problem)
        origin = _IDENTITY
        if j.origin is not None:
            origin = np.asarray(j.origin, dtype=float)
            origins.append(origin)
        axis = _X_AXIS
        if j.axis is not None:
            axis = np.asarray(j.axis, dtype=float)
            if jtype in MOVABLE:  # a 3-vector, finite, not zero
                if axis.shape != (3,):
                    raise _Unsound(problem)
                x, y, z = axis.tolist()
                if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)
                        and (x or y or z)):
                    raise _Unsound(problem)
        lower = upper = None
        if limit is not None:
            lo = None if limit.lower is None else float(limit.lower)
            up = None if limit.upper is None else float(limit.upper)
            if (lo is not None and not math.isfinite(lo)) or (
                up is not None and not math.isfinite(up)
            ):
                raise _Unsound(problem)
            if jtype != "continuous":
                lower, upper = lo, up
        if mimic is not None and not mimic.joint:
            raise _Unsound(problem)
        uj = UrdfJoint(
            jname, jtype, parent, child, origin, axis, lower, upper,
            None if mimic is None else mimic.joint,
            1.0 if mimic is None or mimic.multiplier is None else float(mimic.multiplier),
            0.0 if mimic is None or mimic.offset is None else float(mimic.offset),
        )
        joints[jname] = uj
        if child in parent_joint:
            loop = loop or (child, parent_joint[child].name, jname)
            continue
        parent_joint[child] = uj
        children.setdefault(parent, []).append(uj)
    try:  # all origins 4x4 and finite: one array for them all
        o = np.array(origins) if origins else np.zeros((0, 4, 4))
    except ValueError as e:  # ragged: some element has the wrong number of values
        raise _Unsound(problem) from e
    if o.shape[1:] != (4, 4) or not np.isfinite(o).all():
        raise _Unsound(problem)
    if loop is not None:
        raise InputError(
            f"{display}: link '{loop[0]}' is the child of both joint '{loop[1]}' and joint "
            f"'{loop[2]}' (a kinematic loop; URDF describes trees only)"
        )
    roots = [link for link in links if link not in parent_joint]
    if not roots:
        raise InputError(f"{display}: every link has a parent joint (a kinematic loop)")
    if len(roots) > 1:
        raise InputError(
            f"{display}: several root links {choices(roots)}; a URDF is a single tree"
        )
    tree = UrdfTree(
        name, display, links, joints, parent_joint,
        {k: tuple(v) for k, v in children.items()}, roots[0],
    )
    reached = tree.subtree(roots[0])  # each link at most once: it has at most one parent
    if len(reached) != len(links):
        unreached = [link for link in links if link not in set(reached)]
        raise InputError(
            f"{display}: links {choices(unreached)} are not connected to root '{roots[0]}' "
            "(a kinematic loop)"
        )
    return tree


# --------------------------------------------------------------------------- chain -> POE


class _Movable(NamedTuple):
    name: str
    kind: JointKind
    axis: frames.Vec3
    point: frames.Vec3
    pitch: float
    lower: float | None
    upper: float | None


def _helical_lead(uj: UrdfJoint, axis: frames.Vec3, movable: list[_Movable]) -> float | None:
    """The pitch, if ``uj`` is the lead of a helical joint as urdf2dh writes one: a prismatic
    joint mimicking the revolute joint just before it on the chain (offset 0), along its axis."""
    if uj.type != "prismatic" or uj.mimic is None or uj.offset != 0.0 or not movable:
        return None
    prev = movable[-1]
    if prev.name != uj.mimic or prev.kind != "revolute":
        return None
    cos = sum(a * b for a, b in zip(axis, prev.axis, strict=True))
    if abs(abs(cos) - 1.0) > 1e-12:
        return None
    return uj.multiplier * (1.0 if cos > 0 else -1.0)


def tree_to_poe(
    tree: UrdfTree,
    base: str | None = None,
    tip: str | None = None,
    ignore_mimic: bool = False,
    name: str | None = None,
) -> PoeModel:
    """Walk from ``base`` to ``tip``, fold fixed joints, and build the POE model.

    ``base`` defaults to the root link and ``tip`` to the single deepest leaf (SPEC §1).
    Each movable joint's axis and origin at the home pose, expressed in the base frame, give its
    screw: direction ``R axis`` through the joint frame's origin.
    """
    base = base or tree.root
    if base not in tree.links:
        raise ChainError(
            f"{tree.path}: unknown base link '{base}'; links are {choices(tree.links)}"
        )
    tip = tip or tree.default_tip(base)
    path = tree.chain(base, tip)
    t = frames.IDENTITY  # the joint frame at the home pose, in the base frame
    movable: list[_Movable] = []
    warnings: list[str] = []
    for uj in path:
        t = frames.compose(t, frames.frame_of(uj.origin))
        if uj.type in ("floating", "planar"):
            raise ChainError(
                f"{tree.path}: joint '{uj.name}' on the chain '{base}' -> '{tip}' is "
                f"{uj.type}; only revolute, continuous, prismatic and fixed joints have D-H rows"
            )
        if uj.type == "fixed":
            continue
        axis = frames.unit(frames.rotate(t, frames.unit(uj.axis.tolist())))
        if uj.mimic is not None:
            lead = _helical_lead(uj, axis, movable)
            if lead is not None:  # revolute + coaxial prismatic mimicking it = one helical joint
                movable[-1] = movable[-1]._replace(kind="helical", pitch=lead)
                continue
            if not ignore_mimic:
                raise ChainError(
                    f"{tree.path}: joint '{uj.name}' on the chain mimics joint '{uj.mimic}'; "
                    "pass --ignore-mimic to treat it as an independent joint"
                )
            warnings.append(
                f"joint '{uj.name}' mimics '{uj.mimic}' in the URDF; treated as an independent "
                "joint (--ignore-mimic)"
            )
        kind: JointKind = MOVABLE[uj.type]
        movable.append(_Movable(uj.name, kind, axis, (t[0][3], t[1][3], t[2][3]), 0.0,
                                uj.lower, uj.upper))
    # the joints' axes and points: rows of two read-only arrays (two array calls, not 2 n)
    axes = np.array([m.axis for m in movable], dtype=float).reshape(-1, 3)
    points = np.array([m.point for m in movable], dtype=float).reshape(-1, 3)
    axes.setflags(write=False)
    points.setflags(write=False)
    joints = [
        Joint(m.name, m.kind, axis, point, m.pitch, 1.0, m.lower, m.upper)
        for m, axis, point in zip(movable, axes, points, strict=True)
    ]
    home = se3.matrix_of(t)
    home.setflags(write=False)  # the model's own: no copy
    return PoeModel(
        tuple(joints), home, name or tree.name, tree.path, base, tip, "m", tuple(warnings)
    )
