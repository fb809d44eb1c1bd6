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
"""

from __future__ import annotations

import numpy as np

from ..table import Row, Table
from .common import (
    Numbers,
    Options,
    floats,
    header,
    matlab_matrix,
    require,
)
from .escape import matlab_comment, matlab_string

__all__ = ["render"]


def _fixed_body(name: str, tform: str) -> list[str]:
    return [
        f"body = rigidBody({matlab_string(name)});",
        f'joint = rigidBodyJoint({matlab_string(name + "_fixed")}, "fixed");',
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
        theta = numbers.angle(p["theta"])
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


def _joint_body(index: int, row: Row, convention: str, numbers: Numbers) -> list[str]:
    p = floats(row.params)
    theta = "0" if row.kind == "revolute" else numbers.ang(p["theta"])
    d = "0" if row.kind == "prismatic" else numbers.lin(p["d"])
    lines = [
        f'body = rigidBody("body{index}");',
        f"joint = rigidBodyJoint({matlab_string(row.name)}, {matlab_string(row.kind)});",
    ]
    if row.lower is not None and row.upper is not None:
        lim = numbers.position(row.kind)
        lines.append(f"joint.PositionLimits = [{lim(row.lower)} {lim(row.upper)}];")
        if not row.lower <= 0.0 <= row.upper:  # the home position must lie within the limits
            lines.append(f"joint.HomePosition = {lim((row.lower + row.upper) / 2)};")
    lines += [
        f"setFixedTransform(joint, [{numbers.lin(p['a'])} {numbers.ang(p['alpha'])} {d} {theta}],"
        f' "{convention}");',
        "body.Joint = joint;",
        "addBody(robot, body, parent);",
        "parent = body.Name;",
    ]
    return lines


def render(table: Table, opts: Options) -> str:
    """A MATLAB script building ``robot``, a ``rigidBodyTree`` of the table."""
    require(table, "matlab", ("dh", "mdh"))
    numbers = Numbers.of(table, opts.tol)
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
    out.append('robot = rigidBodyTree("DataFormat", "row");')
    out.append(f"robot.BaseName = {matlab_string(table.base_link or 'base_link')};")
    out.append("parent = robot.BaseName;")
    out.append("")
    out += _fixed_body("dh_base", matlab_matrix(table.base_matrix, numbers))
    for i, row in enumerate(table.rows, start=1):
        out.append("")
        offset = _offset(row, numbers)
        if offset is not None and table.convention == "dh":
            out += _fixed_body(f"body{i}_offset", matlab_matrix(offset, numbers))
        out += _joint_body(i, row, table.convention, numbers)
        if offset is not None and table.convention == "mdh":
            out += _fixed_body(f"body{i}_offset", matlab_matrix(offset, numbers))
    out.append("")
    out += _fixed_body(table.tip_link or "tool", matlab_matrix(table.tool_matrix, numbers))
    return "\n".join(out) + "\n"
