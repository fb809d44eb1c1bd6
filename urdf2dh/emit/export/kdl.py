"""Orocos KDL (PyKDL): a script that builds the table as a ``Chain`` of ``Segment`` objects.

The consumer: a KDL segment's pose is ``joint.pose(q) . f_tip`` (the joint moves first, then the
segment's fixed frame), a chain is the product of its segments, and KDL documents
``Frame.DH(a, alpha, d, theta) = Rz(theta) Tz(d) Tx(a) Rx(alpha)`` and
``Frame.DH_Craig1989(a, alpha, d, theta) = Rx(alpha) Tx(a) Rz(theta) Tz(d)``.

* ``dh``: a fixed segment for the base ``Frame.DH`` (``B = Rz Tz Rx Tx``), one ``RotZ`` /
  ``TransZ`` segment per row with ``Frame.DH`` of the row (``Q_i`` then ``Rz Tz Rx Tx``: the
  table's formula), and a fixed segment for the tool ``Frame.DH(0, 0, d, theta)``.
* ``mdh``: row ``i`` is ``Rx Tx . Q_i . Rz Tz``, and ``Q_i`` commutes with ``Rz(theta_i)
  Tz(d_i)``, so it equals ``Frame.DH_Craig1989(row i) . Q_i``: a fixed segment carries the base
  and row 1's ``DH_Craig1989``, joint ``i``'s segment carries row ``i + 1``'s, and the last
  joint's carries the tool's (``Rx Tx Rz Tz``, Craig's form too).

Names: each joint keeps its own; the fixed segments carry the base and tip links' names, and a
joint's segment is named after the joint. The segment and fixed-joint names the script makes up
keep clear of the robot's (:mod:`.names`: a suffix ``_2`` where the robot has the name, stated
in the docstring), as a ``KDL::Tree`` built from the chain takes every segment name once.

Angles are exact (:meth:`.Numbers.pi_ang`): a multiple of pi/2 as ``pi/2``, ``pi``, ... (the
script imports ``pi`` from ``math``), any other with the digits that read back as it.
"""

from __future__ import annotations

from typing import Any

from ...conventions.table import Table
from ...escape import python_docstring, python_string
from ..names import Namespace, renaming_notes
from .common import (
    ExportOptions,
    Numbers,
    floats,
    header,
    require,
)

__all__ = ["render"]

JOINT_TYPES = {"revolute": "RotZ", "prismatic": "TransZ"}


def _frame(kind: str, p: dict[str, Any], numbers: Numbers) -> str:
    """``kdl.Frame.DH(a, alpha, d, theta)`` or ``DH_Craig1989``; absent parameters are 0."""
    a = numbers.lin(p.get("a", 0.0))
    alpha = numbers.pi_ang(p.get("alpha", 0.0))
    d = numbers.lin(p.get("d", 0.0))
    theta = numbers.pi_ang(p.get("theta", 0.0))
    return f"kdl.Frame.{kind}({a}, {alpha}, {d}, {theta})"


def _segment(name: str, joint: str, joint_type: str, frame: str) -> str:
    made = f"kdl.Joint({python_string(joint)}, kdl.Joint.{joint_type})"
    return f"    chain.addSegment(kdl.Segment({python_string(name)}, {made}, {frame}))"


class _Names:
    """The script's segments and joints: the robot's names, then made-up ones."""

    def __init__(self, table: Table, links: list[str]) -> None:
        self.segments = Namespace("kdl", "segment", [n for n in links if n])
        self.joints = Namespace("kdl", "joint", [r.name for r in table.rows])

    def fixed(self, link: str, default: str, frame: str) -> str:
        """The fixed segment of a link (``default`` for a chain without link names)."""
        name = link or self.segments.invent(default)
        return _segment(name, self.joints.invent(name), "Fixed", frame)

    def moving(self, name: str, kind: str, frame: str) -> str:
        """A joint's segment, named after the joint."""
        return _segment(self.segments.invent(name), name, JOINT_TYPES[kind], frame)


def render(table: Table, opts: ExportOptions) -> str:
    """A Python script with ``build_chain() -> PyKDL.Chain`` for the table."""
    require(table, "kdl", ("dh", "mdh"))
    numbers = Numbers.of(table, opts.tol)
    lines = []
    if table.convention == "dh":
        names = _Names(table, [table.base_link, table.tip_link])
        lines.append(
            names.fixed(table.base_link, "base", _frame("DH", floats(table.base), numbers))
        )
        for row in table.rows:
            lines.append(
                names.moving(row.name, row.kind, _frame("DH", floats(row.params), numbers))
            )
        lines.append(names.fixed(table.tip_link, "tool", _frame("DH", floats(table.tool), numbers)))
    else:
        names = _Names(table, [table.base_link])
        frames = [_frame("DH_Craig1989", floats(r.params), numbers) for r in table.rows]
        frames.append(_frame("DH_Craig1989", floats(table.tool), numbers))
        base = _frame("DH_Craig1989", floats(table.base), numbers)
        if base != "kdl.Frame.DH_Craig1989(0.0, 0.0, 0.0, 0.0)":  # B = I is left out
            frames[0] = f"{base} * {frames[0]}"
        lines.append(names.fixed(table.base_link, "base", frames[0]))
        for row, frame in zip(table.rows, frames[1:], strict=True):
            lines.append(names.moving(row.name, row.kind, frame))
    base_name, tip_name = table.base_link or "base", table.tip_link or "tool"
    doc = header(table, "PyKDL Chain")
    doc.append(f"Joints in chain order: {', '.join(r.name for r in table.rows)}.")
    doc += renaming_notes(names.segments, names.joints)
    out = [
        python_docstring(doc, block=True),
        "",
        "from math import pi",
        "",
        "import PyKDL as kdl",
        "",
        "",
    ]
    out.append("def build_chain() -> kdl.Chain:")
    out.append(
        "    "
        + python_docstring([f"{base_name} -> {tip_name} as a KDL chain of {table.n} joints."])
    )
    out.append("    chain = kdl.Chain()")
    out.extend(lines)
    out.append("    return chain")
    out.append("")
    out.append("")
    out.append('if __name__ == "__main__":')
    out.append("    chain = build_chain()")
    out.append("    pose = kdl.Frame()")
    out.append(
        "    kdl.ChainFkSolverPos_recursive(chain).JntToCart("
        "kdl.JntArray(chain.getNrOfJoints()), pose)"
    )
    out.append("    print(pose)")
    return "\n".join(out) + "\n"
