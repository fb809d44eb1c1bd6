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
from .chart import LEVELS, Estimate, absorbed, count, names
from .identifiable import free_coordinates
from .measurements import Measurements
from .residuals import Data, model_poses, prefix_products
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
    "identify",
    "level_start",
    "solve_level",
]

Mat = NDArray[np.float64]

_WEIGHT_ROUNDS = 10  # variance-component rounds at most
_WEIGHT_SETTLED = 0.01  # ... stopping when their ratio changes by no more than this fraction


@dataclass(frozen=True)
class Fit:
    """A solved level: the solution, its statistics and the noise levels that weighed it."""

    solution: Solution
    stats: Statistics
    sigma_pos: float
    sigma_rot: float
    notes: tuple[str, ...] = ()


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


def solve_level(
    est: Estimate,
    data: Data,
    opts: FitOptions,
    size: float,
    reference: Estimate | None = None,
    noise: tuple[float, float] | None = None,
) -> Fit:
    """Solve ``est``'s level on ``data``, weighting as ``opts`` says (module docstring, step 3).

    ``noise`` is where the estimation of the noise levels starts (a previous fit's levels);
    ``reference`` is the prior's centre."""
    given = opts.noise_pos is not None
    notes: list[str] = []
    if given:
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
                f"the position noise given ({opts.noise_pos:.3g}) would weigh positions over "
                f"{1 / NOISE_RATIO:.0e} times rotations and drown them; weighted as {sp:.3g}"
            )
    else:
        sp, sr = noise if noise is not None else (1.0, 1.0 / size)
    prior = opts.prior if est.level.name != "base-tool" else None
    problem = Problem(data, sp, sr, prior, reference if prior is not None else None)
    if count(est) == 0:
        sol = Solution(est, 0, True, 0.0)
    else:
        sol = solve(est, problem, size, opts.max_iterations)
    rounds = 0
    while not given and sol.converged and rounds < _WEIGHT_ROUNDS:
        # variance components: without a prior only the ratio of the levels changes the
        # solution (and positions alone have none); with one, their size does too
        rounds += 1
        stats = statistics(sol.estimate, problem, exact=False)
        new_sp, new_sr = _components(data, stats, sp, sr)
        new_sp, new_sr = bounded_noise(new_sp, new_sr if opts.pose else sr, size)
        if prior is not None:
            settled = max(abs(new_sp / sp - 1.0), abs(new_sr / sr - 1.0)) <= _WEIGHT_SETTLED
        else:
            settled = not opts.pose or abs((new_sr / new_sp) / (sr / sp) - 1.0) <= _WEIGHT_SETTLED
        sp, sr = new_sp, new_sr
        problem = problem.with_noise(sp, sr)
        if settled or not count(est):
            break
        again = solve(sol.estimate, problem, size, opts.max_iterations)
        sol = replace(again, iterations=sol.iterations + again.iterations)
    stats = statistics(sol.estimate, problem)
    return Fit(sol, stats, sp, sr, tuple(notes))


def fit_before(
    nominal: PoeModel, fit: Measurements, opts: FitOptions, ids: list[int]
) -> tuple[Estimate, Fit]:
    """The start (the nominal placed by the rigid fit) and the ``base-tool`` level's fit."""
    start = start_estimate(nominal, placement(nominal, fit, opts, ids), opts, ids)
    data = to_data(fit, opts.pose, ids)
    check_equations(count(start), data, fit.source, opts.pose)
    base_opts = replace(opts, prior=None)
    return start, solve_level(start, data, base_opts, nominal.size())


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
    check_equations(count(est0), data, fit.source, opts.pose)
    if solved is not None:
        result = solved
    elif opts.level == "base-tool" and not opts.fixed_patterns:
        result = base_fit
    else:
        result = solve_level(est0, data, opts, size, est0, (base_fit.sigma_pos, base_fit.sigma_rot))
    est = result.solution.estimate
    notes = list(result.notes)
    device, markers_on_tool = _device_model(nominal, start, est, fit, opts, ids, notes)
    identified_points = (
        pose_points(model_poses(absorbed(est), fit.q), size)
        if opts.pose
        else _identified_points(absorbed(est), data)
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
        result.stats,
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
    if flat.home is not None:
        home = flat.home
        if est.keep_tool_axis:
            assert start.home is not None
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
        assert flat.markers is not None and start.markers is not None
        g = placement(nominal, fit, opts, ids)
        reference = (est.base_motion() @ g @ nominal.home)[:3, :3]  # the nominal's, placed
        home = fit_rigid(layout_points(opts, ids), flat.markers, reference)
        inv_home = inv(home)
        markers_on_tool = {
            k: inv_home[:3, :3] @ c + inv_home[:3, 3]
            for k, c in zip(ids, flat.markers, strict=True)
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


def _identified_points(est: Estimate, data: Data) -> Mat:
    assert est.markers is not None and data.marker_rows is not None
    last = prefix_products(est, data.q)[-1]
    c = est.markers[data.marker_rows]
    points: Mat = np.einsum("nij,nj->ni", last[:, :3, :3], c) + last[:, :3, 3]
    return points
