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

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from ..checks import check_count, check_flag, check_instance, check_seed
from ..errors import InputError
from ..model.poe import PoeModel
from ..tolerances import DEFAULT, Tolerances
from .figures import assemble
from .identify import identify
from .levels import AUTO
from .measurements import Measurements
from .outliers import settle
from .plausible import judged, unconverged
from .prior import AUTO as AUTO_PRIOR
from .prior import Prior
from .problem import (
    MEASUREMENTS_HINT,
    CalibrationProblem,
    LevelChoice,
    Options,
    Output,
    fit_options,
)
from .result import Calibration
from .select import judge_levels
from .solver import one_thread
from .start import MAX_ITERATIONS

__all__ = ["calibrate", "run"]

Mat = NDArray[np.float64]


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
        ``auto`` (chosen by cross-validation), or a level of :data:`.levels.LEVELS`.
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
    check_instance(nominal, PoeModel, "calibrate: nominal", "urdf2dh.load(SOURCE) reads one")
    check_instance(measurements, Measurements, "calibrate: measurements", MEASUREMENTS_HINT)
    if validation is not None:
        check_instance(validation, Measurements, "calibrate: validation", MEASUREMENTS_HINT)
    check_seed(seed, "calibrate: seed")
    if folds is not None:
        check_count(folds, "calibrate: folds", 2)
    check_count(max_iterations, "calibrate: max_iterations")
    check_flag(accept, "calibrate: accept")
    choice = LevelChoice(level, rule, folds, seed)
    problem = CalibrationProblem.of(
        nominal, measurements, pose, (noise_pos, noise_rot), layout, holdout, seed, validation
    )
    fitting = fit_options(
        problem, fixed, prior, helical, keep_scale, keep_tool_axis, frame, max_iterations, tol
    )
    options = Options(fitting, choice, reject, Output(convention, style, check_samples), accept)
    with one_thread():  # small matrices: BLAS threads only cost wake-ups
        return run(problem, options)


def run(problem: CalibrationProblem, options: Options) -> Calibration:
    """The calibration of ``problem`` made as ``options`` say (module docstring): what
    :func:`calibrate` returns, for its problem and options."""
    first = judge_levels(problem, options)
    fitting, source = options.fitting, problem.source
    if not first.before.solution.converged:
        raise unconverged(
            problem.nominal, problem.fit, fitting, problem.markers,
            "the fit of the base and tool", first.before.solution,
        )  # fmt: skip
    level = options.choice.chosen(first.selection, source)
    if level not in first.fits:
        raise InputError(
            f"{source}: the {level} level cannot be identified: "
            f"{first.selection.score(level).failure}"
        )
    chosen, outliers = settle(first, level, options)
    level = chosen.level or level
    at_level = replace(fitting, level=level)
    fit = chosen.fit
    result = identify(
        problem.nominal, fit, at_level, problem.markers, (chosen.start, chosen.before),
        chosen.fits[level], chosen.placed,
    )  # fmt: skip
    if not result.solution.converged:
        raise unconverged(
            problem.nominal, fit, fitting, problem.markers, "the identification", result.solution
        )
    cal = assemble(chosen, result, outliers, options)
    return judged(cal, chosen.problem, at_level, result, options.accept)
