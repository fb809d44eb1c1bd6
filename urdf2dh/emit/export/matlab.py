"""MATLAB Robotics System Toolbox: a script that builds the table as a ``rigidBodyTree``.

The consumer, as MathWorks documents it: a body's pose in its parent is
``JointToParentTransform . J(q) . ChildToJointTransform``, with ``J(q)`` a rotation about (or a
translation along) the joint axis, ``[0 0 1]`` by default.
``setFixedTransform(joint, [a alpha d theta], "dh")`` sets ``ChildToJointTransform`` to the
standard D-H matrix ``Rz(theta) Tz(d) Tx(a) Rx(alpha)`` (``JointToParentTransform`` becomes the
identity); ``"mdh"`` sets ``JointToParentTransform`` to Craig's ``Rx(alpha) Tx(a) Rz(theta)
Tz(d)`` (``ChildToJointTransform`` the identity); ``setFixedTransform(joint, tform)`` sets
``JointToParentTransform`` to a 4x4 matrix. For revolute joints ``theta`` is ignored (the joint
angle takes its place), for prismatic joints ``d``.

So each row is written with its ignored entry 0, and the offset it would have carried, ``Rz(theta)``
or ``Tz(d)``, goes into a fixed body of its own: before the joint's body for ``dh``
(``Rz(q) Rz(theta) = Rz(theta) Rz(q)``) and after it for ``mdh`` (``Rz(theta) Tz(d)`` commutes
with the joint motion). Base and tool are fixed bodies with 4x4 transforms; the last body is named
after the tip link, so ``getTransform(robot, q, "<tip>")`` is the table's forward kinematics.

Names: the base (``robot.BaseName``) and the last body carry the chain's base and tip links'
names and each joint its own; the names the script makes up (bodies ``dh_base``, ``body<i>``,
``body<i>_offset``, their joints ``<body>_fixed``, the tip's joint ``<tip>_fixed``) keep clear
of those (:mod:`.names`: a suffix ``_2`` where the robot has the name, stated in a comment), as
``addBody`` refuses a second body or joint of one name.

D-H angles are exact (:meth:`.Numbers.pi_ang`): a multiple of pi/2 as ``pi/2``, ``pi``, ...
(MATLAB's ``pi``), any other with the digits that read back as it.
"""

from __future__ import annotations

import numpy as np

from ...conventions.table import Row, Table
from ...escape import matlab_comment, matlab_string
from ..names import Namespace, renaming_notes
from .common import (
    ExportOptions,
    Numbers,
    floats,
    header,
    matlab_matrix,
    require,
)

__all__ = ["render"]


def _fixed_body(body: str, joint: str, tform: str) -> list[str]:
    return [
        f"body = rigidBody({matlab_string(body)});",
        f'joint = rigidBodyJoint({matlab_string(joint)}, "fixed");',
        f"setFixedTransform(joint, {tform});",
        "body.Joint = joint;",
        "addBody(robot, body, parent);",
        "parent = body.Name;",
    ]


def _offset(row: Row, numbers: Numbers) -> np.ndarray | None:
    """The fixed transform carrying what ``setFixedTransform`` ignores for this joint."""
    p = floats(row.params)
    out = np.eye(4)
    if row.kind == "revolute":
        theta = numbers.pi_angle(p["theta"])  # pi exactly: Rz(pi) is [-1 0; 0 -1]
        if theta == 0.0:
            return None
        c, s = np.cos(theta), np.sin(theta)
        out[:2, :2] = [[c, -s], [s, c]]
    else:
        d = numbers.length(p["d"])
        if d == 0.0:
            return None
        out[2, 3] = d
    return out


def _joint_body(body: str, row: Row, convention: str, numbers: Numbers) -> list[str]:
    p = floats(row.params)
    theta = "0" if row.kind == "revolute" else numbers.pi_ang(p["theta"])
    d = "0" if row.kind == "prismatic" else numbers.lin(p["d"])
    lines = [
        f"body = rigidBody({matlab_string(body)});",
        f"joint = rigidBodyJoint({matlab_string(row.name)}, {matlab_string(row.kind)});",
    ]
    if row.lower is not None and row.upper is not None:
        lim = numbers.position(row.kind)
        lines.append(f"joint.PositionLimits = [{lim(row.lower)} {lim(row.upper)}];")
        if not row.lower <= 0.0 <= row.upper:  # the home position must lie within the limits
            lines.append(f"joint.HomePosition = {lim((row.lower + row.upper) / 2)};")
    a, alpha = numbers.lin(p["a"]), numbers.pi_ang(p["alpha"])
    lines += [
        f'setFixedTransform(joint, [{a} {alpha} {d} {theta}], "{convention}");',
        "body.Joint = joint;",
        "addBody(robot, body, parent);",
        "parent = body.Name;",
    ]
    return lines


class _Names:
    """The script's two namespaces, bodies and joints: the robot's names, then made-up ones."""

    def __init__(self, table: Table) -> None:
        links = [n for n in (table.base_link, table.tip_link) if n]
        self.bodies = Namespace("matlab", "body", links)
        self.joints = Namespace("matlab", "joint", [r.name for r in table.rows])

    def fixed(self, body: str, transform: str) -> list[str]:
        """A made-up fixed body and its joint (``<body>_fixed``), each kept clear on its own."""
        return _fixed_body(self.bodies.invent(body), self.joints.invent(body + "_fixed"), transform)


def render(table: Table, opts: ExportOptions) -> str:
    """A MATLAB script building ``robot``, a ``rigidBodyTree`` of the table."""
    require(table, "matlab", ("dh", "mdh"))
    numbers = Numbers.of(table, opts.tol)
    names = _Names(table)
    base = table.base_link or names.bodies.invent("base_link")
    body = []
    body.append('robot = rigidBodyTree("DataFormat", "row");')
    body.append(f"robot.BaseName = {matlab_string(base)};")
    body.append("parent = robot.BaseName;")
    body.append("")
    body += names.fixed("dh_base", matlab_matrix(table.base_matrix, numbers))
    for i, row in enumerate(table.rows, start=1):
        body.append("")
        offset = _offset(row, numbers)
        if offset is not None and table.convention == "dh":
            body += names.fixed(f"body{i}_offset", matlab_matrix(offset, numbers))
        body += _joint_body(names.bodies.invent(f"body{i}"), row, table.convention, numbers)
        if offset is not None and table.convention == "mdh":
            body += names.fixed(f"body{i}_offset", matlab_matrix(offset, numbers))
    body.append("")
    tip = table.tip_link or names.bodies.invent("tool")
    tool = matlab_matrix(table.tool_matrix, numbers)
    body += _fixed_body(tip, names.joints.invent(tip + "_fixed"), tool)
    out = [matlab_comment(line) for line in header(table, "MATLAB rigidBodyTree")]
    out.append(
        matlab_comment(
            f'setFixedTransform(..., "{table.convention}") ignores theta of '
            "revolute joints (d of prismatic ones): those"
        )
    )
    out.append(
        matlab_comment(
            "offsets sit in fixed bodies of their own. Configuration: one "
            "value per joint, in chain order."
        )
    )
    out += [matlab_comment(note) for note in renaming_notes(names.bodies, names.joints)]
    return "\n".join(out + body) + "\n"
