"""Validators at the boundary: a file's numbers as finite floats, or a one-line error naming the
field (STYLE: ``check_*`` returns canonical values and says what was expected and what came)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from .errors import InputError

__all__ = ["check_number", "check_vector"]


def check_number(value: Any, where: str, error: type[InputError] = InputError) -> float:
    """``value`` as a finite float; ``error`` naming ``where`` for anything else (booleans,
    strings, non-finite or out-of-range numbers)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise error(f"{where} must be a number, not {value!r:.40}")
    try:
        out = float(value)
    except OverflowError as e:
        raise error(f"{where} is too large for a float") from e
    if not math.isfinite(out):
        raise error(f"{where} must be finite")
    return out


def check_vector(
    value: Any, where: str, error: type[InputError] = InputError
) -> tuple[float, float, float]:
    """``value`` as three finite floats."""
    if not isinstance(value, Sequence) or isinstance(value, str) or len(value) != 3:
        raise error(f"{where} must be a list of 3 numbers")
    x, y, z = (check_number(v, where, error) for v in value)
    return x, y, z
