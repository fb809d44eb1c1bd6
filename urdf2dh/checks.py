"""Validators at the boundary (STYLE: ``check_*`` returns canonical values and says what was
expected and what came).

* A file's values: a number as a finite float, a name as a non-empty string, or a one-line
  :class:`~urdf2dh.errors.InputError` (or the subclass the reader passes) naming the field.
* The Python API's arguments (:func:`urdf2dh.load`, :func:`urdf2dh.to_table`,
  :func:`urdf2dh.render`, the methods of :class:`~urdf2dh.table.Table` and
  :class:`~urdf2dh.screws.PoeModel`, the value types' constructors): a ``TypeError`` for a value
  of the wrong type, a ``ValueError`` for a wrong value (a shape, a non-finite number, a count
  below 1), each naming the argument, what it takes and what it got. Arrays come back as
  canonical float64 arrays; a batch is checked with one vectorised ``np.isfinite(...).all()``.

Everything past these checks trusts its arguments' types.
"""

from __future__ import annotations

import math
import numbers
import os
import re
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from .errors import InputError, shown
from .tolerances import JOINTS, LARGEST_NUMBER, MAX_SAMPLES, MAX_SEED

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from .mimic import Followed, Mimic

__all__ = [
    "check_array",
    "check_configurations",
    "check_count",
    "check_flag",
    "check_instance",
    "check_joint_count",
    "check_leaders",
    "check_limit",
    "check_name",
    "check_number",
    "check_optional_name",
    "check_real",
    "check_seed",
    "check_source",
    "check_vector",
    "read_mimic",
]


def check_number(value: Any, where: str, error: type[InputError] = InputError) -> float:
    """``value`` as a finite float of magnitude at most
    :data:`~urdf2dh.tolerances.LARGEST_NUMBER`; ``error`` naming
    ``where`` for anything else (booleans, strings, non-finite or huge numbers)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        note = yaml11_note(value) if isinstance(value, str) else ""
        raise error(f"{where} must be a number, not {_short(value)}{note}")
    try:
        out = float(value)
    except OverflowError as e:
        raise error(f"{where} is too large for a float") from e
    if not math.isfinite(out):
        raise error(f"{where} must be finite")
    if abs(out) > LARGEST_NUMBER:
        raise error(
            f"{where} is {out:.3g}: beyond {LARGEST_NUMBER:g}, no kinematic number is that large"
        )
    return out


# Text that YAML 1.1 readers (PyYAML's default loader, ROS 1's rosparam) take for a number or a
# boolean, and YAML 1.2 and JSON, which urdf2dh reads, for text (urdf2dh.io.mappings); an integer
# with a leading zero is octal to the one and decimal to the other, and text to urdf2dh
_YAML11_BOOL = re.compile(r"yes|Yes|YES|no|No|NO|on|On|ON|off|Off|OFF")
_YAML11_INT = re.compile(
    r"[-+]?(?:0b[01_]+|0x[0-9a-fA-F_]+|0[0-7_]+|[0-9][0-9_]*(?::[0-5]?[0-9])+|[1-9][0-9_]*)"
)
_YAML11_FLOAT = re.compile(r"[-+]?(?:[0-9][0-9_]*(?::[0-5]?[0-9])+|[0-9_]*)\.[0-9_]*")


def yaml11_note(text: str) -> str:
    """For text where a number was expected: what a YAML 1.1 reader would have made of it, as a
    note for the error message (``""`` if nothing)."""
    if _YAML11_BOOL.fullmatch(text):
        word = "true" if text.lower() in ("yes", "on") else "false"
        return f" (YAML 1.1 reads it as {word}; a number is needed)"
    value = _yaml11_number(text)
    if re.fullmatch(r"[-+]?0[0-9]+", text):
        octal = "text" if value is None else f"octal {value:g}"
        return (
            f" (a leading zero: YAML 1.1 reads it as {octal}, YAML 1.2 as decimal "
            f"{int(text, 10)}; write the number meant without it)"
        )
    if value is None:
        return ""
    return (
        f" (YAML 1.1 reads it as {value:g}; urdf2dh reads YAML 1.2 and JSON, where it is "
        "text: write the number in decimal)"
    )


def _yaml11_number(text: str) -> float | None:
    """The number YAML 1.1 reads ``text`` as (base 60, octal, binary, hexadecimal, digits
    grouped by ``_``), or ``None``."""
    is_int, is_float = _YAML11_INT.fullmatch(text), _YAML11_FLOAT.fullmatch(text)
    if not (is_int or is_float):
        return None
    sign = -1.0 if text.startswith("-") else 1.0
    digits = text.lstrip("+-").replace("_", "")
    try:
        if ":" in digits:
            total = 0.0
            for part in digits.split(":"):
                total = 60.0 * total + float(part)
            return sign * total
        if is_float:
            return sign * float(digits)
        for prefix, base in (("0b", 2), ("0x", 16)):
            if digits.startswith(prefix):
                return sign * int(digits[2:], base)
        return sign * int(digits, 8 if len(digits) > 1 and digits[0] == "0" else 10)
    except (ValueError, OverflowError):
        return None


def check_name(value: Any, where: str, error: type[InputError] = InputError) -> str:
    """``value`` as a name: a non-empty string."""
    if not isinstance(value, str) or not value:
        raise error(f"{where} must be a non-empty string, not {_short(value)}")
    return value


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _got(value: Any) -> str:
    """What came, for a message: its type, and its value where short (``str 'ur5'``)."""
    kind = type(value).__name__
    if value is None:
        return "None"
    if isinstance(value, bool | numbers.Number | str | bytes):
        return f"{kind} {_short(value)}"
    return kind


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


def check_joint_count(count: int, where: str, error: type[InputError] = InputError) -> None:
    """At most :data:`~urdf2dh.tolerances.JOINTS` joints in a POE or table file."""
    if count > JOINTS:
        raise error(f"{where}: {count:,} joints; urdf2dh reads chains of at most {JOINTS:,}")


def check_leaders(joints: Sequence[Followed], where: str,
                  error: type[InputError] = InputError) -> None:  # fmt: skip
    """Every mimicking joint follows an actuated joint of the same chain."""
    leaders = {j.name for j in joints if j.mimic is None}
    for j in joints:
        if j.mimic is not None and j.mimic.joint not in leaders:
            raise error(
                f"{where}: joint {shown(j.name)} mimics {shown(j.mimic.joint)}, which is not a "
                "joint of the chain without mimic"
            )


# --------------------------------------------------------------------------- Python API arguments


def check_instance(value: Any, kind: type, where: str, hint: str = "") -> Any:
    """``value`` if it is a ``kind``; else ``TypeError`` naming ``where`` (``"to_table: model"``)
    and what came, followed by ``hint`` (how to get a ``kind``)."""
    if not isinstance(value, kind):
        raise TypeError(
            f"{where} must be a {kind.__name__}, not {_got(value)}" + (f"; {hint}" if hint else "")
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
    (Whether it names anything is :func:`urdf2dh.sources.open_source`'s to say.)"""
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
