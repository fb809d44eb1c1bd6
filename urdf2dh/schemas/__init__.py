"""The JSON Schemas (draft 2020-12) of the files urdf2dh writes for other programs to read: the
table file, the POE model file and the calibration report, shipped beside this module.

Each written file names its schema in its ``schema`` field, the schema's ``$id``; the readers
accept that name and the one the same format carried before the schemas were published
(docs/formats/).

>>> from urdf2dh import schemas
>>> schemas.TABLE_FILE
'urdf2dh/schemas/table-file-1.schema.json'
>>> schemas.load(schemas.TABLE_FILE)["title"]
'urdf2dh table file'
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "CALIBRATION_REPORT",
    "POE_FILE",
    "TABLE_FILE",
    "TABLE_FILE_NAMES",
    "load",
    "names",
]

#: The table file's schema (``convert --format json|yaml``).
TABLE_FILE = "urdf2dh/schemas/table-file-1.schema.json"
#: What a table file's ``schema`` may hold: the schema's name, or the format's older name.
TABLE_FILE_NAMES = (TABLE_FILE, "urdf2dh/1")
#: The POE model file's schema (``convert --format poe``; optional in a file, which
#: ``format: poe`` already names).
POE_FILE = "urdf2dh/schemas/poe-file-1.schema.json"
#: The calibration report's schema (``calibrate --report``).
CALIBRATION_REPORT = "urdf2dh/schemas/calibration-report-2.schema.json"


def names() -> tuple[str, ...]:
    """Every shipped schema's name (its ``$id``)."""
    return TABLE_FILE, POE_FILE, CALIBRATION_REPORT


def load(name: str) -> dict[str, Any]:
    """The schema called ``name`` (one of :func:`names`), as a JSON tree.

    Raises
    ------
    ValueError
        ``name`` is not a shipped schema's.
    """
    if name not in names():
        raise ValueError(f"no schema named {name!r}; urdf2dh ships {', '.join(names())}")
    import json  # here, not with the module: a conversion names the schemas without reading them
    from importlib import resources

    text = resources.files(__name__).joinpath(name.rsplit("/", 1)[1]).read_text("utf-8")
    schema: dict[str, Any] = json.loads(text)
    return schema
