"""Choosing how much to identify: every level judged on configurations it was not fitted to.

A level with more parameters always fits the measurements better; whether it predicts new
configurations better depends on how many and how varied they are. So each level of
:mod:`.chart` is fitted to all the measurements (the base-tool level first, each other from the
solution of the simpler one before it; geometry and full with the prior of greatest evidence,
:mod:`.prior`, unless another is asked for) and judged by *leave-one-configuration-out*
prediction: each configuration (a distinct row of joint values, all its measurements together)
predicted by the level fitted to all the others.

The fit without configuration ``c`` is not solved again: the fit is a weighted least-squares
problem, and leaving ``c``'s rows out moves its solution by one Gauss-Newton step, after which
``c``'s residuals are ``e_(c) = (I - H_cc)^-1 e_c`` (the grouped deleted residuals, exact for a
linear model; Cook & Weisberg, *Residuals and Influence in Regression*, 1982, §3.6), ``H`` the
hat matrix ``J (J^T J)^-1 J^T`` of the level's weighted Jacobian (the prior's rows included:
they stay) and ``H_cc`` its block of ``c``'s rows. One factorisation per level gives every
configuration's prediction; on the real data sets they agree with refits to three digits (the
test suite checks one). With ``folds`` the configurations are dealt into that many seeded folds
(``numpy.random.default_rng((seed, 5))``) and each fold is left out in turn the same way.

A level's score is the mean over configurations of the prediction error the fit itself
minimises: each configuration's squared position error over ``sigma_p^2`` plus, for poses, its
squared rotation error over ``sigma_r^2`` (each over its noise: the noise levels of the richest
level judged, the nearest to the measuring noise), each configuration's errors averaged over its
measurements. The choice (rule ``simplest``, the default) is the simplest level whose score
exceeds the best's by no more than one standard error of their paired per-configuration
differences (the one-standard-error rule; Hastie, Tibshirani & Friedman, *The Elements of
Statistical Learning*, 2009, §7.10): a richer level must predict better by more than the
configurations' scatter to be chosen. Rule ``best`` takes the level of the smallest score.

A level that could not be fitted (more parameters than equations without a prior), that did not
converge, or that some configuration alone determines (``I - H_cc`` singular: nothing predicts
it without that configuration) is not chosen, and the report says why.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..model.poe import PoeModel
from ..progress import progress
from ..tolerances import RANK_RELATIVE
from .chart import Estimate, count
from .fit import Fit, check_equations, fit_before, joint_locations, level_start, solve_level
from .identifiable import carried_at_levels, check_patterns
from .levels import AUTO, BASE_TOOL, LEVELS
from .measurements import Measurements
from .prior import Deviations
from .residuals import measurement_errors
from .solver import Linearisation, Problem
from .start import FitOptions, has_prior, placement, prior_of, to_data

if TYPE_CHECKING:
    from .problem import CalibrationProblem, LevelChoice, Options

__all__ = [
    "Pass",
    "Score",
    "Selection",
    "Shared",
    "cross_validate",
    "fold_of_configurations",
    "hat_basis",
    "judge_levels",
    "left_out_errors",
    "level_fits",
    "per_configuration",
    "predicted_without",
    "within",
    "without_rows",
]

Mat = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Score:
    """How one level fitted the measurements and predicted the configurations left out.

    Attributes
    ----------
    level
        The level's name.
    parameters
        Its identified parameters (free coordinates).
    fit_rms_position
        RMS position residual of its fit to all the measurements.
    rms_position
        Left-out RMS position error (``nan`` if the level could not be judged).
    uncertainty
        The standard error of ``rms_position``.
    rms_rotation
        Left-out RMS rotation error, rad (pose measurements), else ``None``.
    iterations
        Levenberg-Marquardt iterations of its fit to all the measurements.
    prior
        The deviations of its prior (:mod:`.prior`), or ``None``.
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
    prior: Deviations | None = None
    failure: str | None = None


@dataclass(frozen=True, slots=True)
class Selection:
    """The levels judged and the choice they led to.

    Attributes
    ----------
    folds
        The groups of configurations left out in turn (each configuration alone: their count).
    seed
        The seed of the folds (``None``: each configuration left out alone).
    configurations
        How many configurations were judged.
    scores
        Each level judged, from the simplest.
    best
        The level of the smallest score (``None``: none could be judged).
    chosen
        The level chosen (module docstring; ``None``: none could be judged).
    reason
        Why, in a sentence.
    left_out
        Per level judged, ``(N, 1 or 2)``: each measurement's squared position (and rotation)
        error when its configuration was left out.
    weights
        How squared position and rotation errors add up in the scores (over the noise levels'
        squares).
    """

    folds: int
    seed: int | None
    configurations: int
    scores: tuple[Score, ...]
    best: str | None
    chosen: str | None
    reason: str
    left_out: dict[str, Mat] = field(default_factory=dict, repr=False, compare=False)
    weights: Mat = field(default_factory=lambda: np.ones(1), repr=False, compare=False)

    def score(self, level: str) -> Score:
        """The score of ``level``."""
        return next(s for s in self.scores if s.level == level)


def fold_of_configurations(count: int, folds: int | None, seed: int) -> NDArray[np.int64]:
    """Each configuration's group: itself (``folds`` ``None``), or one of ``folds`` seeded folds
    (module docstring)."""
    if folds is None or folds >= count:
        return np.arange(count, dtype=np.int64)
    out = np.empty(count, dtype=np.int64)
    for fold, chosen in enumerate(
        np.array_split(np.random.default_rng((seed, 5)).permutation(count), max(1, folds))
    ):
        out[chosen] = fold
    return out


def per_configuration(squared: Mat, index: NDArray[np.int64], count: int) -> Mat:
    """``(count, k)``: each configuration's mean of its rows' values."""
    sums = np.zeros((count, squared.shape[1]))
    np.add.at(sums, index, squared)
    rows = np.bincount(index, minlength=count).astype(float)
    means: Mat = sums / np.maximum(rows, 1.0)[:, None]
    return means


def left_out_errors(problem: Problem, lin: Linearisation, group: NDArray[np.int64]) -> Mat | None:
    """``(N, 1 or 2)``: each measurement's squared position (and rotation) error when its group
    (``group[row]``, a configuration or a fold) is left out of the fit whose linearisation at
    its solution is ``lin`` (module docstring), in the physical units; ``None`` when some group
    alone determines a parameter."""
    return _deleted(problem, lin, _group_rows(group, problem.data.rows), None)


def _group_rows(group: NDArray[np.int64], rows: int) -> NDArray[np.int64]:
    """``(groups, width)``: each group's residual rows side by side, in file order (``rows``
    per measurement, measurement ``k`` in group ``group[k]``), padded with ``-1`` to the
    largest group's (one sort, not a search per group)."""
    count = int(group.max(initial=-1)) + 1
    order = np.argsort(group, kind="stable")
    members = np.bincount(group, minlength=count)
    slot = np.arange(len(group)) - np.repeat(np.cumsum(members) - members, members)
    index = np.full((count, int(members.max(initial=0)) * rows), -1, dtype=np.int64)
    within_row = np.arange(rows)
    index[group[order][:, None], slot[:, None] * rows + within_row] = (
        order[:, None] * rows + within_row
    )
    return index


def _deleted(
    problem: Problem, lin: Linearisation, index: NDArray[np.int64], basis: Mat | None
) -> Mat | None:
    """:func:`left_out_errors`, each group's rows ``index`` (:func:`_group_rows`); ``basis``:
    the hat matrix's basis at ``lin`` (:func:`hat_basis` of ``problem.weighted(lin)``'s
    Jacobian), when known."""
    r, jac = problem.weighted(lin)
    rows, m = problem.data.rows, problem.data_rows
    if basis is None:
        basis = hat_basis(jac)
    u = np.zeros((m + 1, basis.shape[1]))  # the data rows of J B (their products the hat
    np.matmul(jac[:m], basis, out=u[:m])  # matrix), and a row of zeros for the padding
    width = index.shape[1]
    padded_u = u[index]  # (groups, width, rank)
    padded_r = np.append(r[:m], 0.0)[index]
    hat = padded_u @ padded_u.transpose(0, 2, 1)  # each group's H_cc
    system = np.eye(width) - hat
    # every group's I - H_cc has its eigenvalues above RANK_RELATIVE: H_cc's largest is at most
    # its Frobenius norm; where that bound does not show it, I - H_cc - RANK_RELATIVE I has a
    # Cholesky factor
    if float(np.max(np.einsum("gij,gij->g", hat, hat))) >= (1.0 - RANK_RELATIVE) ** 2:
        try:
            np.linalg.cholesky(system - RANK_RELATIVE * np.eye(width))
        except np.linalg.LinAlgError:
            return None
    deleted = np.linalg.solve(system, padded_r[..., None])[..., 0]
    out = np.zeros((m + 1,))
    out[index] = deleted
    sigmas = np.array([problem.sigma_pos, problem.sigma_rot][: rows // 3])
    squared: Mat = (measurement_errors(out[:m], rows) * sigmas) ** 2
    return squared


def hat_basis(jac: Mat) -> Mat:
    """``(p, rank)``: a basis ``B`` of ``jac``'s parameters with ``jac B B^T jac^T`` its hat
    matrix and ``B B^T`` the inverse of ``jac^T jac``, both over its numerical rank: with its
    columns scaled to unit norm (``J_s = jac D^-1``, the rank relative to each parameter's own
    size), the directions whose eigenvalues of ``N = J_s^T J_s`` exceed
    :data:`~urdf2dh.tolerances.RANK_RELATIVE` times the largest. ``D^-1 L^-T`` from the
    Cholesky factor ``N = L L^T`` where :func:`_inverse_factor` shows every direction kept,
    else ``D^-1 V S^-1`` from ``N``'s eigenvectors ``V`` and the square roots ``S`` of the
    eigenvalues kept."""
    normal = jac.T @ jac
    norms = np.sqrt(np.diagonal(normal))
    norms[norms == 0.0] = 1.0  # a column of zeros stays zeros
    normal /= np.outer(norms, norms)
    inverse = _inverse_factor(normal)
    if inverse is not None:
        basis: Mat = inverse.T / norms[:, None]
        return basis
    eig, vec = np.linalg.eigh(normal)
    keep = eig > RANK_RELATIVE * float(eig.max(initial=0.0))
    basis = vec[:, keep] / np.sqrt(eig[keep]) / norms[:, None]
    return basis


def _inverse_factor(normal: Mat) -> Mat | None:
    """``L^-1``, ``L`` the lower Cholesky factor of ``normal`` (a normal matrix of unit columns),
    when a bound shows all its eigenvalues above :data:`~urdf2dh.tolerances.RANK_RELATIVE`
    times the largest, with room for round-off: the smallest is at least ``1 / |L^-1|_F^2``
    (``N^-1 = L^-T L^-1``), the largest at most the trace, and their ratio must clear twice the
    threshold. ``None`` otherwise (no factor, or the bound too loose to tell)."""
    from scipy.linalg.lapack import dtrtri

    try:
        factor = np.linalg.cholesky(normal)
    except np.linalg.LinAlgError:
        return None
    inverse, info = dtrtri(factor, lower=1)
    if info or 2.0 * RANK_RELATIVE * float(np.trace(normal)) * float(np.sum(inverse**2)) >= 1.0:
        return None
    out: Mat = inverse
    return out


def without_rows(
    problem: Problem, lin: Linearisation, keep: NDArray[np.int64]
) -> tuple[Problem, Linearisation, Mat]:
    """The fit whose linearisation at its solution is ``lin``, with only the measurements
    ``keep`` (rows of ``problem.data``): moved by one Gauss-Newton step at ``lin`` with the same
    noise levels and prior (the refit, exact for a linear model; the step of least norm over
    the numerical rank), as the problem, the linearisation at the moved solution (the Jacobian
    ``lin``'s) and its hat matrix's basis (:func:`hat_basis`)."""
    r, jac = problem.weighted(lin)
    rows = lin.rows
    kept = (keep[:, None] * rows + np.arange(rows)).ravel()
    fitted = np.concatenate([kept, np.arange(problem.data_rows, len(r))])  # and the prior's
    a, b = jac[fitted], r[fitted]
    basis = hat_basis(a)  # the normal equations, (A^T A)^-1 = B B^T, and a step of refinement
    delta = -basis @ (basis.T @ (a.T @ b))
    delta -= basis @ (basis.T @ (a.T @ (b + a @ delta)))
    prior = None
    if problem.prior is not None:
        coordinates, tangent = Problem.prior_part(problem.prior, lin)
        prior = (coordinates + tangent @ delta, tangent)
    moved = Linearisation(
        lin.estimate, lin.residuals[kept] + lin.jacobian[kept] @ delta, lin.jacobian[kept], rows,
        prior,
    )  # fmt: skip
    data = problem.data.part(keep)
    return Problem(data, problem.sigma_pos, problem.sigma_rot, problem.prior), moved, basis


def predicted_without(
    first: Pass, keep: NDArray[np.int64], rest: Measurements, choice: LevelChoice
) -> Selection:
    """The levels of ``first`` judged as if only its fitted measurements ``keep`` had been fitted
    (``rest``: those measurements), to first order: each level's fit moved by
    :func:`without_rows`, its configurations (or folds of them, as ``choice`` says) left out in
    turn and the level chosen as :func:`cross_validate` does. Its scores are not filled in:
    only the left-out errors, the weights and the choice are. ``first``'s levels fitted again
    without the other measurements (its noise levels and priors estimated again) may differ by
    more than the step where these move the solution far."""
    data = to_data(first.fit, first.options.pose, first.problem.markers)
    index, configurations = rest.configurations()
    group = fold_of_configurations(configurations, choice.folds, choice.seed)[index]
    failures: dict[str, str] = {}
    at = {
        lv: without_rows(f.problem(data), f.solution.lin, keep)
        for lv, f in first.fits.items()
        if lv in first.selection.left_out
    }
    left_out, per_config = _left_out(at, group, index, configurations, failures)
    judged = [lv for lv in first.selection.left_out if lv in per_config]
    weights = first.selection.weights
    groups = int(group.max(initial=-1)) + 1
    seed = _seed_used(choice.folds, choice.seed, configurations)
    if not judged:
        return Selection(groups, seed, configurations, (), None, None, "")
    best, chosen = _choose(judged, per_config, weights, choice.rule)
    chosen = choice.level if choice.level != AUTO else chosen
    reason = "predicted to first order without the measurements left out"
    return Selection(groups, seed, configurations, (), best, chosen, reason, left_out, weights)


def level_fits(
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    before: Fit,
    levels: tuple[str, ...],
    shared: Shared | None = None,
) -> tuple[dict[str, Fit], dict[str, str]]:
    """Each level fitted to all of ``fit`` (from ``before``, the base-tool fit, each from the
    simpler one's solution), and why the levels that could not be fitted were not.
    ``shared``: what the levels read, when found already (:class:`Shared`)."""
    size = nominal.size()
    if shared is None:
        shared = Shared.of(nominal, fit, opts, ids, before, _fitted(levels, opts))
    structures, locations = shared.structures, shared.locations
    data = to_data(fit, opts.pose, ids)
    fits: dict[str, Fit] = {}
    failures: dict[str, str] = {}
    previous = before.solution.estimate  # each level starts from the simpler one's solution
    noise = (before.sigma_pos, before.sigma_rot)
    deviations: Deviations | None = None  # ... and its prior's estimate from the simpler one's
    for level in progress(levels, what="calibrate: levels"):
        if level == BASE_TOOL.name and not opts.fixed_patterns:
            fits[level] = before
            continue
        lopts = replace(opts, level=level)
        structure = structures[level]
        reference, _, _ = level_start(nominal, before.solution.estimate, lopts, ids, structure)
        # the simpler level's solution with the same free coordinates (they depend on the
        # level, the chain's kinds and the names fixed, not on where it starts)
        start = (
            reference
            if previous is before.solution.estimate
            else previous.with_level(LEVELS[level], reference.free)
        )
        errors, stated = prior_of(start, lopts, reference, locations)
        if errors is None and count(start) > len(data) * data.rows:
            failures[level] = (
                f"{count(start)} parameters, more than the {len(data) * data.rows} equations"
            )
            continue
        fits[level] = solve_level(
            start, data, lopts, size, noise=noise, deviations=deviations, stats=False,
            prior=(errors, stated),
        )  # fmt: skip
        if fits[level].solution.converged:
            previous = fits[level].solution.estimate
            noise = (fits[level].sigma_pos, fits[level].sigma_rot)
            prior = fits[level].prior
            if prior is not None and errors is not None and stated is None:
                deviations = prior.deviations
        else:
            failures[level] = f"its fit did not converge in {opts.max_iterations} iterations"
    return fits, failures


def _fitted(levels: tuple[str, ...], opts: FitOptions) -> tuple[str, ...]:
    """The levels :func:`level_fits` fits (the base-tool level's fit is the one before, unless
    parameters are fixed by name)."""
    return tuple(lv for lv in levels if lv != BASE_TOOL.name or opts.fixed_patterns)


@dataclass(frozen=True, slots=True)
class Shared:
    """What every level fitted from one base-tool fit reads, found once.

    Attributes
    ----------
    structures
        Each level's coordinates that the others carry (:func:`.identifiable.redundant`), by
        name.
    locations
        ``(n, 3)`` the joints' locations in the device frame (:func:`.fit.joint_locations`).
    """

    structures: dict[str, NDArray[np.bool_]]
    locations: Mat

    @classmethod
    def of(
        cls,
        nominal: PoeModel,
        fit: Measurements,
        opts: FitOptions,
        ids: list[int],
        before: Fit,
        levels: tuple[str, ...],
        placed: Mat | None = None,
    ) -> Shared:
        """For ``levels``, fitted from ``before`` to ``fit``; ``placed``: the rigid fit
        (:func:`.start.placement`), when the caller has it."""
        est = before.solution.estimate
        structures = carried_at_levels(
            est, tuple(LEVELS[lv] for lv in levels), nominal.limits(), nominal.size()
        )
        return cls(structures, joint_locations(nominal, fit, opts, ids, est, placed))


def cross_validate(
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    before: Fit,
    levels: tuple[str, ...],
    folds: int | None = None,
    seed: int = 0,
    rule: str = "simplest",
    shared: Shared | None = None,
) -> tuple[Selection, dict[str, Fit]]:
    """Judge ``levels`` on ``fit`` by leaving out configurations (or ``folds`` seeded folds of
    them) and choose one (module docstring).

    ``before`` is the base-tool level's fit to all of ``fit``; ``rule`` is ``simplest`` or
    ``best``; ``shared`` as :func:`level_fits` takes it. Returns the selection and every
    level's fit to all the measurements.
    """
    index, configurations = fit.configurations()
    group = fold_of_configurations(configurations, folds, seed)[index]
    fits, failures = level_fits(nominal, fit, opts, ids, before, levels, shared)
    data = to_data(fit, opts.pose, ids)
    at = {
        lv: (f.problem(data), f.solution.lin, None) for lv, f in fits.items() if lv not in failures
    }
    left_out, per_config = _left_out(at, group, index, configurations, failures)
    judged = [lv for lv in levels if lv in per_config]
    richest = fits[judged[-1]] if judged else before
    weights = _weights(richest, data.rows)
    scores = [_score(level, fits, failures, per_config, opts.pose) for level in levels]
    seed_used = _seed_used(folds, seed, configurations)
    groups = int(group.max(initial=-1)) + 1
    if not judged:
        selection = Selection(groups, seed_used, configurations, tuple(scores), None, None, "")
        return selection, fits
    best, chosen = _choose(judged, per_config, weights, rule)
    by_level = {s.level: s for s in scores}
    reason = _reason(by_level[chosen], by_level[best], opts.pose, seed_used is None)
    selection = Selection(
        groups, seed_used, configurations, tuple(scores), best, chosen, reason, left_out, weights
    )
    return selection, fits


def _seed_used(folds: int | None, seed: int, configurations: int) -> int | None:
    """The seed of the folds, ``None`` where each configuration is left out alone
    (:func:`fold_of_configurations`)."""
    return None if folds is None or folds >= configurations else seed


def _left_out(
    at: Mapping[str, tuple[Problem, Linearisation, Mat | None]],
    group: NDArray[np.int64],
    index: NDArray[np.int64],
    configurations: int,
    failures: dict[str, str],
) -> tuple[dict[str, Mat], dict[str, Mat]]:
    """Per level fitted (its problem, its linearisation at the solution and its hat matrix's
    basis when known, ``at``): each measurement's left-out squared errors
    (:func:`left_out_errors`, its group ``group[row]`` left out) and each configuration's mean
    of them; why the others could not be judged goes to ``failures``."""
    left_out: dict[str, Mat] = {}
    per_config: dict[str, Mat] = {}
    groups = int(group.max(initial=-1)) + 1
    blocks = None  # each group's rows: the same at every level
    for level, (problem, lin, basis) in at.items():
        if groups < 2:
            failures[level] = "a single configuration cannot be left out"
            continue
        if blocks is None:
            blocks = _group_rows(group, problem.data.rows)
        squared = _deleted(problem, lin, blocks, basis)
        if squared is None:
            failures[level] = (
                "a configuration alone determines some of its parameters: without it "
                "nothing predicts them"
            )
            continue
        left_out[level] = squared
        per_config[level] = per_configuration(squared, index, configurations)
    return left_out, per_config


def _weights(richest: Fit, rows: int) -> Mat:
    """How squared position and rotation errors add up: over the richest level's noise levels'
    squares (module docstring)."""
    return np.array([1.0 / richest.sigma_pos**2, 1.0 / richest.sigma_rot**2][: rows // 3])


def _choose(
    judged: list[str], per_config: dict[str, Mat], weights: Mat, rule: str
) -> tuple[str, str]:
    """The best level and the one ``rule`` chooses (module docstring), of ``judged`` (from the
    simplest)."""
    combined = {lv: per_config[lv] @ weights for lv in judged}
    best = min(judged, key=lambda lv: float(np.mean(combined[lv])))
    if rule == "best":
        return best, best
    return best, next(lv for lv in judged if within(combined[lv], combined[best]))


def _score(
    level: str,
    fits: dict[str, Fit],
    failures: dict[str, str],
    per_config: dict[str, Mat],
    pose: bool,
) -> Score:
    f = fits.get(level)
    fit_rms, parameters, iterations, prior = math.nan, 0, 0, None
    if f is not None:
        fit_rms = math.sqrt(float(np.mean(f.solution.lin.errors()[:, 0] ** 2)))
        parameters = count(f.solution.estimate)
        iterations = f.solution.iterations
        prior = None if f.prior is None else f.prior.deviations
    if level not in per_config:
        return Score(
            level, parameters, fit_rms, math.nan, math.nan, None, iterations, prior,
            failures[level],
        )  # fmt: skip
    values = per_config[level]
    rms, se = _rms(values[:, 0])
    rot = math.sqrt(float(np.mean(values[:, 1]))) if pose else None
    return Score(level, parameters, fit_rms, rms, se, rot, iterations, prior)


def _rms(values: Mat) -> tuple[float, float]:
    """RMS of per-configuration mean squares and its standard error."""
    mean = float(np.mean(values))
    rms = math.sqrt(mean)
    if len(values) < 2 or rms == 0.0:
        return rms, 0.0
    se = float(np.std(values, ddof=1)) / math.sqrt(len(values))
    return rms, se / (2.0 * rms)


def within(level: Mat, best: Mat, errors: float = 1.0) -> bool:
    """Whether a level's per-configuration errors are, on average, within ``errors`` standard
    errors of the best level's (the standard error of the paired differences)."""
    d = level - best
    if len(d) < 2:
        return bool(np.mean(d) <= 0.0)
    return bool(np.mean(d) <= errors * float(np.std(d, ddof=1)) / math.sqrt(len(d)))


def _reason(chosen: Score, best: Score, pose: bool, alone: bool) -> str:
    what = "errors in position and rotation, each over its noise" if pose else "position errors"
    left = "each configuration left out in turn" if alone else "each fold left out in turn"
    if chosen.level == best.level:
        return (
            f"{chosen.level} predicts the configurations it was not fitted to best ({left}; {what})"
        )
    return (
        f"{chosen.level} predicts the configurations it was not fitted to within one standard "
        f"error of the best level, {best.level} ({left}; {what}), with fewer parameters "
        f"({chosen.parameters} against {best.parameters})"
    )


@dataclass(frozen=True)
class Pass:
    """The levels fitted to one set of measurements and judged on it.

    Attributes
    ----------
    problem
        The problem, its fitted rows those judged.
    options
        How each level was identified (at the base-tool level).
    placed
        The rigid fit of the nominal's tool points to the measured ones
        (:func:`.start.placement`): found once, read by every step after it.
    start
        The nominal placed in the device frame by ``placed``.
    before
        The base-tool level's fit: the start of every other level, and the fair "before".
    selection
        The levels judged and the choice.
    fits
        Each level's fit to all the fitted measurements.
    level
        The level chosen, or asked for (``None``: none could be judged).
    """

    problem: CalibrationProblem
    options: FitOptions
    placed: Mat
    start: Estimate
    before: Fit
    selection: Selection
    fits: dict[str, Fit]
    level: str | None

    @property
    def fit(self) -> Measurements:
        """The measurements fitted."""
        return self.problem.fit

    @property
    def usable(self) -> bool:
        """Whether the base-tool level converged and the level could be fitted."""
        return self.before.solution.converged and self.level is not None and self.level in self.fits


def judge_levels(problem: CalibrationProblem, options: Options, first: bool = True) -> Pass:
    """Fit every level :class:`~.problem.LevelChoice` asks for to ``problem``'s fitted
    measurements, judge them (module docstring) and take the level asked for or chosen.

    ``first``: the first pass, whose base-tool fit must converge (the caller is told
    otherwise: :attr:`Pass.usable`), and whose fixed parameters and equations are checked.
    """
    choice, opts = options.choice, options.fitting
    nominal, fit, ids = problem.nominal, problem.fit, problem.markers
    levels = choice.levels(opts.keep_scale)
    placed = placement(nominal, fit, opts, ids)
    start, before = fit_before(nominal, fit, opts, ids, placed)
    if first and not before.solution.converged:
        nothing = Selection(0, None, 0, (), None, None, "")
        return Pass(problem, opts, placed, start, before, nothing, {}, None)
    checked = levels if first and opts.fixed else (choice.level,) if first else ()
    found = tuple(lv for lv in levels if lv in _fitted(levels, opts) + checked)
    shared = Shared.of(nominal, fit, opts, ids, before, found, placed)
    structures = shared.structures
    at = before.solution.estimate
    if first and choice.level != AUTO:  # fewer equations than its parameters: say so now
        lopts = replace(opts, level=choice.level)
        est, _, _ = level_start(nominal, at, lopts, ids, structures[choice.level])
        if not has_prior(est, opts):
            check_equations(count(est), to_data(fit, opts.pose, ids), fit.source, opts.pose)
    if first and opts.fixed:
        probes = [
            level_start(nominal, at, replace(opts, level=lv), ids, structures[lv])[0]
            for lv in levels
        ]
        check_patterns(opts.fixed, probes, ids)
    selection, fits = cross_validate(
        nominal, fit, opts, ids, before, levels, choice.folds, choice.seed, choice.rule,
        shared,
    )  # fmt: skip
    level = choice.level if choice.level != AUTO else selection.chosen
    return Pass(problem, opts, placed, start, before, selection, fits, level)
