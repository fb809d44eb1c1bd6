"""Rendering a :class:`~urdf2dh.conventions.table.Table`: text, JSON, YAML, CSV and Markdown.

``json`` and ``yaml`` hold the table file tree (docs/formats/table-file.md) in radians and
source units with full precision;
``csv`` the same numbers flat; ``text`` and ``markdown`` are for people: angles in degrees,
helix pitch in length per degree (the units of Wu 2019 Table II), units in the headers.
Names from the source go through :mod:`urdf2dh.escape`: JSON and YAML escape them
themselves, CSV writes them as :func:`~urdf2dh.escape.csv_cell` does (visible text, no
formula), text shows them as :func:`~urdf2dh.errors.visible` text (one line, no terminal control
characters) and Markdown escapes its markup too.
``urdf`` and ``poe`` write the table's kinematics as a model instead: a URDF in metres
(:mod:`urdf2dh.emit.urdf`) or a POE model file (YAML, docs/formats/poe-file.md).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..conventions.grid import flat_columns, markdown, records, text
from ..errors import UsageError, choices, near
from ..escape import csv_cell

if TYPE_CHECKING:
    from ..conventions.table import Table

__all__ = ["DIFF_FORMATS", "FORMATS", "SUFFIXES", "format_of", "render"]

FORMATS = ("text", "json", "yaml", "csv", "markdown", "urdf", "poe")
DIFF_FORMATS = ("text", "json")  # a diff's report (urdf2dh.check.diff.Diff.render)

#: The file-name suffixes of each format, the one urdf2dh names its files with first
#: (``-o DIR/<tip><suffix>``). A file named with one of them is of that format: ``-o FILE``
#: without ``--format`` writes it, and a ``--format`` that contradicts it is refused.
SUFFIXES = {
    "text": (".txt",),
    "json": (".json",),
    "yaml": (".yaml", ".yml"),
    "csv": (".csv",),
    "markdown": (".md", ".markdown"),
    "urdf": (".urdf",),
    "poe": (".poe.yaml", ".poe.yml"),
}


def format_of(name: str) -> str | None:
    """The format whose suffix ends the file name ``name`` (the longest suffix that matches, so
    ``x.poe.yaml`` is ``poe``; case is ignored), or None."""
    lowered = name.lower()
    found = [(len(s), fmt) for fmt, ss in SUFFIXES.items() for s in ss if lowered.endswith(s)]
    return max(found)[1] if found else None


def render(table: Table, fmt: str) -> str:
    """The table in format ``fmt``, ending with a newline.

    Parameters
    ----------
    table
        A checked table (:func:`urdf2dh.to_table`).
    fmt
        One of :data:`FORMATS`: ``json`` and ``yaml`` (the table file: radians, the source's
        length unit, full precision), ``csv``, ``text`` and ``markdown`` (degrees, for people),
        ``urdf`` (metres) or ``poe`` (a POE model file).

    Returns
    -------
    str
        The file's text.

    Raises
    ------
    TypeError
        ``table`` is not a :class:`~urdf2dh.conventions.table.Table` (a POE model is converted
        first: :func:`urdf2dh.to_table`), or ``fmt`` is not a string.
    UsageError
        An unknown format (a ``ValueError`` too).
    ExportError
        A name the format cannot carry (``urdf``: a character XML 1.0 has no way to write).
    """
    from ..checks import check_instance
    from ..conventions.table import Table

    hint = "convert it first: urdf2dh.to_table(model, 'dh')"
    check_instance(
        table, Table, "render: table", hint if type(table).__name__ == "PoeModel" else ""
    )
    check_instance(fmt, str, "render: fmt")
    if fmt == "json":
        import json

        return json.dumps(table.to_dict(), indent=2) + "\n"
    if fmt == "yaml":
        import yaml

        return str(yaml.safe_dump(table.to_dict(), sort_keys=False, default_flow_style=None))
    if fmt == "csv":
        return _csv(table)
    if fmt == "text":
        return text(table)
    if fmt == "markdown":
        return markdown(table)
    if fmt == "urdf":
        from .urdf import table_to_urdf

        return table_to_urdf(table)[0]
    if fmt == "poe":
        import yaml

        from ..io.poefile import poe_to_dict

        tree = poe_to_dict(table.to_poe())
        return str(yaml.safe_dump(tree, sort_keys=False, default_flow_style=None))
    raise UsageError(f"unknown format '{fmt}'{near(fmt, FORMATS)}; valid: {choices(FORMATS)}")


def _csv(table: Table) -> str:
    cols = [name for name, _ in flat_columns(table)]
    lines = [",".join(["row", "joint", "type", "pitch", "scale", *cols])]
    for label, joint, kind, pitch, scale, params, _ in records(table):
        cells = [
            label,
            csv_cell(joint),
            kind,
            "" if pitch is None else repr(pitch),
            "" if scale is None else repr(scale),
        ]
        lines.append(",".join(cells + [repr(params[c]) if c in params else "" for c in cols]))
    return "\n".join(lines) + "\n"
