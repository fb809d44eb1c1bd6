"""LinuxCNC ``genserkins``: HAL ``setp`` lines for its six Craig-convention links.

The consumer (LinuxCNC's genserkins, ``genserfuncs.c``): six revolute links; link ``i`` is
``go_dh_pose_convert`` of ``(A-i, ALPHA-i, D-i, theta = joint i)``, which is Craig's
``Rx(ALPHA-i) Tx(A-i) Rz(joint i) Tz(D-i)``, and the tool pose is their product: no base or tool
transform and no theta offsets. Joint positions are in degrees, ``A`` and ``D`` in the machine's
length unit, ``ALPHA`` in radians.

From a modified D-H (``mdh``) table ``Rz(theta_B) Tz(d_B) . prod_i [Rx(alpha_i) Tx(a_i) Q_i
Rz(theta_i) Tz(d_i)] . Rx(alpha_T) Tx(a_T) Rz(theta_T) Tz(d_T)``:

* every ``theta_i`` must be 0 (``--style ur`` prefers zero offsets);
* the base height ``d_B`` joins ``D-0``: with ``alpha_1 = a_1 = 0`` the base's ``Rz Tz`` commutes
  with joint 1, so ``theta_B`` must be 0 and ``d_B`` adds to ``d_1``; otherwise the base must be
  the identity;
* the tool length ``d_T`` joins the last link's ``D``; ``alpha_T``, ``a_T``, ``theta_T`` must be 0;
* fewer than six joints leave the last links zero (their joints held at 0).

Values whose effect is below the exactness a table promises (``check_rotation`` rad,
``check_position`` x size) count as zero here; anything more is refused with the reason.
"""

from __future__ import annotations

import math

import numpy as np

from .. import units
from ..errors import ExportError, shown, visible
from ..se3 import dh_matrix
from ..table import Table
from .common import (
    Numbers,
    Options,
    close_to,
    floats,
    header,
    require,
    require_convention,
)
from .escape import hal_comment

__all__ = ["JOINTS", "UNITS", "render"]

JOINTS = 6  # genserkins' GENSER_MAX_JOINTS: it always evaluates six links
UNITS = {"mm": "mm", "inch": "inch", "in": "inch"}


def _refuse(table: Table, why: str) -> ExportError:
    return ExportError(f"linuxcnc: genserkins {why}; this chain cannot be written for it")


def _links(table: Table, opts: Options) -> list[tuple[float, float, float]]:
    """``(a, alpha, d)`` per genserkins link in the table's unit, base and tool folded in."""
    tol = opts.tol
    rows = [floats(r.params) for r in table.rows]
    offsets = [
        f"{shown(r.name)} ({math.degrees(p['theta']):.6g} deg)"
        for r, p in zip(table.rows, rows, strict=True)
        if abs(p["theta"]) > tol.check_rotation
    ]
    if offsets:
        raise _refuse(
            table,
            "has no theta offsets, and joints "
            + ", ".join(offsets)
            + " need them at their zero position (try --style ur)",
        )
    links = [(p["a"], p["alpha"], p["d"]) for p in rows]
    base, tool = floats(table.base), floats(table.tool)
    base_d = base["d"]
    base_moves = abs(base["theta"]) > tol.check_rotation
    a1, alpha1, d1 = links[0]
    if close_to(table, table.base_matrix, np.eye(4), tol):
        pass
    elif not base_moves and close_to(table, dh_matrix(0.0, 0.0, alpha1, a1), np.eye(4), tol):
        links[0] = (0.0, 0.0, d1 + base_d)  # Tz(d_B) slides along joint 1's axis into D-0
    else:
        raise _refuse(
            table,
            f"has no base transform, and the base frame {shown(table.base_link)} "
            f"is turned {math.degrees(base['theta']):.6g} deg about joint 1's "
            "axis from its zero position (or offset off it); choose a base link whose "
            "x axis lies along joint 1's zero direction",
        )
    if not close_to(table, table.tool_matrix, dh_matrix(0.0, tool["d"], 0.0, 0.0), tol):
        raise _refuse(
            table,
            f"has no tool transform beyond a length along the last axis, and "
            f"{shown(table.tip_link)} is turned or offset from it (tool alpha = "
            f"{math.degrees(tool['alpha']):.6g} deg, a = {tool['a']:.6g} "
            f"{visible(table.length_unit)}, theta = "
            f"{math.degrees(tool['theta']):.6g} deg); "
            "choose a tip link on the last joint's axis with the same x",
        )
    a, alpha, d = links[-1]
    links[-1] = (a, alpha, d + tool["d"])
    return links


def render(table: Table, opts: Options) -> str:
    """HAL ``setp`` lines for genserkins (see the module docstring)."""
    require_convention(table, "linuxcnc", ("mdh",))
    if table.n > JOINTS:
        raise _refuse(table, f"evaluates {JOINTS} joints, and this chain has {table.n}")
    require(table, "linuxcnc", ("mdh",), ("revolute",))
    unit = UNITS.get(opts.units or "mm")
    if unit is None:
        raise ExportError(f"linuxcnc: --units must be mm or inch, not '{opts.units}'")
    links = _links(table, opts)
    numbers = Numbers.of(table, opts.tol, units.factor(table.length_unit, unit))
    notes = header(table, "LinuxCNC genserkins parameters")
    notes.append(
        f"genserkins link i = Rx(ALPHA-i) Tx(A-i) Rz(joint i) Tz(D-i) (Craig); A and D "
        f"in {unit}, ALPHA in radians,"
    )
    notes.append(
        "joint positions in degrees. The base height is in D-0, the tool length in "
        f"D-{len(links) - 1}."
    )
    for i, row in enumerate(table.rows):
        lim = ""
        if row.lower is not None and row.upper is not None:
            lim = f", limits {math.degrees(row.lower):.6g} .. {math.degrees(row.upper):.6g} deg"
        notes.append(f"joint {i}: {row.name}{lim}")
    for i in range(table.n, JOINTS):
        notes.append(f"joint {i}: none (a zero link; hold this joint at 0)")
    out = [line for note in notes for line in hal_comment(note)]
    links += [(0.0, 0.0, 0.0)] * (JOINTS - len(links))
    for i, (a, alpha, d) in enumerate(links):
        out.append(f"setp genserkins.A-{i} {numbers.lin(a)}")
        out.append(f"setp genserkins.ALPHA-{i} {numbers.ang(alpha)}")
        out.append(f"setp genserkins.D-{i} {numbers.lin(d)}")
    return "\n".join(out) + "\n"
