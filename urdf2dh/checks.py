"""The Python API's arguments, checked where they come in (:func:`urdf2dh.load`,
:func:`urdf2dh.to_table`, :func:`urdf2dh.render`, the other public functions, the methods of
:class:`~urdf2dh.conventions.table.Table` and :class:`~urdf2dh.model.poe.PoeModel`, the value
types' constructors): each ``check_*`` returns the canonical value, or raises a ``TypeError``
for a value of the wrong type and a ``ValueError`` for a wrong value (a shape, a non-finite
number, a count below 1), each naming the argument, what it takes and what it got. Arrays come
back as canonical float64 arrays; a batch is checked with one vectorised
``np.isfinite(...).all()``.

Everything past these checks trusts its arguments' types. (The values of files are checked by
their readers, :mod:`urdf2dh.io.fields`.) Internal code that makes a value type out of values
checked already (a table's rows out of a checked model's joints, a table with its self-check
filled in) makes it with :func:`unchecked` or :func:`unchecked_replace`, which skip the
constructor's checks; a value a user constructs is always checked.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import os
from typing import TYPE_CHECKING, Any, TypeVar

from .errors import shown
from .tolerances import MAX_SAMPLES, MAX_SEED

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

T = TypeVar("T")

__all__ = [
    "check_array",
    "check_configurations",
    "check_count",
    "check_flag",
    "check_instance",
    "check_limit",
    "check_optional_name",
    "check_real",
    "check_seed",
    "check_source",
    "unchecked",
    "unchecked_replace",
]


def _got(value: Any) -> str:
    """What came, for a message: its type, and its value where short (``str 'ur5'``)."""
    kind = type(value).__name__
    if value is None:
        return "None"
    if isinstance(value, bool | numbers.Number | str | bytes):
        return f"{kind} {shown(value)}"
    return kind


def _article(word: str) -> str:
    return "an" if word[:1] in "AEIOU" else "a"


def check_instance(value: Any, kind: type, where: str, hint: str = "") -> Any:
    """``value`` if it is a ``kind``; else ``TypeError`` naming ``where`` (``"to_table: model"``)
    and what came, followed by ``hint`` (how to get a ``kind``)."""
    if not isinstance(value, kind):
        raise TypeError(
            f"{where} must be {_article(kind.__name__)} {kind.__name__}, not {_got(value)}"
            + (f"; {hint}" if hint else "")
        )
    return value


def check_flag(value: Any, where: str) -> bool:
    """``value`` as a bool (``True``, ``False``, or a numpy bool)."""
    if type(value).__name__ not in ("bool", "bool_"):
        raise TypeError(f"{where} must be True or False, not {_got(value)}")
    return bool(value)


def check_optional_name(value: Any, where: str) -> str | None:
    """``value`` as a name (a string) or ``None``."""
    if value is not None and not isinstance(value, str):
        raise TypeError(f"{where} must be a string or None, not {_got(value)}")
    return value


def check_source(value: Any, where: str) -> str:
    """A SOURCE: a file path (``str`` or ``os.PathLike``) or a bundled robot's name, as text.
    (Whether it names anything is :func:`urdf2dh.io.sources.open_source`'s to say.)"""
    if isinstance(value, os.PathLike):
        value = os.fspath(value)
    if not isinstance(value, str):
        raise TypeError(
            f"{where} must be a file path or a bundled robot's name (str or os.PathLike), not "
            f"{_got(value)}"
        )
    return value


def check_count(value: Any, where: str, least: int = 1, most: int = MAX_SAMPLES) -> int:
    """``value`` as an int from ``least`` to ``most`` (not a bool, not a float)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{where} must be an integer, not {_got(value)}")
    count = int(value)
    if not least <= count <= most:
        raise ValueError(f"{where} must be from {least} to {most:,}, not {count}")
    return count


def check_seed(value: Any, where: str) -> int:
    """A random seed: an int from 0 to :data:`~urdf2dh.tolerances.MAX_SEED` (as
    ``numpy.random.default_rng`` takes it)."""
    return check_count(value, where, 0, MAX_SEED)


def check_real(value: Any, where: str) -> float:
    """``value`` as a finite float (a real number, not a bool)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{where} must be a number, not {_got(value)}")
    out = float(value)
    if not math.isfinite(out):
        raise ValueError(f"{where} must be finite, not {out!r}")
    return out


def check_limit(value: Any, where: str) -> float | None:
    """A joint limit: a finite float, or ``None`` for none."""
    return None if value is None else check_real(value, where)


def check_array(value: Any, shape: tuple[int | None, ...], where: str) -> NDArray[np.float64]:
    """``value`` as a finite float64 array of ``shape`` (``None``: any length there): numbers
    only (no strings, ``None`` or booleans), every entry finite."""
    a = _numbers(value, where, f"an array of shape {_shape(shape)}")
    if a.ndim != len(shape) or any(
        n is not None and n != m for n, m in zip(shape, a.shape, strict=True)
    ):
        raise ValueError(f"{where} must have shape {_shape(shape)}, not {a.shape}")
    return _finite(a, where)


def check_configurations(q: Any, n: int, where: str, batch: bool = False) -> NDArray[np.float64]:
    """Joint positions for a chain of ``n`` actuated joints: ``(n,)`` or a stack ``(..., n)``,
    or with ``batch`` ``(N, n)`` (or one ``(n,)``); as a finite float64 array."""
    shape = f"(N, {n})" if batch else f"({n},) or (..., {n})"
    a = _numbers(q, where, f"an array of shape {shape}")
    if a.ndim == 0 or a.shape[-1] != n or (batch and a.ndim > 2):
        raise ValueError(
            f"{where} must have shape {shape}, one position per actuated joint, not {a.shape}"
        )
    return _finite(a, where)


def _numbers(value: Any, where: str, expected: str) -> NDArray[np.float64]:
    """``value`` as a float64 array (no copy of one), if it holds real numbers only."""
    import numpy as np

    if isinstance(value, np.ndarray) and value.dtype == np.float64:
        return value
    try:
        a = np.asarray(value)
    except ValueError as e:  # a ragged nesting
        raise ValueError(f"{where} must be {expected} ({e})") from None
    if a.dtype.kind == "O" and all(
        isinstance(x, numbers.Real) and not isinstance(x, bool) for x in a.ravel()
    ):
        a = a.astype(np.float64)
    if a.dtype.kind not in "iuf":
        raise TypeError(f"{where} must be {expected} of numbers, not of {_kind(a)}")
    return np.asarray(a, dtype=np.float64)


def _finite(a: NDArray[np.float64], where: str) -> NDArray[np.float64]:
    """``a``, if every entry is finite (one vectorised test; the first bad entry named)."""
    import numpy as np

    if not np.isfinite(a).all():
        bad = tuple(int(i) for i in np.argwhere(~np.isfinite(a))[0])
        raise ValueError(f"{where} must be finite; entry {bad} is {float(a[bad])!r}")
    return a


def _shape(shape: tuple[int | None, ...]) -> str:
    inner = ", ".join("N" if n is None else str(n) for n in shape)
    return f"({inner},)" if len(shape) == 1 else f"({inner})"


def _kind(a: Any) -> str:
    return {"b": "booleans", "U": "strings", "S": "bytes", "c": "complex numbers"}.get(
        a.dtype.kind, "objects such as None"
    )


_FIELDS: dict[type, tuple[tuple[str, Any], ...]] = {}
_NAMES: dict[type, frozenset[str]] = {}


def _fields(kind: type) -> tuple[tuple[str, Any], ...]:
    """A dataclass's fields in order, each with its default (``dataclasses.MISSING``: none)."""
    known = _FIELDS.get(kind)
    if known is None:
        for f in dataclasses.fields(kind):
            if f.default_factory is not dataclasses.MISSING:
                raise TypeError(f"{kind.__name__}.{f.name}: a default factory is not supported")
        known = _FIELDS[kind] = tuple((f.name, f.default) for f in dataclasses.fields(kind))
        _NAMES[kind] = frozenset(name for name, _ in known)
    return known


def unchecked(kind: type[T], *values: Any) -> T:
    """``kind(*values)`` (a frozen dataclass; fields left out take their defaults) without its
    ``__post_init__`` checks: only for values that have passed those checks already, in the
    canonical form the checks give (floats as ``float``, sequences as tuples)."""
    out: T = object.__new__(kind)
    names = _fields(kind)
    if len(values) > len(names):
        raise TypeError(f"{kind.__name__} takes {len(names)} fields, not {len(values)}")
    for (name, _), value in zip(
        names, (*values, *(d for _, d in names[len(values) :])), strict=True
    ):
        if value is dataclasses.MISSING:
            raise TypeError(f"{kind.__name__}: field {name} is missing")
        object.__setattr__(out, name, value)
    return out


def unchecked_replace(value: T, **changes: Any) -> T:
    """``dataclasses.replace(value, **changes)`` without the constructor's checks: only where
    ``value`` is checked already and ``changes`` are checked values in canonical form
    (:func:`unchecked`)."""
    kind = type(value)
    names = _fields(kind)
    if not _NAMES[kind].issuperset(changes):
        unknown = sorted(set(changes) - _NAMES[kind])
        raise TypeError(f"{kind.__name__} has no field {', '.join(unknown)}")
    out: T = object.__new__(kind)
    for name, _ in names:
        object.__setattr__(out, name, changes[name] if name in changes else getattr(value, name))
    return out
