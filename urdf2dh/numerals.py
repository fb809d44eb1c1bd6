"""The one number grammar of every file urdf2dh reads: a URDF's attributes, the numbers of POE
and table files (YAML or JSON) and the cells of a measurement CSV.

A number is a decimal number written in ASCII, as urdfdom's ``strToDouble`` (a classic-locale
``std::stringstream``, the reader of ROS and Pinocchio) and the YAML 1.2 core schema read one:
an optional sign, digits with an optional point and fraction (or a point and a fraction), and an
optional exponent (:data:`DECIMAL`)::

    1   -2.5   .5   5.   +5   1E-3   2.5e+3

and it must be finite in float64. Everything else is refused, whichever file it is in, with the
reason (:func:`why_not`): ``1_000`` (digits grouped), ``0x1F``, ``0o17``, ``0b101`` (another
base), ``nan``, ``inf``, ``.inf``, ``Infinity`` (not finite), ``1e999`` (beyond float64),
``1,5`` (a decimal comma), ``１`` or ``١`` (digits that are not ASCII), ``1e``, ``--1``, ``1.2.3``.
(Python's ``float`` reads several of these; the readers never call it on text this grammar
has not passed.)

What may surround a number is the format's to say: in a URDF attribute, urdfdom's white space
rules (:mod:`urdf2dh.io.urdf.validate`); in a CSV cell, spaces and tabs; in YAML, the scalar is
the number. YAML adds one refusal of its own: an integer written with a leading zero (``0100``),
which YAML 1.1 reads as octal and YAML 1.2 as decimal (:mod:`urdf2dh.io.mappings`).
"""

from __future__ import annotations

import math
import re

from .errors import InputError, shown

__all__ = ["DECIMAL", "INTEGER", "decimal", "integer", "read_decimal", "why_not"]

#: The grammar, as a regular expression (without anchors).
DECIMAL = r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"

#: An integer (a count, a marker's number): decimal ASCII digits with an optional sign.
INTEGER = r"[+-]?[0-9]+"

_DECIMAL = re.compile(DECIMAL)
_INTEGER = re.compile(INTEGER)
_NOT_FINITE = re.compile(r"[+-]?\.?(?:nan|inf|infinity)", re.IGNORECASE)
_BASES = (
    (re.compile(r"[+-]?0[xX][0-9a-fA-F_]*"), "hexadecimal"),
    (re.compile(r"[+-]?0[oO][0-7_]*"), "octal"),
    (re.compile(r"[+-]?0[bB][01_]*"), "binary"),
)


def decimal(text: str) -> float | None:
    """The value of ``text`` if it is a finite number of the grammar (nothing around it), else
    ``None``."""
    if not _DECIMAL.fullmatch(text):
        return None
    value = float(text)  # the grammar is a subset of Python's float syntax
    return value if math.isfinite(value) else None


def integer(text: str) -> int | None:
    """The value of ``text`` if it is an integer of the grammar (nothing around it), else
    ``None`` (Python's ``int`` also takes ``1_000``, ``１`` and white space)."""
    return int(text) if _INTEGER.fullmatch(text) else None


def why_not(text: str) -> str:
    """Why ``text`` is not a number of the grammar, in a few words for a message (``""`` for a
    number)."""
    if _DECIMAL.fullmatch(text):
        return "" if math.isfinite(float(text)) else "beyond the range of float64"
    if _NOT_FINITE.fullmatch(text):
        return "not finite"
    if any(c.isdigit() and not c.isascii() for c in text):
        return "digits that are not ASCII; write 0-9"
    for pattern, base in _BASES:
        if pattern.fullmatch(text):
            return f"{base}; write the number in decimal"
    if "_" in text and _DECIMAL.fullmatch(text.replace("_", "")):
        return "digits grouped with '_'; write them without"
    if "," in text and _DECIMAL.fullmatch(text.replace(",", ".", 1)):
        return "a decimal comma; write a point"
    return "not a decimal number"


def read_decimal(text: str, where: str, error: type[InputError] = InputError) -> float:
    """``text`` as a number of the grammar, or ``error``: ``"<where>: '<text>' is not a number
    (<why>)"`` (``"is not a finite number"`` for ``nan``, ``inf`` and their like)."""
    value = decimal(text)
    if value is not None:
        return value
    reason = why_not(text)
    if reason == "not finite":
        raise error(f"{where}: {shown(text)} is not a finite number")
    if reason == "not a decimal number":
        raise error(f"{where}: {shown(text)} is not a number")
    raise error(f"{where}: {shown(text)} is not a number ({reason})")
