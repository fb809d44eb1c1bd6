"""The figures of a finished identification, made into its :class:`~.result.Calibration`: before
and after on every set, the parameters and their flags, the levels' cross-validation, the
outliers, the output table and its ``diff``, the warnings. How they are shown is
:mod:`.report`'s; whether the measurements contradict them, :mod:`.plausible`'s.

Residual statistics of a model on a set: the position error is the distance between the
modelled and the measured tool point, the rotation error the angle of ``R R_meas^T``; RMS is the
root of their mean square, max the largest. "Before" is the nominal joints with base and tool
fitted (the base-tool level's fit), "after" the identified model. The noise floor is what a
perfect model would leave: ``sqrt(3) sigma`` for isotropic noise of ``sigma`` per coordinate.

Warnings are given when: a held-out, validation or cross-validated RMS position error exceeds
the fit's by more than noise explains (the ratio of mean squares, over its expectation
``(1 + p/m) / (1 - p/m)`` for ``p`` parameters and ``m`` equations, beyond the 99% point of
the F distribution of their degrees of freedom); parameters are poorly identified or not
determined at all (with the cause: a joint that barely moved, or configurations that do not tell
them apart); joints barely moved; outliers were found; the output convention was chosen.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import replace
from functools import partial
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..check.diff import Diff
from ..conventions.table import Table
from ..errors import visible
from ..model.identifiability import LINE_PARAMETERS, SYMBOLS
from ..model.poe import PoeModel
from ..tolerances import DIFF_ANGLE_DEG, DIFF_PARALLEL_DEG, POORLY_IDENTIFIED, Tolerances
from .chart import FRAME, Estimate, absorbed, local_coordinates
from .identifiable import barely_moved
from .identify import Identified
from .levels import LOWER
from .measurements import Measurements
from .outliers import Outliers
from .residuals import Data, errors, evaluate, rms
from .result import Calibration, Comparison, Counts, Held, Later, Noise, Parameter, Residuals
from .select import Pass, Score, Selection
from .start import to_data
from .userunits import UserUnits

if TYPE_CHECKING:
    from .problem import Options

__all__ = ["assemble", "formula", "in_words", "output_table"]

Mat = NDArray[np.float64]

CONFIDENCE = 0.99  # of the test that noise explains a held-out error


def formula(est: Estimate) -> str:
    """The level's parameter count before anything is held fixed, as a formula with its numbers:
    ``full`` is Wu 2019 eq. 23, ``5h + 4r + 2t + n + 6`` (poses; ``3K`` for ``K`` markers); the
    others name their parts (``base 6 + offsets n + tool 6``)."""
    level = est.level
    kinds = Counter(est.chain.kinds)
    tool = (2 if est.keep_tool_axis else 6) if est.tool == FRAME else None
    markers = len(est.markers)
    terms: list[tuple[str, str, int]] = []
    if level.base:
        terms.append(("base 6", "6", 6))
    if level.lines:
        for kind, size in LINE_PARAMETERS.items():
            terms.append((f"{size}{SYMBOLS[kind]}", f"{size}*{kinds[kind]}", size * kinds[kind]))
    if level.offsets:
        terms.append(("offsets n", str(est.n), est.n))
    if level.scales:
        terms.append(("n", str(est.n), est.n))
    end = str(tool) if tool is not None else "3K"
    if level.base:
        end = f"tool {end}" if tool is not None else f"markers {end}"
    terms.append((end, str(tool) if tool is not None else f"3*{markers}", tool or 3 * markers))
    total = sum(t[2] for t in terms)
    return f"{' + '.join(t[0] for t in terms)} = {' + '.join(t[1] for t in terms)} = {total}"


_KIND_WORDS = {"helical": "helical", "revolute": "revolute", "prismatic": "sliding"}


def _count(n: int, one: str, many: str | None = None) -> str:
    return f"{n} {one if n == 1 else (many or one + 's')}"


def in_words(est: Estimate) -> str:
    """What the level's parameters are, counted in words (the same count as :func:`formula`):
    ``6 for the base, 4 for each of 6 revolute joints' lines, 6 joint scales, 6 for the
    tool``."""
    level = est.level
    kinds = Counter(est.chain.kinds)
    parts = []
    if level.base:
        parts.append("6 for the base")
    if level.lines:
        for kind, size in LINE_PARAMETERS.items():
            if kinds[kind]:
                joints = _count(kinds[kind], f"{_KIND_WORDS[kind]} joint")
                parts.append(f"{size} for each of {joints}' lines" if kinds[kind] > 1
                             else f"{size} for the {_KIND_WORDS[kind]} joint's line")  # fmt: skip
    if level.offsets:
        parts.append(_count(est.n, "joint offset"))
    if level.scales:
        parts.append(_count(est.n, "joint scale"))
    if est.tool == FRAME:
        parts.append(f"{2 if est.keep_tool_axis else 6} for the tool")
    else:
        markers = len(est.markers)
        parts.append(
            f"3 for each of {_count(markers, 'marker')}" if markers > 1 else "3 for the marker"
        )
    return ", ".join(parts)


def _residuals(each: Mat) -> Residuals:
    pos = each[:, 0]
    out = Residuals(len(each), rms(pos), float(pos.max()))
    if each.shape[1] > 1:
        rot = each[:, 1]
        out = Residuals(
            out.count,
            out.rms_position,
            out.max_position,
            rms(rot),
            float(rot.max()),
        )
    return out


def _comparison(
    name: str,
    before: Estimate,
    after: Estimate,
    m: Measurements,
    data: Data,
    pose: bool,
    user: UserUnits,
    index: NDArray[np.int64] | None = None,
) -> Comparison:
    """Before and after (each with its offsets :func:`absorbed`, made once for every set) on
    ``m`` (``data``: its :func:`~.start.to_data`), in the user's unit; ``index``: each row's
    configuration number in the file (by default ``m``'s own)."""
    b, a = errors(before, data), errors(after, data)  # (N, 1 or 2): position, rotation errors
    b[:, 0], a[:, 0] = user.shown_array(b[:, 0]), user.shown_array(a[:, 0])
    if index is None:
        index = m.configurations()[0]
    rows = np.bincount(index)
    present = np.flatnonzero(rows)
    rows = rows[present]

    def per_config(e: Mat) -> tuple[float, ...]:
        sums = np.bincount(index, e**2)[present]  # each sum in row order
        return tuple(np.sqrt(sums / rows).tolist())

    return Comparison(
        name,
        _residuals(b),
        _residuals(a),
        tuple(int(c) for c in present),
        per_config(b[:, 0]),
        per_config(a[:, 0]),
        per_config(b[:, 1]) if pose else None,
        per_config(a[:, 1]) if pose else None,
    )


def _unit(name: str, kind: str, length: str) -> str:
    leaf = name.rsplit(".", 1)[1]
    if leaf == "scale":
        return "1"
    if leaf == "pitch":
        return f"{length}/rad"
    if leaf == "offset":
        return length if kind == "prismatic" else "rad"
    return "rad" if leaf.startswith(("turn", "r")) else length


def _reach(est: Estimate, now: Estimate, data: Data, size: float) -> Mat:
    """Per coordinate of ``est``, the largest displacement of a measured tool point (rotations
    at the robot's size) per unit of it, over ``data``; ``now``: ``est`` with its offsets
    :func:`absorbed`."""
    _, jac = evaluate(now if est.offsets is None else est, data, 1.0, 1.0 / size)
    rows = jac.reshape(len(data), data.rows, -1)
    return np.sqrt(np.sum(rows**2, axis=1)).max(axis=0) if len(data) else np.zeros(rows.shape[2])


def _flags(
    result: Identified, reach: Mat, still: dict[str, str], user: UserUnits
) -> tuple[list[str | None], list[str], list[str]]:
    """Each parameter's flag (why it is poorly identified or not determined, else ``None``); the
    poorly identified ones' names; the undetermined ones' names. ``reach``: :func:`_reach`;
    ``still``: the joints that barely moved, with their span."""
    unit = user.length
    sigma = user.shown(result.sigma_pos)
    flags: list[str | None] = []
    poor, lost = [], []
    for k, name in enumerate(result.names):
        owner, leaf = name.rsplit(".", 1)
        std = float(result.stats.std[k])
        flag = None
        moved = owner in still and leaf != "offset"
        if not math.isfinite(std):
            lost.append(name)
            flag = "not determined by the measurements" + (
                f": its joint barely moved ({still[owner]})" if moved else ""
            )
        elif moved:
            poor.append(name)
            flag = f"its joint barely moved ({still[owner]}): it holds near those positions only"
        elif std * reach[k] > POORLY_IDENTIFIED * result.sigma_pos:
            poor.append(name)
            flag = (
                f"one standard deviation moves a measured point by "
                f"{user.shown(std * reach[k]):.3g} {unit}, over {POORLY_IDENTIFIED:g} times the "
                f"position noise ({sigma:.3g} {unit})"
            )
        flags.append(flag)
    return flags, poor, lost


def _parameters(
    est: Estimate,
    before: Estimate,
    names: list[str],
    std: Mat,
    reach: Mat,
    flags: list[str | None],
    user: UserUnits,
) -> tuple[Parameter, ...]:
    """The parameters of ``est`` (``names``, with their standard deviations ``std``) with their
    values, their changes from ``before`` (the base-tool level's solution) and their ``flags``
    (:func:`_flags`), lengths in the user's unit; ``reach``: :func:`_reach`."""
    changes = local_coordinates(before.with_level(est.level, est.free), est)
    kinds = dict(zip(est.chain.names, est.chain.kinds, strict=True))
    index = {n: i for i, n in enumerate(est.chain.names)}
    out = []
    for k, name in enumerate(names):
        owner, leaf = name.rsplit(".", 1)
        value = None
        if owner in index:
            i = index[owner]
            if leaf == "scale":
                value = float(est.chain.scale[i])
            elif leaf == "pitch":
                value = float(est.chain.pitch[i])
            elif leaf == "offset":
                value = float(est.joint_offsets()[i])
        sd = float(std[k])
        kind = _unit(name, kinds.get(owner, ""), "length")
        scale = user.per_model if kind in ("length", "length/rad") else 1.0
        out.append(
            Parameter(
                name,
                kind.replace("length", user.length),
                None if value is None else value * scale,
                float(changes[k]) * scale,
                sd * scale if math.isfinite(sd) else None,
                user.shown(abs(float(changes[k])) * float(reach[k])),
                flags[k],
            )
        )
    return tuple(out)


def _noise_explains(
    fit_rms: float, other_rms: float, other_rows: int, p: int, m: int
) -> tuple[bool, float]:
    """Whether noise explains ``other_rms`` against ``fit_rms`` (module docstring), and the
    largest ratio of RMS it explains."""
    # the F distribution's quantile function itself (what scipy.stats.f.ppf evaluates, without
    # its argument handling, 20 times the cost)
    from scipy.special import fdtri

    if m <= p or fit_rms == 0.0 or other_rows == 0:
        return True, math.inf
    inflation = (1.0 + p / m) / (1.0 - p / m)
    bound = float(fdtri(3 * other_rows, max(m - p, 1), CONFIDENCE))
    limit = math.sqrt(inflation * bound)
    return other_rms <= limit * fit_rms, limit


def output_table(
    model: PoeModel,
    convention: str | None,
    style: str,
    tol: Tolerances,
    samples: int | None,
) -> tuple[str, Table | None, str | None]:
    """The output's convention, its table (``None`` for ``poe``) and, when it was chosen, why:
    ``dh``, unless a D-H table is not the one to write
    (:mod:`urdf2dh.conventions.choice`)."""
    from ..conventions.choice import choose
    from ..conventions.convert import to_table

    if convention == "poe":
        return "poe", None, None
    if convention is not None:
        return convention, to_table(model, convention, tol, samples=samples, style=style), None
    chosen = choose(model, "dh", tol, samples, style)
    return chosen.table.convention, chosen.table, chosen.reason


def _diff(
    nominal: PoeModel, model: PoeModel, table: Table | None, style: str, tol: Tolerances
) -> Diff:
    """The ``diff`` of the nominal and the identified model (``urdf2dh diff``'s, with its
    default thresholds), in the output table's convention (for a POE model file, the
    convention chosen for a table)."""
    from ..check.diff import compare_tables, default_length_threshold
    from ..conventions.convert import to_table

    if table is None:
        _, table, _ = output_table(model, None, style, tol, None)
        assert table is not None
    theirs = to_table(
        nominal, table.convention, tol, style=style if table.convention != "hayati" else "wu"
    )
    return compare_tables(
        theirs,
        table,
        nominal,
        model,
        math.radians(DIFF_ANGLE_DEG),
        default_length_threshold(model.length_unit),
        math.radians(DIFF_PARALLEL_DEG),
    )


def _selection(sel: Selection, user: UserUnits) -> Selection:
    """``sel`` with its scores' lengths in the user's unit (its per-measurement errors, which
    only compare levels, stay in the model's)."""

    def score(s: Score) -> Score:
        prior = s.prior
        if prior is not None:
            prior = replace(prior, length_per_angle=user.shown(prior.length_per_angle))
        return replace(
            s,
            fit_rms_position=user.shown(s.fit_rms_position),
            rms_position=user.shown(s.rms_position),
            uncertainty=user.shown(s.uncertainty),
            prior=prior,
        )

    return replace(sel, scores=tuple(score(s) for s in sel.scores))


def _by_joint(names: list[str], spans: dict[str, float], kinds: dict[str, str], unit: str) -> str:
    """The joints that own ``names`` (parameters), most first, with their measured spans."""
    owners = Counter(n.rsplit(".", 1)[0] for n in names)
    joints = [j for j, _ in owners.most_common() if j in spans]
    return ", ".join(
        f"{visible(j)} ({owners[j]}; moved over {spans[j]:.3g} "
        f"{unit if kinds[j] == 'prismatic' else 'rad'})"
        for j in joints
    )


def _fix(names: list[str], joints: dict[str, str]) -> str:
    """The ``--fix`` that holds ``names`` at the nominal's: the joints' parameters among them
    (the base, the tool and the markers have no nominal to hold them at), or ``""``."""
    held = [n for n in names if n.rsplit(".", 1)[0] in joints]
    return f"--fix {','.join(held)}" if held else ""


def assemble(chosen: Pass, result: Identified, outliers: Outliers, options: Options) -> Calibration:
    """The :class:`~.result.Calibration` of a finished identification (``result``, at the level
    of ``chosen``, with its ``outliers``), its figures in the user's length unit
    (:mod:`.userunits`)."""
    problem, opts, before = chosen.problem, chosen.options, chosen.before
    nominal, m, fit, held = problem.nominal, problem.measurements, problem.fit, problem.held
    validation, fit_rows, held_rows = problem.validation, problem.fit_rows, problem.held_rows
    ids, user, level = problem.markers, problem.units, result.level
    selection, found, rejected = chosen.selection, outliers.suspects, outliers.rejected
    outlier_note, chosen_by = outliers.note, options.choice.chosen_by
    convention, style = options.output.convention, options.output.style
    tol, check_samples = opts.tol, options.output.check_samples
    size = nominal.size()
    unit = user.length
    pose = opts.pose
    before_est, after_est = before.solution.estimate, result.estimate
    was, now = absorbed(before_est), result.flat
    index = m.configurations()[0]
    fit_data = to_data(fit, pose, ids)  # for the comparison and the parameters' reach
    comparisons = [_comparison("fit", was, now, fit, fit_data, pose, user, index[fit_rows])]
    if len(held):
        held_data = to_data(held, pose, ids)
        comparisons.append(
            _comparison("held_out", was, now, held, held_data, pose, user, index[held_rows])
        )
    if validation is not None:
        data = to_data(validation, pose, ids)
        comparisons.append(_comparison("validation", was, now, validation, data, pose, user))
    selection = _selection(selection, user)
    found = tuple(replace(s, position=user.shown(s.position)) for s in found)
    still = barely_moved(fit.q, before_est, size)
    span_of = np.ptp(fit.q, axis=0)
    kinds: dict[str, str] = {j.name: j.kind for j in nominal.joints}
    spans = {
        j.name: float(s) * (user.per_model if j.kind == "prismatic" else 1.0)
        for j, s in zip(nominal.joints, span_of, strict=True)
    }
    spans_text = {
        j.name: f"{spans[j.name]:.3g} {unit if j.kind == 'prismatic' else 'rad'}"
        for j in nominal.joints
        if j.name in still
    }
    reach = _reach(after_est, now, fit_data, result.device_model.size())
    flags, poor, lost = _flags(result, reach, spans_text, user)
    held_list = [Held(n, "the level's other parameters carry it") for n in result.carried]
    held_list += [Held(n, "fixed as asked") for n in result.fixed]
    warnings = list(result.notes)
    stats = result.stats
    p = len(result.names)
    equations = len(fit) * (6 if pose else 3)
    fit_rms = comparisons[0].after.rms_position
    for comp in comparisons[1:]:
        fine, limit = _noise_explains(
            fit_rms, comp.after.rms_position, comp.after.count, p, equations
        )
        if not fine:
            what = "held-out" if comp.name == "held_out" else "validation"
            warnings.append(_overfit(what, comp.after.rms_position, fit_rms, limit, level, p, unit))
    score = selection.score(level)
    if math.isfinite(score.rms_position):
        fine, limit = _noise_explains(fit_rms, score.rms_position, len(fit), p, equations)
        if not fine:
            warnings.append(
                _overfit("cross-validated", score.rms_position, fit_rms, limit, level, p, unit)
            )
    lower = LOWER.get(level)
    if still:
        lines = [
            n for n in result.names if n.rsplit(".", 1)[0] in still and not n.endswith(".offset")
        ]
        hold = _fix(lines, kinds)
        warnings.append(
            "barely moved: "
            + ", ".join(f"{visible(n)} ({spans_text[n]})" for n in still)
            + "; how their lines lie and how far they scale is identified near these positions "
            "only: measure configurations that move them over their range"
            + (f", or hold their lines at the nominal's ({hold})" if hold else "")
        )
    if lost:
        causes = {n.rsplit(".", 1)[0] for n in lost} & set(still)
        why = (
            f"their joints barely moved ({', '.join(sorted(causes))})"
            if causes
            else "the configurations measured do not tell them apart from the others"
        )
        hold = _fix(lost, kinds)
        warnings.append(
            f"the measurements determine {stats.rank} of the {p} parameters; not determined: "
            f"{', '.join(lost)} ({why}): their values are the nominal's plus whatever the "
            "others left; measure configurations that move these joints differently"
            + (f", or hold them at the nominal's ({hold})" if hold else "")
        )
    if poor:
        one = len(poor) == 1
        owners = {n.rsplit(".", 1)[0] for n in poor if n.rsplit(".", 1)[0] in spans}
        joints = "joint" if len(owners) == 1 else "joints"
        hold = _fix(poor, kinds)
        remedies = []
        if owners:
            remedies.append(
                f"to pin {'it' if one else 'them'} down, measure more configurations moving "
                f"{'it over its' if len(owners) == 1 else 'these joints over their'} range"
            )
        if hold:
            remedies.append(
                f"hold {'it' if one else 'them'} at the nominal's ({hold}), which gives up what "
                f"{'it explains' if one else 'they explain'} (judge it on held-out "
                "configurations: --holdout)"
            )
        if lower and 2 * len(poor) > p:  # most of the level: the measurements do not support it
            remedies.append(f"choose a lower level (--identify {lower})")
        belong = (
            f"; {'it belongs' if one else 'they belong'} to {joints} "
            f"{_by_joint(poor, spans, kinds, unit)}"
            if owners
            else ""
        )
        todo = ": " + ", or ".join(remedies) if remedies else ""
        warnings.append(
            f"{len(poor)} of the {p} parameters {'is' if one else 'are'} poorly identified: "
            f"one standard deviation of {'it' if one else 'each'} moves a measured point by "
            f"more than {POORLY_IDENTIFIED:g} times the position noise, so "
            f"{'its value is' if one else 'their values are'} uncertain, though the model as a "
            f"whole fits as the residuals say{belong}{todo}: {', '.join(poor)}"
        )
    if found:
        rows = ", ".join(
            f"row {s.row + 1} ({s.position:.3g} {unit}"
            + (f", {s.rotation:.3g} rad" if s.rotation is not None else "")
            + f", chance {s.chance:.1e})"
            for s in found
        )
        many = len(found) > 1
        warnings.append(
            (
                f"rejected {len(found)} outlier{'s' if many else ''} ({outlier_note}): "
                if rejected
                else f"{len(found)} measurement{'s' if many else ''} the fit cannot explain "
                f"({outlier_note}): "
            )
            + rows
        )
    conv, table, reason = output_table(result.model, convention, style, tol, check_samples)
    if table is not None:  # the reason for a chosen convention is the table's first warning
        warnings += list(table.warnings)
    sigma_pos = user.shown(result.sigma_pos)
    noise = Noise(
        sigma_pos,
        result.sigma_rot if pose else None,
        result.noise_given,
        stats.variance_factor,
        math.sqrt(3.0) * sigma_pos,
        math.sqrt(3.0) * result.sigma_rot if pose else None,
    )
    configurations = int(index.max(initial=-1)) + 1
    counts = Counts(
        len(m),
        configurations,
        len(fit),
        len(held),
        0 if validation is None else len(validation),
        len(found) if rejected else 0,
        equations,
        p,
        stats.rank,
        0 if after_est.tool == FRAME else len(after_est.markers),
    )
    parameters = Later(
        partial(_parameters, after_est, result.before, result.names, result.stats.std, reach,
                flags, user)
    )  # fmt: skip
    base_in_device = result.base_in_device.copy()
    base_in_device[:3, 3] = user.shown_array(base_in_device[:3, 3])
    return Calibration(
        nominal,
        result.model,
        result.device_model,
        m.source,
        "pose" if pose else "position",
        opts.frame,
        level,
        chosen_by,
        selection,
        counts,
        noise,
        stats.condition,
        result.solution.iterations,
        result.solution.converged,
        formula(after_est),
        in_words(after_est),
        tuple(comparisons),
        parameters,
        tuple(held_list),
        tuple((n, spans[n]) for n in still),
        found,
        rejected,
        base_in_device,
        {k: user.shown_array(v) for k, v in result.markers_on_tool.items()},
        conv,
        table,
        reason,
        Later(partial(_diff, nominal, result.model, table, style, tol)),
        tuple(warnings),
        user,
        tuple(int(r) + 1 for r in fit_rows),
    )


def _overfit(
    what: str, other: float, fit: float, limit: float, level: str, p: int, unit: str
) -> str:
    lower = LOWER.get(level)
    remedy = f"choose a lower level (--identify {lower}), or " if lower else ""
    return (
        f"the {what} RMS position error ({other:.3g} {unit}) is {other / fit:.3g} times the "
        f"fit's ({fit:.3g}), more than noise explains (up to {limit:.3g} "
        f"times): the {level} level's {p} parameters follow the fitted measurements' noise, or "
        f"the other configurations are unlike the fitted ones; {remedy}measure more "
        "configurations, spread over every joint's range"
    )
