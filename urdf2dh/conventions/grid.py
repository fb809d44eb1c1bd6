"""A table for people: its cells, with headers, units and decimals (angles in degrees, helix pitch
in length per degree: the units of Wu 2019 Table II), as the text and Markdown formats print it
and as a notebook shows it (:meth:`~.table.Table._repr_markdown_`).

Names from the source are shown by the function each caller passes: :func:`~urdf2dh.errors.visible`
text for the terminal, :func:`~urdf2dh.escape.markdown_text` for Markdown.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING

from ..errors import visible
from ..escape import markdown_table, markdown_text, text_table
from ..units import DECIMALS, fixed
from . import Params, columns, get

if TYPE_CHECKING:
    from .table import Table

__all__ = [
    "flat_columns",
    "flat_params",
    "markdown",
    "parameter_lines",
    "records",
    "summary",
    "text",
]

# --------------------------------------------------------------------------- flat rows

VECTORS = ("direction", "offset")


def flat_columns(table: Table) -> list[tuple[str, str]]:
    """Parameter columns ``(name, quantity)``, vectors split into ``_x``, ``_y``, ``_z``."""
    out: list[tuple[str, str]] = []
    for c in columns(get(table.convention)):
        names = [f"{c.name}_{k}" for k in "xyz"] if c.quantity in VECTORS else [c.name]
        out.extend((name, c.quantity) for name in names)
    return out


def flat_params(params: Params) -> dict[str, float]:
    out: dict[str, float] = {}
    for k, v in params.values().items():
        if isinstance(v, tuple):
            out.update({f"{k}_{c}": x for c, x in zip("xyz", v, strict=True)})
        else:
            out[k] = v
    return out


Record = tuple[str, str, str, float | None, float | None, dict[str, float], str]


def records(table: Table) -> list[Record]:
    """(label, joint, type, pitch, scale, params, form) for base, each joint row and tool."""
    recs: list[Record] = [("base", "", "", None, None, flat_params(table.base), table.base.form)]
    for i, r in enumerate(table.rows, 1):
        recs.append(
            (str(i), r.name, r.kind, r.pitch, r.scale, flat_params(r.params), r.params.form)
        )
    recs.append(("tool", "", "", None, None, flat_params(table.tool), table.tool.form))
    return recs


def _forms(table: Table) -> bool:
    """Whether the convention's rows take several forms (then the text says each row's)."""
    conv = get(table.convention)
    return len({cls.form for cls in (*conv.base_types, *conv.row_types)}) > 1


# --------------------------------------------------------------------------- for people


def _cell(quantity: str, value: float, unit: str) -> str:
    if quantity == "angle":
        return fixed(math.degrees(value), 4)
    if quantity == "direction":
        return fixed(value, 6)
    return fixed(value, DECIMALS.get(unit, 6))


def _header(name: str, quantity: str, unit: str) -> str:
    if quantity == "angle":
        return f"{name} [deg]"
    if quantity == "direction":
        return name
    return f"{name} [{unit}]"


def parameter_lines(params: Params, unit: str) -> list[str]:
    """A record's parameters for people, one ``name [unit] = value`` line each, with the
    headers, units and decimals of the text table (angles in degrees; a 3-vector in
    parentheses)."""
    out = []
    for name, quantity in params.quantities().items():
        value = getattr(params, name)
        cells = [_cell(quantity, v, unit) for v in (value if isinstance(value, tuple) else [value])]
        shown = cells[0] if len(cells) == 1 else "(" + ", ".join(cells) + ")"
        out.append(f"{_header(name, quantity, unit)} = {shown}")
    return out


def _grid(table: Table, show: Callable[[str], str]) -> tuple[list[str], list[list[str]]]:
    """Header and rows of the tables for people; names (and the unit) as ``show`` writes
    them."""
    unit = table.length_unit
    cols = flat_columns(table)
    show_pitch = any(r.kind == "helical" for r in table.rows)
    show_scale = any(r.scale != 1.0 for r in table.rows)
    show_form = _forms(table)
    head = ["", "joint", "type", *(["form"] if show_form else []),
            *(_header(name, quantity, show(unit)) for name, quantity in cols)]  # fmt: skip
    if show_pitch:
        head.append(f"h [{show(unit)}/deg]")
    if show_scale:
        head.append("scale")
    follows = {r.name: r.mimic for r in table.rows if r.mimic}
    if follows:
        head.append("mimics (q = m q_leader + o)")
    body = []
    for label, joint, kind, pitch, scale, params, form in records(table):
        if not params:
            continue  # a record without parameters (CPC's tool: its shape is the last row's)
        line = [label, show(joint), kind, *([form] if show_form else [])]
        line += [_cell(q, params[c], unit) if c in params else "" for c, q in cols]
        if show_pitch:
            line.append("" if pitch is None else f"{pitch * math.pi / 180.0:.6g}")
        if show_scale:
            line.append("" if scale is None else f"{scale:.8g}")
        if follows:
            m = follows.get(joint) if label not in ("base", "tool") else None
            line.append("" if m is None else f"{show(m.joint)} m={m.multiplier:g} o={m.offset:g}")
        body.append(line)
    return head, body


def summary(table: Table) -> list[str]:
    """The self-check and the warnings, one line each (text tables and exported files)."""
    lines = []
    if table.check is not None:
        c = table.check
        lines.append(
            f"check: FK against the source at {c.samples} configurations: max position error "
            f"{c.max_position_error:.2g} {table.length_unit}, max rotation error "
            f"{c.max_rotation_error:.2g} rad"
            + (
                f"; declared bound {c.declared_position:.2g} {table.length_unit}, "
                f"{c.declared_rotation:.2g} rad"
                if c.declared_position or c.declared_rotation
                else ""
            )
        )
    lines.extend(f"warning: {w}" for w in table.warnings)
    return lines


def _title(table: Table, show: Callable[[str], str]) -> str:
    where = f"{show(table.base_link)} -> {show(table.tip_link)}" if table.base_link else ""
    src = f" ({show(table.source)})" if table.source and table.source != table.robot else ""
    return f"{show(table.robot)}{src}  {where}".strip()


def text(table: Table) -> str:
    """The table as ``--format text`` writes it, and ``str(table)`` shows it."""
    head, body = _grid(table, visible)
    out = [_title(table, visible), get(table.convention).title, ""]
    out += text_table(head, body, 4 if _forms(table) else 3)  # label, joint, type (and form)
    out.append("")
    out.extend(visible(s) for s in summary(table))
    return "\n".join(out) + "\n"


def markdown(table: Table) -> str:
    head, body = _grid(table, markdown_text)
    head[0] = "row"
    out = [f"**{_title(table, markdown_text)}** — {get(table.convention).title}", ""]
    out += markdown_table(head, body, 4 if _forms(table) else 3)
    lines = summary(table)
    if lines:
        out.append("")
        out.extend(f"- {markdown_text(s)}" for s in lines)
    return "\n".join(out) + "\n"
