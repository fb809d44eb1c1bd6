"""The levels of identification: what each moves, their names and their order, in one place.

From the least to the most (:mod:`.chart` gives each its coordinates):

* ``base-tool``: the nominal joints, placed in the device frame by a base motion, and the tool
  (or the markers): what an unknown base and tool alone explain, the fair "before" of every
  calibration;
* ``offsets``: and each joint's zero setting;
* ``geometry``: every joint's line (Wu 2019 eq. 23 without the scales);
* ``full``: and every joint's scale (Wu 2019 eq. 23).

``auto`` is not a level: it asks for the level to be chosen (:mod:`.select`), by one of
:data:`RULES`. The module
imports nothing heavy, so that the command line's parsers can list the names.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "AUTO",
    "BASE_TOOL",
    "FULL",
    "GEOMETRY",
    "HIGHER",
    "LEVELS",
    "LOWER",
    "NAMES",
    "OFFSETS",
    "RULES",
    "Level",
    "check_level",
]

AUTO = "auto"  # choose the level (by cross-validation): not a level itself
RULES = ("simplest", "best")  # the simplest level within one SE of the best, or the best


@dataclass(frozen=True, slots=True)
class Level:
    """What one level of identification moves (module docstring).

    Attributes
    ----------
    name
        Its name (``base-tool``, ``offsets``, ``geometry``, ``full``).
    base
        A base motion of its own (the levels whose joints keep the nominal's lines).
    lines
        Every joint's line.
    offsets
        Every joint's zero setting.
    scales
        Every joint's scale.
    """

    name: str
    base: bool
    lines: bool
    offsets: bool
    scales: bool


BASE_TOOL = Level("base-tool", base=True, lines=False, offsets=False, scales=False)
OFFSETS = Level("offsets", base=True, lines=False, offsets=True, scales=False)
GEOMETRY = Level("geometry", base=False, lines=True, offsets=False, scales=False)
FULL = Level("full", base=False, lines=True, offsets=False, scales=True)
LEVELS = {lv.name: lv for lv in (BASE_TOOL, OFFSETS, GEOMETRY, FULL)}  # from the simplest
NAMES = tuple(LEVELS)
LOWER = dict(zip(NAMES[1:], NAMES[:-1], strict=True))  # each level's simpler neighbour
HIGHER = {low: high for high, low in LOWER.items()}  # ... and its richer one


def check_level(name: object, what: str, auto: bool = False) -> str:
    """``name`` if it names a level (or, with ``auto``, is ``auto``); else
    :class:`~urdf2dh.errors.UsageError` listing the valid names."""
    from ..errors import UsageError, choices, shown

    valid = (AUTO, *NAMES) if auto else NAMES
    if not isinstance(name, str) or name not in valid:
        raise UsageError(f"{what}: unknown level {shown(str(name))}; valid: {choices(valid)}")
    return name
