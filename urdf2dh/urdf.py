"""URDF -> kinematic tree -> serial chain -> POE model. The only module that reads URDF XML.

The file is parsed by lxml once and checked element by element (so a bad value is reported
with the joint or link that carries it), then loaded with yourdfpy, which supplies the joint
origins, axes, limits and mimic relations. Meshes are never loaded: a URDF whose mesh files are
absent loads all the same.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .errors import ChainError, InputError, choices
from .files import read_file
from .screws import Joint, JointKind, PoeModel

__all__ = ["UrdfJoint", "UrdfTree", "load_tree", "parse_tree", "tree_to_poe"]

MOVABLE = {"revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic"}
KNOWN_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")


@dataclass(frozen=True)
class UrdfJoint:
    """A URDF joint as the chain walk needs it (origin is the 4x4 parent->child transform)."""

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
        out, stack = [], [link]
        while stack:
            cur = stack.pop()
            out.append(cur)
            stack.extend(j.child for j in self.children.get(cur, ()))
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
    parts = text.split()
    try:
        values = [float(p) for p in parts]
    except ValueError as e:
        raise InputError(f"{where}: {what} '{text}' is not {count} numbers") from e
    if len(values) != count:
        raise InputError(f"{where}: {what} '{text}' is not {count} numbers")
    if not all(math.isfinite(v) for v in values):
        raise InputError(f"{where}: {what} '{text}' is not finite")
    return values


def _check_xml(root: Any, display: str) -> None:
    """Check every element the chain walk relies on, naming the joint or link at fault."""
    if root.tag != "robot":
        raise InputError(f"{display}: not a URDF robot (root element is <{root.tag}>)")
    if not root.get("name"):
        raise InputError(f"{display}: <robot> has no name attribute")
    links: set[str] = set()
    for el in root.findall("link"):
        name = el.get("name")
        if not name:
            raise InputError(f"{display}: a <link> has no name attribute")
        if name in links:
            raise InputError(f"{display}: link '{name}' is declared twice")
        links.add(name)
    if not links:
        raise InputError(f"{display}: robot '{root.get('name')}' declares no links")
    joints: set[str] = set()
    for el in root.findall("joint"):
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
        for role in ("parent", "child"):
            sub = el.find(role)
            link = sub.get("link") if sub is not None else None
            if not link:
                raise InputError(f"{where} has no <{role} link=...>")
            if link not in links:
                raise InputError(f"{where} names undeclared link '{link}' as its {role}")
        origin = el.find("origin")
        if origin is not None:
            _floats(origin.get("xyz"), 3, "origin xyz", where)
            _floats(origin.get("rpy"), 3, "origin rpy", where)
        axis = el.find("axis")
        if axis is not None:
            xyz = _floats(axis.get("xyz"), 3, "axis xyz", where)
            if xyz is not None and jtype in MOVABLE and not any(xyz):
                raise InputError(f"{where} has a zero axis")
        limit = el.find("limit")
        if limit is not None:
            for attr in ("lower", "upper"):
                _floats(limit.get(attr), 1, f"limit {attr}", where)
        mimic = el.find("mimic")
        if mimic is not None and not mimic.get("joint"):
            raise InputError(f"{where} has a <mimic> without a joint attribute")


def parse_tree(data: bytes, display: str) -> UrdfTree:
    """Parse URDF text into a checked :class:`UrdfTree` (``display`` names it in messages)."""
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
    return _from_yourdfpy(data, display, root.get("name"))


def load_tree(path: str | Path, display: str | None = None) -> UrdfTree:
    """Read and check a URDF file."""
    path = Path(path)
    return parse_tree(read_file(path, display or str(path)), display or str(path))


def _from_yourdfpy(data: bytes, display: str, name: str) -> UrdfTree:
    import yourdfpy

    try:
        urdf = yourdfpy.URDF.load(
            io.BytesIO(data),
            build_scene_graph=False,
            build_collision_scene_graph=False,
            load_meshes=False,
            load_collision_meshes=False,
        )
    except Exception as e:  # yourdfpy raises many kinds; our checks ran first
        raise InputError(f"{display}: yourdfpy cannot load it ({type(e).__name__}: {e})") from e
    robot = urdf.robot
    joints: dict[str, UrdfJoint] = {}
    parent_joint: dict[str, UrdfJoint] = {}
    children: dict[str, list[UrdfJoint]] = {}
    for j in robot.joints:
        origin = np.eye(4) if j.origin is None else np.asarray(j.origin, dtype=float)
        axis = np.array([1.0, 0.0, 0.0]) if j.axis is None else np.asarray(j.axis, dtype=float)
        if not (np.all(np.isfinite(origin)) and np.all(np.isfinite(axis))):
            raise InputError(f"{display}: joint '{j.name}' has a non-finite origin or axis")
        lower = upper = None
        if j.limit is not None and j.type != "continuous":
            lower = None if j.limit.lower is None else float(j.limit.lower)
            upper = None if j.limit.upper is None else float(j.limit.upper)
        mimic = j.mimic
        uj = UrdfJoint(
            j.name, j.type, j.parent, j.child, origin, axis, lower, upper,
            None if mimic is None else mimic.joint,
            1.0 if mimic is None or mimic.multiplier is None else float(mimic.multiplier),
            0.0 if mimic is None or mimic.offset is None else float(mimic.offset),
        )
        if uj.child in parent_joint:
            other = parent_joint[uj.child].name
            raise InputError(
                f"{display}: link '{uj.child}' is the child of both joint '{other}' and joint "
                f"'{uj.name}' (a kinematic loop; URDF describes trees only)"
            )
        joints[uj.name] = uj
        parent_joint[uj.child] = uj
        children.setdefault(uj.parent, []).append(uj)
    links = tuple(link.name for link in robot.links)
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
    reached = set(tree.subtree(roots[0]))
    unreached = [link for link in links if link not in reached]
    if unreached:
        raise InputError(
            f"{display}: links {choices(unreached)} are not connected to root '{roots[0]}' "
            "(a kinematic loop)"
        )
    return tree


# --------------------------------------------------------------------------- chain -> POE


def _helical_lead(uj: UrdfJoint, axis: NDArray[np.float64], joints: list[Joint]) -> float | None:
    """The pitch, if ``uj`` is the lead of a helical joint as urdf2dh writes one: a prismatic
    joint mimicking the revolute joint just before it on the chain (offset 0), along its axis."""
    if uj.type != "prismatic" or uj.mimic is None or uj.offset != 0.0 or not joints:
        return None
    prev = joints[-1]
    if prev.name != uj.mimic or prev.kind != "revolute":
        return None
    cos = float(axis @ prev.axis)
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
    t = np.eye(4)
    joints: list[Joint] = []
    warnings: list[str] = []
    for uj in path:
        t = t @ uj.origin
        if uj.type in ("floating", "planar"):
            raise ChainError(
                f"{tree.path}: joint '{uj.name}' on the chain '{base}' -> '{tip}' is "
                f"{uj.type}; only revolute, continuous, prismatic and fixed joints have D-H rows"
            )
        if uj.type == "fixed":
            continue
        norm = float(np.linalg.norm(uj.axis))
        axis = t[:3, :3] @ (uj.axis / norm)
        axis /= np.linalg.norm(axis)
        lead = _helical_lead(uj, axis, joints)
        if lead is not None:  # revolute + coaxial prismatic mimicking it = one helical joint
            prev = joints[-1]
            joints[-1] = Joint(prev.name, "helical", prev.axis, prev.point, lead, 1.0,
                               prev.lower, prev.upper)
            continue
        if uj.mimic is not None:
            if not ignore_mimic:
                raise ChainError(
                    f"{tree.path}: joint '{uj.name}' on the chain mimics joint '{uj.mimic}'; "
                    "pass --ignore-mimic to treat it as an independent joint"
                )
            warnings.append(
                f"joint '{uj.name}' mimics '{uj.mimic}' in the URDF; treated as an independent "
                "joint (--ignore-mimic)"
            )
        kind: JointKind = MOVABLE[uj.type]  # type: ignore[assignment]
        joints.append(Joint(uj.name, kind, axis, t[:3, 3].copy(), 0.0, 1.0, uj.lower, uj.upper))
    return PoeModel(
        tuple(joints), t, name or tree.name, tree.path, base, tip, "m", tuple(warnings)
    )
