"""Tables as people write them: a datasheet's, a paper's or a vendor's D-H table, read with the
precision it is written in (docs/commands/match.md).

A hand-written table is

* a CSV file whose header names the columns ``theta`` (``θ``), ``d``, ``a`` (or ``r``) and
  ``alpha`` (``α``) in any order, with optional ``joint`` (or ``name``) and ``type`` columns; a
  column's unit may be written in its header (``theta [deg]``, ``d (mm)``, ``a_mm``); lines
  starting with ``#`` are comments (provenance);
* or a YAML (or JSON) list of rows with those keys, or a mapping with that list under
  ``joints:`` and, beside it, any of ``units: {length: mm, angle: deg}``, ``convention: dh`` or
  ``mdh``, ``robot:`` and ``source:`` (where the numbers were published).

A cell is a number (``0.089159``, ``-90``, ``1.5e-3``), a number with a degree sign (``90°``), a
fraction of pi (``pi/2``, ``-π``, ``2*pi/3``), or in the column holding the joint variable that
symbol with an offset (``q2 - 90``, ``θ1``, ``d3``): a variable in the ``d`` column makes the
row a prismatic joint, in the ``theta`` column a revolute one. A row of ``type: fixed`` (or
``flange``, ``tool``) is a constant transform with no joint (Franka's flange row).

Each number keeps the step of its last written digit (``0.1519``: 5e-5), so that what the table
can say is judged at the precision it was written in; ``pi/2`` and ``90°`` are exact.
"""

from __future__ import annotations

import csv
import io
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Literal

from ..errors import InputError, choices, shown
from ..numerals import DECIMAL, decimal, why_not
from ..units import metres_per
from .encodings import check_text
from .fields import check_joint_count
from .files import read_file

__all__ = [
    "ANGLE_UNITS",
    "COLUMNS",
    "HandRow",
    "HandTable",
    "Written",
    "is_hand_table",
    "read_hand_table",
]

COLUMNS = ("theta", "d", "a", "alpha")
ANGLE_UNITS = ("deg", "rad")
RowKind = Literal["revolute", "prismatic", "fixed"]

_NAMES = {
    "theta": "theta", "θ": "theta", "th": "theta", "offset": "theta", "theta_offset": "theta",
    "d": "d",
    "a": "a", "r": "a",
    "alpha": "alpha", "α": "alpha",
    "joint": "name", "name": "name", "link": "name", "i": "name", "#": "name", "row": "name",
    "type": "type", "kind": "type",
}  # fmt: skip
_UNIT_WORDS = {
    "deg": "deg", "degree": "deg", "degrees": "deg", "°": "deg",
    "rad": "rad", "radian": "rad", "radians": "rad",
    "m": "m", "mm": "mm", "cm": "cm", "in": "in", "inch": "in", "um": "um",
}  # fmt: skip
_KINDS = {
    "revolute": "revolute", "r": "revolute", "continuous": "revolute",
    "prismatic": "prismatic", "p": "prismatic",
    "fixed": "fixed", "f": "fixed", "flange": "fixed", "tool": "fixed",
}  # fmt: skip
_HEADER = re.compile(r"^\s*([^\[\(]*?)\s*(?:[\[\(]\s*([^\]\)]*?)\s*[\]\)])?\s*$")
_NUMBER = DECIMAL  # the one number grammar (urdf2dh.numerals): ASCII digits
_PI = re.compile(rf"^([-+]?)\s*(?:({_NUMBER})\s*\*?\s*)?(?:pi|π)\s*(?:/\s*({_NUMBER}))?$")
_VARIABLE = re.compile(r"^\s*(q|θ|theta|th|d)_?\{?[0-9]*\}?\s*(?:([-+])\s*(.*))?$", re.IGNORECASE)
_SYMBOLS = {"theta": ("q", "θ", "theta", "th"), "d": ("q", "d")}


@dataclass(frozen=True, slots=True)
class Written:
    """A number as the table wrote it: its value, the step of its last written digit (0 for
    an exact value such as ``pi/2`` or ``90°``), the angle unit the cell itself says (``deg``
    for a degree sign, ``rad`` for a fraction of pi, else ``None``) and its text."""

    value: float
    step: float
    unit: str | None = None
    text: str = ""


ZERO = Written(0.0, 0.0, None, "0")


@dataclass(frozen=True, slots=True)
class HandRow:
    """One row: its name, its kind where the table says it (a ``type`` column or a joint
    variable in a cell), and its four numbers (``theta`` and ``d`` without the variable)."""

    name: str
    kind: RowKind | None
    theta: Written
    d: Written
    a: Written
    alpha: Written

    def number(self, column: str) -> Written:
        """The cell of ``column`` (``theta``, ``d``, ``a`` or ``alpha``)."""
        out: Written = getattr(self, column)
        return out


@dataclass(frozen=True, slots=True)
class HandTable:
    """A hand-written table as read: its rows, and what it states of itself (``None`` where it
    is silent: the convention, the length unit and the angle unit of each angle column).

    Attributes
    ----------
    display
        The file, as messages name it.
    rows
        The rows in order, fixed rows included.
    convention
        ``dh`` or ``mdh`` where the file says, else ``None``.
    length_unit
        The lengths' unit where stated (``m``, ``mm``, ...), else ``None``.
    angle_units
        ``{"theta": ..., "alpha": ...}``: ``deg`` or ``rad`` where stated, else ``None``.
    robot, source
        What the file says it describes and where its numbers come from.
    """

    display: str
    rows: tuple[HandRow, ...]
    convention: str | None = None
    length_unit: str | None = None
    angle_units: tuple[tuple[str, str | None], ...] = (("theta", None), ("alpha", None))
    robot: str = ""
    source: str = ""

    def angle_unit(self, column: str) -> str | None:
        """The stated unit of angle column ``column``, or ``None``."""
        return dict(self.angle_units)[column]

    @property
    def joints(self) -> tuple[HandRow, ...]:
        """The rows that are joints (not fixed)."""
        return tuple(r for r in self.rows if r.kind != "fixed")


def is_hand_table(tree: Any) -> bool:
    """Whether a parsed YAML or JSON tree is a hand-written table (a list of rows, or rows
    under ``joints:``) rather than a table file or a POE model file."""
    if isinstance(tree, Mapping):
        if "schema" in tree or "format" in tree:
            return False
        tree = tree.get("joints")
    if not isinstance(tree, list) or not tree:
        return False
    return all(isinstance(r, Mapping) for r in tree) and any(
        _column(str(k))[0] in COLUMNS for k in tree[0]
    )


def read_hand_table(path: str | Path, display: str | None = None) -> HandTable:
    """Read a hand-written table (module docstring) from a CSV, YAML or JSON file.

    Raises
    ------
    InputError
        A file that cannot be read, or a table naming an unknown column, a cell that is not a
        number, a unit urdf2dh does not know, or no rows; the message names the file, the row
        and the column.
    """
    path = Path(path)
    display = display or str(path)
    data = read_file(path, display)
    check_text(data, display, "a table")
    if path.suffix.lower() == ".csv":
        return _from_csv(data.decode("utf-8-sig"), display)
    from .mappings import read_mapping

    return from_tree(read_mapping(path, display, data), display)


def from_tree(tree: Any, display: str) -> HandTable:
    """A hand-written table from its parsed YAML or JSON tree."""
    meta: Mapping[str, Any] = tree if isinstance(tree, Mapping) else {}
    rows_raw = meta.get("joints") if meta else tree
    if not is_hand_table(tree):
        raise InputError(
            f"{display}: not a hand-written table: expected a list of rows with columns "
            f"{', '.join(COLUMNS)} (or that list under 'joints:')"
        )
    known = {"joints", "units", "convention", "robot", "source"}
    unknown = [k for k in meta if k not in known]
    if unknown:
        raise InputError(
            f"{display}: unknown key {shown(unknown[0])}; a hand-written table has {choices(known)}"
        )
    convention = meta.get("convention")
    if convention is not None and convention not in ("dh", "mdh"):
        raise InputError(f"{display}: convention must be dh or mdh, not {shown(convention)}")
    units = meta.get("units") or {}
    if not isinstance(units, Mapping):
        raise InputError(f"{display}: units must be a mapping such as {{length: mm, angle: deg}}")
    bad = [k for k in units if k not in ("length", "angle")]
    if bad:
        raise InputError(f"{display}: units: unknown key {shown(bad[0])}; valid: [angle, length]")
    length = _length_unit(units.get("length"), f"{display}: units.length")
    angle = _angle_unit(units.get("angle"), f"{display}: units.angle")
    header: dict[str, str | None] = {"theta": angle, "alpha": angle}
    rows = []
    assert isinstance(rows_raw, list)
    for i, raw in enumerate(rows_raw, 1):
        cells: dict[str, Any] = {}
        for key, value in raw.items():
            column, unit = _column(str(key))
            if column is None:
                raise InputError(
                    f"{display}: row {i}: unknown column {shown(key)}; valid: "
                    f"{choices((*COLUMNS, 'name', 'type'))}"
                )
            if unit is not None:
                _column_unit(column, unit, header, f"{display}: row {i}: {key}")
                if column in ("d", "a"):
                    length = _merge(length, unit, f"{display}: row {i}: {key}")
            cells[column] = value
        rows.append(_row(cells, i, display))
    return _table(display, rows, convention, length, header, meta)


def _from_csv(text: str, display: str) -> HandTable:
    lines = [line for line in text.splitlines() if not line.lstrip().startswith("#")]
    notes = [line.lstrip()[1:].strip() for line in text.splitlines() if line.lstrip()[:1] == "#"]
    reader = csv.reader(io.StringIO("\n".join(lines)), skipinitialspace=True)
    records = [r for r in reader if any(c.strip() for c in r)]
    if not records:
        raise InputError(f"{display}: no header row (the columns theta, d, a, alpha)")
    header: dict[str, str | None] = {"theta": None, "alpha": None}
    columns: list[str] = []
    length: str | None = None
    for cell in records[0]:
        column, unit = _column(cell)
        if column is None:
            raise InputError(
                f"{display}: unknown column {shown(cell)}; valid: "
                f"{choices((*COLUMNS, 'name', 'type'))} (a unit may follow, as in 'd [mm]')"
            )
        if column in columns:
            raise InputError(f"{display}: column {shown(cell)} appears twice")
        if unit is not None:
            _column_unit(column, unit, header, f"{display}: column {shown(cell)}")
            if column in ("d", "a"):
                length = _merge(length, unit, f"{display}: column {shown(cell)}")
        columns.append(column)
    missing = [c for c in COLUMNS if c not in columns]
    if missing:
        raise InputError(
            f"{display}: no column {missing[0]} (the header names {', '.join(columns)})"
        )
    rows = []
    for i, record in enumerate(records[1:], 1):
        if len(record) != len(columns):
            raise InputError(
                f"{display}: row {i} has {len(record)} cells, the header {len(columns)}"
            )
        rows.append(_row(dict(zip(columns, record, strict=True)), i, display))
    source = " ".join(notes)
    return _table(display, rows, None, length, header, {"source": source} if source else {})


def _table(
    display: str,
    rows: list[HandRow],
    convention: str | None,
    length: str | None,
    header: dict[str, str | None],
    meta: Mapping[str, Any],
) -> HandTable:
    if not rows:
        raise InputError(f"{display}: no rows")
    if any(r.kind is not None for r in rows):  # joint variables marked: other rows are fixed
        rows = [r if r.kind is not None else replace(r, kind="fixed") for r in rows]
    check_joint_count(len(rows), display)
    if not any(r.kind != "fixed" for r in rows):
        raise InputError(f"{display}: every row is fixed; a table needs a joint")
    names = [r.name for r in rows]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise InputError(f"{display}: row {shown(twice[0])} appears twice")
    for r in rows:  # a cell's own unit (90°, pi/2) states its column's
        for column in ("theta", "alpha"):
            unit = r.number(column).unit
            if unit is not None and r.number(column).value != 0.0:
                header[column] = _merge(header[column], unit, f"{display}: row {shown(r.name)}")
    text = {k: meta.get(k, "") for k in ("robot", "source")}
    for key, value in text.items():
        if not isinstance(value, str):
            raise InputError(f"{display}: {key} must be text, not {shown(value)}")
    return HandTable(display, tuple(rows), convention, length,
                     (("theta", header["theta"]), ("alpha", header["alpha"])),
                     text["robot"], text["source"])  # fmt: skip


def _column(text: str) -> tuple[str | None, str | None]:
    """A header's column and the unit written with it (``theta [deg]``, ``d_mm``)."""
    match = _HEADER.match(text.strip().lower())
    if match is None:
        return None, None
    name, unit = match.group(1).strip(), match.group(2)
    if unit is None and "_" in name:
        head, _, tail = name.rpartition("_")
        if tail in _UNIT_WORDS and head in _NAMES:
            name, unit = head, tail
    if unit is None and name.endswith("°") and name[:-1].strip() in _NAMES:
        name, unit = name[:-1].strip(), "°"
    column = _NAMES.get(name)
    if column is None:
        return None, None
    return column, (unit.strip() if unit else None)


def _column_unit(column: str, unit: str, header: dict[str, str | None], where: str) -> None:
    word = _UNIT_WORDS.get(unit.lower())
    if column in ("theta", "alpha"):
        if word not in ANGLE_UNITS:
            raise InputError(f"{where}: an angle's unit is deg or rad, not {shown(unit)}")
        header[column] = _merge(header[column], word, where)
    elif column in ("d", "a"):
        _length_unit(word or unit, where)
    else:
        raise InputError(f"{where}: column {column} has no unit")


def _length_unit(unit: Any, where: str) -> str | None:
    if unit is None:
        return None
    if not isinstance(unit, str):
        raise InputError(f"{where}: a length unit is text such as mm, not {shown(unit)}")
    word = _UNIT_WORDS.get(unit.lower(), unit)
    try:
        metres_per(word)
    except InputError as e:
        raise InputError(f"{where}: {e}") from None
    return word


def _angle_unit(unit: Any, where: str) -> str | None:
    if unit is None:
        return None
    word = _UNIT_WORDS.get(str(unit).lower())
    if word not in ANGLE_UNITS:
        raise InputError(f"{where}: an angle's unit is deg or rad, not {shown(unit)}")
    return word


def _merge(stated: str | None, unit: str, where: str) -> str:
    word = _UNIT_WORDS.get(unit.lower(), unit)
    if stated is not None and stated != word:
        raise InputError(f"{where}: unit {word} contradicts {stated} stated before")
    return word


def _row(cells: Mapping[str, Any], i: int, display: str) -> HandRow:
    name_cell = cells.get("name")
    name = f"joint{i}" if name_cell in (None, "") else str(name_cell).strip()
    where = f"{display}: row {shown(name)}"
    kind: RowKind | None = None
    type_cell = cells.get("type")
    if type_cell not in (None, ""):
        kind_text = str(type_cell).strip().lower()
        if kind_text not in _KINDS:
            raise InputError(
                f"{where}: type {shown(type_cell)} is not one of [revolute, prismatic, fixed]"
            )
        kind = _KINDS[kind_text]  # type: ignore[assignment]
    missing = [c for c in COLUMNS if c not in cells]
    if missing:
        raise InputError(f"{where}: no {missing[0]}")
    numbers: dict[str, Written] = {}
    variable = None
    for column in COLUMNS:
        value, moves = _cell(cells[column], column, f"{where}: {column}")
        numbers[column] = value
        if moves:
            if variable is not None:
                raise InputError(f"{where}: both theta and d hold the joint variable")
            variable = column
    if variable is not None:
        implied: RowKind = "revolute" if variable == "theta" else "prismatic"
        if kind is not None and kind != implied:
            raise InputError(f"{where}: type {kind} contradicts the variable in {variable}")
        kind = implied
    return HandRow(name, kind, numbers["theta"], numbers["d"], numbers["a"], numbers["alpha"])


def _cell(raw: Any, column: str, where: str) -> tuple[Written, bool]:
    """A cell's number and whether it holds the joint variable (``q2 - 90``)."""
    if isinstance(raw, bool) or raw is None:
        raise InputError(f"{where} must be a number, not {shown(raw)}")
    if isinstance(raw, int | float):
        return _checked(float(raw), _step(repr(raw) if isinstance(raw, float) else str(raw)),
                        None, repr(raw), where), False  # fmt: skip
    text = str(raw).strip()
    moves = False
    if column in ("theta", "d"):
        match = _VARIABLE.match(text)
        if match is not None and match.group(1).lower() in _SYMBOLS[column]:
            rest = match.group(3)
            if match.group(2) is None:
                return ZERO, True
            if not rest:
                raise InputError(f"{where}: {shown(text)}: an offset must follow the sign")
            text, moves = f"{match.group(2)}{rest.strip()}", True
    return _number(text, where), moves


def _number(text: str, where: str) -> Written:
    compact = text.replace(" ", "")
    unit = None
    for suffix in ("°", "deg"):
        if compact.lower().endswith(suffix):
            compact, unit = compact[: -len(suffix)], "deg"
    match = _PI.match(compact)
    if match is not None and unit is None:
        sign = -1.0 if match.group(1) == "-" else 1.0
        factor = decimal(match.group(2)) if match.group(2) else 1.0
        divisor = decimal(match.group(3)) if match.group(3) else 1.0
        if factor is None or divisor is None:
            raise InputError(f"{where}: {shown(text)}: a number beyond the range of float64")
        if divisor == 0.0:
            raise InputError(f"{where}: {shown(text)} divides by zero")
        return _checked(sign * factor * math.pi / divisor, 0.0, "rad", text, where)
    value = decimal(compact)
    if value is None:
        reason = why_not(compact)
        raise InputError(
            f"{where} must be a number, a fraction of pi or an angle in degrees, not {shown(text)}"
            + ("" if reason == "not a decimal number" else f" ({reason})")
        )
    step = 0.0 if unit == "deg" and value == round(value) else _step(compact)
    return _checked(value, step, unit, text, where)


def _checked(value: float, step: float, unit: str | None, text: str, where: str) -> Written:
    from ..io.fields import check_number

    return Written(check_number(value, where), step, unit, text)


def _step(text: str) -> float:
    """Half the unit of the last written digit of a decimal number's text (``0.1519``:
    ``5e-5``; ``90``: ``0.5``; ``1.5e-3``: ``5e-5``)."""
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.partition(".")[2]) - (int(exponent) if exponent else 0)
    return 0.5 * 10.0 ** (-decimals)
