"""``urdf2dh diff NOMINAL ACTUAL``: two parameter sets side by side, for calibration.

Both sources become tables in the same convention and their parameters are compared row by row.
A change is *marked* when it exceeds the thresholds, as Wu 2019 Table II marks the jumps caused
by parallel axes (> 60 degrees or > 30 mm there). Angles are compared modulo 180 degrees: D-H
may describe the same pair of lines with (theta, alpha, a) or (theta + pi, -alpha, -a), and a
sign rule such as a >= 0 switches between them when a crosses 0 (Table II's 0H1 alpha, 90 ->
-88.854, is not marked).

A row whose two tables hold records of different forms (a ``hayati`` row that is a D-H link in
one table and a Hayati link in the other: two axes that were parallel no longer are, exactly what
calibration finds) has no parameter-by-parameter change: it is reported as *changed form*, with
each record's parameters, the link transform each gives (the row's constant transforms composed
at ``q = 0``) and how far those two transforms are apart, in length and angle
(:class:`FormChange`).

The axis pairs where D-H is ill-conditioned are named: consecutive lines (base z, joint axes,
tool z) that are nearly parallel in either model. There the common normal, and with it d, a and
theta, jump under small changes (Wu 2019 §V-B): identify with CPC or the POE model and convert
back. Modified D-H uses the same common normals and shares the problem.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from .. import units
from ..checks import check_source
from ..conventions import Params
from ..conventions.convert import to_table
from ..conventions.table import Row, Table
from ..errors import InputError, UsageError, choices, shown, visible
from ..escape import markdown_table, markdown_text
from ..geometry.frames import compose
from ..geometry.se3 import matrix_of
from ..io.sources import open_source
from ..io.xacro import XacroOptions
from ..model.poe import PoeModel
from ..tolerances import (
    DEFAULT,
    DIFF_ANGLE_DEG,
    DIFF_LENGTH_M,
    DIFF_PARALLEL_DEG,
    DIFF_ROUND_OFF,
    Tolerances,
)
from ..units import fixed

__all__ = [
    "SCHEMA",
    "Change",
    "Diff",
    "FormChange",
    "IllPair",
    "compare",
    "compare_tables",
    "diff",
    "form_changes",
    "ill_conditioned",
]

SCHEMA = "urdf2dh-diff/1"


@dataclass(frozen=True, slots=True)
class Change:
    """One parameter in both tables. Angles in radians, lengths in the nominal's unit; for the
    CPC vectors ``b`` the change is the angle between them, for ``l`` the distance."""

    row: str
    param: str
    nominal: Any
    actual: Any
    change: float
    kind: str  # "angle", "length", "direction", "pitch" or "scale"
    marked: bool


@dataclass(frozen=True, slots=True)
class FormChange:
    """A row (or the base, or the tool) whose records differ in form between the tables.

    Attributes
    ----------
    row
        The row's label (``base``, a joint's name, ``tool``).
    nominal_form, actual_form
        Each record's form (``D-H``, ``Hayati``, or its class name).
    nominal, actual
        Each record's parameters (angles in radians, lengths in the nominal's unit).
    nominal_link, actual_link
        ``4 x 4`` the link transform each record gives (its constant transforms at ``q = 0``).
    length, angle
        How far the two link transforms are apart: the distance of their origins and the angle
        of their relative rotation (rad).
    marked
        Whether either exceeds the thresholds.
    """

    row: str
    nominal_form: str
    actual_form: str
    nominal: dict[str, float | list[float]]
    actual: dict[str, float | list[float]]
    nominal_link: list[list[float]]
    actual_link: list[list[float]]
    length: float
    angle: float
    marked: bool


@dataclass(frozen=True, slots=True)
class IllPair:
    """Consecutive lines nearly parallel in at least one model (angles from parallel, rad)."""

    first: str
    second: str
    nominal_angle: float
    actual_angle: float


def _angle_mod_pi(delta: float) -> float:
    return abs(math.remainder(delta, math.pi))


def compare(
    nominal: Table, actual: Table, angle_threshold: float, length_threshold: float
) -> list[Change]:
    """Row-by-row changes from ``nominal`` to ``actual`` (same convention, same unit); rows whose
    records changed form are left to :func:`form_changes`."""
    out = []
    for label, pa, pb, ra, rb in _pairs(nominal, actual):
        if type(pa) is not type(pb):
            continue  # changed form: see form_changes
        values_a, values_b = pa.values(), pb.values()
        for param, quantity in type(pa).quantities().items():
            va, vb = values_a[param], values_b[param]
            kind = "length" if quantity == "offset" else quantity
            if quantity == "angle":
                change = float(vb) - float(va)  # type: ignore[arg-type]
                marked = _angle_mod_pi(change) > angle_threshold
                change = math.remainder(change, 2 * math.pi)
            elif quantity == "direction":
                change = math.acos(max(-1.0, min(1.0, float(np.dot(va, vb)))))
                marked = change > angle_threshold
            elif quantity == "offset":
                change = float(np.linalg.norm(np.subtract(vb, va)))
                marked = change > length_threshold
            else:
                change = float(vb) - float(va)  # type: ignore[arg-type]
                marked = abs(change) > length_threshold
            out.append(Change(label, param, va, vb, change, kind, marked))
        out += _motion_changes(label, ra, rb)
    return out


def _motion_changes(label: str, ra: Row | None, rb: Row | None) -> list[Change]:
    if ra is None or rb is None:
        return []
    return [
        Change(label, "pitch", ra.pitch, rb.pitch, rb.pitch - ra.pitch, "pitch", False),
        Change(label, "scale", ra.scale, rb.scale, rb.scale - ra.scale, "scale", False),
    ]


def _pairs(
    nominal: Table, actual: Table
) -> list[tuple[str, Params, Params, Row | None, Row | None]]:
    """The records of both tables side by side, labelled (after checking they match)."""
    if nominal.convention != actual.convention:
        raise UsageError("diff compares tables of one convention")
    if nominal.n != actual.n:
        raise InputError(
            f"NOMINAL has {nominal.n} joints and ACTUAL {actual.n}: the tables do not match"
        )
    rows: list[tuple[str, Params, Params, Row | None, Row | None]] = [
        ("base", nominal.base, actual.base, None, None)
    ]
    for a, b in zip(nominal.rows, actual.rows, strict=True):
        label = a.name if a.name == b.name else f"{a.name}/{b.name}"
        rows.append((label, a.params, b.params, a, b))
    rows.append(("tool", nominal.tool, actual.tool, None, None))
    return rows


def _link(params: Params) -> np.ndarray:
    """The record's link transform at ``q = 0`` (its constant transforms composed)."""
    before, after = params.around_joint()
    return matrix_of(after if before is None else compose(before, after))


def form_changes(
    nominal: Table, actual: Table, angle_threshold: float, length_threshold: float
) -> list[FormChange]:
    """The rows whose records differ in form between the tables (module docstring)."""
    out = []
    for label, pa, pb, _, _ in _pairs(nominal, actual):
        if type(pa) is type(pb):
            continue
        la, lb = _link(pa), _link(pb)
        length = float(np.linalg.norm(lb[:3, 3] - la[:3, 3]))
        rel = la[:3, :3].T @ lb[:3, :3]
        angle = math.acos(max(-1.0, min(1.0, 0.5 * (float(np.trace(rel)) - 1.0))))
        out.append(
            FormChange(
                label,
                pa.form or type(pa).__name__,
                pb.form or type(pb).__name__,
                pa.to_dict(),
                pb.to_dict(),
                la.tolist(),
                lb.tolist(),
                length,
                angle,
                length > length_threshold or angle > angle_threshold,
            )
        )
    return out


def _lines(model: PoeModel) -> tuple[list[str], np.ndarray]:
    """The chain's lines in order, base z, the joint axes, tool z: their names and their
    directions ``(n + 2, 3)``."""
    names = ["base z", *(j.name for j in model.joints), "tool z"]
    axes = [(0.0, 0.0, 1.0), *(j.axis for j in model.joints), model.home[:3, 2]]
    return names, np.array(axes, dtype=float)


def _apart(axes: np.ndarray) -> np.ndarray:
    """Each pair of consecutive directions' angle from (anti-)parallel ``(n + 1,)``, all pairs
    at once: ``atan2(|u x v|, |u . v|)``."""
    u, v = axes[:-1], axes[1:]
    out: np.ndarray = np.arctan2(
        np.linalg.norm(np.cross(u, v), axis=1), np.abs((u * v).sum(axis=1))
    )
    return out


def ill_conditioned(nominal: PoeModel, actual: PoeModel, within: float) -> list[IllPair]:
    """Consecutive lines within ``within`` rad of (anti-)parallel in either model."""
    names, axes = _lines(nominal)
    first, second = _apart(axes).tolist(), _apart(_lines(actual)[1]).tolist()
    return [
        IllPair(names[k], names[k + 1], a, b)
        for k, (a, b) in enumerate(zip(first, second, strict=True))
        if min(a, b) <= within
    ]


def default_length_threshold(unit: str) -> float:
    """:data:`~urdf2dh.tolerances.DIFF_LENGTH_M` in ``unit``."""
    return DIFF_LENGTH_M / units.metres_per(unit)


RECOMMENDATION = (
    "D-H parameters jump near (nearly) parallel axes (Wu 2019 §V-B): identify with CPC or the "
    "POE model and convert back for compensation; modified D-H uses the same common normals and "
    "shares the problem"
)


@dataclass(frozen=True, slots=True)
class Diff:
    """A comparison of two parameter sets in one convention (:func:`diff`).

    Attributes
    ----------
    convention, nominal, actual
        The convention and the two models' names.
    length_unit
        The tables' length unit (the nominal's).
    size
        The nominal's size.
    angle_threshold, length_threshold
        What is marked: changes beyond these (rad; length unit).
    warnings
        The two tables' warnings.
    changes, forms, pairs
        The parameter changes of rows of one form, the rows that changed form, the
        ill-conditioned axis pairs.
    """

    convention: str
    nominal: str
    actual: str
    length_unit: str
    size: float
    angle_threshold: float
    length_threshold: float
    warnings: tuple[str, ...]
    changes: tuple[Change, ...]
    forms: tuple[FormChange, ...]
    pairs: tuple[IllPair, ...]

    @property
    def marked(self) -> int:
        """How many parameters changed beyond the thresholds."""
        return sum(c.marked for c in self.changes)

    def to_dict(self) -> dict[str, Any]:
        """The JSON report as a tree (docs/commands/diff.md gives its shape)."""
        return {
            "schema": SCHEMA,
            "convention": self.convention,
            "nominal": self.nominal,
            "actual": self.actual,
            "units": {"length": self.length_unit, "angle": "rad"},
            "size": self.size,
            "thresholds": {"angle": self.angle_threshold, "length": self.length_threshold},
            "warnings": list(self.warnings),
            "parameters": [asdict(c) for c in self.changes],
            "changed_form": [asdict(f) for f in self.forms],
            "ill_conditioned": [asdict(p) for p in self.pairs],
            "recommendation": RECOMMENDATION if self.pairs else None,
        }

    def render(self, fmt: str = "text") -> str:
        """The report as ``urdf2dh diff`` writes it: ``text`` (angles in degrees) or ``json``
        (radians)."""
        if fmt == "json":
            import json

            return json.dumps(self.to_dict(), indent=2) + "\n"
        if fmt != "text":
            from ..emit.formats import DIFF_FORMATS

            raise UsageError(f"unknown diff format {shown(fmt)}; valid: {choices(DIFF_FORMATS)}")
        return _text(self)

    def __str__(self) -> str:
        """The report as ``urdf2dh diff`` prints it."""
        return _text(self)

    def __repr__(self) -> str:
        return (
            f"<Diff {self.convention}: {shown(self.nominal)} -> {shown(self.actual)}, "
            f"{self.marked} of {len(self.changes)} parameters marked>"
        )

    def _repr_markdown_(self) -> str:
        """In a notebook: the changed parameters as a table, marked ones in bold (names
        escaped)."""
        t, unit = markdown_text, markdown_text(self.length_unit)
        out = [f"**diff ({self.convention})**: {t(self.nominal)} -> {t(self.actual)}; "
               f"{self.marked} parameters changed beyond {math.degrees(self.angle_threshold):g}"
               f" deg or {self.length_threshold:g} {unit}", ""]  # fmt: skip
        shown_value = _shown_value(self)
        rows = [
            [t(c.row), c.param, shown_value(c.nominal, c.kind), shown_value(c.actual, c.kind),
             _delta(self, c) + (" **\\***" if c.marked else "")]
            for c in self.changes if not (c.kind in ("pitch", "scale") and c.change == 0.0)
        ]  # fmt: skip
        out += markdown_table(["row", "param", *labels(self, markdown_text), "change"], rows, 2)
        out += [f"- {t(f.row)}: changed form, {f.nominal_form} -> {f.actual_form}"
                for f in self.forms]  # fmt: skip
        if self.pairs:
            out += ["", RECOMMENDATION]
        return "\n".join(out) + "\n"


def compare_tables(
    nominal: Table,
    actual: Table,
    nominal_model: PoeModel,
    actual_model: PoeModel,
    angle_threshold: float,
    length_threshold: float,
    parallel_within: float,
) -> Diff:
    """Two tables of one convention and unit compared (:func:`diff`); their models name the
    ill-conditioned axis pairs."""
    return Diff(
        nominal.convention,
        nominal_model.name,
        actual_model.name,
        nominal.length_unit,
        nominal_model.size(),
        angle_threshold,
        length_threshold,
        (*nominal.warnings, *actual.warnings),
        tuple(compare(nominal, actual, angle_threshold, length_threshold)),
        tuple(form_changes(nominal, actual, angle_threshold, length_threshold)),
        tuple(ill_conditioned(nominal_model, actual_model, parallel_within)),
    )


def diff(
    nominal: str | os.PathLike[str] | PoeModel,
    actual: str | os.PathLike[str] | PoeModel,
    convention: str = "dh",
    *,
    style: str = "wu",
    tol: Tolerances = DEFAULT,
    angle_threshold: float = math.radians(DIFF_ANGLE_DEG),
    length_threshold: float | None = None,
    parallel_within: float = math.radians(DIFF_PARALLEL_DEG),
    base: str | None = None,
    tip: str | None = None,
    ignore_mimic: bool = False,
    samples: int | None = None,
    xacro: XacroOptions | None = None,
) -> Diff:
    """Two parameter sets side by side: both models as tables of ``convention`` (ACTUAL in
    NOMINAL's length unit), compared row by row (module docstring).

    Parameters
    ----------
    nominal, actual
        Each a SOURCE (as :func:`urdf2dh.load` reads it, the chain ``base -> tip``) or a
        :class:`~urdf2dh.model.poe.PoeModel`.
    convention, style
        The tables compared (:func:`urdf2dh.to_table`).
    tol, samples
        The tolerances of the conversions, and the configurations of their self-checks.
    angle_threshold
        Radians: angle changes beyond this, modulo pi, are marked (default 0.01 deg).
    length_threshold
        Length changes beyond this, in the nominal's unit, are marked (default 0.1 mm in it).
    parallel_within
        Radians: consecutive axes this close to parallel in either model are named as
        ill-conditioned for D-H (default 5 deg).
    base, tip, ignore_mimic, xacro
        How a SOURCE's chain is read: ``base`` and ``tip`` choose the chain of each SOURCE with
        a tree of links (URDF, xacro, MJCF, a bundled robot made from one); a POE or table
        file, or a model, is a single chain and is taken as it is (one of the two may be a
        table of the chain chosen in the other).

    Returns
    -------
    Diff
        Its :meth:`~Diff.render` is what ``urdf2dh diff`` writes.

    Raises
    ------
    Urdf2DhError
        A SOURCE that cannot be read, tables whose joint counts differ, a table that failed its
        own check; ``base`` or ``tip`` where neither side has a tree of links.
    TypeError, ValueError
        An argument of the wrong type or out of range.
    """
    sides = [
        given
        if isinstance(given, PoeModel)
        else open_source(check_source(given, f"diff: {what}"), tol, xacro=xacro)
        for what, given in (("nominal", nominal), ("actual", actual))
    ]
    trees = [side for side in sides if not isinstance(side, PoeModel) and side.tree is not None]
    if (base or tip) and not trees:
        names = " and ".join(shown(s.name if isinstance(s, PoeModel) else s.display) for s in sides)
        raise UsageError(
            f"diff: base and tip links choose the chain of a source with a tree of links (URDF, "
            f"xacro, MJCF); {names} are single chains already"
        )
    models = []
    for side in sides:
        if isinstance(side, PoeModel):
            models.append(side)
            continue
        # the chain base -> tip of a tree; a single chain (a POE or table file) as it is
        model = side.model(base, tip, ignore_mimic) if side.tree is not None else side.model()
        # named as given: a bundled robot by its name, a file by its path
        models.append(model.named(side.name if side.bundled else side.display))
    nominal_model, actual_model = models
    if actual_model.length_unit != nominal_model.length_unit:
        actual_model = actual_model.scaled(
            units.factor(actual_model.length_unit, nominal_model.length_unit),
            nominal_model.length_unit,
        )
    tables = [
        to_table(m, convention, tol, samples=samples, style=style)
        for m in (nominal_model, actual_model)
    ]
    length = (
        default_length_threshold(nominal_model.length_unit)
        if length_threshold is None
        else length_threshold
    )
    return compare_tables(tables[0], tables[1], nominal_model, actual_model,
                          angle_threshold, length, parallel_within)  # fmt: skip


def _decimals(unit: str) -> int:
    """Decimals of a length: to a micrometre or finer."""
    return max(units.DECIMALS.get(unit, 6), round(-math.log10(1e-6 / units.metres_per(unit))))


def _shown_value(d: Diff) -> Callable[[Any, str], str]:
    """How the report writes a parameter's value of a kind (angles in degrees, pitch per
    degree)."""
    decimals = _decimals(d.length_unit)

    def show(value: Any, kind: str) -> str:
        if isinstance(value, list | tuple):
            places = 6 if kind == "direction" else decimals
            return "[" + ", ".join(fixed(v, places) for v in value) + "]"
        if kind == "angle":
            return fixed(math.degrees(value), 4)
        if kind == "pitch":
            return f"{value * math.pi / 180:.6g}"
        return f"{value:.6g}" if kind == "scale" else fixed(value, decimals)

    return show


def _signed(x: float, places: int, exact: float) -> str:
    """``x`` to ``places``; a change under that but beyond round-off (``exact``) in full (3
    digits) rather than as +0.0000."""
    text = fixed(x, places, "+")
    return f"{x:+.3g}" if float(text) == 0.0 and abs(x) > exact else text


def _delta(d: Diff, c: Change) -> str:
    """A change as the report writes it (angles in degrees, to 1e-4 deg)."""
    exact, unit = DIFF_ROUND_OFF, visible(d.length_unit)  # below it: the conversions' round-off
    if c.kind in ("angle", "direction"):
        return f"{_signed(math.degrees(c.change), 4, math.degrees(exact))} deg"
    if c.kind == "pitch":
        return f"{c.change * math.pi / 180:+.3g} {unit}/deg"
    if c.kind == "scale":
        return f"{c.change:+.6g}"
    return f"{_signed(c.change, _decimals(d.length_unit), exact * d.size)} {unit}"


def labels(d: Diff, show: Callable[[str], str] = visible) -> tuple[str, str]:
    """The names of the two columns: what is compared (each source's name, as ``show`` writes
    it; a path by its file name), or ``NOMINAL`` and ``ACTUAL`` where the two names are one."""
    first, second = (os.path.basename(name.rstrip("/\\")) or name for name in (d.nominal, d.actual))
    if not first or not second or first == second:
        return "NOMINAL", "ACTUAL"
    return show(first), show(second)


def _text(d: Diff) -> str:
    """The text report (angles in degrees)."""
    unit, show, exact = d.length_unit, _shown_value(d), DIFF_ROUND_OFF
    rows = [visible(c.row) for c in d.changes]
    width = max(map(len, [*rows, *(visible(f.row) for f in d.forms), "row"]))
    first, second = labels(d)
    w1, w2 = max(28, len(first)), max(28, len(second))
    out = [
        f"diff ({d.convention}): {visible(d.nominal)} -> {visible(d.actual)}; marked (*): "
        f"changes over {math.degrees(d.angle_threshold):g} deg (modulo 180) or "
        f"{d.length_threshold:g} {unit}",
        f"{'row':<{width}}  {'param':<6} {first:>{w1}} {second:>{w2}}  change",
    ]
    for c, row in zip(d.changes, rows, strict=True):
        if c.kind in ("pitch", "scale") and c.change == 0.0:
            continue
        out.append(
            f"{row:<{width}}  {c.param:<6} {show(c.nominal, c.kind):>{w1}} "
            f"{show(c.actual, c.kind):>{w2}}  {_delta(d, c)}{'  *' if c.marked else ''}"
        )
    for f in d.forms:
        out.append(
            f"{visible(f.row):<{width}}  form   {f.nominal_form:>{w1}} {f.actual_form:>{w2}}  "
            f"link moved {_signed(f.length, _decimals(unit), exact * d.size)} {unit}, "
            f"{_signed(math.degrees(f.angle), 4, math.degrees(exact))} deg"
            + ("  *" if f.marked else "")
        )
    marked = d.marked
    out.append(f"{marked} parameter{'' if marked == 1 else 's'} changed beyond the thresholds")
    if d.forms:
        out.append(
            f"{len(d.forms)} row{'' if len(d.forms) == 1 else 's'} changed form (parameters of "
            "different kinds: compared by the link transform each gives)"
        )
    if d.pairs:
        names = ", ".join(
            f"({visible(p.first)}, {visible(p.second)}) {math.degrees(p.nominal_angle):.3f} / "
            f"{math.degrees(p.actual_angle):.3f} deg"
            for p in d.pairs
        )
        out.append(f"ill-conditioned axis pairs (nearly parallel; {first} / {second}): {names}")
        out.append(RECOMMENDATION)
    return "\n".join(out) + "\n"
