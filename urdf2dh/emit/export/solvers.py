"""What the exports for analytic inverse-kinematics solvers share (``eaik``, ``ikdh``, ``rtb``):
the chain each writes, refused with the reason where the solver cannot take it, and the lines
that state what the file's joint variables, base and tool are and how exact it is.
"""

from __future__ import annotations

from dataclasses import dataclass

from ...conventions.analytic import AnalyticChain, analytic_form
from ...conventions.dh import DhLink
from ...conventions.families import Relations, refusal, rtb_method
from ...conventions.grid import summary
from ...conventions.table import Table
from ...errors import ExportError
from .common import ExportOptions, header, require, require_uncoupled

__all__ = ["RtbForm", "chain_header", "rtb_form", "solver_chain"]


def solver_chain(
    table: Table, target: str, opts: ExportOptions, unless: str | None = ""
) -> AnalyticChain:
    """The analytic form of a checked ``dh`` table (:mod:`urdf2dh.conventions.analytic`), or
    :class:`~urdf2dh.errors.ExportError` naming why ``target`` cannot solve the chain
    (:func:`urdf2dh.conventions.families.refusal`, followed by ``unless``: what else was tried;
    no error where ``unless`` is ``None``)."""
    require_uncoupled(table.rows, target)  # the coupling first: it names what to do
    require(table, target, ("dh",), ("revolute",))
    chain = analytic_form(table, opts.tol)
    why = refusal(target, chain)
    if why is not None and unless is not None:
        raise ExportError(f"{target}: {why}{unless}")
    return chain


def chain_header(chain: AnalyticChain, what: str, formula: str) -> list[str]:
    """Comment lines (without the comment marker): the robot and chain, ``formula`` (the
    solver's forward kinematics), the table's check and warnings, and what the analytic form
    changed, with the bound of the whole chain against the source where it declares one."""
    lines = header(chain.table, what)
    lines[1] = formula
    own = set(summary(chain.table))
    lines += [f"warning: {w}" for w in chain.warnings() if f"warning: {w}" not in own]
    c = chain.check
    if c.declared_position or c.declared_rotation:
        lines.append(
            f"declared bound against the source: {c.declared_position:.2g} {chain.length_unit}, "
            f"{c.declared_rotation:.2g} rad (the table's and the snaps' above)"
        )
    return lines


@dataclass(frozen=True, slots=True)
class RtbForm:
    """What the ``rtb`` export writes of a table: the analytic form where roboticstoolbox's
    analytic IK can take the chain (``chain``, else ``None``: the table's rows), the motions the
    tool takes over from the last row (``Rx``, ``Tx``), the docstring's lines, and the method
    roboticstoolbox solves the chain with (``closed form``, ``general 6R``; ``None``: none)."""

    chain: AnalyticChain | None
    tool_motions: list[tuple[str, float]]
    lines: list[str]
    method: str | None = None


def rtb_form(table: Table, opts: ExportOptions) -> RtbForm:
    """The ``rtb`` export's chain: a six-joint ``dh`` table as its analytic form (exact multiples
    of pi and zeros, the last row's tilt in the tool), so that ``robot.analytic_ik()`` derives
    its solver; any other table as it is, saying why roboticstoolbox has no analytic IK for it."""
    what = "roboticstoolbox-python DHRobot"
    if table.convention != "dh" or table.n != 6:
        why = (
            f"it takes six joints, the chain has {table.n}"
            if table.convention == "dh"
            else "it takes standard D-H tables: --convention dh"
        )
        return RtbForm(None, [], [*header(table, what), f"analytic IK: none ({why})"])
    chain = analytic_form(table, opts.tol)
    method = rtb_method(Relations.of(chain))
    lines = chain_header(chain, what, table.spec.formula)
    if isinstance(method, str):
        lines.append(f"analytic IK: none in roboticstoolbox ({method})")
    else:
        axes = f" (axes {', '.join(map(str, method[1]))})" if method[1] else ""
        lines.append(
            f"analytic IK: solve(T), every branch of roboticstoolbox's robot.analytic_ik(): "
            f"{method[0]}{axes}, each polished on robot's own forward kinematics "
            "(docs/exports/rtb.md#analytic-ik); roboticstoolbox derives its solver symbolically "
            "once per robot and process (seconds to minutes)"
        )
    last = table.rows[-1].params
    assert isinstance(last, DhLink)  # a dh table's rows
    name = None if isinstance(method, str) else method[0]
    return RtbForm(chain, [("Rx", last.alpha), ("Tx", last.a)], lines, name)
