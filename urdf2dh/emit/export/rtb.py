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

Where roboticstoolbox-python 1.5 has an analytic IK for the chain (six joints, standard D-H: a
closed form, or Raghavan and Roth's method), the script also defines ``solve(T)``, which returns
every branch of it for the pose ``T``, each polished by Gauss-Newton steps on ``robot``'s own
forward kinematics (:data:`SOLVE`). Its closed form for arms with three parallel axes (the UR
family) solves joint 2 from an equation whose coefficients vanish with ``cos q1``, computed from
terms that do not: as the arm turns to ``q1 = +-pi/2`` the branches lose digits (1e-6 x size at
``|cos q1|`` = 0.003) and, beyond the 1e-6 its own check allows, are dropped. So ``solve`` also
asks for the pose turned a quarter turn about joint 1's axis, where the same branches are away
from that (docs/exports/rtb.md#analytic-ik has the measurements).
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


# The script's analytic IK (module doc): the rows solve() polishes (roboticstoolbox's branches
# for T and, where joint 1 turns, for T turned a quarter turn about its axis), then the rest.
CANDIDATES = {
    "revolute": """\
# robot reaches QUARTER @ T where it reaches T, joint 1 a quarter turn further (its axis
# is the base's z)
QUARTER = (robot.base * SE3.Rz(pi / 2) * robot.base.inv()).A


def candidates(T):
    \"\"\"The rows solve() polishes for the pose T (4x4 array), as
    robot.analytic_ik().solve(T, joint_limits=False) returns them (k, n): roboticstoolbox's
    branches for T, then its branches for QUARTER @ T with joint 1 turned back into [-pi, pi)
    (its closed form loses digits as cos(q1) -> 0, and drops such branches; the turned pose
    has them away from there).\"\"\"
    ik = robot.analytic_ik()  # derived on the first call, then kept: seconds to minutes
    turned = ik.solve(QUARTER @ T, joint_limits=False).q
    turned[:, 0] = np.remainder(turned[:, 0] + pi / 2, 2 * pi) - pi
    return np.vstack([ik.solve(T, joint_limits=False).q, turned])
""",
    "prismatic": """

def candidates(T):
    \"\"\"The rows solve() polishes for the pose T (4x4 array): roboticstoolbox's branches, as
    robot.analytic_ik().solve(T, joint_limits=False) returns them (k, n).\"\"\"
    ik = robot.analytic_ik()  # derived on the first call, then kept: seconds to minutes
    return ik.solve(T, joint_limits=False).q
""",
}
SOLVE = """
SIZE = @SIZE@  # @UNIT@: the robot's size; solve() holds positions to tol x SIZE
REVOLUTE = np.array([link.isrevolute for link in robot.links])
@CANDIDATES@


def polish(q, T, steps=10):
    \"\"\"Gauss-Newton steps on robot's own forward kinematics (robot.fkine, robot.jacobe) from
    q toward T, each taken if it at least halves the error: (q, error, steps taken), the error
    the larger of the position's (/ SIZE) and the rotation's (rad).\"\"\"

    def error(q):
        delta = tr2delta(robot.fkine(q).A, T)  # in the tip's frame, as robot.jacobe(q)
        return delta, max(np.linalg.norm(delta[:3]) / SIZE, np.linalg.norm(delta[3:]))

    delta, worst = error(q)
    for taken in range(steps):
        if not worst > 0.0:  # exact, or not a number
            return q, worst, taken
        moved = q + np.linalg.lstsq(robot.jacobe(q), delta, rcond=None)[0]
        delta_moved, worst_moved = error(moved)
        if not worst_moved <= worst / 2:  # no longer converging
            return q, worst, taken
        q, delta, worst = moved, delta_moved, worst_moved
    return q, worst, steps


def same(a, b):
    \"\"\"Whether configurations a and b are one: every revolute joint within 1e-9 rad (modulo
    2 pi), every prismatic one within 1e-9 x SIZE.\"\"\"
    gap = np.where(REVOLUTE, np.remainder(a - b + pi, 2 * pi) - pi, (a - b) / SIZE)
    return bool(np.abs(gap).max() <= 1e-9)


def solve(T, joint_limits=True, tol=1e-10):
    \"\"\"Every branch of the analytic IK for the pose T (SE3 or 4x4 array: the tip link in the
    base link): each row of candidates(T) polished until it reaches T within tol x SIZE and
    tol rad, a row that lands on a branch found before left out. An IKSolution, as
    robot.analytic_ik().solve(T): q has a branch a row, revolute joints moved by whole turns
    into their limits and, with joint_limits, the branches beyond them dropped; iterations is
    the most steps a row took; reason names the rows that did not reach T (not in q), and
    success is whether q has a branch and every row reached T.\"\"\"
    T = np.asarray(T.A if isinstance(T, SE3) else T, dtype=float)
    found, reasons, most = [], [], 0
    for k, row in enumerate(candidates(T)):
        q, worst, taken = polish(row, T)
        most = max(most, taken)
        if not worst <= tol:
            reasons.append(f"candidate {k} stops {worst:.1e} from T")
        elif not any(same(q, other) for other in found):
            found.append(q)
    q = np.array([normalise_q(b, robot.qlim, REVOLUTE) for b in found]).reshape(-1, robot.n)
    if joint_limits:
        q = q[np.array([within_limits(b, robot.qlim) for b in q], dtype=bool)]
        if found and not len(q):
            reasons.append(f"all {len(found)} branches violate the joint limits")
    return IKSolution(q, len(q) > 0 and not reasons, most, reason="; ".join(reasons))
"""


def _solve(table: Table) -> list[str]:
    """The script's ``solve`` and its helpers (:data:`SOLVE`, :data:`CANDIDATES` by the kind of
    joint 1)."""
    text = (
        SOLVE.replace("@SIZE@", repr(table.size))
        .replace("@UNIT@", table.length_unit)
        .replace("@CANDIDATES@", CANDIDATES[table.rows[0].kind].rstrip("\n"))
    )
    return text.split("\n")


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
    if form.method is not None:
        out += ["import numpy as np"]
    out.append(f"from roboticstoolbox import DHRobot, {', '.join(classes)}")
    if form.method is not None:
        out.append("from roboticstoolbox.robot.IK import IKSolution, normalise_q, within_limits")
    out.append("from spatialmath import SE3")
    if form.method is not None:
        out.append("from spatialmath.base import tr2delta")
    out.append("")
    out.append("robot = DHRobot(")
    out.append("    [")
    out.extend(_link(table, r, numbers) for r in rows)
    out.append("    ],")
    out.append(f"    name={python_string(table.robot or 'robot')},")
    out.append(f"    base={_se3(base, numbers)},")
    out.append(f"    tool={_se3(tool, numbers)},")
    out.append(")")
    if form.method is not None:
        out += _solve(table)
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
