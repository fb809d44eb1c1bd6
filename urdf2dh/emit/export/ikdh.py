"""ikdh (``ikdh`` on PyPI): the robot file of the Husty-Pfurner general 6R solver.

ikdh 1.2 reads a robot with ``ikdh.load_robot(path)``, a line scanner (``include/robots.h``), not
a YAML parser: a line holding ``dh:`` or ``limits:`` opens that section, ``#`` starts a comment
anywhere, ``name:`` takes the rest of its line, in ``dh:`` the lines starting ``a:``, ``d:``,
``alpha:`` and ``theta:`` each hold ``[v1, ..., v6]`` (a number, ``pi``, ``pi/N``, ``pi*N``, with
a leading ``-``), and in ``limits:`` the first six lines with ``[`` are each joint's ``[lo, hi]``
in degrees. Its forward kinematics is ``prod_i Rz(theta_i + q_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``:
standard D-H, so the table's rows go over one to one, ``theta`` the joint offsets and ``q`` the
source's joint positions (``Solver.solve`` returns them in degrees).

ikdh has no base or tool: they follow what it reads, as ``base`` and ``tool`` (4x4, rows), so
that ``pose = base . F(q) . tool`` and the solver is asked for ``base^-1 . T . tool^-1``. Lengths
are in millimetres (``--units m``: metres): ikdh polishes every solution by Newton's method until
the 12 entries of its pose error have a norm below 1e-9, so in the file's length unit, which
keeps every solution within 1e-9 mm and 7.1e-10 rad of the pose (in metres, 1e-9 m is more than
1e-9 of the size of an arm under a metre). Exact multiples of pi/2 are written ``pi/2``; names
appear in comments and, as :func:`~urdf2dh.escape.ikdh_name` makes them, on the ``name:`` line.
The file is valid YAML too (``pi/2`` reads as a string there).
"""

from __future__ import annotations

import math

import numpy as np

from ... import units
from ...conventions.families import ikdh_method, kinds_of
from ...conventions.table import Table
from ...errors import ExportError, shown
from ...escape import ikdh_name, yaml_comment
from .common import (
    ExportOptions,
    Numbers,
    floats,
    header,
    require,
    require_uncoupled,
    yaml_float,
)

__all__ = ["UNITS", "render"]

UNITS = ("mm", "m")
FORMULA = (
    "pose(q) = base . prod_i [Rz(theta_i + q_i) Tz(d_i) Tx(a_i) Rx(alpha_i)] . tool (ikdh: "
    "standard D-H)"
)


def _matrix(key: str, m: np.ndarray, numbers: Numbers) -> list[str]:
    rows = numbers.matrix(m)
    return [f"{key}:"] + [f"  - [{', '.join(yaml_float(v) for v in row)}]" for row in rows]


def render(table: Table, opts: ExportOptions) -> str:
    """The ikdh robot file of a ``dh`` table (module doc)."""
    require_uncoupled(table.rows, "ikdh")  # the coupling first: it names what to do
    require(table, "ikdh", ("dh",), ("revolute",))
    why = ikdh_method(kinds_of(table.rows))
    if why is not None:
        raise ExportError(f"ikdh: {why}")
    for row in table.rows:
        if row.lower is not None and row.upper is not None and row.lower > row.upper:
            raise ExportError(
                f"ikdh: joint {shown(row.name)} has its lower limit {row.lower:.6g} above its "
                f"upper limit {row.upper:.6g}; ikdh keeps only solutions within [lower, upper], "
                "so it would return none"
            )
    unit = opts.units or UNITS[0]
    if unit not in UNITS:
        raise ExportError(f"ikdh: the length unit must be mm or m, not '{unit}'")
    numbers = Numbers.of(table, opts.tol, units.factor(table.length_unit, unit))
    params = [floats(r.params) for r in table.rows]
    notes = header(table, "ikdh robot file")
    notes[1] = FORMULA
    notes[2] = f"Lengths in {unit}, angles in radians, joint limits in degrees."
    notes += [
        "Read it with ikdh.load_robot(path) and solve with ikdh.Solver(robot.dh, robot.limits)."
        "solve(base^-1 . T . tool^-1), T the pose of "
        f"{table.tip_link or 'the tip'} in {table.base_link or 'the base'} ({unit}); each "
        "solution is the source's joint positions in degrees.",
        "Joints: " + ", ".join(f"{i} '{r.name}'" for i, r in enumerate(table.rows, 1)) + ".",
        "base and tool (below what ikdh reads, 4x4 rows): ikdh has no place for them.",
    ]
    lines = [yaml_comment(n) for n in notes]
    lines.append(f"name: {ikdh_name(table.robot)}")
    lines.append("dh:")
    for key in ("a", "d"):
        lines.append(f"  {key}: [{', '.join(numbers.lin(p[key]) for p in params)}]")
    for key in ("alpha", "theta"):
        lines.append(f"  {key}: [{', '.join(numbers.pi_ang(p[key]) for p in params)}]")
    lines.append("limits:")
    for i, row in enumerate(table.rows, 1):
        lo, hi = (-math.pi, math.pi) if row.lower is None or row.upper is None else (
            row.lower, row.upper)  # fmt: skip
        lines.append(f"  J{i}: [{yaml_float(math.degrees(lo))}, {yaml_float(math.degrees(hi))}]")
    lines += _matrix("base", table.base_matrix, numbers)
    lines += _matrix("tool", table.tool_matrix, numbers)
    lines.append(yaml_comment(_chain(table, unit)))
    return "\n".join(lines) + "\n"


def _chain(table: Table, unit: str) -> str:
    """``urdf2dh chain: {...}``, the comment urdf2dh reads the file back with
    (:mod:`urdf2dh.io.ikdhfile`): the robot, its links, its joints' names, the length unit and
    the joints whose limits the file makes up (+-180 deg: the table has none)."""
    from ...io.chaincomment import encoded

    unlimited = [i for i, r in enumerate(table.rows) if r.lower is None or r.upper is None]
    return encoded({"robot": table.robot, "base_link": table.base_link,
                    "tip_link": table.tip_link, "joints": [r.name for r in table.rows],
                    "unit": unit, "unlimited": unlimited})  # fmt: skip
