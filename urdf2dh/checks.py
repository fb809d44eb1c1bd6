"""Validators at the boundary: a file's numbers as finite floats, or a one-line error naming the
field (STYLE: ``check_*`` returns canonical values and says what was expected and what came)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from .errors import InputError

if TYPE_CHECKING:
    from .mimic import Followed, Mimic

__all__ = ["LARGEST", "check_leaders", "check_name", "check_number", "check_vector", "read_mimic"]

# No number a kinematic file holds is larger: 1e12 of any length unit urdf2dh knows is over a
# million kilometres, and angles, scales and limits are far smaller. Beyond it, products and
# sums of squares in the geometry would overflow, so such a number is an input error.
LARGEST = 1e12


def check_number(value: Any, where: str, error: type[InputError] = InputError) -> float:
    """``value`` as a finite float of magnitude at most :data:`LARGEST`; ``error`` naming
    ``where`` for anything else (booleans, strings, non-finite or huge numbers)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise error(f"{where} must be a number, not {_short(value)}")
    try:
        out = float(value)
    except OverflowError as e:
        raise error(f"{where} is too large for a float") from e
    if not math.isfinite(out):
        raise error(f"{where} must be finite")
    if abs(out) > LARGEST:
        raise error(f"{where} is {out:.3g}: beyond {LARGEST:g}, no kinematic number is that large")
    return out


def check_name(value: Any, where: str, error: type[InputError] = InputError) -> str:
    """``value`` as a name: a non-empty string."""
    if not isinstance(value, str) or not value:
        raise error(f"{where} must be a non-empty string, not {_short(value)}")
    return value


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def check_vector(
    value: Any, where: str, error: type[InputError] = InputError
) -> tuple[float, float, float]:
    """``value`` as three finite floats."""
    if not isinstance(value, Sequence) or isinstance(value, str) or len(value) != 3:
        raise error(f"{where} must be a list of 3 numbers")
    x, y, z = (check_number(v, where, error) for v in value)
    return x, y, z


def read_mimic(raw: Any, where: str, error: type[InputError] = InputError) -> Mimic | None:
    """A file's ``mimic: {joint, multiplier, offset}`` (SPEC §5) of the joint at ``where``."""
    from .mimic import Mimic

    if raw is None:
        return None
    if not isinstance(raw, dict) or set(raw) - {"joint", "multiplier", "offset"}:
        raise error(f"{where}: mimic must be a mapping of joint, multiplier and offset")
    return Mimic(
        check_name(raw.get("joint"), f"{where}: mimic joint", error),
        check_number(raw.get("multiplier", 1.0), f"{where}: mimic multiplier", error),
        check_number(raw.get("offset", 0.0), f"{where}: mimic offset", error),
    )


def check_leaders(joints: Sequence[Followed], where: str,
                  error: type[InputError] = InputError) -> None:  # fmt: skip
    """Every mimicking joint follows an actuated joint of the same chain."""
    leaders = {j.name for j in joints if j.mimic is None}
    for j in joints:
        if j.mimic is not None and j.mimic.joint not in leaders:
            raise error(
                f"{where}: joint {j.name!r} mimics {j.mimic.joint!r}, which is not a joint of "
                "the chain without mimic"
            )
