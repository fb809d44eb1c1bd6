"""What a calibration is asked: the problem and the options, each a frozen value made once from
:func:`~.calibration.calibrate`'s arguments and checked there.

* :class:`CalibrationProblem`: the nominal model, the measurements (the configurations fitted,
  those held out, a validation set), what they measure (poses, or positions of markers), the
  noise levels given and the user's length unit;
* :class:`LevelChoice`: the level, or how it is chosen (the rule, the folds);
* :class:`Output`: what is written (the convention, its style, the frame, the table's
  self-check);
* :class:`Options`: those, with how each level is identified (:class:`~.start.FitOptions`: the
  parameters held, the prior, helical joints, the solver's bound), what becomes of outlier
  suspects, and whether a result the measurements contradict is returned all the same.

The held-out configurations are ``round(holdout x count)`` of the distinct rows of joint
values, the first of ``numpy.random.default_rng((seed, 3)).permutation(count)``, all rows of a
configuration on the same side.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..checks import check_count, check_flag, check_instance
from ..errors import InputError, NotConverged, UsageError, choices, shown
from ..model.poe import PoeModel
from ..tolerances import DEFAULT, Tolerances
from .levels import AUTO, BASE_TOOL, FULL, NAMES, RULES, check_level
from .measurements import MAX_MEASUREMENTS, Measurements, check_noise
from .prior import AUTO as AUTO_PRIOR
from .prior import Prior
from .start import MAX_ITERATIONS, FitOptions
from .userunits import UserUnits

if TYPE_CHECKING:
    from .select import Selection

__all__ = [
    "MAX_EXTENT",
    "MAX_JOINT_TURN",
    "CalibrationProblem",
    "LevelChoice",
    "Options",
    "Output",
    "check_measurements",
    "fit_options",
    "holdout_split",
]

Mat = NDArray[np.float64]
Rows = NDArray[np.int64]

# Joint values and measured points beyond these are refused: far beyond any joint's travel or any
# measuring volume (a revolute joint's angle of 1e4 rad already carries 2e-12 rad of round-off),
# they can only be a unit mistake or garbage.
MAX_JOINT_TURN = 1e4  # rad
MAX_EXTENT = 1e4  # x the robot's size (points, sliding joints)

MEASUREMENTS_HINT = "urdf2dh.measure(model, N) makes some"


def holdout_split(m: Measurements, fraction: float, seed: int) -> tuple[Rows, Rows]:
    """Rows to fit and rows held out (module docstring), both in file order."""
    if fraction == 0.0:  # none held out: every row fitted
        return np.arange(len(m), dtype=np.int64), np.zeros(0, dtype=np.int64)
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


@dataclass(frozen=True, slots=True)
class CalibrationProblem:
    """What is calibrated, from what (module docstring).

    Attributes
    ----------
    nominal
        The nominal model.
    measurements
        Every measurement given, in the file's order.
    fit_rows, held_rows
        The rows fitted and the rows held out to judge the fit.
    fit, held
        The measurements at those rows.
    validation
        A separate set judged as the held-out one, or ``None``.
    pose
        What is measured: poses (positions and orientations of the tool), or positions of the
        tool's markers.
    markers
        The markers seen, in the measurements and the validation set (``[0]`` without a
        marker column).
    layout
        The markers' positions on the tool, in the nominal's length unit, or ``None``.
    noise_pos, noise_rot
        The noise levels given, as given (the user's length unit, rad; ``None``: estimated).
    units
        The user's length unit beside the nominal's (:mod:`.userunits`).
    """

    nominal: PoeModel
    measurements: Measurements
    fit_rows: Rows
    held_rows: Rows
    fit: Measurements
    held: Measurements
    validation: Measurements | None
    pose: bool
    markers: list[int]
    layout: dict[int, Mat] | None
    noise_pos: float | None
    noise_rot: float | None
    units: UserUnits

    @classmethod
    def of(
        cls,
        nominal: PoeModel,
        measurements: Measurements,
        pose: bool | None,
        noise: tuple[float | None, float | None],
        layout: dict[int, Mat] | None,
        holdout: float,
        seed: int,
        validation: Measurements | None,
    ) -> CalibrationProblem:
        """The problem of :func:`~.calibration.calibrate`'s arguments, checked: ``pose``
        ``None`` uses the orientations where the measurements have them; ``noise`` and
        ``layout`` are in the measurements' length unit.

        Raises
        ------
        InputError
            Measurements no robot or device makes, a model with coupled joints, markers without
            a layout, noise levels no device has, no configuration left to fit.
        UsageError
            A held-out fraction outside ``[0, 1)``.
        """
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
                f"{nominal.source or nominal.name}: joint {shown(coupled[0])} follows another "
                "joint; calibration identifies every joint's screw and scale on its own"
            )
        check_measurements(nominal, m)
        if validation is not None:
            check_measurements(nominal, validation, "the validation set")
            _check_markers(validation, pose, layout)
        units = UserUnits.of(nominal.length_unit, m)
        noise_pos, noise_rot = noise[0], noise[1] if pose else None
        check_noise(noise_pos, noise_rot, units.shown(nominal.size()), units.length)
        _check_markers(m, pose, layout)
        if not 0.0 <= holdout < 1.0:
            raise UsageError(f"the held-out fraction must be in [0, 1), not {holdout}")
        fit_rows, held_rows = holdout_split(m, holdout, seed)
        if not len(fit_rows):
            raise InputError(
                f"{m.source}: holding out {holdout:g} of its {m.configurations()[1]} "
                "configurations leaves none to fit; hold out less, or measure more "
                "configurations"
            )
        seen = set(m.marker_ids()) | set(validation.marker_ids() if validation else [])
        return cls(
            nominal,
            m,
            fit_rows,
            held_rows,
            m.subset(fit_rows),
            m.subset(held_rows),
            validation,
            pose,
            sorted(seen),
            None if layout is None else {k: units.to_model_array(v) for k, v in layout.items()},
            noise_pos,
            noise_rot,
            units,
        )

    @property
    def source(self) -> str:
        """The measurements' name, for messages."""
        return self.measurements.source

    def refitted(self, fit_rows: Rows) -> CalibrationProblem:
        """The same problem fitted to ``fit_rows`` only (outliers rejected); the held-out rows
        stay as they were."""
        return CalibrationProblem(
            self.nominal, self.measurements, fit_rows, self.held_rows,
            self.measurements.subset(fit_rows), self.held, self.validation, self.pose,
            self.markers, self.layout, self.noise_pos, self.noise_rot, self.units,
        )  # fmt: skip


@dataclass(frozen=True, slots=True)
class LevelChoice:
    """The level to identify, or how to choose it (:mod:`.select`).

    Attributes
    ----------
    level
        ``auto`` (chosen by cross-validation), or a level (:data:`.levels.LEVELS`).
    rule
        ``simplest`` (the simplest level within one standard error of the best) or ``best``.
    folds
        Configurations left out in turn: each alone (``None``), or this many seeded folds.
    seed
        The folds' seed.
    """

    level: str = AUTO
    rule: str = "simplest"
    folds: int | None = None
    seed: int = 0

    def __post_init__(self) -> None:
        check_instance(self.level, str, "calibrate: level")
        check_level(self.level, "calibrate", auto=True)
        if self.rule not in RULES:
            raise UsageError(f"unknown rule {shown(self.rule)}; valid: {choices(RULES)}")
        if self.folds is not None:
            check_count(self.folds, "calibrate: folds", 2)

    @property
    def chosen_by(self) -> str:
        """``cross-validation`` or ``option``."""
        return "cross-validation" if self.level == AUTO else "option"

    def levels(self, keep_scale: bool) -> tuple[str, ...]:
        """The levels fitted and judged: every one (``auto``; without ``full`` when the scales
        are kept: that would be ``geometry``), or those up to the one asked for. Each level is
        fitted from the simpler one's solution, so that a level asked for is the model the
        choice among them gives when it chooses that level."""
        if self.level == AUTO:
            return tuple(lv for lv in NAMES if not (keep_scale and lv == FULL.name))
        return NAMES[: NAMES.index(self.level) + 1]

    def chosen(self, selection: Selection, source: str) -> str:
        """The level to identify: the one asked for, or the one cross-validation chose.

        Raises
        ------
        NotConverged
            Not even the base and tool could be fitted.
        InputError
            Too few configurations to judge any level on configurations it was not fitted to.
        """
        if self.level != AUTO:
            return self.level
        if selection.chosen is None:
            why = selection.score(BASE_TOOL.name).failure or ""
            if "converge" in why:
                raise NotConverged(f"{source}: the fit of the base and tool {why}; nothing written")
            raise InputError(
                f"{source}: {selection.configurations} configurations are too few to judge any "
                f"level on configurations it was not fitted to ({why}); measure more "
                "configurations, or choose the level"
            )
        return selection.chosen


@dataclass(frozen=True, slots=True)
class Output:
    """What is written.

    Attributes
    ----------
    convention, style
        The output table's convention (``None``: ``dh``, or ``hayati`` where a D-H table is not
        the one to write; ``poe``: a POE model, no table) and D-H style.
    check_samples
        Configurations of the table's self-check (``None``: the default).
    """

    convention: str | None = None
    style: str = "wu"
    check_samples: int | None = None


@dataclass(frozen=True, slots=True)
class Options:
    """How a calibration is made (module docstring).

    Attributes
    ----------
    fitting
        How each level is identified (its ``level`` is set for each fit).
    choice
        The level, or how it is chosen.
    reject
        The outlier suspects (:mod:`.outliers`): rejected (``True``), kept (``False``), or
        rejected when that predicts the other configurations better (``None``).
    output
        What is written.
    accept
        Return a result the measurements contradict all the same (:mod:`.plausible`).
    """

    fitting: FitOptions = field(default_factory=FitOptions)
    choice: LevelChoice = field(default_factory=LevelChoice)
    reject: bool | None = None
    output: Output = field(default_factory=Output)
    accept: bool = False

    def __post_init__(self) -> None:
        check_count(self.fitting.max_iterations, "calibrate: max_iterations")
        check_flag(self.accept, "calibrate: accept")


def fit_options(
    problem: CalibrationProblem,
    fixed: tuple[str, ...] = (),
    prior: Prior | str = AUTO_PRIOR,
    helical: tuple[str, ...] = (),
    keep_scale: bool = False,
    keep_tool_axis: bool = False,
    frame: str = "device",
    max_iterations: int = MAX_ITERATIONS,
    tol: Tolerances = DEFAULT,
) -> FitOptions:
    """How each level of ``problem`` is identified: what it measures, the noise levels given and
    the marker layout in the nominal's length unit, with these choices."""
    return FitOptions(
        pose=problem.pose,
        level=BASE_TOOL.name,
        fixed=fixed,
        prior=prior,
        helical=helical,
        keep_scale=keep_scale,
        keep_tool_axis=keep_tool_axis,
        frame=frame,
        noise_pos=problem.units.to_model(problem.noise_pos),
        noise_rot=problem.noise_rot,
        layout=problem.layout,
        max_iterations=max_iterations,
        tol=tol,
    )
