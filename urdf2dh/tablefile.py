"""Reading table files (SPEC §2, ``--format json`` or ``yaml``) back into a :class:`Table`.

A table file is a valid SOURCE: its rows are turned into a POE model (:meth:`Table.to_poe`), so
any convention converts to any other. Every field is checked and a mismatch between ``params``
and the ``matrix`` written beside them is an error, never silently preferred one way.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .errors import TableFileError, choices
from .screws import KINDS
from .table import CONVENTIONS, SCHEMA, Check, Row, Table, convention_module
from .tolerances import DEFAULT, Tolerances

__all__ = ["read_table"]


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise TableFileError(f"{where} must be a number, not {value!r}")
    if not math.isfinite(value):
        raise TableFileError(f"{where} must be finite")
    return float(value)


def _params(raw: Any, names: tuple[str, ...], where: str, tol: Tolerances) -> dict[str, Any]:
    if not isinstance(raw, dict):
        raise TableFileError(f"{where}: params must be a mapping of {list(names)}")
    extra = set(raw) - set(names)
    missing = [n for n in names if n not in raw]
    if missing or extra:
        raise TableFileError(
            f"{where}: params must be exactly {list(names)} (missing {missing}, extra "
            f"{sorted(extra)})"
        )
    out: dict[str, Any] = {}
    for n in names:
        if n in ("b", "l"):
            v = raw[n]
            if not isinstance(v, list) or len(v) != 3:
                raise TableFileError(f"{where}: {n} must be a list of 3 numbers")
            vec = [_number(x, f"{where}: {n}") for x in v]
            if n == "b":
                norm = math.sqrt(sum(x * x for x in vec))
                if abs(norm - 1.0) > tol.rotation_input:
                    raise TableFileError(f"{where}: b must be a unit vector (|b| = {norm:.9g})")
                vec = [x / norm for x in vec]
            out[n] = vec
        else:
            out[n] = _number(raw[n], f"{where}: {n}")
    return out


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


def read_table(data: Any, display: str, tol: Tolerances = DEFAULT) -> Table:
    """Check a parsed table file and build the :class:`Table` it describes."""
    if not isinstance(data, dict) or data.get("schema") != SCHEMA:
        raise TableFileError(f"{display}: not a table file (needs schema: {SCHEMA})")
    conv = data.get("convention")
    if conv not in CONVENTIONS:
        raise TableFileError(f"{display}: convention must be one of {choices(CONVENTIONS)}")
    mod = convention_module(conv)
    units = data.get("units") or {}
    if units.get("angle", "rad") != "rad":
        raise TableFileError(f"{display}: angles must be in rad (units.angle)")
    length_unit = str(units.get("length", "m"))
    joints = data.get("joints")
    if not isinstance(joints, list):
        raise TableFileError(f"{display}: 'joints' must be a list")
    rows = []
    for i, j in enumerate(joints, 1):
        if not isinstance(j, dict):
            raise TableFileError(f"{display}: joint {i} must be a mapping")
        name = str(j.get("name", f"joint{i}"))
        where = f"{display}: joint '{name}'"
        kind = j.get("type", "revolute")
        if kind not in KINDS:
            raise TableFileError(f"{where} has unknown type '{kind}'; valid: {choices(KINDS)}")
        pitch = _number(j.get("pitch", 0.0), f"{where} pitch")
        if (kind == "helical") != (pitch != 0.0):
            raise TableFileError(f"{where}: type {kind} contradicts pitch {pitch:g}")
        scale = _number(j.get("scale", 1.0), f"{where} scale")
        if scale == 0.0:
            raise TableFileError(f"{where}: scale must not be 0")
        lower = upper = None
        if j.get("limits") is not None:
            lim = j["limits"]
            if not isinstance(lim, list) or len(lim) != 2:
                raise TableFileError(f"{where}: limits must be [lower, upper]")
            lower, upper = (_number(x, f"{where} limits") for x in lim)
        params = _params(j.get("params"), mod.PARAMS, where, tol)
        rows.append(Row(name, kind, params, pitch, scale, lower, upper))
    sections = {}
    for part, names in (("base", mod.BASE_PARAMS), ("tool", mod.TOOL_PARAMS)):
        sec = data.get(part)
        if not isinstance(sec, dict):
            raise TableFileError(f"{display}: '{part}' must be a mapping with params")
        sections[part] = (_params(sec.get("params", {}), names, f"{display}: {part}", tol),
                          sec.get("matrix"))
    check = None
    if isinstance(data.get("check"), dict):
        c = data["check"]
        check = Check(int(c.get("samples", 0)), float(c.get("max_position_error", 0.0)),
                      float(c.get("max_rotation_error", 0.0)))
    table = Table(
        conv, sections["base"][0], tuple(rows), sections["tool"][0],
        str(data.get("robot", "")), str(data.get("source", display)),
        str(data.get("base_link", "")), str(data.get("tip_link", "")), length_unit, check,
        tuple(str(w) for w in data.get("warnings") or ()),
    )
    size = max(1.0, float(np.abs(table.base_matrix[:3, 3]).max()))
    _matrix_agrees(sections["base"][1], table.base_matrix, f"{display}: base", size)
    _matrix_agrees(sections["tool"][1], table.tool_matrix, f"{display}: tool", size)
    return table
