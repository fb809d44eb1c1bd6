"""Identification: nominal model + measurements -> identified POE model, with its statistics.

Steps (issue 15):

1. The start: the nominal model moved into the device frame by the rigid fit of its tool
   points (poses: origin and axis tips) to the measured ones (:func:`.frames.fit_rigid`).
2. Levenberg-Marquardt on the minimal chart (:mod:`.chart`, :mod:`.solver`), weighted by the
   noise levels: position residuals / ``sigma_p``, rotation residuals / ``sigma_r``, i.e.
   maximum likelihood for independent isotropic Gaussian noise. Given levels are used as they
   are; otherwise (poses) they are estimated from the residuals by variance components
   (Förstner 1979: ``sigma^2 = weighted sum of squares / redundancy`` for each kind, the
   redundancy being the kind's count minus its leverage), re-solving until they settle.
   Positions need no ratio: one level, estimated from the fit.
3. Statistics at the solution: numerical rank, condition number, per-parameter standard
   deviations ``sqrt(diag(s^2 (J^T W J)^-1))`` (:func:`.solver.statistics`).
4. The identified model in the device frame. For position measurements the tool frame is not
   observed (a marker point is): ``M`` is completed by fitting the marker layout (their
   nominal positions on the tool; the tool origin when there is one marker and no layout) to
   the identified marker points, the rotation the points leave free being kept from the
   nominal (all of it with one marker, the turn about the line with two). With ``frame =
   "nominal"`` the model is then expressed in the nominal's base frame
   (:func:`.frames.anchor_base`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..screws import PoeModel
from ..se3 import inv
from ..tolerances import NOISE_FLOOR, Tolerances
from .chart import Estimate, count, names
from .frames import anchor_base, fit_rigid, pose_points, tool_on_last_axis
from .measurements import Measurements
from .residuals import Data, model_poses, prefix_products
from .solver import Solution, Statistics, solve, statistics
from .start import Options, layout_points, moved, nominal_points, placement, start_estimate, to_data

__all__ = ["Identified", "identify"]

Mat = NDArray[np.float64]

_WEIGHT_ROUNDS = 4  # variance-component rounds at most
_WEIGHT_SETTLED = 0.05  # ... stopping when their ratio changes by no more than this fraction


@dataclass(frozen=True)
class Identified:
    """The result of :func:`identify`."""

    model: PoeModel  # identified, in the output frame
    device_model: PoeModel  # identified, in the device frame
    start: Estimate  # the nominal, placed in the device frame
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


def _components(
    est: Estimate, data: Data, stats: Statistics, sp: float, sr: float, size: float
) -> tuple[float, float]:
    """Variance-component estimates of the two noise levels (module docstring)."""
    res = stats.residuals.reshape(len(data), data.rows)
    lev = stats.leverage.reshape(len(data), data.rows)
    out = []
    for cols, sigma, floor in (
        (slice(0, 3), sp, NOISE_FLOOR * size),
        (slice(3, 6), sr, NOISE_FLOOR),
    ):
        redundancy = res[:, cols].size - float(lev[:, cols].sum())
        ss = float(np.sum(res[:, cols] ** 2)) * sigma * sigma
        out.append(max(math.sqrt(ss / redundancy) if redundancy > 0 else sigma, floor))
    return out[0], out[1]


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


def identify(
    nominal: PoeModel, fit: Measurements, opts: Options, ids: list[int] | None = None
) -> Identified:
    """Identify ``nominal``'s parameters from the measurements ``fit`` (module docstring).

    ``ids`` are the markers (default: those in ``fit``; the caller passes all of a file's when
    it holds some measurements out).

    Raises
    ------
    InputError
        Fewer residual equations than parameters.
    """
    ids = ids if ids is not None else fit.marker_ids()
    size = nominal.size()
    g = placement(nominal, fit, opts, ids)
    start = start_estimate(nominal, g, opts, ids)
    data = to_data(fit, opts.pose, ids)
    p, equations = count(start), len(data) * data.rows
    if equations < p:
        kind = "poses" if opts.pose else "positions"
        raise InputError(
            f"{fit.source}: {len(data)} {kind} give {equations} equations ({data.rows} each), "
            f"fewer than the {p} parameters to identify; measure at least "
            f"{math.ceil(p / data.rows)} {kind}"
        )
    given = opts.noise_pos is not None
    sp = max(opts.noise_pos or 0.0, NOISE_FLOOR * size) if given else 1.0
    sr = max(opts.noise_rot or 0.0, NOISE_FLOOR) if given else 1.0 / size
    sol = solve(start, data, sp, sr, size, opts.max_iterations)
    rounds = 0
    while not given and opts.pose and sol.converged and rounds < _WEIGHT_ROUNDS:
        # variance components: only the ratio of the levels changes the solution
        rounds += 1
        stats = statistics(sol.estimate, data, sp, sr, exact=False)
        new_sp, new_sr = _components(sol.estimate, data, stats, sp, sr, size)
        settled = abs((new_sr / new_sp) / (sr / sp) - 1.0) <= _WEIGHT_SETTLED
        sp, sr = new_sp, new_sr
        if settled:
            break
        again = solve(sol.estimate, data, sp, sr, size, opts.max_iterations)
        sol = replace(again, iterations=sol.iterations + again.iterations)
    stats = statistics(sol.estimate, data, sp, sr)
    if not given and not opts.pose:  # one kind of residual: its level is the fit's
        sp = max(sp * math.sqrt(stats.variance_factor), NOISE_FLOOR * size)
        stats = statistics(sol.estimate, data, sp, sr)
    est = sol.estimate
    notes: list[str] = []
    if est.home is not None:
        home = est.home
        if est.keep_tool_axis:
            assert start.home is not None
            home, snapped = tool_on_last_axis(
                start.joints[-1],
                start.home,
                est.joints[-1],
                home,
                opts.tol.parallel_angle,
                opts.tol.distance(size),
            )
            if snapped > opts.tol.report:
                notes.append(
                    f"the nominal's tool z is {snapped:.3g} rad from the last joint's "
                    "axis: --keep-tool-axis puts it on the axis"
                )
        markers_on_tool: dict[int, Mat] = {}
    else:
        assert est.markers is not None
        reference = (g @ nominal.home)[:3, :3]  # the nominal's tool rotation, placed
        home = fit_rigid(layout_points(opts, ids), est.markers, reference)
        inv_home = inv(home)
        markers_on_tool = {
            k: inv_home[:3, :3] @ c + inv_home[:3, 3] for k, c in zip(ids, est.markers, strict=True)
        }
    device = _output_model(nominal, est, home, fit.source, opts.tol)
    identified_points = (
        pose_points(model_poses(est, fit.q), size) if opts.pose else _identified_points(est, data)
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
        est,
        sol,
        stats,
        names(est, ids),
        sp,
        sr,
        given,
        inv(base),
        markers_on_tool,
        tuple(notes),
    )


def _identified_points(est: Estimate, data: Data) -> Mat:
    assert est.markers is not None and data.marker_rows is not None
    last = prefix_products(est, data.q)[-1]
    c = est.markers[data.marker_rows]
    return np.einsum("nij,nj->ni", last[:, :3, :3], c) + last[:, :3, 3]
