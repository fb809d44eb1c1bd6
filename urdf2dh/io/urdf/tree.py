"""The kinematic tree of a URDF file: its links, its joints, and who hangs below whom.

:func:`build_tree` makes a :class:`UrdfTree` from yourdfpy's ``Robot`` of a document that
:func:`urdf2dh.io.urdf.validate.check_robot` has passed, so it trusts names, links and numbers and
checks only what a tree must be: each link the child of at most one joint, one root, every link
reached from it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...errors import ChainError, InputError, Remedy, choices, near, shown
from .validate import JOINT_TYPES, MOVING_TYPES

__all__ = ["UrdfJoint", "UrdfTree", "build_links", "build_tree", "names"]

Mat = NDArray[np.float64]

_IDENTITY = np.eye(4)  # a joint without <origin>, shared read-only
_IDENTITY.setflags(write=False)


def names(items: Iterable[str], limit: int = 12) -> str:
    """Names from a file, listed for a message with ``repr``-style escapes (one line)."""
    return choices(items, limit, quoted=True)


def _read_only(a: Mat) -> Mat:
    a.setflags(write=False)
    return a


@dataclass(frozen=True, slots=True)
class UrdfJoint:
    """A URDF joint as the chain walk needs it.

    Attributes
    ----------
    name, type, parent, child
        As in the file (``type`` one of :data:`~urdf2dh.io.urdf.validate.JOINT_TYPES`).
    origin
        ``(4, 4)`` read-only transform from the parent link's frame to the joint's frame.
    axis
        ``(3,)`` read-only: the unit axis in the joint's frame for a moving joint (normalised as
        urdfdom does); as written for the other types.
    lower, upper
        Position limits of a revolute or prismatic joint (``None`` for the other types, and
        where the file has no ``<limit>``); ``lower <= upper``.
    mimic, multiplier, offset
        The joint this one mimics (``None`` if none): ``q = multiplier * q_mimic + offset``.
    swapped
        The file's ``<limit>`` has ``lower`` above ``upper``: they are read as the range between
        them (as Gazebo's URDF reader reads them), and the chain's model warns of it.
    refused
        Why a chain may not hold this joint, beyond its type (an MJCF ball joint, a coupling no
        mimic relation describes), said after its name; ``None`` where it may.
    refused_coupling
        Whether ``refused`` is about how the joint is coupled to another: treating mimic joints
        as independent (``ignore_mimic``) then lifts it.
    """

    name: str
    type: str
    parent: str
    child: str
    origin: Mat
    axis: Mat
    lower: float | None
    upper: float | None
    mimic: str | None
    multiplier: float = 1.0
    offset: float = 0.0
    swapped: bool = False
    refused: str | None = None
    refused_coupling: bool = False

    def __post_init__(self) -> None:
        if self.type not in JOINT_TYPES:
            raise ValueError(f"joint {shown(self.name)}: unknown type {shown(self.type)}")
        if self.origin.shape != (4, 4) or self.axis.shape != (3,):
            raise ValueError(f"joint {shown(self.name)}: origin must be (4, 4) and axis (3,)")


@dataclass(frozen=True, slots=True)
class UrdfTree:
    """The kinematic tree of one URDF file (or of an MJCF file's bodies,
    :mod:`urdf2dh.io.mjcf`).

    Attributes
    ----------
    name
        The robot's name.
    path
        The file's name in messages.
    links
        Link names in file order.
    joints
        Joint name -> joint, in file order.
    parent_joint
        Link name -> the joint it is the child of (every link but the root).
    children
        Link name -> the joints it is the parent of (links with children only).
    root
        The link that is no joint's child.
    xml
        The document as UTF-8 bytes, as it was parsed (what Pinocchio is given to read).
    """

    name: str
    path: str
    links: tuple[str, ...]
    joints: dict[str, UrdfJoint]
    parent_joint: dict[str, UrdfJoint]
    children: dict[str, tuple[UrdfJoint, ...]]
    root: str
    xml: bytes = b""

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
        """The single deepest leaf below ``base``, the default tip of a chain; ties are an error
        listing them."""
        depths = {leaf: self.depth(leaf) for leaf in self.leaves(base)}
        deepest = max(depths.values())
        tied = [leaf for leaf, d in depths.items() if d == deepest]
        if len(tied) > 1:
            raise ChainError(
                f"{self.path}: several leaves tie as the deepest below {shown(base)}: "
                f"{names(tied)}",
                remedy=Remedy("tip", "; choose one with {}"),
            )
        return tied[0]

    def beside(self, base: str, tip: str) -> list[UrdfJoint]:
        """The fixed joints from ``base`` up to the nearest link above it that ``tip`` lies below
        (nothing where ``tip`` lies below ``base``), base's own first: a base hanging beside the
        chain (a site, a sensor frame). A moving joint on the way up is an error: the chain would
        run through it backwards."""
        above = {tip}
        link = tip
        while link in self.parent_joint:
            link = self.parent_joint[link].parent
            above.add(link)
        out: list[UrdfJoint] = []
        link = base
        while link not in above and link in self.parent_joint:
            joint = self.parent_joint[link]
            if joint.type != "fixed":
                break
            out.append(joint)
            link = joint.parent
        return out if link in above else []

    def chain(self, base: str, tip: str) -> list[UrdfJoint]:
        """The joints from ``base`` down to ``tip`` (fixed ones included), base first."""
        for role, link in (("base", base), ("tip", tip)):
            if link not in self.children and link not in self.parent_joint and link != self.root:
                raise ChainError(
                    f"{self.path}: unknown {role} link {shown(link)}"
                    f"{near(link, self.links)}; links are {names(self.links)}"
                )
        out: list[UrdfJoint] = []
        link = tip
        while link != base:
            if link not in self.parent_joint:
                raise ChainError(
                    f"{self.path}: tip link {shown(tip)} is not below base link {shown(base)} "
                    f"(links below {shown(base)} end in {names(self.leaves(base))})"
                )
            joint = self.parent_joint[link]
            out.append(joint)
            link = joint.parent
        out.reverse()
        return out


def _joint(j: Any) -> UrdfJoint:
    """Our :class:`UrdfJoint` of a yourdfpy ``Joint`` whose element was checked."""
    origin = _IDENTITY if j.origin is None else _read_only(np.array(j.origin, dtype=float))
    axis = np.array(j.axis, dtype=float)
    if j.type in MOVING_TYPES:  # v / sqrt(x^2 + y^2 + z^2), as urdfdom; the check made it safe
        x, y, z = axis.tolist()
        axis /= math.sqrt(x * x + y * y + z * z)
    lower = upper = None
    if j.limit is not None and j.type in ("revolute", "prismatic"):  # urdfdom: absent is 0
        lower = 0.0 if j.limit.lower is None else j.limit.lower
        upper = 0.0 if j.limit.upper is None else j.limit.upper
    swapped = lower is not None and upper is not None and lower > upper
    if swapped:
        lower, upper = upper, lower
    mimic = j.mimic
    return UrdfJoint(
        j.name,
        j.type,
        j.parent,
        j.child,
        origin,
        _read_only(axis),
        lower,
        upper,
        None if mimic is None else mimic.joint,
        1.0 if mimic is None else float(mimic.multiplier),
        0.0 if mimic is None else float(mimic.offset),
        swapped,
    )


def build_tree(robot: Any, display: str, xml: bytes = b"") -> UrdfTree:
    """The :class:`UrdfTree` of yourdfpy's ``Robot`` of a checked document.

    Parameters
    ----------
    robot
        yourdfpy's ``Robot`` (links and joints) of a document that passed ``check_robot``.
    display
        The file's name in messages.
    xml
        The parsed document as UTF-8 bytes, kept in the tree.

    Raises
    ------
    InputError
        When the links and joints do not form one tree (a link with two parent joints, no root
        or several, links not reached from the root).
    """
    links = tuple(link.name for link in robot.links)
    return build_links(str(robot.name), display, links, [_joint(j) for j in robot.joints], xml)


def build_links(
    name: str, display: str, links: tuple[str, ...], edges: Iterable[UrdfJoint], xml: bytes = b""
) -> UrdfTree:
    """The :class:`UrdfTree` of links and the joints between them.

    Raises
    ------
    InputError
        When they do not form one tree (a link with two parent joints, no root or several,
        links not reached from the root).
    """
    joints: dict[str, UrdfJoint] = {}
    parent_joint: dict[str, UrdfJoint] = {}
    children: dict[str, list[UrdfJoint]] = {}
    for uj in edges:
        joints[uj.name] = uj
        if uj.child in parent_joint:
            raise InputError(
                f"{display}: link {shown(uj.child)} is the child of both joint "
                f"{shown(parent_joint[uj.child].name)} and joint {shown(uj.name)} (a kinematic "
                "loop; URDF describes trees only)"
            )
        parent_joint[uj.child] = uj
        children.setdefault(uj.parent, []).append(uj)
    roots = [link for link in links if link not in parent_joint]
    if not roots:
        raise InputError(f"{display}: every link has a parent joint (a kinematic loop)")
    if len(roots) > 1:
        raise InputError(f"{display}: several root links {names(roots)}; a URDF is a single tree")
    tree = UrdfTree(
        name,
        display,
        links,
        joints,
        parent_joint,
        {k: tuple(v) for k, v in children.items()},
        roots[0],
        xml,
    )
    reached = set(tree.subtree(roots[0]))  # each link at most once: it has at most one parent
    if len(reached) != len(links):
        unreached = [link for link in links if link not in reached]
        raise InputError(
            f"{display}: links {names(unreached)} are not connected to root {shown(roots[0])} "
            "(a kinematic loop)"
        )
    return tree
