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
geometry's own distances) where the reader takes one. A reader of D-H tables only (most export
targets) gets the D-H table of far rows all the same, which is exact, with the reason among its
warnings, and is refused the one that deviates beyond what was asked (:attr:`Objection.exact`).
A convention asked for by name is written as asked.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..checks import unchecked_replace
from ..errors import visible
from .convert import build_table, check_arguments, checked, deviation_bound, unchecked_table

if TYPE_CHECKING:
    from ..geometry.normals import Judgement
    from ..model.poe import PoeModel
    from ..tolerances import Tolerances
    from .table import Table

__all__ = ["D_H", "FALLBACK", "Choice", "Objection", "choose", "objection"]

D_H = ("dh", "mdh")  # the conventions built on common normals, which the rule judges
FALLBACK = "hayati"  # exact where D-H is not, with every length within the geometry's own


@dataclass(frozen=True, slots=True)
class Objection:
    """Why a D-H table is not the one to write; ``exact``: whether it is exact all the same
    (rows far away, within the bound it declares), or deviates beyond what was asked."""

    reason: str
    exact: bool


@dataclass(frozen=True, slots=True)
class Choice:
    """The table to write; ``objection`` to the one first in line (``None``: none), and
    ``reason``, what the table's first warning says of it (``None``: nothing)."""

    table: Table
    objection: Objection | None
    reason: str | None


def objection(
    model: PoeModel,
    table: Table,
    tol: Tolerances,
    style: str = "wu",
    judgements: tuple[Judgement, ...] | None = None,
) -> Objection | None:
    """Why ``table`` (of ``model``, in ``style``) is not the table to write, or ``None`` (module
    docstring); tables of conventions other than ``dh`` and ``mdh`` have none. ``judgements``:
    those of the conversion that made ``table``, when the caller has them (else it is made
    again, where the rows alone raise no objection)."""
    if table.convention not in D_H:
        return None
    return _far(table, tol) or _unasked(
        model,
        table,
        judgements
        if judgements is not None
        else build_table(model, table.convention, tol, style)[1].judgements,
        tol,
    )


def _far(table: Table, tol: Tolerances) -> Objection | None:
    """A row of the D-H ``table`` beyond ``far_factor`` x the robot's size, or ``None``."""
    name, unit, size = table.convention, table.length_unit, table.size
    far = tol.far_factor * size
    for row in table.rows:
        for key, value in row.params.scalars().items():
            if key in ("d", "a") and abs(value) > far:
                return Objection(
                    f"{name} would put row {visible(row.name)!r} {abs(value):.3g} {unit} away "
                    f"({key}), {abs(value) / size:.3g} times the robot's size",
                    True,
                )
    return None


def _unasked(
    model: PoeModel, table: Table, judgements: tuple[Judgement, ...], tol: Tolerances
) -> Objection | None:
    """Axes beyond ``--parallel-angle`` from parallel treated as parallel all the same by the
    conversion to the D-H ``table`` (its ``judgements``), or ``None``."""
    name, unit, size = table.convention, table.length_unit, table.size
    unasked = tuple(j for j in judgements if j.kind == "parallel" and j.angle > tol.parallel_angle)
    pos, rot = deviation_bound(unasked, model.reach() + model.travel())
    if unasked and (pos > tol.report * size or rot > tol.report):
        j = max(unasked, key=lambda j: j.angle)
        return Objection(
            f"{name} would treat {visible(j.first)!r} and {visible(j.second)!r}, "
            f"{j.angle:.3g} rad from parallel (beyond --parallel-angle {tol.parallel_angle:g}), "
            f"as parallel: a deviation of up to {pos:.3g} {unit}, {rot:.3g} rad",
            False,
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
    ``convention``'s table all the same, the reason its first warning where it is exact (the
    reader refuses it where it is not). The table returned is checked as
    :func:`~urdf2dh.conventions.convert.to_table` checks it; a D-H table set aside for the
    ``fallback`` is not checked (nothing reads it).

    Raises
    ------
    ConversionError, UsageError
        As :func:`~urdf2dh.conventions.convert.to_table` does.
    """
    check_arguments(model, convention, tol, samples, 0, style)
    # the D-H table and its judgements, made once for the objection and for its check
    built = unchecked_table(model, convention, tol, style)
    problem = objection(model, built[0], tol, style, built[1].judgements)
    if problem is None or fallback is None:  # the D-H table is the one returned
        table, _ = checked(model, convention, tol, samples, 0, style, built)
        if problem is None:
            return Choice(table, None, None)
        if not problem.exact:
            return Choice(table, problem, None)
        reason = (
            f"{problem.reason}; written in {convention} all the same: the reader takes D-H "
            "tables only, and this one is exact"
        )
        return Choice(unchecked_replace(table, warnings=(reason, *table.warnings)), problem, reason)
    chosen, _ = checked(model, fallback, tol, samples, 0, "wu")
    reason = (
        f"written in {fallback}, not {convention}: {problem.reason}; {fallback} is exact and "
        f"every length stays within the geometry's own distances (--convention {convention} "
        f"writes {convention} all the same)"
    )
    # a checked table with one more warning (text made here)
    return Choice(unchecked_replace(chosen, warnings=(reason, *chosen.warnings)), problem, reason)
