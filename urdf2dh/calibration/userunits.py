"""The one place where a calibration's lengths change unit: between the nominal's (in which every
computation runs) and its user's (in which every stated quantity is given and reported).

The user's length unit is the measurement file's (``--length-unit``, :attr:`.Reading.length_unit`)
when its lengths were converted into the nominal's, else the nominal's own. A noise level given
for the positions (``--noise-pos``, ``noise_pos=``) and a marker layout (``--marker-layout``,
``layout=``) are in that unit, and the report, its text and its picture speak it. Angles are
radians throughout.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .. import units
from .measurements import Measurements

__all__ = ["UserUnits"]

Mat = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class UserUnits:
    """A user's length unit beside the model's.

    Attributes
    ----------
    length
        The user's length unit (``mm``, ...).
    model
        The model's (the nominal's) length unit.
    per_model
        The user's units in one of the model's.
    """

    length: str
    model: str
    per_model: float = 1.0

    @classmethod
    def of(cls, model_unit: str, measurements: Measurements | None = None) -> UserUnits:
        """The units of a calibration of a nominal in ``model_unit`` from ``measurements`` (the
        file's length unit where they were converted from it)."""
        unit = None if measurements is None else measurements.length_unit
        if unit is None or units.factor(unit, model_unit) == 1.0:
            return cls(model_unit, model_unit)
        return cls(unit, model_unit, units.factor(model_unit, unit))

    def shown(self, value: float) -> float:
        """A length in the model's unit, in the user's."""
        return value * self.per_model

    def shown_array(self, values: Mat) -> Mat:
        """Lengths in the model's unit, in the user's."""
        out: Mat = np.asarray(values, dtype=float) * self.per_model
        return out

    def to_model(self, value: float | None) -> float | None:
        """A length the user gave (``None``: none), in the model's unit."""
        return None if value is None else value / self.per_model

    def to_model_array(self, values: Mat) -> Mat:
        """Lengths the user gave, in the model's unit."""
        out: Mat = np.asarray(values, dtype=float) / self.per_model
        return out
