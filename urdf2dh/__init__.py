"""urdf2dh: a robot's URDF (or POE model) -> exact standard D-H, modified D-H and CPC tables.

Pipeline: :func:`load` (URDF, POE file, table file or bundled robot -> :class:`PoeModel`),
:func:`to_table` (POE -> :class:`Table` in ``dh``, ``mdh`` or ``cpc``, self-checked), and
:meth:`Table.to_poe` back. Pinocchio cross-checks live in :mod:`urdf2dh.verify`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

__version__ = "0.1.0"

__all__ = [
    "DEFAULT",
    "EXACT",
    "Joint",
    "PoeModel",
    "Table",
    "Tolerances",
    "Urdf2DhError",
    "__version__",
    "load",
    "to_table",
]

if TYPE_CHECKING:
    from .convert import to_table
    from .errors import Urdf2DhError
    from .screws import Joint, PoeModel
    from .table import Table
    from .tolerances import DEFAULT, EXACT, Tolerances

_LAZY = {
    "to_table": "convert",
    "Urdf2DhError": "errors",
    "Joint": "screws",
    "PoeModel": "screws",
    "Table": "table",
    "Tolerances": "tolerances",
    "DEFAULT": "tolerances",
    "EXACT": "tolerances",
}


def __getattr__(name: str) -> object:
    # Lazy, so that `urdf2dh --help` does not pay for numpy.
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module 'urdf2dh' has no attribute {name!r}")


def load(source: str, base: str | None = None, tip: str | None = None,
         ignore_mimic: bool = False) -> PoeModel:
    """The POE model of a SOURCE: URDF file, POE file, table file or bundled robot name."""
    from .sources import open_source

    return open_source(source).model(base, tip, ignore_mimic)
