"""One level's fit: Levenberg-Marquardt on its chart (:mod:`.solver`) over the coordinates that
are free (:mod:`.identifiable`), weighted by the noise levels, with its prior (:mod:`.prior`).

1. The start: the nominal model moved into the device frame by the rigid fit of its tool
   points (poses: origin and axis tips) to the measured ones (:func:`.rigid.fit_rigid`).
2. The ``base-tool`` level fitted from there (:mod:`.chart`): the nominal joints with base and
   tool fitted, the fair "before" of the calibration and the start of every other level (a
   start near the solution: the iterations then settle the joints, not the placement).
3. A level from a simpler one's solution: position residuals / ``sigma_p``, rotation residuals
   / ``sigma_r``, i.e. maximum likelihood for independent isotropic Gaussian noise (with a
   prior, maximum a posteriori). Given levels are used as they are; otherwise (poses) they are
   estimated from the residuals by variance components (Förstner 1979: ``sigma^2 = weighted
   sum of squares / redundancy`` for each kind, the redundancy being the kind's count minus
   its leverage), re-solving until they settle. Positions need no ratio: one level, estimated
   from the fit. Either way neither kind is weighted more than ``1 / NOISE_RATIO`` times the
   other (:func:`.start.bounded_noise`). With the prior's deviations estimated (``auto``), they
   and the noise levels are those of greatest evidence (:mod:`.evidence`), found at a
   linearisation and the level solved with them, again from each new solution until none
   changes by more than :data:`_EVIDENCE_SETTLED` in log.
4. Statistics at the solution, from its linearisation: numerical rank, condition number,
   per-parameter standard deviations ``sqrt(diag(s^2 (J^T W J)^-1))``
   (:func:`.solver.statistics`).

Each solve starts from the linearisation its predecessor ended with, and the linearised
model's solution is tried as its first step (:func:`.solver.solve`): the model is evaluated
once per step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..model.poe import PoeModel
from ..tolerances import NOISE_FLOOR
from .chart import Estimate, all_names, count
from .evidence import linearised, maximise
from .identifiable import free_coordinates
from .levels import LEVELS
from .measurements import Measurements
from .prior import NONE, Deviations, LinkErrors, Regulariser
from .residuals import Data
from .solver import Linearisation, Problem, Solution, Statistics, solve, statistics
from .start import (
    FitOptions,
    bounded_noise,
    given_noise,
    placement,
    prior_of,
    start_estimate,
    to_data,
)

__all__ = [
    "Fit",
    "check_equations",
    "fit_before",
    "joint_locations",
    "level_start",
    "solve_level",
    "with_statistics",
]

Mat = NDArray[np.float64]

_WEIGHT_ROUNDS = 10  # variance-component rounds at most
_WEIGHT_SETTLED = 0.01  # ... stopping when their ratio changes by no more than this fraction
_EVIDENCE_ROUNDS = 5  # rounds of the deviations' estimate at most (each from a new solution)
_EVIDENCE_SETTLED = 0.05  # ... stopping when no estimate changes by more than this (in log)
_DEVIATION_START = 0.1  # rad (and x the robot's size): a prior too weak to pull: the search's start
_DEVIATION_NEGLIGIBLE = 1e-6  # rad: deviations below this count as this in the settling test


@dataclass(frozen=True)
class Fit:
    """A solved level: the solution (with its linearisation), the noise levels and the prior
    that weighed it, and its statistics (``None`` until asked for: :func:`with_statistics`)."""

    solution: Solution
    stats: Statistics | None
    sigma_pos: float
    sigma_rot: float
    notes: tuple[str, ...] = ()
    prior: Regulariser | None = None

    def problem(self, data: Data) -> Problem:
        """What the fit minimised, on ``data``."""
        return Problem(data, self.sigma_pos, self.sigma_rot, self.prior)

    @property
    def statistics(self) -> Statistics:
        if self.stats is None:
            raise ValueError("the fit's statistics were not computed (with_statistics)")
        return self.stats


def with_statistics(fit: Fit, data: Data) -> Fit:
    """``fit`` with its statistics (:func:`.solver.statistics`) at its solution on ``data``."""
    if fit.stats is not None:
        return fit
    return replace(fit, stats=statistics(fit.solution.lin, fit.problem(data)))


def _components(data: Data, stats: Statistics, sp: float, sr: float) -> tuple[float, float]:
    """Variance-component estimates of the two noise levels (module docstring)."""
    m = len(data) * data.rows
    res = stats.residuals[:m].reshape(len(data), data.rows)
    lev = stats.leverage[:m].reshape(len(data), data.rows)
    out = []
    for cols, sigma in ((slice(0, 3), sp), (slice(3, 6), sr)):
        redundancy = res[:, cols].size - float(lev[:, cols].sum())
        ss = float(np.sum(res[:, cols] ** 2)) * sigma * sigma
        out.append(math.sqrt(ss / redundancy) if redundancy > 0 else sigma)
    return out[0], out[1]


def solve_level(
    est: Estimate,
    data: Data,
    opts: FitOptions,
    size: float,
    reference: Estimate | None = None,
    noise: tuple[float, float] | None = None,
    locations: Mat | None = None,
    deviations: Deviations | None = None,
    stats: bool = True,
    prior: tuple[LinkErrors | None, Deviations | None] | None = None,
) -> Fit:
    """Solve ``est``'s level on ``data``, weighting as ``opts`` says (module docstring, step 3).

    ``noise`` is where the estimation of the noise levels starts (a previous fit's levels);
    ``reference`` is the prior's centre and ``locations`` ``(n, 3)`` the joints' locations in
    the device frame (:func:`joint_locations`), for a level with a prior; ``deviations``,
    where their estimate starts (a simpler level's: nested levels continue from there);
    ``stats``: whether to compute the solution's statistics (:func:`with_statistics`);
    ``prior``: :func:`.start.prior_of` of ``est``, ``reference`` and ``locations``, when the
    caller found it already."""
    notes: list[str] = []
    given = opts.noise_pos is not None
    sp, sr = (
        given_noise(opts, size, notes)
        if given
        else (noise if noise is not None else (1.0, 1.0 / size))
    )
    errors, stated = prior_of(est, opts, reference, locations) if prior is None else prior
    if errors is not None and stated is None:
        fit = _solve_with_evidence(est, data, opts, size, errors, (sp, sr), deviations, notes)
        return with_statistics(fit, data) if stats else fit
    rows = None if errors is None or stated is None else Regulariser.of(errors, stated)
    problem = Problem(data, sp, sr, rows)
    floors = (NOISE_FLOOR * size, NOISE_FLOOR)
    if count(est) == 0:
        lin = problem.linearise(est)
        sol = Solution(est, 0, True, math.sqrt(problem.cost(lin)), lin)
    else:
        sol = solve(est, problem, size, opts.max_iterations)
    rounds = 0
    step = np.zeros(0)
    while not given and sol.converged and count(est) and rounds < _WEIGHT_ROUNDS:
        rounds += 1
        if rows is None and opts.pose:  # only their ratio matters: that of greatest evidence
            lin = sol.lin
            found, _, step = maximise(
                linearised(lin.residuals, lin.jacobian, data.rows), (sp, sr), np.zeros(0), floors
            )
            new_sp, new_sr = bounded_noise(found[0], found[1], size)
            settled = abs((new_sr / new_sp) / (sr / sp) - 1.0) <= _WEIGHT_SETTLED
        else:  # variance components (positions alone: the level of the residuals, once)
            at = statistics(sol.lin, problem, exact=False)
            new_sp, new_sr = _components(data, at, sp, sr)
            new_sp, new_sr = bounded_noise(new_sp, new_sr if opts.pose else sr, size)
            settled = rows is None or (
                max(abs(new_sp / sp - 1.0), abs(new_sr / sr - 1.0)) <= _WEIGHT_SETTLED
            )
        sp, sr = new_sp, new_sr
        problem = problem.with_noise(sp, sr)
        if settled:
            break
        again = solve(sol.estimate, problem, size, opts.max_iterations, lin=sol.lin, first=step)
        sol = replace(again, iterations=sol.iterations + again.iterations)
    fit = Fit(sol, None, sp, sr, tuple(notes), rows)
    return with_statistics(fit, data) if stats else fit


def _solve_with_evidence(
    est: Estimate,
    data: Data,
    opts: FitOptions,
    size: float,
    errors: LinkErrors,
    noise: tuple[float, float],
    deviations: Deviations | None,
    notes: list[str],
) -> Fit:
    """Solve with the deviations (and, unless given, the noise levels) of greatest evidence
    (:mod:`.evidence`): estimated at a linearisation at ``est`` (their search starting from a
    prior too weak to pull, or from ``deviations``, a simpler level's), the level solved with
    them from the linearised model's solution, and again from the new solution until no
    estimate changes by more than :data:`_EVIDENCE_SETTLED` (the solution at the previous
    estimates then stands)."""
    given = opts.noise_pos is not None
    sp, sr = noise
    present = errors.present()
    weak = np.full(errors.links + 2, _DEVIATION_START)
    lin = Linearisation.at(est, data, errors)
    sol = Solution(est, 0, True, 0.0, lin)
    if deviations is None:
        deviations = Deviations.of_groups(weak, errors.links, size)
    values = deviations.groups()
    if len(values) != len(weak):  # a simpler level's: its links and offsets, weak scales
        values = np.append(values[: errors.links + 1], _DEVIATION_START)
    parts = errors.parts(size)
    problem = Problem(data, sp, sr)
    for _ in range(_EVIDENCE_ROUNDS):
        lin = sol.lin
        coordinates, tangent = errors.evaluate(lin.estimate) if lin.prior is None else lin.prior
        here = (errors, tangent, coordinates, parts)
        lin_ev = linearised(lin.residuals, lin.jacobian, data.rows, here)
        levels = (sp, sr) if opts.pose else (sp,)
        floors = levels if given else (NOISE_FLOOR * size, NOISE_FLOOR)[: len(levels)]
        found, estimated, step = maximise(lin_ev, levels, values[present], floors)
        new_sp, new_sr = (found[0], found[1]) if opts.pose else (found[0], sr)
        if not given:
            new_sp, new_sr = bounded_noise(new_sp, new_sr, size)
        else:  # as given (the search returns them through exp(log(.)))
            new_sp, new_sr = sp, sr
        new_values = values.copy()
        new_values[present] = estimated
        floor = _DEVIATION_NEGLIGIBLE
        change = max(
            float(
                np.max(
                    np.abs(
                        np.log(
                            np.maximum(new_values[present], floor)
                            / np.maximum(values[present], floor)
                        )
                    )
                )
            ),
            abs(math.log(new_sp / sp)),
            abs(math.log(new_sr / sr)),
        )
        if change <= _EVIDENCE_SETTLED and problem.prior is not None:
            break  # the solution at the previous estimates stands
        sp, sr, values = new_sp, new_sr, new_values
        deviations = Deviations.of_groups(values, errors.links, size)
        problem = Problem(data, sp, sr, Regulariser.of(errors, deviations))
        again = solve(sol.estimate, problem, size, opts.max_iterations, lin=lin, first=step)
        sol = replace(again, iterations=sol.iterations + again.iterations)
        if not sol.converged:
            break
    return Fit(sol, None, sp, sr, tuple(notes), problem.prior)


def fit_before(
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    placed: Mat | None = None,
) -> tuple[Estimate, Fit]:
    """The start (the nominal placed by the rigid fit, ``placed`` when the caller has it:
    :func:`.start.placement`) and the ``base-tool`` level's fit (its statistics not computed:
    :func:`with_statistics`)."""
    g = placement(nominal, fit, opts, ids) if placed is None else placed
    start = start_estimate(nominal, g, opts, ids)
    data = to_data(fit, opts.pose, ids)
    check_equations(count(start), data, fit.source, opts.pose)
    base_opts = replace(opts, prior=NONE)
    return start, solve_level(start, data, base_opts, nominal.size(), stats=False)


def joint_locations(
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    before: Estimate,
    placed: Mat | None = None,
) -> Mat:
    """``(n, 3)`` each joint's location in the device frame: the nominal's joint points (the
    joint origins of a URDF; a point of the line where none is given) as the rigid fit
    (``placed``, when the caller has it: :func:`.start.placement`) and the base-and-tool fit
    placed them."""
    g = before.base_motion() @ (placement(nominal, fit, opts, ids) if placed is None else placed)
    given = [j.point for j in nominal.joints]
    if any(p is None for p in given):
        line = start_estimate(nominal, np.eye(4), opts, ids).chain.point
        given = [c if p is None else p for p, c in zip(given, line, strict=True)]
    points = np.array(given)
    return points @ g[:3, :3].T + g[:3, 3]


def check_equations(p: int, data: Data, source: str, pose: bool) -> None:
    equations = len(data) * data.rows
    if equations < p:
        kind = "poses" if pose else "positions"
        raise InputError(
            f"{source}: {len(data)} {kind} give {equations} equations ({data.rows} each), "
            f"fewer than the {p} parameters to identify; measure at least "
            f"{math.ceil(p / data.rows)} {kind}"
        )


def level_start(
    nominal: PoeModel,
    before: Estimate,
    opts: FitOptions,
    ids: list[int],
    structure: NDArray[np.bool_] | None = None,
) -> tuple[Estimate, list[str], list[str]]:
    """The start of ``opts.level`` (the base-tool solution) with its free coordinates, the
    coordinates the others carry and those fixed by name. ``structure``: the coordinates the
    others carry, when found already (:func:`.identifiable.redundant`)."""
    level = LEVELS[opts.level]
    est = before.with_level(level)  # helical joints are so from the start on
    free, carried = free_coordinates(
        est, opts.fixed_patterns, nominal.limits(), nominal.size(), ids, structure
    )
    every = all_names(est, ids)  # est.free is None: every coordinate's
    fixed = [n for n, f in zip(every, free, strict=True) if not f and n not in carried]
    return replace(est, free=free), carried, fixed
