"""What a calibration found: :class:`Calibration`, the one value that its text, its JSON report,
its pictures and a notebook read (:mod:`.report`, :mod:`.plot`), and its parts.

Every figure is in the measurements' length unit (:mod:`.userunits`) and radians; the models
and the table keep the nominal's length unit.

What the fit decided, and what judging it reads, is made by :func:`~.calibration.calibrate`;
a figure that only its presentation reads (the parameters' values and changes, the ``diff``
against the nominal) is made the first time it is read, and kept (:class:`Later`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Generic, TypeVar, cast

import numpy as np
from numpy.typing import NDArray

from ..check.diff import Diff
from ..conventions.table import Table
from ..errors import shown
from ..model.poe import PoeModel
from ..schemas import CALIBRATION_REPORT
from .outliers import Suspect
from .report import markdown, summary
from .select import Selection
from .userunits import UserUnits

__all__ = [
    "SCHEMA",
    "Calibration",
    "Comparison",
    "Counts",
    "Held",
    "Later",
    "Noise",
    "Parameter",
    "Residuals",
]

Mat = NDArray[np.float64]

SCHEMA = CALIBRATION_REPORT  # the report's ``schema`` (docs/formats/calibration-report.md)

T = TypeVar("T")


class Later(Generic[T]):
    """A figure made when it is first read (:meth:`get`), by ``make()``, and then kept; two are
    equal when their figures are. A value of it pickles as what makes it, or as the figure once
    made."""

    __slots__ = ("_make", "_value")

    def __init__(self, make: Callable[[], T]) -> None:
        self._make: Callable[[], T] | None = make
        self._value: T | None = None

    def get(self) -> T:
        """The figure (made now, where it was not made yet)."""
        make = self._make
        if make is not None:
            self._value = make()
            self._make = None
        return cast(T, self._value)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Later) and (other is self or self.get() == other.get())


@dataclass(frozen=True, slots=True)
class Residuals:
    """Residual statistics of one model on one set (rotation ``None`` for positions)."""

    count: int
    rms_position: float
    max_position: float
    rms_rotation: float | None = None
    max_rotation: float | None = None


@dataclass(frozen=True, slots=True)
class Comparison:
    """Before (base and tool fitted to the nominal joints) and after, on one set.

    Attributes
    ----------
    name
        ``fit``, ``held_out`` or ``validation``.
    before, after
        The statistics of the two models on the set.
    configurations
        The set's configurations (their numbers in the file's order).
    before_position, after_position
        Each configuration's RMS position error (over its markers).
    before_rotation, after_rotation
        Each configuration's rotation error (poses), else ``None``.
    """

    name: str
    before: Residuals
    after: Residuals
    configurations: tuple[int, ...]
    before_position: tuple[float, ...]
    after_position: tuple[float, ...]
    before_rotation: tuple[float, ...] | None = None
    after_rotation: tuple[float, ...] | None = None


@dataclass(frozen=True, slots=True)
class Parameter:
    """One identified parameter.

    Attributes
    ----------
    name, unit
        Its name (``j1.turn1``, ``j3.offset``, ``tool.z``, ...) and unit.
    value
        Its value, for scales, pitches and offsets; ``None`` for the chart's coordinates
        (turns and shifts of a line, base and tool motions), which are changes only.
    change
        How far the identified model moved it from the nominal (base and tool fitted).
    std
        Its standard deviation, ``None`` where the measurements do not determine it.
    effect
        How far its change moves a measured tool point at most (length unit; rotations at the
        robot's size): the changes of different units on one scale.
    flag
        Why it is poorly identified, or ``None``.
    """

    name: str
    unit: str
    value: float | None
    change: float
    std: float | None
    effect: float
    flag: str | None = None


@dataclass(frozen=True, slots=True)
class Held:
    """A parameter of the level that was held at the nominal's value, and why."""

    name: str
    reason: str


@dataclass(frozen=True, slots=True)
class Noise:
    """The noise levels that weighed the fit.

    Attributes
    ----------
    position, rotation
        Per coordinate: length unit, and rad (``None`` for positions).
    given
        Whether they were given (else estimated by variance components).
    variance_factor
        The weighted residual sum of squares over the redundancy (about 1 when they are right).
    floor_position, floor_rotation
        What a perfect model leaves: ``sqrt(3)`` times the levels.
    """

    position: float
    rotation: float | None
    given: bool
    variance_factor: float
    floor_position: float
    floor_rotation: float | None


@dataclass(frozen=True, slots=True)
class Counts:
    """How many of each: measurements, configurations, equations, parameters."""

    measurements: int
    configurations: int
    fit: int
    held_out: int
    validation: int
    rejected: int
    equations: int
    parameters: int
    rank: int
    markers: int


@dataclass(frozen=True)
class Calibration:
    """The result of :func:`~.calibration.calibrate`.

    Attributes
    ----------
    nominal
        The nominal model.
    model
        The identified model, in the output frame (``frame``).
    device_model
        The identified model in the measuring device's frame.
    measurements
        Where the measurements came from.
    measure
        ``pose`` or ``position``.
    frame
        ``device`` or ``nominal``.
    level
        The level identified (:data:`.levels.LEVELS`).
    chosen_by
        ``cross-validation`` or ``option``.
    selection
        The cross-validation of the levels and the choice.
    counts, noise
        Counts and noise levels.
    condition_number, iterations, converged
        Of the final fit.
    formula, in_words
        The level's parameter count as a formula (Wu 2019 eq. 23 for ``full``) and in words.
    comparisons
        Before and after on each set (fit, held out, validation).
    parameters
        The identified parameters (made when first read).
    held
        The level's parameters held at the nominal's values, with the reason.
    barely_moved
        ``(joint, span)`` of the joints that barely moved.
    suspects
        The outlier suspects, and whether they were ``rejected``.
    base_in_device
        ``(4, 4)`` the pose of the nominal's base frame in the device frame.
    markers_on_tool
        Each marker's position on the identified tool (position measurements).
    convention
        The output's convention (``poe`` for a POE model file).
    table
        The output table (``None`` for ``poe``).
    convention_reason
        Why this convention, when it was chosen.
    diff
        The ``diff`` of the nominal and the identified model (``urdf2dh diff``'s), made when it
        is first read.
    warnings
        Everything worth a person's attention.
    units
        The length unit of every figure above (residuals, noise, parameters, suspects, the
        levels' scores, ``base_in_device``, ``markers_on_tool``): the measurements' own
        (:mod:`.userunits`); ``nominal``, ``model``, ``device_model``, ``table`` and ``diff``
        keep the nominal's.
    """

    nominal: PoeModel
    model: PoeModel
    device_model: PoeModel
    measurements: str
    measure: str
    frame: str
    level: str
    chosen_by: str
    selection: Selection | None
    counts: Counts
    noise: Noise
    condition_number: float
    iterations: int
    converged: bool
    formula: str
    in_words: str
    comparisons: tuple[Comparison, ...]
    _parameters: Later[tuple[Parameter, ...]]  # what ``parameters`` reads
    held: tuple[Held, ...]
    barely_moved: tuple[tuple[str, float], ...]
    suspects: tuple[Suspect, ...]
    rejected: bool
    base_in_device: Mat
    markers_on_tool: dict[int, Mat]
    convention: str
    table: Table | None
    convention_reason: str | None
    _diff: Later[Diff]  # what ``diff`` reads
    warnings: tuple[str, ...]
    units: UserUnits
    rows: tuple[int, ...] = field(default=(), repr=False)  # fitted rows' numbers in the file
    schema: str = SCHEMA

    @property
    def parameters(self) -> tuple[Parameter, ...]:
        """The identified parameters."""
        return self._parameters.get()

    @property
    def diff(self) -> Diff:
        """The ``diff`` of the nominal and the identified model (``urdf2dh diff``'s)."""
        return self._diff.get()

    def comparison(self, name: str) -> Comparison | None:
        """The comparison on ``name`` (``fit``, ``held_out``, ``validation``), if there is one."""
        return next((c for c in self.comparisons if c.name == name), None)

    def __str__(self) -> str:
        """What ``urdf2dh calibrate`` prints: the levels, the residuals before and after, the
        warnings."""
        return summary(self)

    def __repr__(self) -> str:
        done = "converged" if self.converged else "NOT converged"
        return (
            f"<Calibration of {shown(self.nominal.name)} at level {self.level}, "
            f"{self.counts.parameters} parameters, {done}; written in {self.convention}>"
        )

    def _repr_markdown_(self) -> str:
        """In a notebook: the residuals before and after on each set, and the identified
        parameters, as tables (names escaped)."""
        return markdown(self)
