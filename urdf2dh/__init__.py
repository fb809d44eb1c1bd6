"""urdf2dh: a robot's URDF (or POE model) -> exact standard D-H, modified D-H, CPC and Hayati
tables, checked against the source and against Pinocchio; controller files; calibration.

Every job of the ``urdf2dh`` command is a function here, returning a typed value that shows
itself as a table in a notebook:

>>> import urdf2dh
>>> model = urdf2dh.load("ur5")                  # PoeModel: screws at home + tip pose
>>> table = urdf2dh.to_table(model, "dh")        # Table, checked against the model
>>> pose = table.fk([0.1, -0.5, 1.0, 0.2, 0.3, 0.4])          # (4, 4)
>>> text = urdf2dh.render(table, "json")         # a table file (docs/formats/table-file.md)

===============  ===========================================  ===========================
function         does                                         returns
===============  ===========================================  ===========================
:func:`load`     reads a SOURCE (URDF, xacro, POE file,        :class:`PoeModel`
                 table file, bundled robot)
:func:`to_table` converts to a convention, self-checked       :class:`Table`
:func:`render`   writes a table (text, JSON, YAML, CSV, ...)   ``str``
:func:`plot`     draws a table's frames                       ``bytes``
:func:`export`   writes a controller or toolbox file          ``str``
:func:`verify`   every convention against Pinocchio           :class:`VerifyReport`
:func:`diff`     two parameter sets side by side              :class:`Diff`
:func:`match`    which table is this: a hand-written table    :class:`Match`
                 against a robot, what differs in words
:func:`info`     what a SOURCE holds, identifiability         :class:`Info`
:func:`measure`  synthetic measurements of a model            :class:`Measurements`
:func:`calibrate` identifies a model from measurements        :class:`Calibration`
:func:`plan`     configurations worth measuring               :class:`Plan`
===============  ===========================================  ===========================

Twists are ``[w, v]`` (angular first); angles are radians; lengths are in the source's unit
(metres for URDF). Errors are :class:`Urdf2DhError` (:mod:`urdf2dh.errors`), with one-line
messages naming the file, link or joint at fault; wrong argument types are ``TypeError``.

Nothing heavy is imported until a name is used: ``import urdf2dh`` needs no numpy.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ._version import __version__

__all__ = [
    "CONVENTIONS",
    "DEFAULT",
    "EXACT",
    "Calibration",
    "Check",
    "Diff",
    "ExportOptions",
    "Info",
    "Joint",
    "Match",
    "Measurements",
    "ModelCheck",
    "Plan",
    "PoeModel",
    "Row",
    "Table",
    "Tolerances",
    "Urdf2DhError",
    "VerifyReport",
    "XacroOptions",
    "__version__",
    "calibrate",
    "diff",
    "export",
    "info",
    "load",
    "match",
    "measure",
    "plan",
    "plot",
    "render",
    "to_table",
    "verify",
]

if TYPE_CHECKING:
    from .calibration.calibration import calibrate
    from .calibration.measure import measure
    from .calibration.measurements import Measurements
    from .calibration.plan import Plan, plan
    from .calibration.result import Calibration
    from .check.diff import Diff, diff
    from .check.info import Info, info
    from .check.match import Match, match
    from .check.verify import ModelCheck, VerifyReport, verify
    from .conventions import NAMES as CONVENTIONS
    from .conventions.convert import to_table
    from .conventions.table import Check, Row, Table
    from .emit.export import ExportOptions, export
    from .emit.formats import render
    from .emit.plot import plot
    from .errors import Urdf2DhError
    from .io.sources import load
    from .io.xacro import XacroOptions
    from .model.poe import Joint, PoeModel
    from .tolerances import DEFAULT, EXACT, Tolerances

#: Public name -> (module, attribute), imported on first use.
_LAZY = {
    "CONVENTIONS": ("urdf2dh.conventions", "NAMES"),
    "DEFAULT": ("urdf2dh.tolerances", "DEFAULT"),
    "EXACT": ("urdf2dh.tolerances", "EXACT"),
    "Calibration": ("urdf2dh.calibration.result", "Calibration"),
    "Check": ("urdf2dh.conventions.table", "Check"),
    "Diff": ("urdf2dh.check.diff", "Diff"),
    "ExportOptions": ("urdf2dh.emit.export.common", "ExportOptions"),
    "Info": ("urdf2dh.check.info", "Info"),
    "Joint": ("urdf2dh.model.poe", "Joint"),
    "Match": ("urdf2dh.check.match", "Match"),
    "Measurements": ("urdf2dh.calibration.measurements", "Measurements"),
    "ModelCheck": ("urdf2dh.check.verify", "ModelCheck"),
    "Plan": ("urdf2dh.calibration.plan", "Plan"),
    "PoeModel": ("urdf2dh.model.poe", "PoeModel"),
    "Row": ("urdf2dh.conventions.table", "Row"),
    "Table": ("urdf2dh.conventions.table", "Table"),
    "Tolerances": ("urdf2dh.tolerances", "Tolerances"),
    "Urdf2DhError": ("urdf2dh.errors", "Urdf2DhError"),
    "VerifyReport": ("urdf2dh.check.verify", "VerifyReport"),
    "XacroOptions": ("urdf2dh.io.xacro", "XacroOptions"),
    "calibrate": ("urdf2dh.calibration.calibration", "calibrate"),
    "diff": ("urdf2dh.check.diff", "diff"),
    "export": ("urdf2dh.emit.export", "export"),
    "info": ("urdf2dh.check.info", "info"),
    "load": ("urdf2dh.io.sources", "load"),
    "match": ("urdf2dh.check.match", "match"),
    "measure": ("urdf2dh.calibration.measure", "measure"),
    "plan": ("urdf2dh.calibration.plan", "plan"),
    "plot": ("urdf2dh.emit.plot", "plot"),
    "render": ("urdf2dh.emit.formats", "render"),
    "to_table": ("urdf2dh.conventions.convert", "to_table"),
    "verify": ("urdf2dh.check.verify", "verify"),
}


def __getattr__(name: str) -> object:
    # imported on first use, so that `import urdf2dh` (and `urdf2dh --help`) needs no numpy
    if name in _LAZY:
        import importlib

        module, attribute = _LAZY[name]
        return getattr(importlib.import_module(module), attribute)
    raise AttributeError(f"module 'urdf2dh' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
