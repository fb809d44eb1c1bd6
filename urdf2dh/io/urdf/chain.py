"""The chain walk: from a base link down to a tip link, fixed joints folded, to a POE model.

Each moving joint's axis and origin at the home pose, expressed in the base frame, give its
screw: direction ``R axis`` through the joint frame's origin. Fixed joints only carry the frame
along. A revolute joint followed by a coaxial prismatic joint that mimics it with offset 0 is one
helical joint whose pitch is the multiplier: that is how :mod:`urdf2dh.emit.urdf` writes a
helical joint, since URDF has none.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ...errors import ChainError, Remedy, near, shown
from ...geometry.frames import unit
from ...geometry.se3 import inv
from ...model.mimic import Mimic
from ...model.poe import Joint, JointKind, PoeModel
from .tree import UrdfJoint, UrdfTree, names

__all__ = ["KINDS", "final_leader", "tree_to_poe"]

#: URDF joint type -> the kind of the POE model's joint.
KINDS: dict[str, JointKind] = {
    "revolute": "revolute",
    "continuous": "revolute",
    "prismatic": "prismatic",
}

#: How far from exactly (anti-)parallel, in cos, a mimicking prismatic joint may be and still be
#: read as the lead of the revolute joint before it: float round-off of a rotated unit vector.
COAXIAL_COS = 1e-12

Vec = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class _Moving:
    """A moving joint met on the walk, in the base frame at the home pose."""

    name: str
    kind: JointKind
    axis: Vec  # (3,) unit
    point: Vec  # (3,)
    pitch: float
    lower: float | None
    upper: float | None
    mimic: Mimic | None = None


def _helical_lead(uj: UrdfJoint, axis: Vec, moving: list[_Moving]) -> float | None:
    """The pitch, if ``uj`` is the lead of a helical joint as urdf2dh writes one: a prismatic
    joint mimicking the revolute joint just before it on the chain (offset 0), along its axis."""
    if uj.type != "prismatic" or uj.mimic is None or uj.offset != 0.0 or not moving:
        return None
    prev = moving[-1]
    if prev.name != uj.mimic or prev.kind != "revolute":
        return None
    cos = float(axis @ prev.axis)
    if abs(abs(cos) - 1.0) > COAXIAL_COS:
        return None
    return uj.multiplier * (1.0 if cos > 0 else -1.0)


def _walk(
    tree: UrdfTree, path: list[UrdfJoint], ignore_mimic: bool, base: str, tip: str, start: Vec
) -> tuple[list[_Moving], Vec, list[str]]:
    """The moving joints of ``path``, the tip's home pose ``(4, 4)`` and the warnings made;
    ``start`` is the pose of the path's first link in the base frame."""
    t = start  # the joint frame at the home pose, in the base frame
    moving: list[_Moving] = []
    warnings: list[str] = []
    for uj in path:
        t = t @ uj.origin
        if uj.refused is not None:
            if not (uj.refused_coupling and ignore_mimic):
                raise ChainError(
                    f"{tree.path}: joint {shown(uj.name)} on the chain {shown(base)} -> "
                    f"{shown(tip)} {uj.refused}",
                    remedy=Remedy("ignore_mimic", "; pass {} to drive it on its own")
                    if uj.refused_coupling
                    else None,
                )
            warnings.append(
                f"joint {shown(uj.name)} {uj.refused.split(';')[0]}; treated as an independent "
                "joint (--ignore-mimic)"
            )
        if uj.type in ("floating", "planar"):
            raise ChainError(
                f"{tree.path}: joint {shown(uj.name)} on the chain {shown(base)} -> {shown(tip)} "
                f"is {uj.type}; only revolute, continuous, prismatic and fixed joints have D-H rows"
            )
        if uj.type == "fixed":
            continue
        if uj.swapped:
            warnings.append(
                f"joint {shown(uj.name)}: its <limit> has lower {uj.upper:.6g} above upper "
                f"{uj.lower:.6g}; read as the range [{uj.lower:.6g}, {uj.upper:.6g}] (as Gazebo "
                "reads it; urdfdom and Pinocchio keep lower and upper as written)"
            )
        axis = np.array(unit((t[:3, :3] @ uj.axis).tolist()))
        if uj.mimic is not None:
            lead = _helical_lead(uj, axis, moving)
            if lead is not None:  # revolute + coaxial prismatic mimicking it = one helical joint
                moving[-1] = replace(moving[-1], kind="helical", pitch=lead)
                continue
            if ignore_mimic:
                warnings.append(
                    f"joint {shown(uj.name)} mimics {shown(uj.mimic)} in the URDF; treated as an "
                    "independent joint (--ignore-mimic)"
                )
        mimic = None
        if uj.mimic is not None and not ignore_mimic:
            mimic = Mimic(uj.mimic, uj.multiplier, uj.offset)
        point = t[:3, 3].copy()
        moving.append(_Moving(uj.name, KINDS[uj.type], axis, point, 0.0, uj.lower, uj.upper, mimic))
    return _followed(tree, moving, base, tip, warnings), t, warnings


def final_leader(tree: UrdfTree, relation: Mimic) -> Mimic:
    """``relation`` to the joint that moves on its own: a leader that mimics in turn is replaced
    by its own leader, ``m2 (m1 q + o1) + o2`` (URDF allows mimics of mimics)."""
    seen = {relation.joint}
    while (leader := tree.joints.get(relation.joint)) is not None and leader.mimic is not None:
        if leader.mimic in seen:
            raise ChainError(f"{tree.path}: joints {names(sorted(seen))} mimic each other")
        seen.add(leader.mimic)
        relation = Mimic(leader.mimic, relation.multiplier * leader.multiplier,
                         relation.multiplier * leader.offset + relation.offset)  # fmt: skip
    return relation


def _followed(
    tree: UrdfTree, moving: list[_Moving], base: str, tip: str, warnings: list[str]
) -> list[_Moving]:
    """Each mimicking joint following a joint of the chain that moves on its own.

    A leader off the chain (a gripper finger following its twin on another branch) is no input
    of this chain: the first joint on the chain that follows it stands in for it, driven on its
    own (a warning says so), and any other joint following the same leader follows the stand-in
    (``q2 = m2 (q1 - o1) / m1 + o2``).
    """
    on_chain = {m.name for m in moving}
    stand_ins: dict[str, tuple[str, Mimic]] = {}  # off-chain leader -> (stand-in, its relation)
    out = []
    for m in moving:
        relation = None if m.mimic is None else final_leader(tree, m.mimic)
        if relation is not None and relation.joint not in on_chain:
            if relation.joint not in stand_ins and relation.multiplier != 0.0:
                stand_ins[relation.joint] = (m.name, relation)
                warnings.append(
                    f"joint {shown(m.name)} follows {shown(relation.joint)}, which is not on the "
                    f"chain {shown(base)} -> {shown(tip)}: it is driven on its own here (in the "
                    f"file, q = {relation.multiplier:g} q_{shown(relation.joint)} + "
                    f"{relation.offset:g})"
                )
                relation = None
            elif relation.joint in stand_ins:
                first, r1 = stand_ins[relation.joint]
                ratio = relation.multiplier / r1.multiplier
                relation = Mimic(first, ratio, relation.offset - ratio * r1.offset)
            else:  # a multiplier of 0: a constant position, of no joint
                raise ChainError(
                    f"{tree.path}: joint {shown(m.name)} mimics {shown(relation.joint)} with "
                    "multiplier 0",
                    remedy=Remedy("ignore_mimic", "; pass {} to treat it as an independent joint"),
                )
        out.append(m if relation == m.mimic else replace(m, mimic=relation))
    return out


def tree_to_poe(
    tree: UrdfTree,
    base: str | None = None,
    tip: str | None = None,
    ignore_mimic: bool = False,
    name: str | None = None,
) -> PoeModel:
    """Walk from ``base`` to ``tip``, fold fixed joints, and build the POE model.

    Parameters
    ----------
    tree
        The URDF's kinematic tree.
    base, tip
        Link names; ``base`` defaults to the root link and ``tip`` to the single deepest leaf
        below it (ties are an error). ``tip`` lies below ``base``, or below a link that ``base``
        hangs from by fixed joints (a site or sensor frame as the base).
    ignore_mimic
        Treat a mimic joint on the chain as an independent joint (with a warning) instead of
        keeping it coupled to its leader; the lead of a helical joint is read as such either way.
    name
        The model's name (default: the robot's).

    Returns
    -------
    PoeModel
        One joint per moving joint on the chain (a helical pair counts once) and the tip's home
        pose in the base link's frame.

    Raises
    ------
    ChainError
        An unknown base or tip link, a tip not below the base, a floating or planar joint on the
        chain, or a mimic joint on it whose leader is not (without ``ignore_mimic``).
    """
    base = base or tree.root
    if base not in tree.links:
        raise ChainError(
            f"{tree.path}: unknown base link {shown(base)}{near(base, tree.links)}; links are "
            f"{names(tree.links)}"
        )
    tip = tip or tree.default_tip(base)
    beside = tree.beside(base, tip)  # fixed joints up from a base beside the chain
    anchor = beside[-1].parent if beside else base
    start = np.eye(4)
    for joint in beside:
        start = start @ inv(joint.origin)
    moving, home, warnings = _walk(tree, tree.chain(anchor, tip), ignore_mimic, base, tip, start)
    joints = tuple(
        Joint(m.name, m.kind, m.axis, m.point, m.pitch, 1.0, m.lower, m.upper, m.mimic)
        for m in moving
    )
    return PoeModel(joints, home, name or tree.name, tree.path, base, tip, "m", tuple(warnings))
