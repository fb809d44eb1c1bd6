"""Choosing how much to identify: k-fold cross-validation over configurations.

A level with more parameters always fits the measurements better; whether it predicts new
configurations better depends on how many and how varied they are (24 configurations support a
robot's joint offsets, not its 41 geometric parameters). So each level of :mod:`.chart` is
judged on configurations it was not fitted to:

* the configurations (distinct rows of joint values: a configuration's markers stay together)
  are dealt into ``k`` folds by a permutation drawn from ``numpy.random.default_rng((seed,
  5))`` (``k`` = :data:`FOLDS`, or the number of configurations if fewer);
* for each fold, every level is fitted to the other folds exactly as the final fit is (the
  base-tool level first, each other level from the solution of the simpler one before it, to
  convergence), with the noise levels of that level's fit to all the measurements, and predicts
  the fold's positions;
* a level's cross-validated error is the RMS position (and, for poses, rotation) error over all
  configurations, each configuration's mean squared error over its markers; its uncertainty is
  the standard error of that mean, carried to the RMS (``se(mean e^2) / (2 RMS)``);
* the levels are compared by the prediction error the fit itself minimises: each
  configuration's squared position error over ``sigma_p^2`` plus, for poses, its squared
  rotation error over ``sigma_r^2``, with the noise levels of the richest level judged (the
  nearest to the measuring noise), so that a level that predicts orientations better counts;
* the choice (rule ``simplest``, the default) is the simplest level whose error is within its
  uncertainty of the best level's:
  the mean of its per-configuration differences from the best is within one standard error of
  those differences (the one-standard-error rule of Hastie, Tibshirani & Friedman, *The
  Elements of Statistical Learning*, 2009, §7.10, on paired errors): a more complex level must
  predict better by more than the configurations' scatter to be chosen. Rule ``best`` takes the
  level of the smallest error (with few configurations, the simplest rule keeps to simple
  levels more often than a held-out set may show was needed).

A level that a fold leaves with fewer equations than parameters, or that does not converge
there, is not chosen, and the report says why.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ..errors import UsageError
from ..model.poe import PoeModel
from ..progress import progress
from .chart import LEVELS, Estimate, absorbed, count
from .identifiable import redundant
from .identify import Fit, level_start, solve_level
from .measurements import Measurements
from .residuals import Data, evaluate
from .start import FitOptions, to_data

__all__ = [
    "FOLDS",
    "RULES",
    "Score",
    "Selection",
    "cross_validate",
    "fold_errors",
    "fold_of_configurations",
    "level_fits",
    "noise_weights",
    "per_configuration",
]

Mat = NDArray[np.float64]

FOLDS = 5  # folds of the cross-validation (fewer when there are fewer configurations)
RULES = ("simplest", "best")  # the simplest level within its uncertainty of the best, or the best


@dataclass(frozen=True, slots=True)
class Score:
    """How one level fitted the measurements and predicted the folds it was not fitted to.

    Attributes
    ----------
    level
        The level's name.
    parameters
        Its identified parameters (free coordinates).
    fit_rms_position
        RMS position residual of its fit to all the measurements.
    rms_position
        Cross-validated RMS position error (``nan`` if the level could not be judged).
    uncertainty
        The standard error of ``rms_position``.
    rms_rotation
        Cross-validated RMS rotation error, rad (pose measurements), else ``None``.
    iterations
        Levenberg-Marquardt iterations of its fit to all the measurements.
    failure
        Why the level could not be judged, or ``None``.
    """

    level: str
    parameters: int
    fit_rms_position: float
    rms_position: float
    uncertainty: float
    rms_rotation: float | None
    iterations: int
    failure: str | None = None


@dataclass(frozen=True, slots=True)
class Selection:
    """The cross-validation of the levels and the choice it led to.

    Attributes
    ----------
    folds, seed, configurations
        How the configurations were dealt.
    scores
        Each level judged, from the simplest.
    best
        The level of the smallest cross-validated error (``None``: none could be judged).
    chosen
        The level chosen (module docstring; ``None``: none could be judged).
    reason
        Why, in a sentence.
    """

    folds: int
    seed: int
    configurations: int
    scores: tuple[Score, ...]
    best: str | None
    chosen: str | None
    reason: str

    def score(self, level: str) -> Score:
        """The score of ``level``."""
        return next(s for s in self.scores if s.level == level)


def fold_of_configurations(count: int, folds: int, seed: int) -> NDArray[np.int64]:
    """Each configuration's fold (module docstring)."""
    k = max(1, min(folds, count))
    out = np.empty(count, dtype=np.int64)
    for fold, chosen in enumerate(
        np.array_split(np.random.default_rng((seed, 5)).permutation(count), k)
    ):
        out[chosen] = fold
    return out


def _squared_errors(est: Estimate, m: Measurements, pose: bool, ids: list[int]) -> Mat:
    """``(N, 3 or 4)``: each row's squared position error and, for poses, squared rotation."""
    data = to_data(m, pose, ids)
    r, _ = evaluate(absorbed(est), data, 1.0, 1.0, jacobian=False)
    rows = r.reshape(len(data), data.rows)
    out: Mat = np.sum(rows[:, :3] ** 2, axis=1, keepdims=True)
    if pose:
        out = np.hstack([out, np.sum(rows[:, 3:] ** 2, axis=1, keepdims=True)])
    return out


def per_configuration(squared: Mat, index: NDArray[np.int64], count: int) -> Mat:
    """``(count, k)``: each configuration's mean of its rows' values."""
    sums = np.zeros((count, squared.shape[1]))
    np.add.at(sums, index, squared)
    rows = np.bincount(index, minlength=count).astype(float)
    means: Mat = sums / np.maximum(rows, 1.0)[:, None]
    return means


def _rms(values: Mat) -> tuple[float, float]:
    """RMS of per-configuration mean squares and its standard error."""
    mean = float(np.mean(values))
    rms = math.sqrt(mean)
    if len(values) < 2 or rms == 0.0:
        return rms, 0.0
    se = float(np.std(values, ddof=1)) / math.sqrt(len(values))
    return rms, se / (2.0 * rms)


def level_fits(
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    before: Fit,
    levels: tuple[str, ...],
) -> tuple[dict[str, Fit], dict[str, str], dict[str, NDArray[np.bool_]]]:
    """Each level fitted to all of ``fit`` (from ``before``, the base-tool fit), why the levels
    that could not be fitted were not, and each level's coordinates that the others carry (found
    once: every fold's chain differs from this one by its fit, not in structure)."""
    size = nominal.size()
    data = to_data(fit, opts.pose, ids)
    fits: dict[str, Fit] = {}
    failures: dict[str, str] = {}
    structures = {
        level: redundant(before.solution.estimate.with_level(LEVELS[level]), nominal.limits(), size)
        for level in levels
    }
    previous = before.solution.estimate  # each level starts from the simpler one's solution
    for level in levels:
        if level == "base-tool" and not opts.fixed_patterns:
            fits[level] = before
            continue
        lopts = replace(opts, level=level)
        start, reference = _starts(nominal, before, previous, lopts, ids, structures[level])
        if count(start) > len(data) * data.rows:
            failures[level] = (
                f"{count(start)} parameters, more than the {len(data) * data.rows} equations"
            )
            continue
        noise = (before.sigma_pos, before.sigma_rot)
        fits[level] = solve_level(start, data, lopts, size, reference, noise)
        if fits[level].solution.converged:
            previous = fits[level].solution.estimate
    return fits, failures, structures


def _starts(
    nominal: PoeModel,
    before: Fit,
    previous: Estimate,
    opts: FitOptions,
    ids: list[int],
    structure: NDArray[np.bool_] | None,
) -> tuple[Estimate, Estimate]:
    """A level's start, the solution of the simpler level fitted before it (levels are nested:
    it is a point of this level too, nearer the solution than the base-tool one), and the
    prior's centre, the base-tool solution at this level (the nominal as placed)."""
    reference, _, _ = level_start(nominal, before.solution.estimate, opts, ids, structure)
    if previous is before.solution.estimate:
        return reference, reference
    start, _, _ = level_start(nominal, previous, opts, ids, structure)
    return start, reference


def fold_errors(
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    before: Fit,
    fits: dict[str, Fit],
    fold_of_row: NDArray[np.int64],
    structures: dict[str, NDArray[np.bool_]] | None = None,
    trained: NDArray[np.bool_] | None = None,
) -> tuple[dict[str, Mat], dict[str, str]]:
    """Each row's squared position (and rotation) error when its fold is predicted by each level
    of ``fits`` fitted to the other folds (module docstring): ``(N, 1 or 2)`` per level, and why
    a level could not be judged. ``trained`` says which rows a fit may use (default all)."""
    size = nominal.size()
    k = int(fold_of_row.max(initial=0)) + 1
    rows = len(fit)
    errors = {level: np.full((rows, 2 if opts.pose else 1), np.nan) for level in fits}
    failures: dict[str, str] = {}
    usable = np.ones(rows, dtype=bool) if trained is None else trained
    if k < 2:
        why = "a single configuration cannot be split into folds"
        return {}, dict.fromkeys(fits, why)
    for fold in progress(range(k), total=k, what="calibrate: cross-validation"):
        train = fit.subset(np.flatnonzero((fold_of_row != fold) & usable))
        held = np.flatnonzero(fold_of_row == fold)
        valid = fit.subset(held)
        train_data = to_data(train, opts.pose, ids)
        equations = len(train_data) * train_data.rows
        if equations < count(before.solution.estimate):
            why = (
                f"a fold leaves {equations} equations, fewer than the base and tool's "
                f"{count(before.solution.estimate)} parameters"
            )
            return {}, dict.fromkeys(fits, why)
        fold_before = _refit(before, before.solution.estimate, train_data, opts, size)
        previous = fold_before.solution.estimate
        for level, template in fits.items():
            if level in failures:
                continue
            if level == "base-tool" and not opts.fixed_patterns:
                fold_fit = fold_before
            else:
                lopts = replace(opts, level=level)
                structure = None if structures is None else structures.get(level)
                est, reference = _starts(nominal, fold_before, previous, lopts, ids, structure)
                if count(est) > len(train_data) * train_data.rows:
                    failures[level] = (
                        f"a fold leaves {len(train_data) * train_data.rows} equations for its "
                        f"{count(est)} parameters"
                    )
                    continue
                fold_fit = _refit(template, est, train_data, lopts, size, reference)
                if fold_fit.solution.converged:
                    previous = fold_fit.solution.estimate
            if not fold_fit.solution.converged:
                failures[level] = (
                    f"its fit did not converge in {opts.max_iterations} iterations in fold "
                    f"{fold + 1} of {k}"
                )
                continue
            errors[level][held] = _squared_errors(fold_fit.solution.estimate, valid, opts.pose, ids)
    return {lv: e for lv, e in errors.items() if lv not in failures}, failures


def cross_validate(
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    before: Fit,
    levels: tuple[str, ...],
    folds: int = FOLDS,
    seed: int = 0,
    rule: str = "simplest",
) -> tuple[Selection, dict[str, Fit]]:
    """Judge ``levels`` on ``fit`` by cross-validation and choose one (module docstring).

    ``before`` is the base-tool level's fit to all of ``fit``; ``rule`` is ``simplest`` (the
    simplest level within its uncertainty of the best) or ``best`` (the best). Returns the
    selection and every level's fit to all the measurements.
    """
    if rule not in RULES:
        raise UsageError(f"unknown rule {rule!r}; valid: {', '.join(RULES)}")
    index, configurations = fit.configurations()
    fold_of = fold_of_configurations(configurations, folds, seed)
    fits, failures, structures = level_fits(nominal, fit, opts, ids, before, levels)
    errors, fold_failures = fold_errors(
        nominal, fit, opts, ids, before, fits, fold_of[index], structures
    )
    failures |= fold_failures
    judged = [lv for lv in levels if lv in errors]
    per_config = {lv: per_configuration(errors[lv], index, configurations) for lv in judged}
    weights = noise_weights(fits[judged[-1]], opts.pose) if judged else np.ones(1)
    combined = {lv: per_config[lv] @ weights for lv in judged}
    scores = []
    for level in levels:
        fit_level = fits.get(level)
        fit_rms, parameters, iterations = math.nan, 0, 0
        if fit_level is not None:
            squared = _squared_errors(fit_level.solution.estimate, fit, opts.pose, ids)
            fit_rms = math.sqrt(float(np.mean(squared[:, 0])))
            parameters = count(fit_level.solution.estimate)
            iterations = fit_level.solution.iterations
        if level not in per_config:
            scores.append(
                Score(
                    level,
                    parameters,
                    fit_rms,
                    math.nan,
                    math.nan,
                    None,
                    iterations,
                    failures[level],
                )
            )
            continue
        values = per_config[level]
        rms, se = _rms(values[:, 0])
        rot = math.sqrt(float(np.mean(values[:, 1]))) if opts.pose else None
        scores.append(Score(level, parameters, fit_rms, rms, se, rot, iterations))
    k = int(fold_of.max(initial=0)) + 1
    if not judged:
        return Selection(k, seed, configurations, tuple(scores), None, None, ""), fits
    best = min(judged, key=lambda lv: float(np.mean(combined[lv])))
    chosen = (
        best
        if rule == "best"
        else next(lv for lv in judged if _within(combined[lv], combined[best]))
    )
    by_level = {s.level: s for s in scores}
    reason = _reason(by_level[chosen], by_level[best], opts.pose)
    return Selection(k, seed, configurations, tuple(scores), best, chosen, reason), fits


def noise_weights(richest: Fit, pose: bool) -> Mat:
    """How squared position and rotation errors add up: over their noise levels' squares."""
    if not pose:
        return np.array([1.0 / richest.sigma_pos**2])
    return np.array([1.0 / richest.sigma_pos**2, 1.0 / richest.sigma_rot**2])


def _within(level: Mat, best: Mat) -> bool:
    """Whether a level's per-configuration errors are, on average, within one standard error
    of the best level's (the standard error of the paired differences)."""
    d = level - best
    if len(d) < 2:
        return bool(np.mean(d) <= 0.0)
    return bool(np.mean(d) <= float(np.std(d, ddof=1)) / math.sqrt(len(d)))


def _refit(
    template: Fit,
    est: Estimate,
    data: Data,
    opts: FitOptions,
    size: float,
    reference: Estimate | None = None,
) -> Fit:
    """``est`` solved on ``data`` with the noise levels of ``template`` (no statistics);
    ``reference``: the prior's centre (default ``est``)."""
    from .solver import Problem, solve

    problem = Problem(data, template.sigma_pos, template.sigma_rot, opts.prior, reference or est)
    if opts.prior is None or est.level.name == "base-tool":
        problem = Problem(data, template.sigma_pos, template.sigma_rot)
    sol = solve(est, problem, size, opts.max_iterations)
    return Fit(sol, template.stats, template.sigma_pos, template.sigma_rot)


def _reason(chosen: Score, best: Score, pose: bool) -> str:
    what = "errors in position and rotation, each over its noise" if pose else "position errors"
    if chosen.level == best.level:
        return (
            f"{chosen.level} predicts the configurations it was not fitted to best ({what}); "
            "every simpler level predicts them worse by more than the folds' scatter"
        )
    return (
        f"{chosen.level} predicts the configurations it was not fitted to within the folds' "
        f"scatter of the best level, {best.level} ({what}), with fewer parameters "
        f"({chosen.parameters} against {best.parameters})"
    )
