"""Reading table files (``--format json`` or ``yaml``; docs/formats/table-file.md) back into a
:class:`Table`.

A table file is a valid SOURCE: its rows are turned into a POE model (:meth:`Table.to_poe`), so
any convention converts to any other. Every field is checked and a mismatch between ``params``
and the ``matrix`` written beside them is an error, never silently preferred one way. The
table's size is the file's ``size`` (its source's, which the conversion measured its tolerances
against); a file without one (older, or written by hand) takes the size of its POE model's own
points (:meth:`~urdf2dh.model.poe.PoeModel.own_size`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from ..conventions import NAMES, Convention, Params, get
from ..conventions.base import Part, Value, unit_direction
from ..conventions.table import SCHEMA, Check, Row, Table
from ..errors import InputError, TableFileError, choices, shown
from ..model.poe import KINDS
from ..schemas import TABLE_FILE_NAMES
from ..tolerances import DEFAULT, Tolerances
from ..units import metres_per
from .fields import (
    check_joint_count,
    check_leaders,
    check_number,
    check_vector,
    read_mimic,
    read_size,
)
from .sources import Content, Reading, Source

__all__ = ["read_source", "read_table"]


def _matrix_agrees(given: Any, built: np.ndarray, where: str, scale: float) -> None:
    if given is None:
        return
    try:
        m = np.array(given, dtype=float)
    except (TypeError, ValueError) as e:
        raise TableFileError(f"{where}: matrix must be 4x4 numbers") from e
    if m.shape != (4, 4) or not np.all(np.isfinite(m)):
        raise TableFileError(f"{where}: matrix must be 4x4 finite numbers")
    dr = float(np.abs(m[:3, :3] - built[:3, :3]).max())
    dt = float(np.abs(m[:3, 3] - built[:3, 3]).max())
    if dr > 1e-9 or dt > 1e-9 * scale:
        raise TableFileError(
            f"{where}: matrix disagrees with params (by {max(dr, dt / scale):.2g}); "
            "params must reproduce the matrix"
        )


def _text(data: dict[str, Any], key: str, default: str, where: str) -> str:
    """A string field (``default`` where absent); anything but a string is an error."""
    value = data.get(key, default)
    if not isinstance(value, str):
        raise TableFileError(f"{where}: {key} must be a string, not {type(value).__name__}")
    return value


def read_source(content: Content, reading: Reading) -> Source:
    """The SOURCE of a table file, its chain the table's POE model (the ``table`` entry of
    :data:`~urdf2dh.io.sources.READERS`)."""
    table = read_table(content.mapping, content.display, reading.tol)
    name = content.name(table.robot or content.path.stem)
    return Source("table", content.display, name, poe=table.to_poe(), bundled=content.bundled)


def read_table(data: Any, display: str, tol: Tolerances = DEFAULT) -> Table:
    """Check a parsed table file and build the :class:`Table` it describes."""
    if not isinstance(data, dict) or data.get("schema") not in TABLE_FILE_NAMES:
        raise TableFileError(f"{display}: not a table file (needs schema: {SCHEMA})")
    if data.get("convention") not in NAMES:
        raise TableFileError(f"{display}: convention must be one of {choices(NAMES)}")
    conv = get(data["convention"])
    units = data.get("units") or {}
    if units.get("angle", "rad") != "rad":
        raise TableFileError(f"{display}: angles must be in rad (units.angle)")
    length_unit = _text(units, "length", "m", f"{display}: units")
    try:
        metres_per(length_unit)
    except InputError as e:
        raise TableFileError(f"{display}: units.length: {e}") from None
    size = read_size(data, display, length_unit, TableFileError)
    joints = data.get("joints")
    if not isinstance(joints, list):
        raise TableFileError(f"{display}: 'joints' must be a list")
    check_joint_count(len(joints), display, TableFileError)
    rows: list[Row] = []
    seen: set[str] = set()
    for i, j in enumerate(joints, 1):
        if not isinstance(j, dict):
            raise TableFileError(f"{display}: joint {i} must be a mapping")
        name = _text(j, "name", f"joint{i}", f"{display}: joint {i}")
        where = f"{display}: joint {shown(name)}"
        if name in seen:
            raise TableFileError(f"{where} appears twice")
        seen.add(name)
        kind = j.get("type", "revolute")
        if kind not in KINDS:
            raise TableFileError(f"{where} has unknown type {shown(kind)}; valid: {choices(KINDS)}")
        pitch = check_number(j.get("pitch", 0.0), f"{where} pitch", TableFileError)
        if (kind == "helical") != (pitch != 0.0):
            raise TableFileError(f"{where}: type {kind} contradicts pitch {pitch:g}")
        scale = check_number(j.get("scale", 1.0), f"{where} scale", TableFileError)
        if scale == 0.0:
            raise TableFileError(f"{where}: scale must not be 0")
        lower = upper = None
        if j.get("limits") is not None:
            lim = j["limits"]
            if not isinstance(lim, list) or len(lim) != 2:
                raise TableFileError(f"{where}: limits must be [lower, upper]")
            lower, upper = (check_number(x, f"{where} limits", TableFileError) for x in lim)
        params = read_params(conv, "row", j.get("params"), where, tol)
        mimic = read_mimic(j.get("mimic"), where, TableFileError)
        rows.append(Row(name, kind, params, pitch, scale, lower, upper, mimic))
    check_leaders(rows, display, TableFileError)
    sections = {}
    for part in ("base", "tool"):
        sec = data.get(part)
        if not isinstance(sec, dict):
            raise TableFileError(f"{display}: '{part}' must be a mapping with params")
        params = read_params(conv, part, sec.get("params", {}), f"{display}: {part}", tol)
        sections[part] = (params, sec.get("matrix"))
    check = None
    if isinstance(data.get("check"), dict):
        c = data["check"]
        samples = check_number(c.get("samples", 0), f"{display}: check samples", TableFileError)
        if samples < 0 or samples != int(samples):
            raise TableFileError(
                f"{display}: check samples must be a whole number, not {samples:g}"
            )
        check = Check(
            int(samples),
            *(check_number(c.get(k, 0.0), f"{display}: check {k}", TableFileError)
              for k in ("max_position_error", "max_rotation_error", "declared_position",
                        "declared_rotation")),
        )  # fmt: skip
    warnings = data.get("warnings") or []
    if not isinstance(warnings, list) or not all(isinstance(w, str) for w in warnings):
        raise TableFileError(f"{display}: warnings must be a list of strings")
    table = Table(
        conv.name,
        sections["base"][0],
        tuple(rows),
        sections["tool"][0],
        1.0 if size is None else size,
        _text(data, "robot", "", display),
        _text(data, "source", display, display),
        _text(data, "base_link", "", display),
        _text(data, "tip_link", "", display),
        length_unit,
        check,
        tuple(warnings),
    )
    if size is None:  # a file without its robot's size: the size of the table's own points
        table = replace(table, size=table.to_poe().own_size())
    scale = max(1.0, float(np.abs(table.base_matrix[:3, 3]).max()))
    _matrix_agrees(sections["base"][1], table.base_matrix, f"{display}: base", scale)
    _matrix_agrees(sections["tool"][1], table.tool_matrix, f"{display}: tool", scale)
    return table


def read_params(conv: Convention, part: Part, raw: Any, where: str, tol: Tolerances) -> Params:
    """A table file's ``params`` mapping as a record of ``conv`` for ``part``: its keys must be
    exactly one record's parameters; numbers finite; a direction a unit vector within
    ``tol.rotation_input`` (then normalised)."""
    types = {"base": conv.base_types, "row": conv.row_types, "tool": conv.tool_types}[part]
    wanted = " or ".join(str(list(cls.quantities())) for cls in types)
    if not isinstance(raw, Mapping):
        raise TableFileError(f"{where}: params must be a mapping of {wanted}")
    keys = set(raw)
    cls = next((c for c in types if set(c.quantities()) == keys), None)
    if cls is None:
        raise TableFileError(
            f"{where}: params must be exactly {wanted} (got {sorted(map(str, keys))})"
        )
    values: dict[str, Value] = {}
    for name, quantity in cls.quantities().items():
        label = f"{where}: {name}"
        if quantity == "direction":
            v = check_vector(raw[name], label, TableFileError)
            norm = math.hypot(*v)
            if abs(norm - 1.0) > tol.rotation_input:
                raise TableFileError(f"{label} must be a unit vector (|{name}| = {norm:.9g})")
            values[name] = unit_direction(v)
        elif quantity == "offset":
            values[name] = check_vector(raw[name], label, TableFileError)
        else:
            values[name] = check_number(raw[name], label, TableFileError)
    return cls(**values)
