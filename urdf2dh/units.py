"""Length units: the one table of them (POE and table files, exports, the URDF writer, diff), and
how a number is written for people (:data:`DECIMALS`, :func:`fixed`).

Angles are radians in every file; lengths are in the source's unit (metres for URDF, the POE
file's ``length_unit`` otherwise) until a target asks for another.
"""

from __future__ import annotations

from .errors import InputError, choices, shown

__all__ = ["DECIMALS", "METRES_PER_UNIT", "factor", "fixed", "metres_per"]

METRES_PER_UNIT = {"m": 1.0, "cm": 0.01, "mm": 0.001, "um": 1e-6, "in": 0.0254, "ft": 0.3048}
ALIASES = {"inch": "in"}

# Decimals of a length in the text and Markdown tables (0.1 to 1 micrometre).
DECIMALS = {"m": 6, "cm": 5, "mm": 4, "um": 2, "in": 5, "ft": 6}


def metres_per(unit: str) -> float:
    """Metres in one ``unit`` (``m``, ``cm``, ``mm``, ``um``, ``in`` or ``inch``, ``ft``)."""
    known = ALIASES.get(unit, unit)
    if known not in METRES_PER_UNIT:
        raise InputError(
            f"unknown length unit {shown(unit)}; known units are {choices(METRES_PER_UNIT)}"
        )
    return METRES_PER_UNIT[known]


def factor(source: str, target: str) -> float:
    """Multiply a length in ``source`` units by this to get ``target`` units."""
    return metres_per(source) / metres_per(target)


def fixed(value: float, decimals: int, sign: str = "") -> str:
    """``value`` with ``decimals`` decimals, never printed as ``-0.000``."""
    text = f"{value:{sign}.{decimals}f}"
    if float(text) == 0.0:
        return f"{0.0:{sign}.{decimals}f}"
    return text
