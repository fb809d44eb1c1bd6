"""One calibration from start to finish: :func:`calibrate`, and its result :class:`Calibration`.

1. The measurements are checked (joint values, points, noise levels, markers), and held out by
   configuration: ``holdout`` of the configurations (distinct rows of joint values, numbered in
   file order) drawn by ``numpy.random.default_rng((seed, 3))``, all rows of a configuration on
   the same side; ``validation`` is a separate set judged the same way.
2. The base-tool level is fitted: the nominal joints with base and tool fitted, the fair
   "before" of every figure (:mod:`.identify`).
3. The level is chosen by leaving each configuration out of the fit in turn (:mod:`.select`;
   geometry and full with the prior of :mod:`.prior`), or is the one asked for (then judged
   against base-tool all the same, for the warning below).
4. Outlier suspects of the chosen level's fit are found with a stated threshold
   (:mod:`.outliers`) and listed; the choice is made again without them, and they are rejected
   when that predicts the other configurations better (or always, or never, when ``reject``
   says so).
5. The chosen level's fit gives the identified model, its statistics, the flags (parameters
   whose uncertainty at the tool exceeds :data:`~urdf2dh.tolerances.POORLY_IDENTIFIED` x the
   position noise; joints that barely moved) and the warnings (held-out or cross-validated
   error beyond what noise explains; undetermined parameters, with their cause).
6. The output table: the convention asked for, or the first of ``dh`` and ``hayati`` that is
   exact and sane (no tolerance judgement, no ``|d|`` or ``|a|`` beyond ``far_factor`` x size;
   ``hayati`` always is), as ``convert`` would write it, with the reason; and its ``diff``
   against the nominal. Every figure in the measurements' length unit (:mod:`.userunits`).
7. The judgement: whether the measurements contradict the result (:mod:`.plausible`), and then
   its likely cause (:mod:`.diagnosis`).

Nothing is returned unless the final fit converged, the table passed its self-check and the
measurements do not contradict it (or ``accept`` says to return it all the same). Outlier
suspects are not rejected when they are more than
:data:`~urdf2dh.tolerances.OUTLIER_SHARE` of the measurements or would leave too few equations:
the judgement names them.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from ..check.diff import Diff
from ..checks import check_count, check_flag, check_instance, check_seed
from ..conventions.table import Table
from ..errors import InputError, NotConverged, UsageError, choices, shown
from ..escape import markdown_table, markdown_text
from ..model.poe import PoeModel
from ..schemas import CALIBRATION_REPORT
from ..tolerances import DEFAULT, OUTLIER_SHARE, Tolerances
from .chart import LEVELS, count
from .identifiable import check_patterns
from .identify import (
    Fit,
    check_equations,
    fit_before,
    has_prior,
    identify,
    level_start,
    with_statistics,
)
from .measurements import MAX_MEASUREMENTS, Measurements, check_noise
from .outliers import Suspect, rejecting_helps, suspects
from .plausible import judged, unconverged
from .prior import AUTO as AUTO_PRIOR
from .prior import Prior
from .select import Selection, cross_validate
from .start import MAX_ITERATIONS, FitOptions, to_data
from .userunits import UserUnits

__all__ = [
    "AUTO",
    "SCHEMA",
    "Calibration",
    "Comparison",
    "Counts",
    "Held",
    "Noise",
    "NotConverged",
    "Parameter",
    "Residuals",
    "calibrate",
    "check_measurements",
    "check_noise",
    "holdout_split",
]

Mat = NDArray[np.float64]

SCHEMA = CALIBRATION_REPORT  # the report's ``schema`` (docs/formats/calibration-report.md)
AUTO = "auto"  # choose the level by cross-validation

# Joint values and measured points beyond these are refused: far beyond any joint's travel or any
# measuring volume (a revolute joint's angle of 1e4 rad already carries 2e-12 rad of round-off),
# they can only be a unit mistake or garbage.
MAX_JOINT_TURN = 1e4  # rad
MAX_EXTENT = 1e4  # x the robot's size (points, sliding joints)

MEASUREMENTS_HINT = "urdf2dh.measure(model, N) makes some"


@dataclass(frozen=True, slots=True)
class Residuals:
    """Residual statistics of one model on one set (rotation ``None`` for positions)."""

    count: int
    rms_position: float
    max_position: float
    rms_rotation: float | None = None
    max_rotation: float | None = None


@dataclass(frozen=True, slots=True)
class Comparison:
    """Before (base and tool fitted to the nominal joints) and after, on one set.

    Attributes
    ----------
    name
        ``fit``, ``held_out`` or ``validation``.
    before, after
        The statistics of the two models on the set.
    configurations
        The set's configurations (their numbers in the file's order).
    before_position, after_position
        Each configuration's RMS position error (over its markers).
    before_rotation, after_rotation
        Each configuration's rotation error (poses), else ``None``.
    """

    name: str
    before: Residuals
    after: Residuals
    configurations: tuple[int, ...]
    before_position: tuple[float, ...]
    after_position: tuple[float, ...]
    before_rotation: tuple[float, ...] | None = None
    after_rotation: tuple[float, ...] | None = None


@dataclass(frozen=True, slots=True)
class Parameter:
    """One identified parameter.

    Attributes
    ----------
    name, unit
        Its name (``j1.turn1``, ``j3.offset``, ``tool.z``, ...) and unit.
    value
        Its value, for scales, pitches and offsets; ``None`` for the chart's coordinates
        (turns and shifts of a line, base and tool motions), which are changes only.
    change
        How far the identified model moved it from the nominal (base and tool fitted).
    std
        Its standard deviation, ``None`` where the measurements do not determine it.
    effect
        How far its change moves a measured tool point at most (length unit; rotations at the
        robot's size): the changes of different units on one scale.
    flag
        Why it is poorly identified, or ``None``.
    """

    name: str
    unit: str
    value: float | None
    change: float
    std: float | None
    effect: float
    flag: str | None = None


@dataclass(frozen=True, slots=True)
class Held:
    """A parameter of the level that was held at the nominal's value, and why."""

    name: str
    reason: str


@dataclass(frozen=True, slots=True)
class Noise:
    """The noise levels that weighed the fit.

    Attributes
    ----------
    position, rotation
        Per coordinate: length unit, and rad (``None`` for positions).
    given
        Whether they were given (else estimated by variance components).
    variance_factor
        The weighted residual sum of squares over the redundancy (about 1 when they are right).
    floor_position, floor_rotation
        What a perfect model leaves: ``sqrt(3)`` times the levels.
    """

    position: float
    rotation: float | None
    given: bool
    variance_factor: float
    floor_position: float
    floor_rotation: float | None


@dataclass(frozen=True, slots=True)
class Counts:
    """How many of each: measurements, configurations, equations, parameters."""

    measurements: int
    configurations: int
    fit: int
    held_out: int
    validation: int
    rejected: int
    equations: int
    parameters: int
    rank: int
    markers: int


@dataclass(frozen=True)
class Calibration:
    """The result of :func:`calibrate`.

    Attributes
    ----------
    nominal
        The nominal model.
    model
        The identified model, in the output frame (``frame``).
    device_model
        The identified model in the measuring device's frame.
    measurements
        Where the measurements came from.
    measure
        ``pose`` or ``position``.
    frame
        ``device`` or ``nominal``.
    level
        The level identified (:data:`.chart.LEVELS`).
    chosen_by
        ``cross-validation`` or ``option``.
    selection
        The cross-validation of the levels and the choice.
    counts, noise
        Counts and noise levels.
    condition_number, iterations, converged
        Of the final fit.
    formula, in_words
        The level's parameter count as a formula (Wu 2019 eq. 23 for ``full``) and in words.
    comparisons
        Before and after on each set (fit, held out, validation).
    parameters
        The identified parameters.
    held
        The level's parameters held at the nominal's values, with the reason.
    barely_moved
        ``(joint, span)`` of the joints that barely moved.
    suspects
        The outlier suspects, and whether they were ``rejected``.
    base_in_device
        ``(4, 4)`` the pose of the nominal's base frame in the device frame.
    markers_on_tool
        Each marker's position on the identified tool (position measurements).
    convention
        The output's convention (``poe`` for a POE model file).
    table
        The output table (``None`` for ``poe``).
    convention_reason
        Why this convention, when it was chosen.
    diff
        The ``diff`` of the nominal and the identified model (``urdf2dh diff``'s).
    warnings
        Everything worth a person's attention.
    units
        The length unit of every figure above (residuals, noise, parameters, suspects, the
        levels' scores, ``base_in_device``, ``markers_on_tool``): the measurements' own
        (:mod:`.userunits`); ``nominal``, ``model``, ``device_model``, ``table`` and ``diff``
        keep the nominal's.
    """

    nominal: PoeModel
    model: PoeModel
    device_model: PoeModel
    measurements: str
    measure: str
    frame: str
    level: str
    chosen_by: str
    selection: Selection | None
    counts: Counts
    noise: Noise
    condition_number: float
    iterations: int
    converged: bool
    formula: str
    in_words: str
    comparisons: tuple[Comparison, ...]
    parameters: tuple[Parameter, ...]
    held: tuple[Held, ...]
    barely_moved: tuple[tuple[str, float], ...]
    suspects: tuple[Suspect, ...]
    rejected: bool
    base_in_device: Mat
    markers_on_tool: dict[int, Mat]
    convention: str
    table: Table | None
    convention_reason: str | None
    diff: Diff
    warnings: tuple[str, ...]
    units: UserUnits
    rows: tuple[int, ...] = field(default=(), repr=False)  # fitted rows' numbers in the file
    schema: str = SCHEMA

    def comparison(self, name: str) -> Comparison | None:
        """The comparison on ``name`` (``fit``, ``held_out``, ``validation``), if there is one."""
        return next((c for c in self.comparisons if c.name == name), None)

    def __str__(self) -> str:
        """What ``urdf2dh calibrate`` prints: the levels, the residuals before and after, the
        warnings."""
        from .report import summary

        return summary(self)

    def __repr__(self) -> str:
        done = "converged" if self.converged else "NOT converged"
        return (
            f"<Calibration of {shown(self.nominal.name)} at level {self.level}, "
            f"{self.counts.parameters} parameters, {done}; written in {self.convention}>"
        )

    def _repr_markdown_(self) -> str:
        """In a notebook: the residuals before and after on each set, and the identified
        parameters, as tables (names escaped)."""
        t, unit = markdown_text, markdown_text(self.units.length)
        c = self.counts
        out = [
            f"**{t(self.nominal.name)}** calibrated at level {self.level} ({self.chosen_by}) "
            f"from {t(self.measurements)}: {c.measurements} {self.measure} measurements at "
            f"{c.configurations} configurations, {c.parameters} parameters (rank {c.rank}), "
            f"{'converged' if self.converged else 'NOT converged'} in {self.iterations} "
            f"iterations",
            "",
        ]

        def rms(r: Residuals) -> list[str]:
            rot = "" if r.rms_rotation is None else f"{r.rms_rotation:.3g}"
            return [f"{r.rms_position:.3g}", f"{r.max_position:.3g}", rot]

        rows = [[k.name, str(k.before.count), *rms(k.before), *rms(k.after)]
                for k in self.comparisons]  # fmt: skip
        out += markdown_table(
            ["set", "measurements", f"RMS before [{unit}]", f"max before [{unit}]",
             "RMS rot. before [rad]", f"RMS after [{unit}]", f"max after [{unit}]",
             "RMS rot. after [rad]"], rows)  # fmt: skip
        out.append("")
        rows = [[t(q.name), f"{q.change:.3g}", "" if q.std is None else f"{q.std:.3g}",
                 t(q.unit), t(q.flag or "")] for q in self.parameters]  # fmt: skip
        out += markdown_table(["parameter", "change", "std", "unit", "note"], rows)
        out += [f"- {t(w)}" for w in self.warnings]
        return "\n".join(out) + "\n"


def holdout_split(
    m: Measurements, fraction: float, seed: int
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Rows to fit and rows held out: ``round(fraction x count)`` of the configurations, the
    first of ``numpy.random.default_rng((seed, 3)).permutation(count)``, with all their rows;
    both in file order."""
    index, count = m.configurations()
    held = np.sort(np.random.default_rng((seed, 3)).permutation(count)[: round(fraction * count)])
    out = np.isin(index, held)
    return np.flatnonzero(~out), np.flatnonzero(out)


def check_measurements(nominal: PoeModel, m: Measurements, what: str = "") -> None:
    """Refuse joint values and points no robot or measuring device makes (module constants)."""
    size = nominal.size()
    display = m.source or what or "the measurements"
    for k, j in enumerate(nominal.joints):
        bound = MAX_JOINT_TURN if j.kind != "prismatic" else MAX_EXTENT * size
        worst = int(np.argmax(np.abs(m.q[:, k]))) if len(m) else 0
        if len(m) and abs(float(m.q[worst, k])) > bound:
            unit = "rad" if j.kind != "prismatic" else nominal.length_unit
            raise InputError(
                f"{display}: row {worst + 1}, joint {shown(j.name)}: {float(m.q[worst, k]):.6g} "
                f"is beyond any joint's travel (|q| <= {bound:.3g} {unit}); wrong unit or column?"
            )
    if len(m):
        far = float(np.abs(m.points).max())
        if far > MAX_EXTENT * size:
            row = int(np.argmax(np.abs(m.points).max(axis=1)))
            raise InputError(
                f"{display}: row {row + 1}: a measured point {far:.6g} {nominal.length_unit} "
                f"from the device's origin, over {MAX_EXTENT:g} times the robot's size "
                f"({size:.3g}); wrong unit?"
            )


def _check_markers(m: Measurements, pose: bool, layout: dict[int, Mat] | None) -> None:
    ids = m.marker_ids()
    if pose or layout is None:
        if not pose and len(ids) > 1:
            raise InputError(
                f"{m.source}: {len(ids)} markers; their positions on the tool are needed (a "
                "marker layout, marker,x,y,z) to define the tool frame"
            )
        return
    missing = [k for k in ids if k not in layout]
    if missing:
        raise InputError(
            f"{m.source}: marker {missing[0]} is not in the marker layout "
            f"(markers there: {sorted(layout)})"
        )


def _level(selection: Selection, identify_level: str, source: str) -> str:
    """The level to identify: the one asked for, or the one cross-validation chose."""
    if identify_level != AUTO:
        return identify_level
    if selection.chosen is None:
        why = selection.score("base-tool").failure or ""
        if "converge" in why:
            raise NotConverged(f"{source}: the fit of the base and tool {why}; nothing written")
        raise InputError(
            f"{source}: {selection.configurations} configurations are too few to judge any "
            f"level on configurations it was not fitted to ({why}); measure more "
            "configurations, or choose the level"
        )
    return selection.chosen


def calibrate(
    nominal: PoeModel,
    measurements: Measurements,
    *,
    level: str = AUTO,
    pose: bool | None = None,
    fixed: tuple[str, ...] = (),
    prior: Prior | str = AUTO_PRIOR,
    holdout: float = 0.0,
    validation: Measurements | None = None,
    seed: int = 0,
    folds: int | None = None,
    rule: str = "simplest",
    noise_pos: float | None = None,
    noise_rot: float | None = None,
    helical: tuple[str, ...] = (),
    keep_scale: bool = False,
    keep_tool_axis: bool = False,
    frame: str = "device",
    layout: dict[int, Mat] | None = None,
    reject: bool | None = None,
    convention: str | None = None,
    style: str = "wu",
    tol: Tolerances = DEFAULT,
    max_iterations: int = MAX_ITERATIONS,
    check_samples: int | None = None,
    accept: bool = False,
) -> Calibration:
    """Identify ``nominal``'s parameters from ``measurements`` (module docstring).

    Parameters
    ----------
    nominal
        The nominal model (:func:`urdf2dh.load`).
    measurements
        What was measured (:func:`.measurements.read_measurements`, :func:`.measure.synthesize`).
    level
        ``auto`` (chosen by cross-validation), or a level of :data:`.chart.LEVELS`.
    pose
        Use the orientations (default: when the measurements have them).
    fixed
        Parameters held at the nominal's values: names or shell-style patterns.
    prior
        The prior on the joints' parameters (:mod:`.prior`): ``auto`` (the deviations of
        greatest evidence, at the geometry and full levels), ``none``, or stated deviations.
    holdout, validation, seed
        A fraction of the configurations held out of the fit (drawn with ``seed``), and a
        separate set, both judged.
    folds, rule
        How the levels are judged (:mod:`.select`): each configuration left out in turn
        (``None``), or ``folds`` seeded folds of them; the ``simplest`` level within one
        standard error of the best, or the ``best``.
    noise_pos, noise_rot
        Noise levels that weigh the residuals, per coordinate (default: estimated): positions
        in the measurements' length unit (``Measurements.length_unit``: the file's, where it
        was read with ``Reading.length_unit``; else the nominal's), rotations in rad.
    helical
        Revolute joints whose pitch is identified too (``("all",)`` for all).
    keep_scale, keep_tool_axis
        Keep the nominal's joint scales; keep the tool on the last joint's axis.
    frame
        ``device`` or ``nominal``: the frame of the output model.
    layout
        The markers' positions on the tool (the measurements' length unit, as ``noise_pos``).
    reject
        The outlier suspects (:mod:`.outliers`): rejected (``True``), kept (``False``), or
        rejected when that predicts the other configurations better (``None``).
    convention, style
        The output table's convention (``None``: chosen, see module docstring; ``poe``: none)
        and D-H style.
    tol, max_iterations, check_samples
        Tolerances, iterations of one solve at most, configurations of the table's self-check.
    accept
        Return a calibration the measurements contradict (:mod:`.plausible`) all the same, its
        findings among the warnings, instead of raising :class:`~urdf2dh.errors.Implausible`.

    Returns
    -------
    Calibration
        Its figures (residuals, noise, parameters, ...) in the measurements' length unit.

    Raises
    ------
    InputError
        Inconsistent or impossible measurements, bad noise levels, too few measurements.
    Implausible
        The measurements contradict the calibration (exit 3): the cause the data point to and
        the argument that fixes it are named (:mod:`.plausible`, :mod:`.diagnosis`).
    NotConverged
        The final fit did not converge (exit 1).
    ConversionError
        The output table failed its self-check (exit 1).
    """
    import scipy.linalg  # noqa: F401  (loaded before the limit below, so that it holds for it)
    from threadpoolctl import threadpool_limits

    check_instance(nominal, PoeModel, "calibrate: nominal", "urdf2dh.load(SOURCE) reads one")
    check_instance(measurements, Measurements, "calibrate: measurements", MEASUREMENTS_HINT)
    if validation is not None:
        check_instance(validation, Measurements, "calibrate: validation", MEASUREMENTS_HINT)
    check_seed(seed, "calibrate: seed")
    if folds is not None:
        check_count(folds, "calibrate: folds", 2)
    check_count(max_iterations, "calibrate: max_iterations")
    check_flag(accept, "calibrate: accept")
    check_instance(level, str, "calibrate: level")
    if level != AUTO and level not in LEVELS:
        raise UsageError(f"unknown level {level!r}; valid: {choices((AUTO, *LEVELS))}")
    m = measurements
    if pose is None:
        pose = m.quaternions is not None
    if pose and m.quaternions is None:
        raise InputError(f"{m.source}: pose measurements need orientations (qx, qy, qz, qw)")
    if pose and m.markers is not None:
        raise InputError(
            f"{m.source}: a 'marker' column goes with position measurements, not poses"
        )
    if len(m) > MAX_MEASUREMENTS:
        raise InputError(f"{m.source}: more than {MAX_MEASUREMENTS} measurements")
    coupled = [j.name for j in nominal.joints if j.mimic is not None]
    if coupled:
        raise InputError(
            f"{nominal.source or nominal.name}: joint {shown(coupled[0])} follows another joint; "
            "calibration identifies every joint's screw and scale on its own"
        )
    size = nominal.size()
    check_measurements(nominal, m)
    if validation is not None:
        check_measurements(nominal, validation, "the validation set")
        _check_markers(validation, pose, layout)
    user = UserUnits.of(nominal.length_unit, m)
    check_noise(noise_pos, noise_rot if pose else None, user.shown(size), user.length)
    _check_markers(m, pose, layout)
    if not 0.0 <= holdout < 1.0:
        raise UsageError(f"the held-out fraction must be in [0, 1), not {holdout}")
    opts = FitOptions(
        pose=pose,
        level="base-tool" if level == AUTO else level,
        fixed=fixed,
        prior=prior,
        helical=helical,
        keep_scale=keep_scale,
        keep_tool_axis=keep_tool_axis,
        frame=frame,
        noise_pos=user.to_model(noise_pos),
        noise_rot=noise_rot if pose else None,
        layout=None if layout is None else {k: user.to_model_array(v) for k, v in layout.items()},
        max_iterations=max_iterations,
        tol=tol,
    )
    asked = _Asked(user, noise_pos, noise_rot if pose else None, accept)
    with threadpool_limits(1, "blas"):  # small matrices: BLAS threads only cost wake-ups
        return _calibrate(
            nominal, m, opts, level, holdout, validation, seed, folds, rule, reject,
            convention, style, tol, check_samples, asked,
        )  # fmt: skip


def _levels(identify_level: str, opts: FitOptions) -> tuple[str, ...]:
    if identify_level != AUTO:
        return ("base-tool", identify_level) if identify_level != "base-tool" else ("base-tool",)
    levels = tuple(LEVELS)
    if opts.keep_scale:  # full without scales is geometry
        levels = tuple(lv for lv in levels if lv != "full")
    return levels


@dataclass(frozen=True, slots=True)
class _Asked:
    """What the user stated, in the user's units, and whether a contradicted fit is accepted."""

    units: UserUnits
    noise_pos: float | None
    noise_rot: float | None
    accept: bool


def _calibrate(
    nominal: PoeModel,
    m: Measurements,
    opts: FitOptions,
    identify_level: str,
    holdout: float,
    validation: Measurements | None,
    seed: int,
    folds: int | None,
    rule: str,
    reject: bool | None,
    convention: str | None,
    style: str,
    tol: Tolerances,
    check_samples: int | None,
    asked: _Asked,
) -> Calibration:
    ids = sorted(set(m.marker_ids()) | set(validation.marker_ids() if validation else []))
    fit_rows, held_rows = holdout_split(m, holdout, seed)
    if not len(fit_rows):
        raise InputError(
            f"{m.source}: holding out {holdout:g} of its {m.configurations()[1]} configurations "
            "leaves none to fit; hold out less, or measure more configurations"
        )
    fit, held = m.subset(fit_rows), m.subset(held_rows)
    levels = _levels(identify_level, opts)
    start, before = fit_before(nominal, fit, opts, ids)
    if not before.solution.converged:
        raise unconverged(nominal, fit, opts, ids, "the fit of the base and tool", before.solution)
    if identify_level != AUTO:  # fewer equations than its parameters: say so now
        est, _, _ = level_start(nominal, before.solution.estimate, opts, ids)
        if not has_prior(est, opts):
            check_equations(count(est), to_data(fit, opts.pose, ids), fit.source, opts.pose)
    if opts.fixed:
        probes = [
            level_start(nominal, before.solution.estimate, replace(opts, level=lv), ids)[0]
            for lv in levels
        ]
        check_patterns(opts.fixed, probes, ids)
    selection, fits = cross_validate(nominal, fit, opts, ids, before, levels, folds, seed, rule)
    level = _level(selection, identify_level, m.source)
    if level not in fits:
        raise InputError(
            f"{m.source}: the {level} level cannot be identified: {selection.score(level).failure}"
        )
    fits[level] = with_statistics(fits[level], to_data(fit, opts.pose, ids))
    found = [
        replace(s, row=int(fit_rows[s.row])) for s in suspects(fit, fits[level], opts.pose, ids)
    ]
    rejected, note = False, ""
    user = asked.units
    if found and reject is not False and not _rejectable(found, fit, fits[level], opts):
        note = (
            f"kept: {len(found)} of {len(fit)} are too many to be outliers (the noise or the "
            "model is wrong)"
            if len(found) > OUTLIER_SHARE * len(fit)
            else "kept: without them too few measurements would be left to identify the level"
        )
    elif found and reject is not False:
        kept_rows = np.setdiff1d(fit_rows, [s.row for s in found])
        fit2 = m.subset(kept_rows)
        start2, before2 = fit_before(nominal, fit2, opts, ids)
        selection2, fits2 = cross_validate(
            nominal, fit2, opts, ids, before2, levels, folds, seed, rule
        )
        level2 = selection2.chosen if identify_level == AUTO else identify_level
        helps, with_rms, without_rms = rejecting_helps(
            np.flatnonzero(np.isin(fit_rows, kept_rows)),
            fit2.configurations()[0],
            (selection, level),
            (selection2, level2 or ""),
        )
        figures = (
            f"left-out RMS position {user.shown(without_rms):.3g} against "
            f"{user.shown(with_rms):.3g} {user.length}"
        )
        if reject is None and not helps:
            note = (
                "kept: the other configurations are predicted no better without them "
                f"({figures}); a wrong measurement, or the model's error at an unusual "
                "configuration"
            )
        elif level2 is not None and level2 in fits2 and before2.solution.converged:
            rejected = True
            note = (
                "as asked"
                if reject
                else f"without them the other configurations are predicted better ({figures})"
            )
            fit_rows, fit, start, before = kept_rows, fit2, start2, before2
            selection, fits, level = selection2, fits2, level2
    elif found:
        note = (
            "kept as asked; a wrong measurement, or the model's error at an unusual configuration"
        )
    result = identify(nominal, fit, replace(opts, level=level), ids, (start, before), fits[level])
    if not result.solution.converged:
        raise unconverged(nominal, fit, opts, ids, "the identification", result.solution)
    from .report import assemble

    cal = assemble(
        nominal,
        m,
        fit,
        held,
        validation,
        fit_rows,
        held_rows,
        result,
        before,
        opts,
        ids,
        level,
        "cross-validation" if identify_level == AUTO else "option",
        selection,
        tuple(found),
        rejected,
        note,
        convention,
        style,
        tol,
        check_samples,
        user,
    )
    return judged(
        cal, nominal, fit, replace(opts, level=level), ids, result,
        (asked.noise_pos, asked.noise_rot), asked.accept,
    )  # fmt: skip


def _rejectable(found: list[Suspect], fit: Measurements, level_fit: Fit, opts: FitOptions) -> bool:
    """Whether the suspects may be rejected: not more than
    :data:`~urdf2dh.tolerances.OUTLIER_SHARE` of the measurements (then the noise or the model
    is wrong, not they), and leaving as many equations as the level has parameters."""
    if len(found) > OUTLIER_SHARE * len(fit):
        return False
    rows = 6 if opts.pose else 3
    left = (len(fit) - len(found)) * rows
    return left >= count(level_fit.solution.estimate) and len(fit) - len(found) >= 2
