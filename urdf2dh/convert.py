"""POE model -> table in any convention, with the self-check that guards every answer.

:func:`to_table` is the one entry point: it converts, measures the table's forward kinematics
against the POE model's at seeded random configurations, turns every tolerance judgement into a
warning with the deviation it caused, and refuses (``ConversionError``, exit 1) a table whose
deviation is not accounted for.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import chainfk, cpc, dh, se3
from .errors import ConversionError, UsageError, choices
from .lines import Judgement, LinkParams
from .screws import PoeModel
from .table import CONVENTIONS, Check, Row, Table
from .tolerances import DEFAULT, Tolerances

__all__ = [
    "DEFAULT_SAMPLES",
    "JUDGED_SAMPLES",
    "build_table",
    "sample_configurations",
    "self_check",
    "to_table",
]

# The self-check's configurations, unless asked for a number. An exact table agrees with its
# source everywhere and a wrong one almost nowhere (forward kinematics is analytic in q), so
# 100 configurations settle exactness. Where a reported judgement (axes treated as parallel)
# introduces a deviation, the check measures how large it is: there it looks at 1000.
DEFAULT_SAMPLES = 100
JUDGED_SAMPLES = 1000


def sample_configurations(
    model: PoeModel, samples: int, seed: int | tuple[int, ...]
) -> NDArray[np.float64]:
    """``(samples, n)`` joint positions drawn uniformly within the model's limits (seeded; a
    tuple seed names a separate stream, as ``numpy.random.default_rng`` takes it)."""
    lim = model.limits()
    # the same numbers as rng.uniform(low, high, size), without its slow broadcasting path
    # default_rng(seed), by way of its SeedSequence (the quicker path, the same stream)
    unit = np.random.Generator(np.random.PCG64(_seed_sequence(seed))).random((samples, model.n))
    return lim[:, 0] + (lim[:, 1] - lim[:, 0]) * unit


@functools.lru_cache(maxsize=64)
def _seed_sequence(seed: int | tuple[int, ...]) -> np.random.SeedSequence:
    """The seed's entropy, hashed once per process (a third of the cost of starting a
    generator; a SeedSequence is not changed by the generators made from it)."""
    return np.random.SeedSequence(seed)


def _link(p: LinkParams) -> dict[str, float]:
    return {"theta": p.theta, "d": p.d, "alpha": p.alpha, "a": p.a}


def build_table(
    model: PoeModel, convention: str, tol: Tolerances, style: str = "wu"
) -> tuple[Table, list[Any]]:
    """Convert without checking. Returns the table and the judgements/notes made.

    ``style`` chooses among equivalent D-H tables: ``wu`` (SPEC §3, Wu 2019), ``ur`` (zero
    theta offsets and Universal Robots' sign choices) or ``zero`` (zero theta offsets, the
    base's included, wherever the geometry allows); it does not apply to ``cpc``.
    """
    if convention not in CONVENTIONS:
        raise UsageError(f"unknown convention '{convention}'; valid: {choices(CONVENTIONS)}")
    if style not in dh.STYLES:
        raise UsageError(f"unknown style '{style}'; valid: {choices(dh.STYLES)}")
    if style != "wu" and convention == "cpc":
        raise UsageError(f"--style {style} applies to the D-H conventions (dh, mdh), not cpc")
    scales = [j.scale for j in model.joints]
    found: list[Any] = []
    if convention == "cpc":
        shapes, signs, notes = cpc.shapes_from_poe(model, tol)
        base, params, tool = shapes[0], shapes[1:], {}
        scales = [s * sign for s, sign in zip(scales, signs, strict=True)]
        found.extend(notes)
        found.extend(
            f"cpc: joint '{j.name}' points against the previous frame's z; its frame is "
            "reversed (scale = -scale) to avoid R(b)'s singularity at b = -z"
            for j, sign in zip(model.joints, signs, strict=True) if sign < 0
        )
    else:
        links, (tt, td), judgements = dh.links_from_poe(model, tol, style)
        found.extend(judgements)
        if convention == "dh":
            base = _link(links[0])
            params = [_link(p) for p in links[1:]]
            tool = {"theta": tt, "d": td}
        else:  # mdh: the same common normals grouped Rx Tx | Q | Rz Tz (see mdh.py)
            base = {"theta": links[0].theta, "d": links[0].d}
            params = [
                {"alpha": prev.alpha, "a": prev.a, "theta": cur.theta, "d": cur.d}
                for prev, cur in itertools.pairwise(links)
            ]
            tool = {"alpha": links[-1].alpha, "a": links[-1].a, "theta": tt, "d": td}
    rows = tuple(
        Row(j.name, j.kind, p, j.pitch, s, j.lower, j.upper)
        for j, p, s in zip(model.joints, params, scales, strict=True)
    )
    table = Table(
        convention, base, rows, tool, model.name, model.source, model.base_link,
        model.tip_link, model.length_unit,
    )
    return table, found


def self_check(
    model: PoeModel, table: Table, samples: int = DEFAULT_SAMPLES, seed: int = 0
) -> Check:
    """The table's FK against the model's at ``samples`` seeded configurations.

    Both in link form (:meth:`Table.link_form`; :meth:`PoeModel.link_form`, the exponentials
    written as ``C Q C^-1``), evaluated side by side in the same numpy calls
    (:func:`urdf2dh.chainfk.compare_links`). ``Table.fk_batch`` and ``PoeModel.fk_batch`` are the
    same functions evaluated otherwise; the tests hold all of them to each other.
    """
    q = sample_configurations(model, samples, seed)
    (table_links, table_motions), (poe_links, poe_motions) = table.link_form(), model.link_form()
    links = se3.stack(table_links + poe_links).reshape(2, -1, 4, 4)
    pos, rot = chainfk.compare_links(links, [table_motions, poe_motions], q)
    return Check(samples, pos, rot)


def _fmt_len(x: float, unit: str) -> str:
    return f"{x:.3g} {unit}"


def to_table(
    model: PoeModel,
    convention: str = "dh",
    tol: Tolerances = DEFAULT,
    samples: int | None = None,
    seed: int = 0,
    style: str = "wu",
) -> Table:
    """Convert ``model`` to ``convention`` and check the result, at ``samples`` configurations
    (by default :data:`DEFAULT_SAMPLES`, or :data:`JUDGED_SAMPLES` where a reported judgement
    introduced a deviation), before returning it.

    Raises
    ------
    ConversionError
        If the table's forward kinematics deviates from the model's by more than the machine
        tolerance plus what the reported judgements account for.
    """
    table, found = build_table(model, convention, tol, style)
    size, reach, unit = model.size(), max(model.reach(), model.size()), model.length_unit
    warnings = list(model.warnings)
    allowed_pos, allowed_rot = tol.check_position * size, tol.check_rotation
    snapped = False
    for item in found:
        if isinstance(item, str):
            warnings.append(item)
            continue
        j: Judgement = item
        allowed_pos += 2.0 * (j.angle * reach + j.gap)
        allowed_rot += 2.0 * j.angle
        # a judgement is new only if the lines are apart both in the frames built so far and in
        # the source; otherwise it carries on (or undoes) an earlier judgement's deviation
        shown = j.angle if j.source_angle is None else min(j.angle, j.source_angle)
        if shown <= tol.report and j.gap <= tol.report * size:
            continue  # below the exactness promised, or a consequence of an earlier judgement
        snapped = True
        if j.kind == "parallel":
            warnings.append(
                f"{convention}: '{j.first}' and '{j.second}' are {shown:.3g} rad from parallel; "
                f"treated as parallel (--parallel-angle {tol.parallel_angle:g})"
            )
        else:
            warnings.append(
                f"{convention}: '{j.first}' and '{j.second}' are {_fmt_len(j.gap, unit)} apart; "
                f"treated as {j.kind} (--intersect-distance {tol.distance(size):.3g})"
            )
    if samples is None:
        samples = JUDGED_SAMPLES if snapped else DEFAULT_SAMPLES
    check = self_check(model, table, samples, seed)
    if snapped:
        warnings.append(
            f"{convention}: FK deviation from the source caused by these judgements: "
            f"{_fmt_len(check.max_position_error, unit)}, {check.max_rotation_error:.3g} rad "
            f"(worst of {samples} configurations); --exact keeps the exact geometry"
        )
    if convention in ("dh", "mdh"):
        far = tol.far_factor * size
        for row in table.rows:
            big = [k for k in ("d", "a") if abs(row.params[k]) > far]
            if big:
                vals = ", ".join(f"|{k}| = {_fmt_len(abs(row.params[k]), unit)}" for k in big)
                warnings.append(
                    f"{convention}: row '{row.name}' has {vals}, far beyond the robot's extent "
                    f"({_fmt_len(model.extent(), unit)}): nearly parallel axes put the common "
                    "normal far away and D-H loses precision there; cpc (or the POE model) "
                    "describes this geometry without it, while mdh shares the common normals"
                )
    if not (check.max_position_error <= allowed_pos and check.max_rotation_error <= allowed_rot):
        raise ConversionError(
            f"{model.source or model.name}: the {convention} table's forward kinematics deviates "
            f"from the source by {_fmt_len(check.max_position_error, unit)} and "
            f"{check.max_rotation_error:.3g} rad (allowed {_fmt_len(allowed_pos, unit)}, "
            f"{allowed_rot:.3g} rad); the table is not written"
            + ("" if math.isfinite(check.max_position_error) else " (non-finite result)")
        )
    return replace(table, check=check, warnings=tuple(warnings))
