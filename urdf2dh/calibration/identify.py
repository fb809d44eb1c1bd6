"""Identification at one level: nominal model + measurements -> identified POE model, with its
statistics: the level fitted (:mod:`.fit`: the start, the base-and-tool fit, the level from
it), then made a model.

The identified model in the device frame has the joint offsets absorbed by the lines
(:func:`.chart.absorbed`). For position measurements the tool frame is not observed (a marker
point is): ``M`` is completed by fitting the marker layout (their nominal positions on the
tool; the tool origin when there is one marker and no layout) to the identified marker points,
the rotation the points leave free being kept from the nominal (all of it with one marker, the
turn about the line with two). With ``frame = "nominal"`` the model is then expressed in the
nominal's base frame (:func:`.rigid.anchor_base`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from ..geometry.se3 import inv
from ..model.poe import PoeModel
from ..tolerances import Tolerances
from .chart import FRAME, Estimate, absorbed, count, names
from .fit import (
    Fit,
    check_equations,
    fit_before,
    joint_locations,
    level_start,
    solve_level,
    with_statistics,
)
from .levels import BASE_TOOL
from .measurements import Measurements
from .residuals import model_poses, modelled_points
from .rigid import anchor_base, fit_rigid, pose_points, tool_on_last_axis
from .solver import Solution, Statistics
from .start import (
    FitOptions,
    has_prior,
    layout_points,
    moved,
    nominal_points,
    placement,
    to_data,
)

__all__ = ["Identified", "identify", "moved"]

Mat = NDArray[np.float64]


@dataclass(frozen=True)
class Identified:
    """The result of :func:`identify`."""

    model: PoeModel  # identified, in the output frame
    device_model: PoeModel  # identified, in the device frame
    start: Estimate  # the nominal, placed in the device frame by the rigid fit
    before: Estimate  # the base-tool level's solution
    estimate: Estimate
    flat: Estimate  # the estimate with its offsets absorbed (:func:`.chart.absorbed`)
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


def identify(
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int] | None = None,
    before: tuple[Estimate, Fit] | None = None,
    solved: Fit | None = None,
    placed: Mat | None = None,
) -> Identified:
    """Identify ``nominal``'s parameters at ``opts.level`` from the measurements ``fit``
    (module docstring).

    ``ids`` are the markers (default: those in ``fit``; the caller passes all of a file's when
    it holds some measurements out). ``before`` is :func:`fit_before`'s result, ``solved``
    the level's fit and ``placed`` the rigid fit (:func:`.start.placement`), when the caller
    has them already.

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
    # what the solved level did not move: the coordinates its others carry, or fixed by name
    # (fixed ones among the carried are named fixed all the same)
    solved_free = None if solved is None else solved.solution.estimate.free
    est0, carried, fixed = level_start(
        nominal, before_est, opts, ids, None if solved_free is None else ~solved_free
    )
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
    flat = absorbed(est)
    notes = list(result.notes)
    device, markers_on_tool = _device_model(
        nominal, start, est, flat, fit, opts, ids, notes, placed
    )
    identified_points = (
        pose_points(model_poses(flat, fit.q), size) if opts.pose else modelled_points(flat, data)
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
        flat,
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
    flat: Estimate,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    notes: list[str],
    placed: Mat | None = None,
) -> tuple[PoeModel, dict[int, Mat]]:
    """The identified model in the device frame (step 5) and the markers on its tool
    (``flat``: ``est`` with its offsets absorbed, :func:`.chart.absorbed`; ``placed``: the
    rigid fit, when the caller has it: :func:`.start.placement`)."""
    size = nominal.size()
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
        g = placement(nominal, fit, opts, ids) if placed is None else placed
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
