"""Seeded random serial chains as real URDF text, with degenerate axis relations on purpose.

Each joint's relation to the previous one is drawn from RELATIONS:

* ``parallel``      same direction, offset sideways
* ``antiparallel``  opposite direction (rotation by pi about x), offset sideways
* ``intersecting``  rotated about an axis through the joint origin, no offset
* ``coincident``    same line (offset only along the axis), optionally reversed
* ``skew``          random rotation and offset
* ``prismatic``     a prismatic joint (random relation)

Angles are multiples of pi/2 (written with full precision) or random, so that the URDF's own
numbers define exact geometry; the loader and Pinocchio read the same text.
"""

from __future__ import annotations

import math

import numpy as np

RELATIONS = ("parallel", "antiparallel", "intersecting", "coincident", "skew", "prismatic")
QUARTER = (0.0, math.pi / 2, math.pi, -math.pi / 2)


def _f(x: float) -> str:
    return repr(float(x))


def random_chain_urdf(
    seed: int,
    n: int,
    relations: tuple[str, ...] = RELATIONS,
    scale: float = 1.0,
    tool: bool = True,
) -> tuple[str, list[str]]:
    """URDF text of an ``n``-joint chain ``base -> link{n}`` (plus a ``tool`` link), and the
    relation drawn for each joint."""
    rng = np.random.default_rng(seed)
    links = ['<link name="base"/>']
    joints = []
    drawn = []
    for i in range(1, n + 1):
        rel = str(rng.choice(relations))
        drawn.append(rel)
        jtype = "revolute"
        xyz = np.zeros(3)
        rpy = np.zeros(3)
        if rel == "parallel":
            xyz = np.array([rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)]) * scale
            rpy = np.array([0.0, 0.0, float(rng.choice(QUARTER))])
        elif rel == "antiparallel":
            xyz = np.array([rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)]) * scale
            rpy = np.array([math.pi, 0.0, float(rng.choice(QUARTER))])
        elif rel == "intersecting":
            rpy = np.array([float(rng.choice(QUARTER)), float(rng.choice(QUARTER)), 0.0])
            if not rpy.any():
                rpy[0] = math.pi / 2
        elif rel == "coincident":
            xyz = np.array([0.0, 0.0, rng.uniform(-1, 1) * scale])
            rpy = np.array([float(rng.choice((0.0, math.pi))), 0.0, 0.0])
        elif rel == "skew":
            xyz = rng.uniform(-1, 1, 3) * scale
            rpy = rng.uniform(-math.pi, math.pi, 3)
        else:  # prismatic, along a random or quarter-turn direction
            jtype = "prismatic"
            xyz = rng.uniform(-1, 1, 3) * scale
            rpy = (
                rng.uniform(-math.pi, math.pi, 3)
                if rng.random() < 0.5
                else np.array([float(rng.choice(QUARTER)), 0.0, 0.0])
            )
        if rng.random() < 0.2 and jtype == "revolute":
            jtype = "continuous"
        limit = ""
        if jtype == "revolute":
            limit = '<limit lower="-3" upper="3" effort="1" velocity="1"/>'
        elif jtype == "prismatic":
            limit = f'<limit lower="{_f(-scale)}" upper="{_f(scale)}" effort="1" velocity="1"/>'
        parent = "base" if i == 1 else f"link{i - 1}"
        links.append(f'<link name="link{i}"/>')
        joints.append(
            f'<joint name="j{i}" type="{jtype}"><parent link="{parent}"/>'
            f'<child link="link{i}"/>'
            f'<origin xyz="{" ".join(map(_f, xyz))}" rpy="{" ".join(map(_f, rpy))}"/>'
            f'<axis xyz="0 0 1"/>{limit}</joint>'
        )
    if tool:
        xyz = rng.uniform(-1, 1, 3) * scale
        rpy = rng.uniform(-math.pi, math.pi, 3) if rng.random() < 0.5 else np.zeros(3)
        links.append('<link name="tool"/>')
        joints.append(
            f'<joint name="tool_joint" type="fixed"><parent link="link{n}"/>'
            f'<child link="tool"/><origin xyz="{" ".join(map(_f, xyz))}" '
            f'rpy="{" ".join(map(_f, rpy))}"/></joint>'
        )
    text = f'<robot name="random{seed}">' + "".join(links) + "".join(joints) + "</robot>"
    return text, drawn


# joint 2's axis tilted from joint 1's by ANGLE about y, 0.3 m to the side: nearly parallel axes
# whose exact common normal lies about 0.3 / ANGLE away
TILTED_ARM = """<robot name="tilt"><link name="base_link"/><link name="l1"/><link name="l2"/>
<link name="tool"/>
<joint name="j1" type="revolute"><parent link="base_link"/><child link="l1"/><axis xyz="0 0 1"/>
<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
<origin xyz="0.3 0 0.2" rpy="0 {angle} 0"/><axis xyz="0 0 1"/>
<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
<joint name="j3" type="revolute"><parent link="l2"/><child link="tool"/><origin xyz="0 0 0.3"/>
<axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint></robot>"""
