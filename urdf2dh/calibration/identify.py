"""Identification at one level: nominal model + measurements -> identified POE model, with its
statistics.

Steps:

1. The start: the nominal model moved into the device frame by the rigid fit of its tool
   points (poses: origin and axis tips) to the measured ones (:func:`.frames.fit_rigid`).
2. The ``base-tool`` level fitted from there (:mod:`.chart`): the nominal joints with base and
   tool fitted, the fair "before" of the calibration and the start of every other level (a
   start near the solution: the iterations then settle the joints, not the placement).
3. The level asked for, from that solution: Levenberg-Marquardt on its chart (:mod:`.solver`)
   over the coordinates that are free (:mod:`.identifiable`), weighted by the noise levels:
   position residuals / ``sigma_p``, rotation residuals / ``sigma_r``, i.e. maximum likelihood
   for independent isotropic Gaussian noise (with a prior, :mod:`.prior`, maximum a
   posteriori). Given levels are used as they are; otherwise (poses) they are estimated from
   the residuals by variance components (Förstner 1979: ``sigma^2 = weighted sum of squares /
   redundancy`` for each kind, the redundancy being the kind's count minus its leverage),
   re-solving until they settle. Positions need no ratio: one level, estimated from the fit.
   Either way neither kind is weighted more than ``1 / NOISE_RATIO`` times the other (rotation
   against position over the robot's size): exact rotations would otherwise drown every
   position in the weights, and the parameters only positions see would look undetermined.
4. Statistics at the solution: numerical rank, condition number, per-parameter standard
   deviations ``sqrt(diag(s^2 (J^T W J)^-1))`` (:func:`.solver.statistics`).
5. The identified model in the device frame, the joint offsets absorbed by the lines
   (:func:`.chart.absorbed`). For position measurements the tool frame is not observed (a
   marker point is): ``M`` is completed by fitting the marker layout (their nominal positions
   on the tool; the tool origin when there is one marker and no layout) to the identified
   marker points, the rotation the points leave free being kept from the nominal (all of it
   with one marker, the turn about the line with two). With ``frame = "nominal"`` the model is
   then expressed in the nominal's base frame (:func:`.frames.anchor_base`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..geometry.se3 import inv
from ..model.poe import PoeModel
from ..tolerances import NOISE_FLOOR, NOISE_RATIO, Tolerances
from .chart import FRAME, Estimate, absorbed, count, names, retract
from .evidence import linearised, maximise
from .identifiable import free_coordinates
from .levels import BASE_TOOL, LEVELS
from .measurements import Measurements
from .prior import AUTO, NONE, Deviations, LinkErrors, Prior, Regulariser, link_errors
from .residuals import Data, evaluate, model_poses, modelled_points
from .rigid import anchor_base, fit_rigid, pose_points, tool_on_last_axis
from .solver import Problem, Solution, Statistics, solve, statistics
from .start import (
    FitOptions,
    layout_points,
    moved,
    nominal_points,
    placement,
    start_estimate,
    to_data,
)

__all__ = [
    "Fit",
    "Identified",
    "check_equations",
    "fit_before",
    "has_prior",
    "identify",
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
    """A solved level: the solution, the noise levels and the prior that weighed it, and its
    statistics (``None`` until asked for: :func:`with_statistics`)."""

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
        assert self.stats is not None, "the fit's statistics were not computed"
        return self.stats


def with_statistics(fit: Fit, data: Data) -> Fit:
    """``fit`` with its statistics (:func:`.solver.statistics`) at its solution on ``data``."""
    if fit.stats is not None:
        return fit
    return replace(fit, stats=statistics(fit.solution.estimate, fit.problem(data)))


@dataclass(frozen=True)
class Identified:
    """The result of :func:`identify`."""

    model: PoeModel  # identified, in the output frame
    device_model: PoeModel  # identified, in the device frame
    start: Estimate  # the nominal, placed in the device frame by the rigid fit
    before: Estimate  # the base-tool level's solution
    estimate: Estimate
    solution: Solution
    stats: Statistics
    names: list[str]
    sigma_pos: float
    sigma_rot: float
    noise_given: bool
    base_in_device: Mat  # pose of the nominal's base frame in the device frame
    markers_on_tool: dict[int, Mat] = field(default_factory=dict)
    notes: tuple[str, ...] = ()  # judgements made (reported as warnings)
    carried: tuple[str, ...] = ()  # held fixed: the level's other coordinates carry them
    fixed: tuple[str, ...] = ()  # held fixed by name

    @property
    def level(self) -> str:
        return self.estimate.level.name


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


def bounded_noise(sp: float, sr: float, size: float) -> tuple[float, float]:
    """The noise levels raised to the floors (module docstring): each above round-off, and
    neither kind weighted more than ``1 / NOISE_RATIO`` times the other."""
    sp, sr = max(sp, NOISE_FLOOR * size), max(sr, NOISE_FLOOR)
    return max(sp, NOISE_RATIO * sr * size), max(sr, NOISE_RATIO * sp / size)


def _given_noise(opts: FitOptions, size: float, notes: list[str]) -> tuple[float, float]:
    """The noise levels given, raised to the floors, with a note where they were raised."""
    assert opts.noise_pos is not None
    sp, sr = bounded_noise(opts.noise_pos, opts.noise_rot or opts.noise_pos / size, size)
    if opts.pose and opts.noise_rot is not None and sr > opts.noise_rot:
        notes.append(
            f"the rotation noise given ({opts.noise_rot:.3g} rad) would weigh rotations "
            f"over {1 / NOISE_RATIO:.0e} times positions and drown them; weighted as "
            f"{sr:.3g} rad"
        )
    if opts.pose and sp > opts.noise_pos:
        notes.append(
            f"the position noise given would weigh positions over {1 / NOISE_RATIO:.0e} times "
            f"rotations and drown them; weighted as {sp / opts.noise_pos:.3g} times it"
        )
    return sp, sr


def has_prior(est: Estimate, opts: FitOptions) -> bool:
    """Whether ``est``'s level is fitted with a prior (:func:`prior_of`)."""
    if est.level == BASE_TOOL or opts.prior == NONE:
        return False
    return opts.prior != AUTO or est.level.lines


def prior_of(
    est: Estimate, opts: FitOptions, reference: Estimate | None, locations: Mat | None
) -> tuple[LinkErrors | None, Deviations | None]:
    """The level's link errors (:mod:`.prior`) and the stated deviations (``None``: to be
    estimated), or ``(None, None)`` when the level has no prior: the base-tool level, ``none``,
    and with ``auto`` the offsets level (zero settings that the measurements see directly)."""
    if not has_prior(est, opts):
        return None, None
    assert reference is not None and locations is not None
    errors = link_errors(reference, locations)
    if errors is None or opts.prior == AUTO:
        return errors, None
    assert isinstance(opts.prior, Prior)
    return errors, Deviations.stated(opts.prior, errors.links)


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
) -> Fit:
    """Solve ``est``'s level on ``data``, weighting as ``opts`` says (module docstring, step 3).

    ``noise`` is where the estimation of the noise levels starts (a previous fit's levels);
    ``reference`` is the prior's centre and ``locations`` ``(n, 3)`` the joints' locations in
    the device frame (:func:`joint_locations`), for a level with a prior; ``deviations``,
    where their estimate starts (a simpler level's: nested levels continue from there);
    ``stats``: whether to compute the solution's statistics (:func:`with_statistics`)."""
    notes: list[str] = []
    given = opts.noise_pos is not None
    sp, sr = (
        _given_noise(opts, size, notes)
        if given
        else (noise if noise is not None else (1.0, 1.0 / size))
    )
    errors, stated = prior_of(est, opts, reference, locations)
    if errors is not None and stated is None:
        fit = _solve_with_evidence(est, data, opts, size, errors, (sp, sr), deviations, notes)
        return with_statistics(fit, data) if stats else fit
    prior = None if errors is None or stated is None else Regulariser.of(errors, stated)
    problem = Problem(data, sp, sr, prior)
    floors = (NOISE_FLOOR * size, NOISE_FLOOR)
    if count(est) == 0:
        sol = Solution(est, 0, True, 0.0)
    else:
        sol = solve(est, problem, size, opts.max_iterations)
    rounds = 0
    step = np.zeros(0)
    while not given and sol.converged and count(est) and rounds < _WEIGHT_ROUNDS:
        rounds += 1
        if prior is None and opts.pose:  # only their ratio matters: that of greatest evidence
            r0, jac = evaluate(sol.estimate, data, 1.0, 1.0)
            found, _, step = maximise(linearised(r0, jac, data.rows), (sp, sr), np.zeros(0), floors)
            new_sp, new_sr = bounded_noise(found[0], found[1], size)
            settled = abs((new_sr / new_sp) / (sr / sp) - 1.0) <= _WEIGHT_SETTLED
        else:  # variance components (positions alone: the level of the residuals, once)
            at = statistics(sol.estimate, problem, exact=False)
            new_sp, new_sr = _components(data, at, sp, sr)
            new_sp, new_sr = bounded_noise(new_sp, new_sr if opts.pose else sr, size)
            settled = prior is None or (
                max(abs(new_sp / sp - 1.0), abs(new_sr / sr - 1.0)) <= _WEIGHT_SETTLED
            )
        sp, sr = new_sp, new_sr
        problem = problem.with_noise(sp, sr)
        if settled:
            break
        again = solve(_stepped(sol.estimate, step, problem), problem, size, opts.max_iterations)
        sol = replace(again, iterations=sol.iterations + again.iterations)
    fit = Fit(sol, None, sp, sr, tuple(notes), prior)
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
    sol = Solution(est, 0, True, 0.0)
    if deviations is None:
        deviations = Deviations.of_groups(weak, errors.links, size)
    values = deviations.groups()
    if len(values) != len(weak):  # a simpler level's: its links and offsets, weak scales
        values = np.append(values[: errors.links + 1], _DEVIATION_START)
    parts = errors.parts(size)
    problem = Problem(data, sp, sr)
    for _ in range(_EVIDENCE_ROUNDS):
        r0, jac = evaluate(sol.estimate, data, 1.0, 1.0)
        here = (errors, errors.tangent(sol.estimate), errors.deviations(sol.estimate), parts)
        lin = linearised(r0, jac, data.rows, here)
        levels = (sp, sr) if opts.pose else (sp,)
        floors = levels if given else (NOISE_FLOOR * size, NOISE_FLOOR)[: len(levels)]
        found, estimated, step = maximise(lin, levels, values[present], floors)
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
        again = solve(_stepped(sol.estimate, step, problem), problem, size, opts.max_iterations)
        sol = replace(again, iterations=sol.iterations + again.iterations)
        if not sol.converged:
            break
    return Fit(sol, None, sp, sr, tuple(notes), problem.prior)


def _stepped(est: Estimate, step: Mat, problem: Problem) -> Estimate:
    """``est`` moved by the linearised model's ``step`` (:func:`.evidence.maximise`) when that
    lowers ``problem``'s cost: the solve then starts next to its solution."""
    if not len(step) or len(step) != count(est):
        return est
    moved = retract(est, step)
    before = problem.residuals(est)
    after = problem.residuals(moved)
    return moved if float(after @ after) < float(before @ before) else est


def fit_before(
    nominal: PoeModel, fit: Measurements, opts: FitOptions, ids: list[int]
) -> tuple[Estimate, Fit]:
    """The start (the nominal placed by the rigid fit) and the ``base-tool`` level's fit."""
    start = start_estimate(nominal, placement(nominal, fit, opts, ids), opts, ids)
    data = to_data(fit, opts.pose, ids)
    check_equations(count(start), data, fit.source, opts.pose)
    base_opts = replace(opts, prior=NONE)
    return start, solve_level(start, data, base_opts, nominal.size())


def joint_locations(
    nominal: PoeModel, fit: Measurements, opts: FitOptions, ids: list[int], before: Estimate
) -> Mat:
    """``(n, 3)`` each joint's location in the device frame: the nominal's joint points (the
    joint origins of a URDF; a point of the line where none is given) as the rigid fit and the
    base-and-tool fit placed them."""
    g = before.base_motion() @ placement(nominal, fit, opts, ids)
    chain = start_estimate(nominal, np.eye(4), opts, ids).chain
    points = np.array(
        [
            j.point if j.point is not None else c
            for j, c in zip(nominal.joints, chain.point, strict=True)
        ]
    )
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
    every = names(est, ids)
    fixed = [n for n, f in zip(every, free, strict=True) if not f and n not in carried]
    return replace(est, free=free), carried, fixed


def identify(
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int] | None = None,
    before: tuple[Estimate, Fit] | None = None,
    solved: Fit | None = None,
) -> Identified:
    """Identify ``nominal``'s parameters at ``opts.level`` from the measurements ``fit``
    (module docstring).

    ``ids`` are the markers (default: those in ``fit``; the caller passes all of a file's when
    it holds some measurements out). ``before`` is :func:`fit_before`'s result and ``solved``
    the level's fit, when the caller has them already.

    Raises
    ------
    InputError
        Fewer residual equations than parameters.
    """
    ids = ids if ids is not None else fit.marker_ids()
    size = nominal.size()
    start, base_fit = before if before is not None else fit_before(nominal, fit, opts, ids)
    before_est = base_fit.solution.estimate
    data = to_data(fit, opts.pose, ids)
    est0, carried, fixed = level_start(nominal, before_est, opts, ids)
    if not has_prior(est0, opts):
        check_equations(count(est0), data, fit.source, opts.pose)
    if solved is not None:
        result = with_statistics(solved, data)
    elif opts.level == BASE_TOOL.name and not opts.fixed_patterns:
        result = base_fit
    else:
        noise = (base_fit.sigma_pos, base_fit.sigma_rot)
        where = joint_locations(nominal, fit, opts, ids, before_est)
        result = solve_level(est0, data, opts, size, est0, noise, where)
    est = result.solution.estimate
    notes = list(result.notes)
    device, markers_on_tool = _device_model(nominal, start, est, fit, opts, ids, notes)
    identified_points = (
        pose_points(model_poses(absorbed(est), fit.q), size)
        if opts.pose
        else modelled_points(absorbed(est), data)
    )
    nominal_pts = nominal_points(nominal, fit, opts, ids)
    if nominal.n:
        base = anchor_base(device.joints[0], nominal.joints[0], identified_points, nominal_pts)
    else:  # no joint axis to anchor on: the rigid fit alone
        base = fit_rigid(identified_points, nominal_pts)
    model = device
    if opts.frame == "nominal":
        model = PoeModel(
            moved(device.joints, base),
            base @ device.home,
            device.name,
            device.source,
            nominal.base_link,
            device.tip_link,
            device.length_unit,
        )
    return Identified(
        model,
        device,
        start,
        before_est,
        est,
        result.solution,
        result.statistics,
        names(est, ids),
        result.sigma_pos,
        result.sigma_rot,
        opts.noise_pos is not None,
        inv(base),
        markers_on_tool,
        tuple(notes),
        tuple(carried),
        tuple(fixed),
    )


def _device_model(
    nominal: PoeModel,
    start: Estimate,
    est: Estimate,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    notes: list[str],
) -> tuple[PoeModel, dict[int, Mat]]:
    """The identified model in the device frame (step 5) and the markers on its tool."""
    size = nominal.size()
    flat = absorbed(est)
    markers_on_tool: dict[int, Mat] = {}
    if est.tool == FRAME:
        home = flat.home
        if est.keep_tool_axis:
            home, snapped = tool_on_last_axis(
                start.joints[-1],
                start.home,
                flat.joints[-1],
                home,
                opts.tol.parallel_angle,
                opts.tol.distance(size),
            )
            if snapped > opts.tol.report:
                notes.append(
                    f"the nominal's tool z is {snapped:.3g} rad from the last joint's "
                    "axis: --keep-tool-axis puts it on the axis"
                )
    else:
        g = placement(nominal, fit, opts, ids)
        reference = (est.base_motion() @ g @ nominal.home)[:3, :3]  # the nominal's, placed
        points = flat.device_markers()
        home = fit_rigid(layout_points(opts, ids), points, reference)
        inv_home = inv(home)
        markers_on_tool = {
            k: inv_home[:3, :3] @ c + inv_home[:3, 3] for k, c in zip(ids, points, strict=True)
        }
    return _output_model(nominal, flat, home, fit.source, opts.tol), markers_on_tool


def _output_model(
    nominal: PoeModel, est: Estimate, home: Mat, source: str, tol: Tolerances
) -> PoeModel:
    joints = []
    for j in est.joints:
        # revolute again when the identified pitch is round-off: its advance over a radian is
        # below float noise of the robot's size
        if j.kind == "helical" and abs(j.pitch) <= tol.noise * nominal.size():
            j = replace(j, kind="revolute", pitch=0.0)
        joints.append(j)
    return PoeModel(
        tuple(joints),
        home,
        f"{nominal.name}-calibrated",
        source,
        "device",
        nominal.tip_link,
        nominal.length_unit,
    )
