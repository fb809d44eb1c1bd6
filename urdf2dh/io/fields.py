"""The values of POE and table files: a number as a finite float, a name as a non-empty string, a
3-vector, a mimic relation, a chain's joint count, the robot's size; otherwise a one-line
:class:`~urdf2dh.errors.InputError` (or the subclass the reader passes) naming the field and
saying what was expected and what came.

Numbers come as YAML 1.2 and JSON read them (:mod:`.mappings`), of urdf2dh's one number grammar
(:mod:`urdf2dh.numerals`); where text arrives, the message says why it is not a number, or what a
YAML 1.1 reader would have read it as (:func:`yaml11_note`).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import InputError, shown
from ..model.mimic import Followed, Mimic
from ..numerals import why_not
from ..tolerances import JOINTS, LARGEST_NUMBER, SMALLEST_SIZE

__all__ = [
    "JointBound",
    "check_joint_count",
    "check_leaders",
    "check_name",
    "check_number",
    "check_vector",
    "read_mimic",
    "read_size",
    "yaml11_note",
]


def check_number(value: Any, where: str, error: type[InputError] = InputError) -> float:
    """``value`` as a finite float of magnitude at most
    :data:`~urdf2dh.tolerances.LARGEST_NUMBER`; ``error`` naming
    ``where`` for anything else (booleans, strings, non-finite or huge numbers)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        note = _text_note(value) if isinstance(value, str) else ""
        raise error(f"{where} must be a number, not {shown(value)}{note}")
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


def _text_note(text: str) -> str:
    """Why ``text``, where a number is expected, is not one: another base or not finite (YAML
    1.2 reads these as numbers, urdf2dh's grammar does not), what YAML 1.1 would read it as, or
    the grammar's reason."""
    reason = why_not(text)
    if reason.startswith(("hexadecimal", "octal", "not finite", "digits that")):
        return f" ({reason})"
    return yaml11_note(text) or ("" if reason == "not a decimal number" else f" ({reason})")


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
        raise error(f"{where} must be a non-empty string, not {shown(value)}")
    return value


def check_vector(
    value: Any, where: str, error: type[InputError] = InputError
) -> tuple[float, float, float]:
    """``value`` as three finite floats."""
    if not isinstance(value, Sequence) or isinstance(value, str) or len(value) != 3:
        raise error(f"{where} must be a list of 3 numbers")
    x, y, z = (check_number(v, where, error) for v in value)
    return x, y, z


def read_mimic(raw: Any, where: str, error: type[InputError] = InputError) -> Mimic | None:
    """A file's ``mimic: {joint, multiplier, offset}`` of the joint at ``where``: it moves to
    ``multiplier * q_joint + offset``."""
    if raw is None:
        return None
    if not isinstance(raw, dict) or set(raw) - {"joint", "multiplier", "offset"}:
        raise error(f"{where}: mimic must be a mapping of joint, multiplier and offset")
    return Mimic(
        check_name(raw.get("joint"), f"{where}: mimic joint", error),
        check_number(raw.get("multiplier", 1.0), f"{where}: mimic multiplier", error),
        check_number(raw.get("offset", 0.0), f"{where}: mimic offset", error),
    )


def read_size(
    data: dict[str, Any], where: str, unit: str, error: type[InputError] = InputError
) -> float | None:
    """A file's ``size``: the robot's size in the file's length unit ``unit``
    (:meth:`~urdf2dh.model.poe.PoeModel.size`), a finite number of at least
    :data:`~urdf2dh.tolerances.SMALLEST_SIZE`; ``None`` where the file does not state it."""
    if "size" not in data:
        return None
    size = check_number(data["size"], f"{where}: size", error)
    if not size >= SMALLEST_SIZE:
        raise error(
            f"{where}: size must be positive (the robot's size in {unit}, at least "
            f"{SMALLEST_SIZE:.2g}), not {size:g}"
        )
    return size


def check_joint_count(count: int, where: str, error: type[InputError] = InputError) -> None:
    """At most :data:`~urdf2dh.tolerances.JOINTS` joints in a POE or table file."""
    if count > JOINTS:
        raise error(f"{where}: {count:,} joints; urdf2dh reads chains of at most {JOINTS:,}")


@dataclass(frozen=True, slots=True)
class JointBound:
    """A bound a command sets on the joints of its SOURCE, checked by the reader as soon as they
    are counted (a URDF's joint elements once parsed, before anything is built from them).

    Attributes
    ----------
    most
        The most joints accepted.
    command
        Who says so, in the message (``"verify checks"``).
    why
        Why, in the message (``"(Pinocchio's model of more takes minutes ...)"``).
    """

    most: int
    command: str
    why: str = ""

    def check(self, count: int, display: str, what: str) -> None:
        """Refuse ``count`` joints beyond the bound: ``"<display>: <what> <count> joints;
        <command> at most <most> <why>"``."""
        if count > self.most:
            raise InputError(
                f"{display}: {what} {count:,} joints; {self.command} at most {self.most:,}"
                + (f" {self.why}" if self.why else "")
            )


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
