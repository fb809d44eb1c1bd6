"""Peter Corke's Robotics Toolbox for MATLAB (RTB 10): a script building a ``SerialLink``.

The consumer, as the toolbox documents it: ``SerialLink.fkine(q) = base . A_1(q_1) ... A_n(q_n)
. tool``, where a ``'standard'`` link's ``A = Rz(theta) Tz(d) Tx(a) Rx(alpha)`` and a
``'modified'`` link's ``A = Rx(alpha) Tx(a) Rz(theta) Tz(d)``; the joint variable plus
``'offset'`` is ``theta`` of a ``'revolute'`` link and ``d`` of a ``'prismatic'`` one. Like the
Python toolbox, that is the table's own formula, so rows go over one to one (``offset`` = the
table's theta, or d for prismatic rows); ``base`` and ``tool`` are the table's 4x4 transforms.
"""

from __future__ import annotations

from ...conventions.table import Row, Table
from ...escape import matlab_comment, matlab_string
from .common import (
    ExportOptions,
    Numbers,
    floats,
    header,
    matlab_matrix,
    require,
)

__all__ = ["render"]

FLAVOURS = {"dh": "standard", "mdh": "modified"}


def _link(index: int, row: Row, convention: str, numbers: Numbers) -> str:
    p = floats(row.params)
    if row.kind == "revolute":
        args = ["'revolute'", f"'d', {numbers.lin(p['d'])}"]
        offset = numbers.pi_ang(p["theta"])
    else:
        args = ["'prismatic'", f"'theta', {numbers.pi_ang(p['theta'])}"]
        offset = numbers.lin(p["d"])
    args += [
        f"'a', {numbers.lin(p['a'])}",
        f"'alpha', {numbers.pi_ang(p['alpha'])}",
        f"'offset', {offset}",
    ]
    if row.lower is not None and row.upper is not None:
        lim = numbers.position(row.kind)
        args.append(f"'qlim', [{lim(row.lower)} {lim(row.upper)}]")
    args.append(f"'{FLAVOURS[convention]}'")
    return f"L({index}) = Link({', '.join(args)});  {matlab_comment(row.name)}"


def render(table: Table, opts: ExportOptions) -> str:
    """A MATLAB script building ``robot``, a ``SerialLink`` of the table."""
    require(table, "corke-matlab", ("dh", "mdh"))
    numbers = Numbers.of(table, opts.tol)
    out = [matlab_comment(line) for line in header(table, "Robotics Toolbox for MATLAB SerialLink")]
    out += [_link(i, r, table.convention, numbers) for i, r in enumerate(table.rows, start=1)]
    name = matlab_string(table.robot or "robot", "'")
    base = matlab_matrix(table.base_matrix, numbers)
    tool = matlab_matrix(table.tool_matrix, numbers)
    out.append(f"robot = SerialLink(L, 'name', {name}, 'base', {base}, 'tool', {tool});")
    return "\n".join(out) + "\n"
