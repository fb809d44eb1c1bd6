"""When a D-H table is not the one to write: the one rule that ``convert``, every export and
``calibrate`` apply where no convention is asked for (docs/parallel-axes.md).

A D-H table (``dh``, ``mdh``) of a chain is exact up to the judgements the tolerances ask for
(:class:`~urdf2dh.tolerances.Tolerances`: axes within ``--parallel-angle`` of parallel are treated
as parallel, with their deviation declared). It is not the table to write when

* a row's ``|d|`` or ``|a|`` lies beyond ``far_factor`` x the robot's size: nearly parallel axes
  put the exact common normal far away (an identified axis 0.6 degrees off, or ``--exact``),
  where D-H loses precision and the numbers say nothing about the robot; or
* axes farther from parallel than ``--parallel-angle`` were treated as parallel all the same
  (their exact common normal lies beyond ``sane_factor`` x the robot's size): a deviation
  beyond what was asked for.

Then :func:`choose` writes the ``hayati`` table instead (exact, every length within the
geometry's own distances) where the reader takes one, and an export target that reads D-H only
refuses the chain. A convention asked for by name is written as asked.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from ..errors import visible
from .convert import build_table, deviation_bound, to_table

if TYPE_CHECKING:
    from ..model.poe import PoeModel
    from ..tolerances import Tolerances
    from .table import Table

__all__ = ["D_H", "FALLBACK", "Choice", "choose", "objection"]

D_H = ("dh", "mdh")  # the conventions built on common normals, which the rule judges
FALLBACK = "hayati"  # exact where D-H is not, with every length within the geometry's own


@dataclass(frozen=True, slots=True)
class Choice:
    """The table to write, and why it is not the one first in line (``None``: it is)."""

    table: Table
    reason: str | None


def objection(model: PoeModel, table: Table, tol: Tolerances, style: str = "wu") -> str | None:
    """Why ``table`` (of ``model``, in ``style``) is not the table to write, or ``None`` (module
    docstring); tables of conventions other than ``dh`` and ``mdh`` have none."""
    if table.convention not in D_H:
        return None
    name, unit, size = table.convention, table.length_unit, table.size
    far = tol.far_factor * size
    for row in table.rows:
        for key, value in row.params.scalars().items():
            if key in ("d", "a") and abs(value) > far:
                return (
                    f"{name} would put row {visible(row.name)!r} {abs(value):.3g} {unit} away "
                    f"({key}), {abs(value) / size:.3g} times the robot's size"
                )
    _, result = build_table(model, name, tol, style)
    unasked = tuple(
        j for j in result.judgements if j.kind == "parallel" and j.angle > tol.parallel_angle
    )
    pos, rot = deviation_bound(unasked, model.reach() + model.travel())
    if unasked and (pos > tol.report * size or rot > tol.report):
        j = max(unasked, key=lambda j: j.angle)
        return (
            f"{name} would treat {visible(j.first)!r} and {visible(j.second)!r}, "
            f"{j.angle:.3g} rad from parallel (beyond --parallel-angle {tol.parallel_angle:g}), "
            f"as parallel: a deviation of up to {pos:.3g} {unit}, {rot:.3g} rad"
        )
    return None


def choose(
    model: PoeModel,
    convention: str,
    tol: Tolerances,
    samples: int | None = None,
    style: str = "wu",
    fallback: str | None = FALLBACK,
) -> Choice:
    """The table of ``convention`` (the reader's first), unless :func:`objection` has one: then
    the ``fallback`` table (``hayati``), or with ``fallback=None`` (a reader of D-H only) the
    ``convention``'s table all the same, with the reason, for the reader to refuse it.

    Raises
    ------
    ConversionError, UsageError
        As :func:`~urdf2dh.conventions.convert.to_table` does.
    """
    table = to_table(model, convention, tol, samples=samples, style=style)
    problem = objection(model, table, tol, style)
    if problem is None or fallback is None:
        return Choice(table, problem)
    chosen = to_table(model, fallback, tol, samples=samples, style="wu")
    reason = (
        f"written in {fallback}, not {convention}: {problem}; {fallback} is exact and every "
        f"length stays within the geometry's own distances (--convention {convention} writes "
        f"{convention} all the same)"
    )
    return Choice(replace(chosen, warnings=(reason, *chosen.warnings)), reason)
