"""roboticstoolbox-python: a script that builds the table as a ``DHRobot`` (``dh``, ``mdh``), or
as a ``Robot`` of an elementary transform sequence (``hayati``, whose rows D-H links cannot
hold).

The consumer (roboticstoolbox-python 1.x, ``DHRobot.fkine``) evaluates
``base . A_1(q_1) ... A_n(q_n) . tool`` with, for ``RevoluteDH`` / ``PrismaticDH``,
``A = Rz(theta) Tz(d) Tx(a) Rx(alpha)`` and for ``RevoluteMDH`` / ``PrismaticMDH``
``A = Rx(alpha) Tx(a) Rz(theta) Tz(d)``, where the joint variable plus ``offset`` is ``theta``
(revolute) or ``d`` (prismatic). That is the table's own formula (``Tx`` and ``Rx`` commute, and
``Q_i`` commutes with ``Rz(theta_i) Tz(d_i)``), so the rows go over one to one: ``offset`` is
the table's ``theta`` (revolute) or ``d`` (prismatic). ``qlim`` comes from the URDF limits, and
``base`` / ``tool`` are written as the table's own products of elementary ``SE3`` transforms.

A ``hayati`` table is written as one ``ETS``: the base's, each row's and the tool's elementary
transforms in their own order (a record's parameters are listed in the order of its transform:
``theta`` a turn about z, ``d`` along z, ``alpha`` about x, ``a`` along x, ``beta`` about y), and
each joint as ``ET.Rz()`` or ``ET.tz()`` with its limits, which ``Robot`` evaluates in that order.

What a person reads shows no round-off: an angle that is a multiple of 90 degrees is written
``pi/2``, ``pi``, ``-pi/2`` (the float Python makes of it, which rtb prints as ``90.0°``), and the
script's ``__main__`` prints rtb's table, and the pose at home, of a copy whose angles are given
to 1e-9 degree (rtb prints every digit, and a URDF's pi/2 written ``1.57079632679`` would show as
``2.81e-10°``); the ``robot`` it defines keeps every value exactly.
"""

from __future__ import annotations

from ...conventions import Params
from ...conventions.table import Row, Table
from ...escape import python_docstring, python_string
from .common import (
    ExportOptions,
    Numbers,
    floats,
    header,
    require,
)
from .solvers import rtb_form

__all__ = ["render"]

CLASSES = {
    ("dh", "revolute"): "RevoluteDH",
    ("dh", "prismatic"): "PrismaticDH",
    ("mdh", "revolute"): "RevoluteMDH",
    ("mdh", "prismatic"): "PrismaticMDH",
}


def _factor(op: str, value: float, numbers: Numbers) -> str | None:
    """An elementary motion's argument (a multiple of pi/2 as ``pi/2``, ...), or None for a
    zero one."""
    if op.startswith("R"):
        return None if numbers.angle(value) == 0.0 else numbers.pi_ang(value)
    return None if numbers.length(value) == 0.0 else numbers.lin(value)


def _se3(parts: list[tuple[str, float]], numbers: Numbers) -> str:
    """``SE3.Rz(..) * SE3.Tz(..) * ...``; zero factors dropped (``SE3()`` if all are)."""
    terms = [(op, _factor(op, value, numbers)) for op, value in parts]
    return " * ".join(f"SE3.{op}({text})" for op, text in terms if text) or "SE3()"


OPS = {"theta": "Rz", "d": "Tz", "alpha": "Rx", "a": "Tx", "beta": "Ry"}  # each one's motion
ET_OPS = {"Rz": "Rz", "Tz": "tz", "Rx": "Rx", "Tx": "tx", "Ry": "Ry"}  # their names in ET


def _motions(record: Params) -> list[tuple[str, float]]:
    """A record as its elementary motions, in the record's own order (the order of its
    transform: ``Rz Tz Rx Tx``, ``Rz Tz``, Craig's ``Rx Tx Rz Tz``, Hayati's ``Rz Tx Rx Ry``)."""
    return [(OPS[k], v) for k, v in floats(record).items()]


def _et(parts: list[tuple[str, float]], numbers: Numbers) -> list[str]:
    """``ET.Rz(..)``, ``ET.tx(..)``, ...; zero factors dropped."""
    terms = [(op, _factor(op, value, numbers)) for op, value in parts]
    return [f"ET.{ET_OPS[op]}({text})" for op, text in terms if text]


def _render_ets(table: Table, numbers: Numbers) -> str:
    """The script of a ``hayati`` table: a ``Robot`` of one elementary transform sequence."""
    out = [python_docstring(header(table, "roboticstoolbox-python Robot (ETS)"), block=True), ""]
    out += ["from math import pi", "", "from roboticstoolbox import ET, Robot", "", "ets = ("]
    factors = _et(_motions(table.base), numbers)
    for i, row in enumerate(table.rows, 1):
        joint = "Rz" if row.kind == "revolute" else "tz"
        limits = ""
        if row.lower is not None and row.upper is not None:
            lim = numbers.position(row.kind)
            limits = f"qlim=[{lim(row.lower)}, {lim(row.upper)}]"
        factors.append(f"ET.{joint}({limits})  # joint {i}: {python_string(row.name)}")
        factors += _et(_motions(row.params), numbers)
    factors += _et(_motions(table.tool), numbers)
    out += [f"    {'' if k == 0 else '* '}{f}" for k, f in enumerate(factors)]
    out += [")", "", f"robot = Robot(ets, name={python_string(table.robot or 'robot')})", ""]
    out += ['if __name__ == "__main__":', "    print(robot)",
            "    print(robot.fkine([0.0] * robot.n))"]  # fmt: skip
    return "\n".join(out) + "\n"


def _link(table: Table, row: Row, numbers: Numbers) -> str:
    p = floats(row.params)
    cls = CLASSES[(table.convention, row.kind)]
    if row.kind == "revolute":
        args = [f"d={numbers.lin(p['d'])}", f"offset={numbers.pi_ang(p['theta'])}"]
    else:
        args = [f"theta={numbers.pi_ang(p['theta'])}", f"offset={numbers.lin(p['d'])}"]
    args[1:1] = [f"a={numbers.lin(p['a'])}", f"alpha={numbers.pi_ang(p['alpha'])}"]
    if row.lower is not None and row.upper is not None:
        lim = numbers.position(row.kind)
        args.append(f"qlim=[{lim(row.lower)}, {lim(row.upper)}]")
    args.append(f"name={python_string(row.name)}")
    return f"        {cls}({', '.join(args)}),"


def render(table: Table, opts: ExportOptions) -> str:
    """A Python script defining ``robot``, a roboticstoolbox ``DHRobot`` of the table (of its
    analytic form where roboticstoolbox's analytic IK can take it: module doc)."""
    require(table, "rtb", ("dh", "mdh", "hayati"))
    numbers = Numbers.of(table, opts.tol)
    if table.convention == "hayati":
        return _render_ets(table, numbers)
    form = rtb_form(table, opts)
    rows = table.rows if form.chain is None else form.chain.rows
    base, tool = _motions(table.base), form.tool_motions + _motions(table.tool)
    classes = sorted({CLASSES[(table.convention, r.kind)] for r in table.rows})
    out = [python_docstring(form.lines, block=True), ""]
    out += ["import copy", "from math import degrees, pi, radians", ""]
    out.append(f"from roboticstoolbox import DHRobot, {', '.join(classes)}")
    out.append("from spatialmath import SE3")
    out.append("")
    out.append("robot = DHRobot(")
    out.append("    [")
    out.extend(_link(table, r, numbers) for r in rows)
    out.append("    ],")
    out.append(f"    name={python_string(table.robot or 'robot')},")
    out.append(f"    base={_se3(base, numbers)},")
    out.append(f"    tool={_se3(tool, numbers)},")
    out.append(")")
    out.append("")
    out += [
        'if __name__ == "__main__":',
        "    # rtb prints every digit of an angle: the robot shown, and its pose at home, have",
        "    # them to 1e-9 degree, its base and tool to 1e-9 (robot keeps them exactly, a URDF's",
        "    # rounding of pi/2 included)",
        "    shown = copy.deepcopy(robot)",
        "    for link in shown.links:",
        "        link.alpha = radians(round(degrees(link.alpha), 9))",
        "        if link.isrevolute:",
        "            link.offset = radians(round(degrees(link.offset), 9))",
        "        else:",
        "            link.theta = radians(round(degrees(link.theta), 9))",
        "    shown.base = SE3(robot.base.A.round(9), check=False)",
        "    shown.tool = SE3(robot.tool.A.round(9), check=False)",
        "    print(shown)",
        "    print(shown.fkine([0.0] * shown.n))",
    ]
    return "\n".join(out) + "\n"
