"""POE model -> table in any convention, with the self-check that guards every answer.

:func:`to_table` is the one entry point: it converts (the convention's ``from_poe``), measures
the table's forward kinematics against the POE model's at seeded random configurations, turns
every tolerance judgement into a warning with the deviation it caused, and refuses
(``ConversionError``, exit 1) a table whose deviation is not accounted for.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from ..checks import check_count, check_instance, check_seed, unchecked, unchecked_replace
from ..errors import ConversionError, UsageError, choices, near, shown
from ..geometry.normals import Judgement
from ..geometry.se3 import pose_errors
from ..model.fk import chains_fk
from ..model.poe import PoeModel
from ..tolerances import DEFAULT, EPS, FK_ROUNDING, Tolerances
from . import REGISTRY, STYLES, Conversion, get
from .base import Guide, Style
from .table import Check, Row, Table

__all__ = [
    "DEFAULT_SAMPLES",
    "JUDGED_SAMPLES",
    "build_table",
    "check_arguments",
    "checked",
    "deviation_bound",
    "rounding_bound",
    "self_check",
    "to_table",
    "unchecked_table",
    "written",
]

# The self-check's configurations, unless asked for a number. An exact table agrees with its
# source everywhere and a wrong one almost nowhere (forward kinematics is analytic in q), so
# 100 configurations settle exactness. Where a reported judgement (axes treated as parallel)
# introduces a deviation, the check measures how large it is: there it looks at 1000.
DEFAULT_SAMPLES = 100
JUDGED_SAMPLES = 1000

Mat = NDArray[np.float64]


def build_table(
    model: PoeModel, convention: str, tol: Tolerances, style: Style = "wu"
) -> tuple[Table, Conversion]:
    """Convert without checking: the table and what the convention made of the model (its
    judgements and notes).

    ``style`` chooses among equally exact tables where the convention allows a choice
    (:mod:`urdf2dh.conventions.dh`: ``wu``, ``ur``, ``zero``, or a
    :class:`~urdf2dh.conventions.base.Guide`).
    """
    conv = get(convention)
    if isinstance(style, Guide):
        if not conv.guided:
            takers = [c.name for c in REGISTRY.values() if c.guided]
            raise UsageError(f"a guide applies to {', '.join(takers)} tables, not {conv.name}")
    elif style not in STYLES:
        raise UsageError(f"unknown style '{style}'{near(style, STYLES)}; valid: {choices(STYLES)}")
    elif style not in conv.styles:
        takers = [c.name for c in REGISTRY.values() if style in c.styles]
        raise UsageError(f"style {style} applies to {', '.join(takers)} tables, not {conv.name}")
    result = conv.from_poe(model, tol, style)
    # the rows and the table are made of the model's checked joints and fields and of the
    # convention's own records: the constructors' checks would find nothing new
    rows = tuple(
        unchecked(Row, j.name, j.kind, p, j.pitch, float(j.scale * sign), j.lower, j.upper,
                  j.mimic)
        for j, p, sign in zip(model.joints, result.rows, result.signs, strict=True)
    )  # fmt: skip
    table = unchecked(
        Table, conv.name, result.base, rows, result.tool, model.size(), model.name, model.source,
        model.base_link, model.tip_link, model.length_unit,
    )  # fmt: skip
    return table, result


def unchecked_table(
    model: PoeModel, convention: str, tol: Tolerances, style: Style
) -> tuple[Table, Conversion]:
    """:func:`build_table`'s table as its files write it (:func:`written`), not yet checked
    (:func:`checked` checks it)."""
    table, result = build_table(model, convention, tol, style)
    return written(table, tol.written, tol.written * model.size()), result


def written(table: Table, angle: float, length: float) -> Table:
    """The table as its files write it (:meth:`~urdf2dh.conventions.base.Params.written`)."""
    # the same checked table with records of the same types in place of its records
    return unchecked_replace(
        table,
        base=table.base.written(angle, length),
        rows=tuple(
            unchecked_replace(r, params=r.params.written(angle, length)) for r in table.rows
        ),
        tool=table.tool.written(angle, length),
    )


def self_check(
    model: PoeModel, table: Table, samples: int = DEFAULT_SAMPLES, seed: int = 0
) -> Check:
    """The table's FK against the model's at ``samples`` seeded configurations (both by the
    reference FK, :func:`urdf2dh.model.fk.chains_fk`)."""
    positions = model.positions(model.sample(samples, seed))
    ours, source = chains_fk([table.link_form(), model.link_form()], positions)
    return Check(samples, *pose_errors(ours, source))


def deviation_bound(judgements: tuple[Judgement, ...], reach: float) -> tuple[float, float]:
    """What tolerance judgements can cost, at most, at any configuration: ``(position,
    rotation)``; ``reach`` bounds every point's distance from the base origin.

    A pair of lines treated as parallel (``angle`` apart) leaves the table's joint axis turned by
    ``angle`` about a point ``a`` of it (the judgement's ``pivot`` is ``|a|`` at home). Every
    frame after it is fitted to the source, so the table is the source's product of
    exponentials with that one screw turned: a turn ``q`` about it differs from the source's by
    ``S R S^T - R`` (``S`` the turn by ``angle``), of norm at most ``2 angle``, and moves a point
    ``p`` at most ``2 angle |p - a| <= 2 angle (reach + |a|)``, the orientation at most
    ``2 angle``. Lines ``gap`` apart treated as meeting shift the axis by ``gap``: a point moves
    at most ``2 gap``, the orientation not at all. A product of rigid motions differs from
    another by at most the sum of its factors' differences, so the judgements add.
    """
    position = math.fsum(2.0 * j.angle * (reach + j.pivot) + 2.0 * j.gap for j in judgements)
    return position, math.fsum(2.0 * j.angle for j in judgements)


def rounding_bound(table: Table) -> float:
    """What float64 evaluation of the table's forward kinematics may round by, at most:
    :data:`~urdf2dh.tolerances.FK_ROUNDING` x eps x the sum of its lengths (every length
    parameter and offset component of the base, rows and tool)."""
    lengths = []
    for params in (table.base, *(r.params for r in table.rows), table.tool):
        for name, quantity in params.quantities().items():
            value = getattr(params, name)
            if quantity == "length":
                lengths.append(abs(value))
            elif quantity == "offset":
                lengths.extend(abs(x) for x in value)
    return FK_ROUNDING * EPS * math.fsum(lengths)


def _length(x: float, unit: str) -> str:
    return f"{x:.3g} {unit}"


def check_arguments(
    model: object, convention: object, tol: object, samples: object, seed: object, style: object
) -> None:
    """:func:`to_table`'s arguments, each of its type and range (names are checked where they
    are looked up, listing the valid ones)."""
    hint = f"read one first: urdf2dh.load({shown(model)})" if isinstance(model, str) else (
        "urdf2dh.load(SOURCE) reads one")  # fmt: skip
    check_instance(model, PoeModel, "to_table: model", hint)
    check_instance(convention, str, "to_table: convention")
    if not isinstance(style, Guide):
        check_instance(style, str, "to_table: style")
    check_instance(tol, Tolerances, "to_table: tol", "urdf2dh.Tolerances(...) or urdf2dh.DEFAULT")
    if samples is not None:
        check_count(samples, "to_table: samples")
    check_seed(seed, "to_table: seed")


def to_table(
    model: PoeModel,
    convention: str = "dh",
    tol: Tolerances = DEFAULT,
    samples: int | None = None,
    seed: int = 0,
    style: Style = "wu",
) -> Table:
    """Convert ``model`` to ``convention`` and check the result before returning it.

    Parameters
    ----------
    model
        The chain (:func:`urdf2dh.load`).
    convention
        A name in :data:`urdf2dh.conventions.NAMES`.
    tol
        The tolerances of the judgements and of the check.
    samples
        Configurations of the self-check: by default :data:`DEFAULT_SAMPLES`, or
        :data:`JUDGED_SAMPLES` where a reported judgement introduced a deviation.
    seed
        Seed of the self-check's configurations.
    style
        Which of the equally exact tables (``wu``, ``ur``, ``zero``; D-H conventions), or a
        :class:`~urdf2dh.conventions.base.Guide` whose frames the D-H tables come nearest.

    Returns
    -------
    Table
        The table, its ``check`` and ``warnings`` filled in.

    Raises
    ------
    ConversionError
        If the table's forward kinematics deviates from the model's by more than the machine
        tolerance plus what the reported judgements account for.
    UsageError
        An unknown ``convention`` or ``style`` (the message lists the valid ones; a
        ``ValueError`` too).
    TypeError, ValueError
        An argument of the wrong type (``model`` not a :class:`~urdf2dh.model.poe.PoeModel`,
        ``tol`` not a :class:`~urdf2dh.tolerances.Tolerances`), or ``samples`` or ``seed`` out
        of range (``samples`` from 1 to :data:`~urdf2dh.checks.MAX_SAMPLES`).
    """
    check_arguments(model, convention, tol, samples, seed, style)
    return checked(model, convention, tol, samples, seed, style)[0]


def checked(
    model: PoeModel,
    convention: str,
    tol: Tolerances,
    samples: int | None,
    seed: int,
    style: Style,
    built: tuple[Table, Conversion] | None = None,
) -> tuple[Table, Conversion]:
    """:func:`to_table` of arguments checked already (:func:`check_arguments`), with what the
    convention made of the model (its judgements; :func:`build_table`). ``built``: the table
    and its conversion of these arguments made already (:func:`unchecked_table`), else made
    here.
    """
    table, result = built or unchecked_table(model, convention, tol, style)
    size, reach, unit = model.size(), model.reach() + model.travel(), model.length_unit
    warnings = list(model.warnings)
    declared_pos, declared_rot = deviation_bound(result.judgements, reach)
    snapped = False
    rounding = rounding_bound(table)
    for j in result.judgements:
        # a judgement is new only if the lines are apart both in the frames built so far and in
        # the source; otherwise it carries on (or undoes) an earlier judgement's deviation
        apart = j.angle if j.source_angle is None else min(j.angle, j.source_angle)
        pos, rot = deviation_bound((replace(j, angle=apart),), reach)
        if pos <= max(tol.report * size, rounding) and rot <= tol.report:
            continue  # below the exactness promised or the table's own rounding, or a
            # consequence of an earlier judgement
        snapped = True
        if j.kind == "parallel":
            warnings.append(
                f"{convention}: {shown(j.first)} and {shown(j.second)} are {apart:.3g} rad from "
                f"parallel; treated as parallel (--parallel-angle {tol.parallel_angle:g}; the "
                "exact D-H row is beyond reach or precision; --convention hayati is exact here)"
            )
        else:
            warnings.append(
                f"{convention}: {shown(j.first)} and {shown(j.second)} are "
                f"{_length(j.gap, unit)} apart; "
                f"treated as {j.kind} (--intersect-distance {tol.distance(size):.3g})"
            )
    judged_pos = declared_pos
    rounds = rounding > tol.report * size
    if rounds:  # lengths far beyond the robot's (their rows are named in the notes)
        declared_pos += rounding
    if samples is None:
        samples = JUDGED_SAMPLES if snapped else DEFAULT_SAMPLES
    check = self_check(model, table, samples, seed)
    allowed_pos = tol.check_position * size + declared_pos
    allowed_rot = tol.check_rotation + declared_rot
    worst = (
        f"(the worst of {samples} checked: {_length(check.max_position_error, unit)}, "
        f"{check.max_rotation_error:.3g} rad)"
    )
    if snapped:
        warnings.append(
            f"{convention}: FK deviation from the source caused by these judgements: at most "
            f"{_length(judged_pos, unit)}, {declared_rot:.3g} rad at any configuration"
            + ("" if rounds else " " + worst)
            + "; --exact keeps the exact geometry"
        )
    if rounds:
        total = rounding / (FK_ROUNDING * EPS)
        warnings.append(
            f"{convention}: its lengths add up to {_length(total, unit)}, "
            f"{total / size:.3g} x the robot's size: float64 evaluation of its FK may round by "
            f"up to {_length(rounding, unit)} {worst}"
        )
    if snapped or rounds:
        check = replace(check, declared_position=declared_pos, declared_rotation=declared_rot)
    warnings.extend(result.notes)
    if not (check.max_position_error <= allowed_pos and check.max_rotation_error <= allowed_rot):
        raise ConversionError(
            f"{model.source or model.name}: the {convention} table's forward kinematics deviates "
            f"from the source by {_length(check.max_position_error, unit)} and "
            f"{check.max_rotation_error:.3g} rad (allowed {_length(allowed_pos, unit)}, "
            f"{allowed_rot:.3g} rad); the table is not written"
            + ("" if math.isfinite(check.max_position_error) else " (non-finite result)")
        )
    # the table checked, with the Check made here and the warnings as text
    return unchecked_replace(table, check=check, warnings=tuple(warnings)), result
