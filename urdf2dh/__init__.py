"""urdf2dh: a robot's URDF (or POE model) -> exact standard D-H, modified D-H and CPC tables.

The pipeline, in the public names of this package:

>>> import urdf2dh
>>> model = urdf2dh.load("ur5")                  # PoeModel: screws at home + tip pose
>>> table = urdf2dh.to_table(model, "dh")        # Table, checked against the model
>>> pose = table.fk([0.1, -0.5, 1.0, 0.2, 0.3, 0.4])          # (4, 4)
>>> text = urdf2dh.render(table, "json")         # SPEC §2 table file

:func:`load` reads any SOURCE (URDF, xacro, POE file, table file, bundled robot) into a
:class:`PoeModel`; :func:`to_table` converts it to a :class:`Table` in one of
:data:`CONVENTIONS` and checks its forward kinematics against the model's; :func:`render`
writes it; :func:`plot` draws its frames (a picture, or an interactive view as an HTML page).
:meth:`Table.to_poe` goes back. Pinocchio cross-checks live in :mod:`urdf2dh.check.verify`,
controller files in :mod:`urdf2dh.emit.export`, the conventions themselves in
:mod:`urdf2dh.conventions`.

Twists are ``[w, v]`` (angular first); angles are radians; lengths are in the source's unit
(metres for URDF).
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from ._version import __version__

__all__ = [
    "CONVENTIONS",
    "DEFAULT",
    "EXACT",
    "Check",
    "Joint",
    "PoeModel",
    "Row",
    "Table",
    "Tolerances",
    "Urdf2DhError",
    "__version__",
    "load",
    "plot",
    "render",
    "to_table",
]

if TYPE_CHECKING:
    from .conventions import NAMES as CONVENTIONS
    from .conventions.convert import to_table
    from .conventions.table import Check, Row, Table
    from .emit.formats import render
    from .emit.plot import plot
    from .errors import Urdf2DhError
    from .model.poe import Joint, PoeModel
    from .tolerances import DEFAULT, EXACT, Tolerances

_LAZY = {
    "CONVENTIONS": ("urdf2dh.conventions", "NAMES"),
    "to_table": ("urdf2dh.conventions.convert", "to_table"),
    "render": ("urdf2dh.emit.formats", "render"),
    "plot": ("urdf2dh.emit.plot", "plot"),
    "Urdf2DhError": ("urdf2dh.errors", "Urdf2DhError"),
    "Joint": ("urdf2dh.model.poe", "Joint"),
    "PoeModel": ("urdf2dh.model.poe", "PoeModel"),
    "Check": ("urdf2dh.conventions.table", "Check"),
    "Row": ("urdf2dh.conventions.table", "Row"),
    "Table": ("urdf2dh.conventions.table", "Table"),
    "Tolerances": ("urdf2dh.tolerances", "Tolerances"),
    "DEFAULT": ("urdf2dh.tolerances", "DEFAULT"),
    "EXACT": ("urdf2dh.tolerances", "EXACT"),
}


def __getattr__(name: str) -> object:
    # Lazy, so that `urdf2dh --help` does not pay for numpy.
    if name in _LAZY:
        import importlib

        module, attribute = _LAZY[name]
        return getattr(importlib.import_module(module), attribute)
    raise AttributeError(f"module 'urdf2dh' has no attribute {name!r}")


def load(
    source: str | os.PathLike[str],
    base: str | None = None,
    tip: str | None = None,
    ignore_mimic: bool = False,
) -> PoeModel:
    """The POE model of the serial chain in a SOURCE.

    Parameters
    ----------
    source
        A URDF or ``.xacro`` file, a POE model file (SPEC §4), a table file (SPEC §2), or the
        name of a bundled robot (``urdf2dh robots``).
    base, tip
        Links that bound the chain (URDF sources; defaults: the root link, or the bundled
        robot's own, and the single deepest leaf below the base).
    ignore_mimic
        Treat mimic joints on the chain as independent joints (with a warning).

    Returns
    -------
    PoeModel
        The movable joints' screws at the home pose, ``(4, 4)`` home pose of the tip.

    Raises
    ------
    Urdf2DhError
        A one-line message naming the file, link or joint at fault (:class:`SourceError` for
        a SOURCE that is empty or names neither a file nor a bundled robot).
    TypeError
        An argument of the wrong type (``source`` neither text nor a path, ``ignore_mimic``
        not a bool).
    """
    from .checks import check_flag, check_optional_name, check_source
    from .io.sources import open_source

    source = check_source(source, "load: source")
    base = check_optional_name(base, "load: base")
    tip = check_optional_name(tip, "load: tip")
    ignore_mimic = check_flag(ignore_mimic, "load: ignore_mimic")
    return open_source(source).model(base, tip, ignore_mimic)
