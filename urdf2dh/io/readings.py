"""The ways a hand-written table can be read, each a chain: its convention (standard or modified
D-H), the unit of its angles and of its lengths (docs/commands/match.md).

A :class:`Reading` is one such interpretation of a :class:`~urdf2dh.io.handtable.HandTable`:
numbers in radians and the source's length unit, each with the step it was written to, and the
chain they make (:meth:`Reading.model`, the frames just before each joint: :meth:`Reading.frames`).
:func:`readings` lists the interpretations the table's own statements leave open.

Precision (what a written number can say): the angles are written to the finest step of any
angle cell and the lengths to the finest step of any length cell (a table that writes
``0.089159`` writes ``0.425`` to the same micrometre, its trailing zeros left off); a zero, and
an angle within its step of a multiple of 15 degrees (``1.570796`` is pi/2, ``90`` is 90), are
exact.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..model.poe import Joint, JointKind, PoeModel
from ..units import metres_per
from .handtable import COLUMNS, HandRow, HandTable

if TYPE_CHECKING:
    from .sources import Content, Source
    from .sources import Reading as SourceReading

__all__ = ["LENGTH_UNITS", "SPECIAL_ANGLE", "Reading", "readings"]

Mat = NDArray[np.float64]

#: The length units a table without a stated unit is tried in.
LENGTH_UNITS = ("m", "mm", "cm", "in")
#: Angles within their written step of a multiple of this are taken as exact (15 degrees).
SPECIAL_ANGLE = math.pi / 12


@dataclass(frozen=True, slots=True)
class Reading:
    """One interpretation of a hand-written table, in the source's length unit and radians.

    Attributes
    ----------
    convention
        ``dh`` (standard: ``Rz(theta + q) Tz(d) Rx(alpha) Tx(a)`` per row) or ``mdh`` (Craig:
        ``Rx(alpha) Tx(a) Rz(theta + q) Tz(d)``).
    angle_units
        ``(theta's, alpha's)``: ``deg`` or ``rad``.
    length_unit
        The table's length unit.
    factor
        Source length units per table length unit.
    kinds
        Each row's kind (a joint's from the table, else the source's; ``fixed`` rows).
    values, steps
        ``(rows, 4)``: ``theta, d, a, alpha`` of each row in radians and source units, and the
        step each is written to (0: exact).
    names
        The rows' names.
    stated
        Which of convention, angle unit and length unit the table stated.
    """

    convention: str
    angle_units: tuple[str, str]
    length_unit: str
    factor: float
    kinds: tuple[str, ...]
    values: Mat
    steps: Mat
    names: tuple[str, ...]
    stated: tuple[bool, bool, bool] = (False, False, False)

    @property
    def joint_rows(self) -> list[int]:
        """The indices of the rows that are joints."""
        return [i for i, k in enumerate(self.kinds) if k != "fixed"]

    def describe(self) -> str:
        """``lengths in mm; angles in degrees; modified D-H`` (what a person reads)."""
        theta, alpha = self.angle_units
        words = {"deg": "degrees", "rad": "radians"}
        angles = (
            f"angles in {words[theta]}"
            if theta == alpha
            else f"theta in {words[theta]}, alpha in {words[alpha]}"
        )
        convention = "standard D-H" if self.convention == "dh" else "modified D-H (Craig)"
        return f"lengths in {self.length_unit}; {angles}; {convention}"

    def row_transforms(self, values: Mat | None = None) -> list[tuple[Mat, Mat]]:
        """Each row's constant transforms ``(before, after)`` its joint motion."""
        v = self.values if values is None else values
        out = []
        for theta, d, a, alpha in v:
            rz_tz = _rz_tz(theta, d)
            rx_tx = _rx_tx(alpha, a)
            out.append((np.eye(4), rz_tz @ rx_tx) if self.convention == "dh" else (rx_tx, rz_tz))
        return out

    def frames(self, q: NDArray[np.float64] | None = None, values: Mat | None = None) -> list[Mat]:
        """The frame just before each joint's motion (its z on the joint's axis), then the
        table's last frame, at joint positions ``q`` (the table's own; default 0)."""
        positions = np.zeros(len(self.joint_rows)) if q is None else np.asarray(q, dtype=float)
        out, f, k = [], np.eye(4), 0
        for kind, (before, after) in zip(self.kinds, self.row_transforms(values), strict=True):
            f = f @ before
            if kind == "fixed":
                f = f @ after
                continue
            out.append(f)
            s = float(positions[k])
            f = f @ (_rz_tz(s, 0.0) if kind == "revolute" else _rz_tz(0.0, s)) @ after
            k += 1
        out.append(f)
        return out

    def model(self, names: tuple[str, ...] | None = None, values: Mat | None = None) -> PoeModel:
        """The table's chain as a POE model (joints named ``names``, or the rows' names)."""
        fs = self.frames(values=values)
        joint_names = names or tuple(self.names[i] for i in self.joint_rows)
        joints = tuple(
            Joint(name, _kind(self.kinds[i]), f[:3, 2].copy(), f[:3, 3].copy())
            for name, i, f in zip(joint_names, self.joint_rows, fs[:-1], strict=True)
        )
        return PoeModel(joints, fs[-1], length_unit="")

    def perturbed(self) -> Iterator[tuple[int, int, PoeModel]]:
        """For each number written to a step, ``(row, column, the chain with that number
        moved by its step)``: what its last digit can change."""
        for i, j in zip(*np.nonzero(self.steps > 0.0), strict=True):
            values = self.values.copy()
            values[i, j] += self.steps[i, j]
            yield int(i), int(j), self.model(values=values)


def _kind(kind: str) -> JointKind:
    return "prismatic" if kind == "prismatic" else "revolute"


def _rz_tz(theta: float, d: float) -> Mat:
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, 0.0, 0.0], [s, c, 0.0, 0.0], [0.0, 0.0, 1.0, d], [0, 0, 0, 1.0]])


def _rx_tx(alpha: float, a: float) -> Mat:
    c, s = math.cos(alpha), math.sin(alpha)
    return np.array([[1.0, 0.0, 0.0, a], [0.0, c, -s, 0.0], [0.0, s, c, 0.0], [0, 0, 0, 1.0]])


def readings(
    table: HandTable,
    source_kinds: tuple[str, ...],
    source_unit: str,
    convention: str | None = None,
    length_unit: str | None = None,
    angle_unit: str | None = None,
) -> list[Reading]:
    """The interpretations of ``table`` its statements (and the arguments) leave open, against
    a source whose joints are of ``source_kinds`` and whose lengths are in ``source_unit``.

    A table whose joints are more or fewer than the source's still has its readings (the match
    then names the difference); rows of unstated kind take the source's joint's kind in order.
    """
    stated_convention = convention or table.convention
    stated_length = length_unit or table.length_unit
    conventions = [stated_convention] if stated_convention else ["dh", "mdh"]
    lengths = [stated_length] if stated_length else list(LENGTH_UNITS)
    theta_units = _angle_choices(table, "theta", angle_unit)
    alpha_units = _angle_choices(table, "alpha", angle_unit)
    silent = _all_zero(table, "theta") or _all_zero(table, "alpha")
    separate = bool(angle_unit or table.angle_unit("theta") or table.angle_unit("alpha"))
    if _all_zero(table, "theta"):  # a column of zeros says nothing: read as the other
        theta_units = alpha_units
    elif _all_zero(table, "alpha"):
        alpha_units = theta_units
    kinds = _kinds(table.rows, source_kinds)
    stated = (
        bool(convention or table.convention),
        bool(angle_unit or (table.angle_unit("theta") and table.angle_unit("alpha"))),
        bool(length_unit or table.length_unit),
    )
    out = []
    for conv in conventions:
        for length in lengths:
            factor = metres_per(length) / metres_per(source_unit)
            for theta_unit in theta_units:
                for alpha_unit in alpha_units:
                    if alpha_unit != theta_unit and (silent or not separate):
                        continue  # one unit for all angles, unless the table says otherwise
                    values, steps = _numbers(table.rows, (theta_unit, alpha_unit), factor)
                    out.append(Reading(conv, (theta_unit, alpha_unit), length, factor, kinds,
                                       values, steps, tuple(r.name for r in table.rows),
                                       stated))  # fmt: skip
    return out


def _angle_choices(table: HandTable, column: str, given: str | None) -> list[str]:
    stated = given or table.angle_unit(column)
    if stated:
        return [stated]
    # a column whose angles reach beyond a turn is in degrees
    if any(abs(r.number(column).value) > 2.0 * math.pi + 1e-9 for r in table.rows):
        return ["deg"]
    return ["deg", "rad"]


def _all_zero(table: HandTable, column: str) -> bool:
    return all(r.number(column).value == 0.0 for r in table.rows)


def _kinds(rows: tuple[HandRow, ...], source_kinds: tuple[str, ...]) -> tuple[str, ...]:
    out, k = [], 0
    for r in rows:
        if r.kind == "fixed":
            out.append("fixed")
            continue
        source = source_kinds[k] if k < len(source_kinds) else "revolute"
        out.append(r.kind or ("prismatic" if source == "prismatic" else "revolute"))
        k += 1
    return tuple(out)


def _numbers(rows: tuple[HandRow, ...], units: tuple[str, str], factor: float) -> tuple[Mat, Mat]:
    """Values and steps ``(rows, 4)`` in radians and source units, by the precision rules of
    the module docstring."""
    per = {"theta": units[0], "alpha": units[1]}
    values = np.zeros((len(rows), 4))
    steps = np.zeros((len(rows), 4))
    length_step = min(
        (r.number(c).step for r in rows for c in ("d", "a") if r.number(c).value != 0.0),
        default=0.0,
    )
    angle_steps = [
        _radians(r.number(c).step, r.number(c).unit or per[c])
        for r in rows
        for c in ("theta", "alpha")
        if r.number(c).value != 0.0 and r.number(c).step > 0.0
    ]
    angle_step = min(angle_steps, default=0.0)
    for i, r in enumerate(rows):
        for j, column in enumerate(COLUMNS):
            w = r.number(column)
            if column in ("d", "a"):
                values[i, j] = factor * w.value
                steps[i, j] = factor * length_step if w.value != 0.0 and w.step > 0.0 else 0.0
                continue
            value = _radians(w.value, w.unit or per[column])
            step = angle_step if w.value != 0.0 and w.step > 0.0 else 0.0
            special = SPECIAL_ANGLE * round(value / SPECIAL_ANGLE)
            if w.step > 0.0 and abs(value - special) <= step:
                value, step = special, 0.0
            values[i, j], steps[i, j] = value, step
    return values, steps


def _radians(value: float, unit: str) -> float:
    return math.radians(value) if unit == "deg" else value


def read_source(content: Content, reading: SourceReading) -> Source:
    """A hand-written table as a SOURCE (the ``hand`` entry of
    :data:`~urdf2dh.io.sources.READERS`): its one reading, which its ``convention`` and
    ``units`` must fix (``urdf2dh match`` finds them where it does not say)."""
    from .handtable import from_tree
    from .sources import Source

    table = from_tree(content.mapping, content.display)
    unit = table.length_unit
    options = readings(table, (), unit or "m")
    if table.convention is None or unit is None or len(options) != 1:
        missing = [what for what, known in (("convention", table.convention),
                   ("units.length", unit)) if known is None]  # fmt: skip
        if not missing:
            missing = ["units.angle"]
        raise InputError(
            f"{content.display}: a hand-written table read as a model must say its "
            f"{' and '.join(missing)} (urdf2dh match finds what a table does not say)"
        )
    one = options[0]
    model = one.model()
    assert unit is not None
    named = replace(model, name=content.name(table.robot or content.path.stem),
                    source=content.display, length_unit=unit)  # fmt: skip
    return Source(
        "hand-written table", content.display, named.name, poe=named, bundled=content.bundled
    )
