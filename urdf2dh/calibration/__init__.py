"""Kinematic calibration: measured poses or points -> identified POE model -> every table and
controller file urdf2dh writes.

The jobs, as public functions returning typed results:

* :func:`calibrate` -> :class:`Calibration` (:mod:`.calibration`): identify, choosing how much
  by cross-validation, and report;
* :func:`.measure.measure`: synthetic measurements of a model;
* :func:`.plan.plan` -> :class:`Plan`: configurations worth measuring;
* :func:`read_measurements` with a :class:`Reading` (:mod:`.measurements`): measurement files as
  they come.

The pipeline, one idea per module: :mod:`.measurements` (files), :mod:`.chart` (the levels and
their local charts), :mod:`.residuals` (residuals and their analytic Jacobian),
:mod:`.identifiable` (which coordinates a level can identify), :mod:`.prior`, :mod:`.solver`
(Levenberg-Marquardt, statistics), :mod:`.rigid` (rigid fits), :mod:`.start` (options and the
start), :mod:`.identify` (one level's identification), :mod:`.select` (the choice by
cross-validation), :mod:`.outliers`, :mod:`.report` (the report and its text),
:mod:`.plot`, :mod:`.plan`, :mod:`.cli` (the ``measure``, ``calibrate`` and ``plan`` commands),
:mod:`.lie` (batched SO(3)/SE(3) helpers).

Nothing is imported until used, so that ``urdf2dh --help`` (which builds the commands' parsers
from :mod:`.cli`) does not import numpy.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

__all__ = ["Calibration", "Measurements", "Plan", "Reading", "calibrate", "read_measurements"]

if TYPE_CHECKING:
    from .calibration import calibrate
    from .measurements import Measurements, Reading, read_measurements
    from .plan import Plan
    from .result import Calibration

_LAZY = {
    "Calibration": "result",
    "calibrate": "calibration",
    "Measurements": "measurements",
    "Reading": "measurements",
    "read_measurements": "measurements",
    "Plan": "plan",
}


def __getattr__(name: str) -> object:
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
