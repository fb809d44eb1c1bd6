"""The one strict check of a URDF document, run on every file before anything is built from it.

It walks the lxml element tree once and reports the first fault on one line naming the file, the
joint or link, and the attribute. What it passes, the rest of the package trusts: every name is
present and unique, every joint joins two declared links, and every number urdf2dh reads obeys
the grammar below.

Numbers follow urdfdom, the parser of ROS and Pinocchio (``urdf_parser``: ``Vector3::init``
splits the attribute at spaces and converts each piece with ``strToDouble``, a classic-locale
``std::stringstream >> double`` that must consume the whole piece): a decimal number with an
optional sign, fraction and exponent, nothing else. So ``1_0``, ``0x10``, ``nan``, ``inf``,
``1e999`` (overflow), ``1,5`` and a tab between numbers are refused, as is a vector with too few
or too many numbers (``xyz="0 0 1 4"``); ``.5``, ``5.``, ``+5`` and ``1E-3`` are read. Lengths,
limits and mimic factors are also bounded by :data:`~urdf2dh.tolerances.LARGEST_URDF_NUMBER`,
and a revolute joint's limits by :data:`~urdf2dh.tolerances.LARGEST_URDF_ANGLE`.

Axes are normalised by urdfdom and Pinocchio as ``v / sqrt(x^2 + y^2 + z^2)``. That is well
defined when the squared length is a normal float64; when it underflows (``1e-300 0 0``: they keep
the axis un-normalised) or overflows (``1e308 1e308 0``: they make it zero), and for ``<axis/>``
without ``xyz`` (a zero axis to urdfdom, ``1 0 0`` to yourdfpy), the file is refused, as is a zero
axis, on every moving joint.
"""

from __future__ import annotations

import math
import re
import sys
from typing import Any

from ...errors import InputError, choices, shown
from ...tolerances import LARGEST_URDF_ANGLE, LARGEST_URDF_NUMBER

__all__ = ["JOINT_TYPES", "MOVING_TYPES", "check_robot", "numbers"]

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
MOVING_TYPES = ("revolute", "continuous", "prismatic")  # the types whose axis gives a D-H row

_NUMBER = r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
_LEADING = " \t\n\v\f\r"  # white space strToDouble skips before a number (none after it)
_DECIMAL = re.compile(f"[{_LEADING}]*{_NUMBER}")
_NON_FINITE = re.compile(r"[+-]?(?:nan|inf|infinity)", re.IGNORECASE)
# Text of digits, signs, points, e and spaces only: there Python's float() reads exactly the
# decimal numbers above (no "_", "nan", "inf" or other white space can occur), a quick path
_PLAIN = re.compile(r"[0-9+\-.eE ]*")
_SMALLEST_NORMAL = sys.float_info.min
_FLOAT_MAX = sys.float_info.max


def numbers(
    text: str, count: int, what: str, where: str, bound: float | None = LARGEST_URDF_NUMBER
) -> list[float]:
    """Read ``count`` numbers from an attribute value, by urdfdom's grammar (module docstring).

    A scalar is one ``strToDouble`` of the whole value (white space before the number, none
    after it); a vector is the value split at spaces, each piece one ``strToDouble``.

    Parameters
    ----------
    text
        The attribute's value.
    count
        How many numbers it must hold (3 for a vector, 1 for a scalar).
    what
        The attribute in messages (``"origin xyz"``).
    where
        The file and element in messages (``"arm.urdf: joint 'j2'"``).
    bound
        Largest magnitude accepted, or ``None`` for any finite value.

    Returns
    -------
    list of float
        ``count`` finite numbers.

    Raises
    ------
    InputError
        Naming ``where``, ``what``, the value and the piece at fault.
    """
    largest = _FLOAT_MAX if bound is None else bound
    if _PLAIN.fullmatch(text) and not (count == 1 and text.endswith(" ")):
        pieces = text.split()
        if len(pieces) == count:
            try:
                values = list(map(float, pieces))
            except ValueError:
                pass  # "1e", "+-1", "1.2.3": said by _read
            else:
                if max(map(abs, values)) <= largest:
                    return values
    return _read(text, count, f"{where}: {what} {shown(text)}", largest)


def _read(text: str, count: int, label: str, largest: float) -> list[float]:
    """:func:`numbers`, piece by piece, raising the error that names the piece at fault."""
    expected = "a number" if count == 1 else f"{count} numbers"
    if count == 1:
        pieces = [text] if text.strip() else []
    else:
        pieces = [piece for piece in text.split(" ") if piece]
    values = []
    for piece in pieces:
        if _NON_FINITE.fullmatch(piece.strip()):
            raise InputError(f"{label} is not finite ({shown(piece)} is not a decimal number)")
        if not _DECIMAL.fullmatch(piece):
            raise InputError(f"{label} is not {expected} ({shown(piece)} is not a decimal number)")
        value = float(piece)
        if math.isinf(value):
            raise InputError(f"{label} is not finite ({shown(piece.strip())} overflows float64)")
        if abs(value) > largest:
            raise InputError(
                f"{label} is out of range ({shown(piece.strip())} is beyond ±{largest:g})"
            )
        values.append(value)
    if len(values) != count:
        raise InputError(f"{label} is not {expected} (it holds {len(values)})")
    return values


def _attribute(
    el: Any, name: str, count: int, what: str, where: str, bound: float | None = LARGEST_URDF_NUMBER
) -> list[float] | None:
    """The numbers of attribute ``name`` of ``el``, or ``None`` where it is absent."""
    text = el.get(name)
    return None if text is None else numbers(text, count, what, where, bound)


def _check_axis(el: Any, jtype: str, where: str) -> None:
    """A moving joint's axis must normalise as urdfdom and Pinocchio do (module docstring)."""
    text = el.get("xyz")
    if text is None:
        if jtype in MOVING_TYPES:
            raise InputError(
                f"{where}: <axis> has no xyz attribute (urdfdom reads that as a zero axis, "
                "yourdfpy as '1 0 0'; write the axis, or leave <axis> out for '1 0 0')"
            )
        return
    x, y, z = numbers(text, 3, "axis xyz", where, None)
    if jtype not in MOVING_TYPES:
        return
    squared = x * x + y * y + z * z
    if not (x or y or z):
        raise InputError(f"{where}: axis xyz {shown(text)} is a zero axis")
    if squared < _SMALLEST_NORMAL:
        raise InputError(
            f"{where}: axis xyz {shown(text)} is too short to normalise (its squared length "
            "underflows float64; urdfdom and Pinocchio would keep it un-normalised)"
        )
    if math.isinf(squared):
        raise InputError(
            f"{where}: axis xyz {shown(text)} is too long to normalise (its squared length "
            "overflows float64; urdfdom and Pinocchio would make it a zero axis)"
        )


def _check_joint(el: Any, display: str, links: set[str], joints: set[str]) -> None:
    name = el.get("name")
    if not name:
        raise InputError(f"{display}: a <joint> has no name attribute")
    where = f"{display}: joint {shown(name)}"
    if name in joints:
        raise InputError(f"{where} is declared twice")
    joints.add(name)
    jtype = el.get("type")
    if jtype not in JOINT_TYPES:
        problem = "has no type attribute" if jtype is None else f"has unknown type {shown(jtype)}"
        raise InputError(f"{where} {problem}; valid: {choices(JOINT_TYPES)}")
    sub: dict[Any, Any] = {}
    for child in el:  # the first of each tag counts, as with urdfdom's FirstChildElement
        sub.setdefault(child.tag, child)
    for role in ("parent", "child"):
        link = sub[role].get("link") if role in sub else None
        if not link:
            raise InputError(f"{where} has no <{role} link=...>")
        if link not in links:
            raise InputError(f"{where} names undeclared link {shown(link)} as its {role}")
    if (origin := sub.get("origin")) is not None:
        _attribute(origin, "xyz", 3, "origin xyz", where)
        _attribute(origin, "rpy", 3, "origin rpy", where, None)
    if (axis := sub.get("axis")) is not None:
        _check_axis(axis, jtype, where)
    if (limit := sub.get("limit")) is not None:
        for attr in ("lower", "upper"):
            value = _attribute(limit, attr, 1, f"limit {attr}", where)
            if jtype == "revolute" and value is not None and abs(value[0]) > LARGEST_URDF_ANGLE:
                raise InputError(
                    f"{where}: limit {attr} {shown(limit.get(attr))} is out of range for a "
                    f"revolute joint (beyond ±{LARGEST_URDF_ANGLE:g} rad; a joint without limits "
                    'is type="continuous")'
                )
        for attr in ("effort", "velocity"):  # not used, but urdfdom and Pinocchio read them
            _attribute(limit, attr, 1, f"limit {attr}", where, None)
    if (mimic := sub.get("mimic")) is not None:
        if not mimic.get("joint"):
            raise InputError(f"{where} has a <mimic> without a joint attribute")
        for attr in ("multiplier", "offset"):
            _attribute(mimic, attr, 1, f"mimic {attr}", where)


def check_robot(root: Any, display: str) -> None:
    """Check a URDF document's root element and everything below it that urdf2dh reads.

    Parameters
    ----------
    root
        The lxml root element (comments and processing instructions removed).
    display
        The file's name in messages.

    Raises
    ------
    InputError
        At the first fault, on one line naming the file, the link or joint and the attribute.
    """
    if root.tag != "robot":
        raise InputError(f"{display}: not a URDF robot (root element is <{root.tag}>)")
    if not root.get("name"):
        raise InputError(f"{display}: <robot> has no name attribute")
    links: set[str] = set()
    for el in root.iterchildren("link"):
        name = el.get("name")
        if not name:
            raise InputError(f"{display}: a <link> has no name attribute")
        if name in links:
            raise InputError(f"{display}: link {shown(name)} is declared twice")
        links.add(name)
    if not links:
        raise InputError(f"{display}: robot {shown(root.get('name'))} declares no links")
    joints: set[str] = set()
    for el in root.iterchildren("joint"):
        _check_joint(el, display, links, joints)
