"""``urdf2dh plot``: a table's frames as a picture (png, svg, pdf) or an interactive view (html).

>>> from urdf2dh import load, plot, to_table
>>> html = plot(to_table(load("panda"), "mdh"), "html")   # one self-contained page
"""

from __future__ import annotations

from ..conventions.table import Table
from ..errors import UsageError, choices
from .scene import scene

__all__ = ["FORMATS", "plot"]

FORMATS = ("png", "svg", "pdf", "html")


def plot(table: Table, fmt: str = "png") -> bytes:
    """``table``'s frames at home, drawn.

    Parameters
    ----------
    table
        A checked table (:func:`urdf2dh.to_table`).
    fmt
        One of :data:`FORMATS`: ``png``, ``svg`` or ``pdf`` (a picture by :mod:`.picture`,
        matplotlib), or ``html`` (a self-contained interactive page by :mod:`.view`, plotly).

    Returns
    -------
    bytes
        The file's content (UTF-8 text for ``svg`` and ``html``).

    Raises
    ------
    TypeError
        ``table`` is not a :class:`~urdf2dh.conventions.table.Table` (a POE model is converted
        first: :func:`urdf2dh.to_table`), or ``fmt`` is not a string.
    UsageError
        An unknown format.
    InputError
        A chain of more than :data:`~.scene.MAX_JOINTS` joints.
    """
    from ..checks import check_instance

    hint = "convert it first: urdf2dh.to_table(model, 'dh')"
    check_instance(table, Table, "plot: table", hint if type(table).__name__ == "PoeModel" else "")
    check_instance(fmt, str, "plot: fmt")
    if fmt not in FORMATS:
        raise UsageError(f"unknown plot format '{fmt}'; valid: {choices(FORMATS)}")
    shown = scene(table)
    if fmt == "html":
        from .view import page

        return page(shown).encode("utf-8")
    from .picture import picture

    return picture(shown, fmt)
