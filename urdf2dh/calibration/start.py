"""The options of an identification and its start: the nominal placed in the device frame.

The start is the nominal model moved by the rigid transform that best fits its tool points to
the measured ones (:func:`.rigid.fit_rigid`; for poses, each pose's origin and axis tips at the
robot's size, so orientations count too; for positions, the markers' points, placed on the tool
by the marker layout, or at the tool origin), at the ``base-tool`` level (:mod:`.chart`): the
identification fits that level first, and starts every other from its solution. Revolute joints
named in ``helical`` (or all) start as helical joints of pitch 0, so that their pitch is
identified.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ..errors import UsageError, choices, shown
from ..geometry.lie import rotation_of
from ..model.poe import Joint, PoeModel
from ..tolerances import DEFAULT, NOISE_FLOOR, NOISE_RATIO, Tolerances
from .chart import Estimate, line_point
from .levels import BASE_TOOL, FULL, check_level
from .measurements import Measurements
from .prior import AUTO, CHOICES, NONE, Deviations, LinkErrors, Prior, link_errors
from .residuals import Data
from .rigid import fit_rigid, pose_points

__all__ = [
    "FitOptions",
    "bounded_noise",
    "given_noise",
    "has_prior",
    "layout_points",
    "moved",
    "nominal_points",
    "placement",
    "prior_of",
    "start_estimate",
    "to_data",
]

Mat = NDArray[np.float64]


MAX_ITERATIONS = 200  # Levenberg-Marquardt iterations of one solve at most: a safety net


@dataclass(frozen=True, slots=True)
class FitOptions:
    """What to identify and how (the ``calibrate`` command's options).

    Attributes
    ----------
    pose
        Pose measurements (else positions).
    level
        The level identified (:data:`.levels.LEVELS`).
    fixed
        Parameters held at the nominal's values: names or shell-style patterns
        (``*.scale``, ``arm_7_joint.*``).
    prior
        The prior (:mod:`.prior`): stated deviations, ``auto`` (estimated at the geometry and
        full levels) or ``none``.
    helical
        Revolute joints whose pitch is identified too (``("all",)`` for every one).
    keep_scale
        The nominal's joint scales are kept (the same as fixing ``*.scale``).
    keep_tool_axis
        The tool keeps its placement relative to the last joint's line.
    frame
        ``device`` or ``nominal``: the frame of the output model.
    noise_pos, noise_rot
        Noise levels that weigh the residuals (``None``: estimated).
    layout
        The markers' nominal positions on the tool.
    max_iterations
        Iterations of one solve at most.
    tol
        The tolerances.
    """

    pose: bool = True
    level: str = FULL.name
    fixed: tuple[str, ...] = ()
    prior: Prior | str = NONE
    helical: tuple[str, ...] = ()
    keep_scale: bool = False
    keep_tool_axis: bool = False
    frame: str = "device"
    noise_pos: float | None = None
    noise_rot: float | None = None
    layout: dict[int, Mat] | None = None
    max_iterations: int = MAX_ITERATIONS
    tol: Tolerances = DEFAULT

    def __post_init__(self) -> None:
        if self.frame not in ("device", "nominal"):
            raise UsageError(f"frame must be device or nominal, not {shown(self.frame)}")
        check_level(self.level, "FitOptions")
        if not isinstance(self.prior, Prior) and self.prior not in CHOICES:
            raise UsageError(
                f"unknown prior {shown(str(self.prior))}; valid: {choices(CHOICES)} or a Prior"
            )
        if self.pose and (self.noise_pos is None) != (self.noise_rot is None):
            raise UsageError("give both noise levels (position and rotation) or neither")

    @property
    def fixed_patterns(self) -> tuple[str, ...]:
        """The fixed parameters' patterns, the scales' with ``keep_scale``."""
        return (*self.fixed, "*.scale") if self.keep_scale else self.fixed


def bounded_noise(sp: float, sr: float, size: float) -> tuple[float, float]:
    """The noise levels raised to the floors (module docstring): each above round-off, and
    neither kind weighted more than ``1 / NOISE_RATIO`` times the other."""
    sp, sr = max(sp, NOISE_FLOOR * size), max(sr, NOISE_FLOOR)
    return max(sp, NOISE_RATIO * sr * size), max(sr, NOISE_RATIO * sp / size)


def given_noise(opts: FitOptions, size: float, notes: list[str]) -> tuple[float, float]:
    """The noise levels given, raised to the floors, with a note where they were raised."""
    given = opts.noise_pos if opts.noise_pos is not None else 1.0
    sp, sr = bounded_noise(given, opts.noise_rot or given / size, size)
    if opts.pose and opts.noise_rot is not None and sr > opts.noise_rot:
        notes.append(
            f"the rotation noise given ({opts.noise_rot:.3g} rad) would weigh rotations "
            f"over {1 / NOISE_RATIO:.0e} times positions and drown them; weighted as "
            f"{sr:.3g} rad"
        )
    if opts.pose and sp > given:
        notes.append(
            f"the position noise given would weigh positions over {1 / NOISE_RATIO:.0e} times "
            f"rotations and drown them; weighted as {sp / given:.3g} times it"
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
    if not has_prior(est, opts) or reference is None or locations is None:
        return None, None
    errors = link_errors(reference, locations)
    if errors is None or not isinstance(opts.prior, Prior):
        return errors, None
    return errors, Deviations.stated(opts.prior, errors.links)


def to_data(m: Measurements, pose: bool, marker_ids: list[int]) -> Data:
    """The residuals' view of measurements: the orientations too with ``pose``; each row's
    marker as its place among ``marker_ids``. Made once for ``m`` and these arguments
    (:meth:`.Measurements.remembered`: its markers and rotations read-only)."""
    ids = tuple(marker_ids)
    return m.remembered(("data", pose, ids), lambda: _data(m, pose, ids))


def _data(m: Measurements, pose: bool, marker_ids: tuple[int, ...]) -> Data:
    rows = (
        np.zeros(len(m), dtype=np.int64)
        if m.markers is None
        else np.searchsorted(np.array(marker_ids), m.markers).astype(np.int64)
    )
    rotations = rotation_of(m.quaternions) if pose and m.quaternions is not None else None
    for made in (rows, rotations):
        if made is not None:
            made.setflags(write=False)
    return Data(m.q, m.points, rows, rotations)


def moved(model_joints: tuple[Joint, ...], g: Mat) -> tuple[Joint, ...]:
    """The joints moved by the rigid transform ``g`` (points as feet of perpendiculars)."""
    out = []
    for j in model_joints:
        u = g[:3, :3] @ j.axis
        point = None if j.point is None else g[:3, :3] @ j.point + g[:3, 3]
        if point is not None and j.kind != "prismatic":
            point = line_point(u, point)
        out.append(Joint(j.name, j.kind, u, point, j.pitch, j.scale, j.lower, j.upper))
    return tuple(out)


def layout_points(opts: FitOptions, ids: list[int]) -> Mat:
    if opts.layout is None:
        return np.zeros((len(ids), 3))
    return np.array([opts.layout[k] for k in ids])


def nominal_points(nominal: PoeModel, m: Measurements, opts: FitOptions, ids: list[int]) -> Mat:
    """The nominal's tool points at the measured configurations (in its base frame): for poses,
    each pose's origin and axis tips (:func:`.rigid.pose_points`); for positions, the markers
    placed on the tool by the layout."""
    poses = nominal.fk_batch(m.q)
    if opts.pose:
        return pose_points(poses, nominal.size())
    local = layout_points(opts, ids)[to_data(m, False, ids).markers]
    points: Mat = np.einsum("nij,nj->ni", poses[:, :3, :3], local) + poses[:, :3, 3]
    return points


def _measured_points(m: Measurements, size: float, pose: bool, ids: list[int]) -> Mat:
    data = to_data(m, pose, ids)  # the fit's own view of them (made once)
    if data.rotations is None:
        return m.points
    poses = np.zeros((len(m), 4, 4))
    poses[:, :3, :3] = data.rotations
    poses[:, :3, 3] = m.points
    return pose_points(poses, size)


def placement(nominal: PoeModel, m: Measurements, opts: FitOptions, ids: list[int]) -> Mat:
    """The rigid fit of the nominal's tool points to the measured ones (step 1)."""
    return fit_rigid(
        nominal_points(nominal, m, opts, ids),
        _measured_points(m, nominal.size(), opts.pose, ids),
    )


def start_estimate(nominal: PoeModel, g: Mat, opts: FitOptions, ids: list[int]) -> Estimate:
    """The nominal placed in the device frame by ``g`` (:func:`placement`)."""
    helical = set(opts.helical)
    joints = tuple(
        replace(j, kind="helical")
        if j.kind == "revolute" and ("all" in helical or j.name in helical)
        else j
        for j in moved(nominal.joints, g)
    )
    home = g @ nominal.home
    if opts.pose:
        return Estimate.of(joints, home, level=BASE_TOOL, keep_tool_axis=opts.keep_tool_axis)
    return Estimate.of(joints, home, layout_points(opts, ids), level=BASE_TOOL)
