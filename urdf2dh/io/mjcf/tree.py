"""An MJCF document's bodies, joints and sites as a kinematic tree
(:class:`~urdf2dh.io.urdf.UrdfTree`), from which chains are taken as from a URDF's.

The links of the tree are the world (``world``), every body, every named site, and the frames
between a body's joints. Its edges:

* a body without joints hangs from its parent by a fixed edge: its ``pos`` and orientation, and
  those of the ``<frame>`` elements around it (MuJoCo's XML reference, "frame");
* a body's joints act in sequence, each about (or along) its own ``axis`` through its own
  ``pos``, both in the body's frame (and in the frames around the joint): the body moves by
  ``T(p1) M1(q1 - ref1) T(-p1) ... T(pn) Mn(qn - refn) T(-pn)`` after its ``pos`` and orientation,
  as MuJoCo's ``mj_kinematics`` moves it. Each joint is an edge whose frame sits at the joint's
  ``pos``, turned back by its ``ref``; a joint not at the body's origin, and every joint but
  a body's last, ends in a link of its own (named ``(joint frame)``) and the body follows by a
  fixed edge;
* a named site hangs from its body by a fixed edge (its ``pos`` and orientation, or its
  ``fromto``); a site sharing a body's name is the link ``site:NAME``.

A joint's position is MuJoCo's ``qpos``: zero where the joint's value is zero, not where the file
draws it (``ref``, MuJoCo's ``qpos0``). ``hinge`` joints are revolute (``continuous`` when not
limited), ``slide`` joints prismatic; ``ball`` and ``free`` joints are refused on a chain, as
URDF's floating joints are (a chain whose base lies below them is read). A joint's range limits
it where ``limited`` says so, or (``autolimits``, the default) where it has a range with its
first value below its second; hinge ranges are in the compiler's angle unit.

An ``<equality><joint joint1="a" joint2="b" polycoef="a0 a1 a2 a3 a4">`` that is active makes
``a`` follow ``b``: ``a - ref_a = a0 + a1 (b - ref_b) + a2 (b - ref_b)^2 + ...``. A linear one
(``a2 = a3 = a4 = 0``) is a mimic joint, ``q_a = a1 q_b + (ref_a + a0 - a1 ref_b)``; a joint held
by a polynomial of higher degree, or held still (no ``joint2``), is refused on a chain unless
``--ignore-mimic`` drives it on its own. Other equality constraints (``connect``, ``weld``,
``tendon``, ...) close loops or couple tendons and are not read: a chain is an open chain.

Unnamed bodies and joints are named ``(body N)`` and ``(joint N)`` with MuJoCo's index.
Geoms, inertials, cameras, lights, actuators, sensors, keyframes and assets are not read;
``<composite>``, ``<flexcomp>``, ``<replicate>`` and ``<attach>``, which make bodies urdf2dh
does not build, are refused naming the element.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...errors import InputError, shown
from ...geometry.se3 import rot_axis
from ...tolerances import JOINTS, LARGEST_URDF_ANGLE, LARGEST_URDF_NUMBER
from ..urdf.tree import UrdfJoint, UrdfTree, build_links
from ..urdf.validate import numbers
from .defaults import MAIN, Defaults
from .document import MjcfDocument
from .placement import AXISANGLE_LENGTH, EXTRINSIC_EULER, Compiler, Lookup, pose, read_compiler

__all__ = ["FEATURES", "WORLD", "Element", "MjcfElements", "build"]

Mat = NDArray[np.float64]

WORLD = "world"  # MuJoCo's name of the world body, the root of every tree

#: What a document may use that an oracle may read otherwise than MuJoCo (the Pinocchio oracle
#: keeps the list of those it does): feature -> what it is.
FEATURES = {
    "frame": "<frame> elements",
    EXTRINSIC_EULER: "euler angles with extrinsic axes (an uppercase letter in eulerseq)",
    AXISANGLE_LENGTH: "an axisangle whose axis is not of unit length",
    "compiler-order": "several <compiler> elements, or one after <worldbody>",
    "site-defaults": "a site placed by its default class (pos, orientation or fromto)",
    "site-fromto": "a site placed by fromto",
    "joint-pos-defaults": "a joint's pos from its default class",
    "unnamed-body": "an unnamed body",
}

#: Elements that make bodies or joints urdf2dh does not build: refused where they stand.
REFUSED = {
    "composite": "it generates bodies",
    "flexcomp": "it generates bodies",
    "replicate": "it repeats bodies",
    "attach": "it attaches another model",
}
JOINT_TYPES = ("hinge", "slide", "ball", "free")
_PLACEMENT = ("pos", "fromto", "quat", "axisangle", "euler", "xyaxes", "zaxis")
_X = np.array([1.0, 0.0, 0.0])  # the axis of a fixed edge (not read)
_X.setflags(write=False)


@dataclass(frozen=True, slots=True)
class Element:
    """What a link or joint of the tree is in the MJCF model (and so in MuJoCo's).

    Attributes
    ----------
    kind
        ``world``, ``body``, ``site``, or ``frame`` for a link urdf2dh made between a body's
        joints; a joint's type (``hinge``, ``slide``, ``ball``, ``free``), or ``fixed`` for an
        edge urdf2dh made.
    name
        Its name in the file (``None`` where it has none: urdf2dh named it).
    qpos
        A joint's first index in MuJoCo's ``qpos`` (``-1`` for the others).
    """

    kind: str
    name: str | None
    qpos: int = -1


@dataclass(frozen=True, slots=True)
class MjcfElements:
    """The tree's links and joints as the MJCF model's elements, and the features the document
    uses (:data:`FEATURES`): what an oracle reading the same file needs to find them.

    Attributes
    ----------
    links, joints
        Link or joint name in the tree -> :class:`Element`.
    nq
        The size of MuJoCo's ``qpos``.
    features
        The :data:`FEATURES` the document uses.
    """

    links: dict[str, Element]
    joints: dict[str, Element]
    nq: int
    features: frozenset[str]


def _translation(p: Mat) -> Mat:
    out = np.eye(4)
    out[:3, 3] = p
    return out


class _Builder:
    """One walk of the document's bodies (module docstring)."""

    def __init__(self, doc: MjcfDocument, display: str) -> None:
        self.display = display
        self.root = doc.root
        self.compiler: Compiler = read_compiler(doc.root, display)
        self.defaults = Defaults(doc.root, display)
        self.edges: list[UrdfJoint] = []
        self.links: dict[str, Element] = {}
        self.joints: dict[str, Element] = {}
        self.joint_names: dict[str, str] = {}  # name in the file -> the tree's joint
        self.refs: dict[str, float] = {}  # the tree's joint -> its ref (qpos units)
        self.features: set[str] = set()
        self.bodies = 0
        self.sites = 0
        self.mjcf_joints = 0
        self.nq = 0
        self.body_names = {el.get("name") for el in doc.root.iter("body") if el.get("name")}
        self._compiler_order()

    # ------------------------------------------------------------------ names

    def _link(self, wanted: str, element: Element) -> str:
        name = wanted
        while name in self.links or (element.kind != "body" and name in self.body_names):
            name = f"{element.kind}:{name}" if ":" not in name else f"{name}'"
        self.links[name] = element  # in the order met: the tree's link order
        return name

    def _edge_name(self, wanted: str) -> str:
        name = wanted
        while name in self.joints:
            name += "'"
        return name

    def where(self, el: Any, owner: str | None = None) -> str:
        """The file and element in messages."""
        name = el.get("name")
        if name:
            return f"{self.display}: {el.tag} {shown(name)}"
        place = f" of body {shown(owner)}" if owner else ""
        return f"{self.display}: an unnamed <{el.tag}>{place}"

    def _compiler_order(self) -> None:
        tags = [el.tag for el in self.root]
        compilers = [i for i, tag in enumerate(tags) if tag == "compiler"]
        later = [i for i, tag in enumerate(tags) if tag == "worldbody"]
        if len(compilers) > 1 or (compilers and later and compilers[0] > later[0]):
            self.features.add("compiler-order")

    # ------------------------------------------------------------------ the walk

    def build(self) -> list[UrdfJoint]:
        self._link(WORLD, Element("world", WORLD))
        for world in self.root.iterchildren("worldbody"):
            self._contents(world, WORLD, None, np.eye(4), MAIN)
        return self.edges

    def _contents(
        self,
        container: Any,
        body: str,
        parent: str | None,
        placed: Mat,
        childclass: str,
    ) -> None:
        """A body (or the world, without ``parent``) placed at ``placed`` in ``parent``: its
        joints between the two, then its sites and bodies, found through its frames."""
        joints: list[tuple[Any, Mat, str]] = []
        sites: list[tuple[Any, Mat, str]] = []
        bodies: list[tuple[Any, Mat, str]] = []
        self._collect(container, body, np.eye(4), childclass, joints, sites, bodies)
        if parent is None:
            if joints:
                raise InputError(f"{self.where(joints[0][0])}: the world body cannot have joints")
        else:
            self._joints(body, parent, placed, joints)
        for el, at, cls in sites:
            self._site(el, body, at, cls)
        for el, at, cls in bodies:
            self._body(el, body, at, cls)

    def _collect(
        self,
        container: Any,
        owner: str,
        frame: Mat,
        childclass: str,
        joints: list[tuple[Any, Mat, str]],
        sites: list[tuple[Any, Mat, str]],
        bodies: list[tuple[Any, Mat, str]],
    ) -> None:
        for el in container:
            tag = el.tag
            if tag == "frame":
                self.features.add("frame")
                where = f"{self.display}: a <frame> of body {shown(owner)}"
                inner = el.get("childclass")
                cls = (
                    childclass if inner is None else self.defaults.check(inner, where, "childclass")
                )
                at = frame @ pose(el.get, self.compiler, where, noted=self.features)
                self._collect(el, owner, at, cls, joints, sites, bodies)
            elif tag in ("joint", "freejoint"):
                joints.append((el, frame, childclass))
            elif tag == "site":
                sites.append((el, frame, childclass))
            elif tag == "body":
                bodies.append((el, frame, childclass))
            elif tag in REFUSED:
                raise InputError(
                    f"{self.display}: <{tag}> in body {shown(owner)} is not read ({REFUSED[tag]})"
                )

    def _body(self, el: Any, parent: str, frame: Mat, childclass: str) -> None:
        self.bodies += 1
        given = el.get("name")
        if not given:
            self.features.add("unnamed-body")
        if given and (given == WORLD or self.links.get(given, Element("", None)).kind == "body"):
            raise InputError(f"{self.display}: body {shown(given)} is declared twice")
        self._count()
        where = self.where(el)
        inner = el.get("childclass")
        cls = childclass if inner is None else self.defaults.check(inner, where, "childclass")
        placed = frame @ pose(el.get, self.compiler, where, noted=self.features)
        name = self._link(given or f"(body {self.bodies})", Element("body", given))
        self._contents(el, name, parent, placed, cls)

    def _count(self) -> None:
        """Refuse a model of more bodies and named sites than :data:`~urdf2dh.tolerances.JOINTS`
        + 1 (a URDF's bound on its links)."""
        if self.bodies + self.sites > JOINTS + 1:
            raise InputError(
                f"{self.display}: more than {JOINTS + 1:,} bodies and sites; urdf2dh reads MJCF "
                f"models of at most {JOINTS:,} joints and {JOINTS + 1:,} bodies and sites"
            )

    def _fixed(self, parent: str, child: str, origin: Mat, name: str) -> None:
        """An edge of no joint from ``parent`` to ``child``."""
        edge = self._edge_name(name)
        self.joints[edge] = Element("fixed", None)
        self.edges.append(UrdfJoint(edge, "fixed", parent, child, origin, _X, None, None, None))

    def _joints(
        self, body: str, parent: str, placed: Mat, joints: list[tuple[Any, Mat, str]]
    ) -> None:
        """The edges from ``parent`` to ``body``: fixed without joints, else one per joint
        (module docstring)."""
        if not joints:
            self._fixed(parent, body, placed, f"({body})")
            return
        origin, previous = placed, np.zeros(3)
        for k, (el, frame, cls) in enumerate(joints):
            get = self.defaults.lookup(el, cls, self.where(el, body))
            joint = self._joint(el, get, frame, body)
            last = k == len(joints) - 1
            child = body
            if not last or joint.anchor.any():
                child = self._link(f"({joint.name} frame)", Element("frame", None))
            step = _translation(joint.anchor - previous) @ joint.back
            self.edges.append(
                UrdfJoint(
                    joint.name,
                    joint.type,
                    parent,
                    child,
                    origin @ step,
                    joint.axis,
                    joint.lower,
                    joint.upper,
                    None,
                    refused=joint.refused,
                )
            )
            parent, origin, previous = child, np.eye(4), joint.anchor
        if parent != body:
            self._fixed(parent, body, _translation(-previous), f"({body} after its joints)")

    def _joint(self, el: Any, get: Lookup, frame: Mat, body: str) -> _Joint:
        """One joint of a body, in the body's frame."""
        where = self.where(el, body)
        kind = "free" if el.tag == "freejoint" else (get("type") or "hinge")
        if kind not in JOINT_TYPES:
            raise InputError(
                f"{where}: unknown type {shown(kind)}; valid: {', '.join(JOINT_TYPES)}"
            )
        self.mjcf_joints += 1
        if self.mjcf_joints > JOINTS:
            raise InputError(f"{self.display}: more than {JOINTS:,} joints; urdf2dh reads at most "
                             f"{JOINTS:,}")  # fmt: skip
        given = el.get("name")
        if given and given in self.joint_names:
            raise InputError(f"{where} is declared twice")
        name = self._edge_name(given or f"(joint {self.mjcf_joints - 1})")
        self.joint_names[given or name] = name
        self.joints[name] = Element(kind, given, self.nq)
        self.nq += {"free": 7, "ball": 4}.get(kind, 1)
        if "pos" not in el.attrib and get("pos") is not None:
            self.features.add("joint-pos-defaults")
        pos = numbers(get("pos") or "0 0 0", 3, "pos", where, LARGEST_URDF_NUMBER)
        anchor = frame[:3, :3] @ np.array(pos) + frame[:3, 3]
        axis = np.array([0.0, 0.0, 1.0])
        refused = None
        if kind in ("hinge", "slide"):
            values = numbers(get("axis") or "0 0 1", 3, "axis", where, LARGEST_URDF_NUMBER)
            norm = math.sqrt(sum(x * x for x in values))
            if not norm > 1e-15 or math.isinf(norm):  # MuJoCo's "axis too small"
                raise InputError(f"{where}: axis {shown(get('axis'))} has no direction")
            axis = frame[:3, :3] @ (np.array(values) / norm)
            axis /= math.sqrt(float(axis @ axis))
        else:
            refused = (
                f"is a {kind} joint ({'three turns' if kind == 'ball' else 'six motions'} in one); "
                "only hinge and slide joints have D-H rows (take --base below it)"
            )
        ref = 0.0
        if kind in ("hinge", "slide") and (text := get("ref")) is not None:
            ref = numbers(text, 1, "ref", where, LARGEST_URDF_NUMBER)[0]
            ref = self.compiler.angle(ref) if kind == "hinge" else ref
        self.refs[name] = ref
        back = np.eye(4)  # the joint frame at qpos = 0: turned back by ref from the file's pose
        if kind == "hinge":
            back[:3, :3] = rot_axis(axis, -ref)
        elif kind == "slide":
            back[:3, 3] = -ref * axis
        lower, upper, limited = self._limits(get, kind, where)
        urdf_type = {"hinge": "revolute" if limited else "continuous", "slide": "prismatic"}
        return _Joint(name, urdf_type.get(kind, "floating"), anchor, axis, back, lower, upper,
                      refused)  # fmt: skip

    def _limits(
        self, get: Lookup, kind: str, where: str
    ) -> tuple[float | None, float | None, bool]:
        """A hinge's or slide's limits (radians or length), and whether it is limited."""
        text = get("range")
        limited = get("limited") or "auto"
        if limited not in ("true", "false", "auto"):
            raise InputError(f"{where}: limited {shown(limited)} is not true, false or auto")
        if kind not in ("hinge", "slide") or limited == "false":
            return None, None, False
        if text is None:
            if limited == "true":
                raise InputError(f"{where} is limited but has no range")
            return None, None, False
        if limited == "auto" and not self.compiler.autolimits:
            raise InputError(
                f"{where} has a range but no limited attribute, and <compiler autolimits="
                '"false"> (MuJoCo refuses that; give limited="true" or "false")'
            )
        bound = LARGEST_URDF_ANGLE if kind == "hinge" else LARGEST_URDF_NUMBER
        lower, upper = numbers(text, 2, "range", where, LARGEST_URDF_NUMBER)
        if kind == "hinge":
            lower, upper = self.compiler.angle(lower), self.compiler.angle(upper)
        if max(abs(lower), abs(upper)) > bound:
            raise InputError(f"{where}: range {shown(text)} is beyond ±{bound:g} rad")
        if not lower < upper:
            if limited == "true":
                raise InputError(f"{where}: range {shown(text)} does not run from low to high")
            return None, None, False  # MuJoCo's autolimits: no limits
        return lower, upper, True

    def _site(self, el: Any, body: str, frame: Mat, cls: str) -> None:
        given = el.get("name")
        if not given:
            return  # an unnamed site is no frame anyone can name
        self.sites += 1
        self._count()
        where = self.where(el)
        get = self.defaults.lookup(el, cls, where)
        if any(a not in el.attrib and get(a) is not None for a in _PLACEMENT):
            self.features.add("site-defaults")
        if get("fromto") is not None:
            self.features.add("site-fromto")
        at = frame @ pose(get, self.compiler, where, fromto=True, noted=self.features)
        name = self._link(given, Element("site", given))
        self._fixed(body, name, at, f"({name})")

    # ------------------------------------------------------------------ equality

    def couple(self) -> None:
        """Mimic relations from the active joint equalities (module docstring)."""
        by_name = {e.name: i for i, e in enumerate(self.edges)}
        followed: set[str] = set()
        for group in self.root.iterchildren("equality"):
            for el in group.iterchildren("joint"):
                self._coupling(el, by_name, followed)

    def _coupling(self, el: Any, by_name: dict[str, int], followed: set[str]) -> None:
        where = self.where(el) if el.get("name") else f"{self.display}: <equality><joint>"
        get = self.defaults.lookup(el, el.get("class") or MAIN, where)
        if (get("active") or "true") == "false":
            return
        names = []
        for attr in ("joint1", "joint2"):
            given = el.get(attr)
            if given is not None and given not in self.joint_names:
                raise InputError(f"{where}: {attr} {shown(given)} is no joint")
            names.append(None if given is None else self.joint_names[given])
        follower, leader = names
        if follower is None:
            raise InputError(f"{where} has no joint1")
        coefficients = [0.0, 1.0, 0.0, 0.0, 0.0]
        if (text := el.get("polycoef")) is not None:
            pieces = text.split()
            if not 1 <= len(pieces) <= 5:
                raise InputError(f"{where}: polycoef {shown(text)} is not 1 to 5 numbers")
            given_values = numbers(text, len(pieces), "polycoef", where, LARGEST_URDF_NUMBER)
            coefficients[: len(given_values)] = given_values
        if follower in followed:
            raise InputError(f"{where}: joint {shown(follower)} follows two equality constraints")
        followed.add(follower)
        edge = self.edges[by_name[follower]]
        kinds = {self.joints[n].kind for n in (follower, leader) if n is not None}
        if not kinds <= {"hinge", "slide"} or follower == leader:
            raise InputError(f"{where} couples {', '.join(sorted(kinds))} joints; MuJoCo couples "
                             "two different hinge or slide joints")  # fmt: skip
        a0, a1, *higher = coefficients
        if leader is None or any(higher):
            held = (
                f"is held at {a0:g} from its ref by an <equality><joint> without joint2"
                if leader is None
                else f"follows {shown(leader)} by a polynomial of degree "
                f"{max(i + 2 for i, a in enumerate(higher) if a)} (polycoef {shown(text)})"
            )
            refused = f"{held}; only linear couplings are mimic joints"
            self.edges[by_name[follower]] = replace(edge, refused=refused, refused_coupling=True)
            return
        offset = self.refs[follower] + a0 - a1 * self.refs[leader]
        self.edges[by_name[follower]] = replace(edge, mimic=leader, multiplier=a1, offset=offset)


@dataclass(frozen=True, slots=True)
class _Joint:
    """One MJCF joint in its body's frame."""

    name: str
    type: str
    anchor: Mat  # (3,) its pos
    axis: Mat  # (3,) unit
    back: Mat  # (4, 4) its motion by -ref
    lower: float | None
    upper: float | None
    refused: str | None


def build(doc: MjcfDocument, path: Path, display: str) -> tuple[UrdfTree, MjcfElements]:
    """The kinematic tree of an MJCF document, and its links and joints as the model's elements.

    Raises
    ------
    InputError
        One line naming the file and the element at fault.
    """
    builder = _Builder(doc, display)
    builder.build()
    builder.couple()
    name = doc.root.get("model") or path.stem
    tree = build_links(name, display, tuple(builder.links), builder.edges, doc.text())
    elements = MjcfElements(dict(builder.links), dict(builder.joints), builder.nq,
                            frozenset(builder.features))  # fmt: skip
    return tree, elements
