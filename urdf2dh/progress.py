"""Progress bars for long runs: on stderr when it is a terminal, nothing otherwise.

Every long loop of a command (verification blocks, chains of a tree, calibration iterations)
reports through :func:`progress`, so that the rule (a bar only for a person watching a terminal,
never in a pipe, a log file or a test) is written once. The bar is tqdm's.
"""

from __future__ import annotations

import sys
from collections.abc import Iterable, Iterator
from typing import TypeVar

__all__ = ["enabled", "progress"]

T = TypeVar("T")


def enabled() -> bool:
    """Whether progress bars are drawn: stderr is a terminal."""
    isatty = getattr(sys.stderr, "isatty", None)
    try:
        return bool(isatty and isatty())
    except ValueError:  # a closed stream
        return False


def progress(items: Iterable[T], total: int | None = None, what: str = "") -> Iterator[T]:
    """Iterate over ``items``, drawing a bar on stderr when it is a terminal.

    Parameters
    ----------
    items
        What to iterate over.
    total
        How many items there are (``len(items)`` when it has one), for the bar's scale.
    what
        The bar's label, e.g. ``"verify"``.
    """
    if not enabled():
        yield from items
        return
    from tqdm import tqdm

    yield from tqdm(items, total=total, desc=what or None, leave=False, file=sys.stderr)
