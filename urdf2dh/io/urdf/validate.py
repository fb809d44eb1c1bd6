"""The one strict check of a URDF document, run on every file before anything is built from it.

It walks the lxml element tree once and reports the first fault on one line naming the file, the
joint or link, and the attribute. What it passes, the rest of the package trusts: every name is
present and unique, every joint joins two declared links, and every number urdf2dh reads obeys
the grammar below.

What urdfdom refuses, urdf2dh refuses. urdfdom (``urdf_parser``, version 6 as Pinocchio ships it)
is the URDF reader of ROS and Pinocchio, so a file it refuses is one that ``verify`` could not
check and no ROS tool would load; each such fault is named with what urdfdom requires:

* numbers: ``Vector3::init`` splits a vector at spaces (only) and converts each piece with
  ``strToDouble``, a classic-locale ``std::stringstream >> double`` that must consume the whole
  piece; a scalar is one ``strToDouble`` of the whole value. So a number is a decimal number of
  urdf2dh's one grammar (:mod:`urdf2dh.numerals`: ``1_0``, ``0x10``, ``nan``, ``inf``, ``1e999``
  and ``1,5`` are refused) with white space before it but none after it, a tab or line break
  between two numbers of a vector is refused (the parse keeps the attribute's white space as
  urdfdom's XML parser does: :func:`urdf2dh.io.urdf.parse.keep_attribute_whitespace`), and a
  vector holds exactly 3 numbers (``xyz="0 0 1 4"`` is refused); ``.5``, ``5.``, ``+5`` and
  ``1E-3`` are read;
* ``<robot version>``, if given: ``MAJOR.MINOR`` of decimal integers, version 1.0 to 1.2;
* a revolute or prismatic joint has a ``<limit>``; a ``<limit>`` (on any joint) has ``effort``
  and ``velocity``, neither negative;
* a joint's ``<dynamics>`` has ``damping`` or ``friction``, its ``<safety_controller>`` a
  ``k_velocity``, its ``<mimic>`` a ``joint``; their numbers (and ``<calibration>``'s) are
  numbers;
* no two ``<material>`` elements of the robot share a name.

What urdfdom does not read (a link's inertial, visual and collision elements: urdfdom keeps a
link whatever they hold), urdf2dh does not check either. A few things urdfdom reads, urdf2dh
refuses: lengths, limits and mimic factors beyond :data:`~urdf2dh.tolerances.LARGEST_URDF_NUMBER`
and a revolute joint's limits beyond :data:`~urdf2dh.tolerances.LARGEST_URDF_ANGLE`; empty names;
and an axis urdfdom and Pinocchio cannot normalise. Axes are normalised by urdfdom and Pinocchio as
``v / sqrt(x^2 + y^2 + z^2)``. That is well defined when the squared length is a normal float64;
when it underflows (``1e-300 0 0``: they keep the axis un-normalised) or overflows (``1e308 1e308
0``: they make it zero), and for ``<axis/>`` without ``xyz`` (a zero axis to urdfdom, ``1 0 0`` to
yourdfpy), the file is refused, as is a zero axis, on every moving joint. One thing urdfdom reads
as written, urdf2dh reads otherwise and warns of: a ``<limit>`` whose ``lower`` is above its
``upper`` (:mod:`urdf2dh.io.urdf.tree`).
"""

from __future__ import annotations

import math
import re
import sys
from typing import Any

from ...errors import InputError, choices, shown
from ...numerals import DECIMAL, why_not
from ...tolerances import LARGEST_URDF_ANGLE, LARGEST_URDF_NUMBER

__all__ = ["JOINT_TYPES", "MOVING_TYPES", "check_robot", "numbers"]

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
MOVING_TYPES = ("revolute", "continuous", "prismatic")  # the types whose axis gives a D-H row
_AXISLESS = ("fixed", "floating")  # the types whose <axis> urdfdom does not read

_LEADING = " \t\n\v\f\r"  # white space strToDouble skips before a number (none after it)
_DECIMAL = re.compile(f"[{_LEADING}]*{DECIMAL}")
_NON_FINITE = re.compile(r"[+-]?(?:nan|inf|infinity)", re.IGNORECASE)
# <robot version="MAJOR.MINOR">: each part as strtol reads it, whole (URDFVersion)
_VERSION_PART = re.compile(f"[{_LEADING}]*[+-]?[0-9]+")
_VERSIONS = ((1, 0), (1, 1), (1, 2))  # the versions urdfdom 6 reads
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
            raise InputError(f"{label} is not {expected} ({shown(piece)} {_why(piece, count)})")
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


def _why(piece: str, count: int) -> str:
    """Why ``piece`` (a vector's piece between spaces, or a scalar) is not a number."""
    inner = piece.lstrip(_LEADING)
    if any(c in _LEADING for c in inner):
        if count > 1 and _DECIMAL.fullmatch(inner.split()[0]):
            return (
                "is not a decimal number: urdfdom separates numbers by spaces only, and reads "
                "no tab or line break between them or after a number"
            )
        return "is not a decimal number: urdfdom reads no white space after a number"
    reason = why_not(inner)
    return "is not a decimal number" + ("" if reason == "not a decimal number" else f": {reason}")


def _attribute(
    el: Any, name: str, count: int, what: str, where: str, bound: float | None = LARGEST_URDF_NUMBER
) -> list[float] | None:
    """The numbers of attribute ``name`` of ``el``, or ``None`` where it is absent."""
    text = el.get(name)
    return None if text is None else numbers(text, count, what, where, bound)


def _check_axis(el: Any, jtype: str, where: str) -> None:
    """A moving joint's axis must normalise as urdfdom and Pinocchio do (module docstring); a
    fixed or floating joint's is not read (urdfdom reads none)."""
    if jtype in _AXISLESS:
        return
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


def _check_joint(
    el: Any, display: str, links: set[str], joints: set[str], version: tuple[int, int]
) -> None:
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
    limit = sub.get("limit")
    if limit is None and jtype in ("revolute", "prismatic"):
        hint = '; a joint without limits is type="continuous"' if jtype == "revolute" else ""
        raise InputError(
            f"{where}: a {jtype} joint needs a <limit> (urdfdom, the URDF reader of ROS and "
            f"Pinocchio, refuses one without){hint}"
        )
    if limit is not None:
        _check_limit(limit, jtype, where, version)
    if (mimic := sub.get("mimic")) is not None:
        if mimic.get("joint") is None:
            raise InputError(f"{where} has a <mimic> without a joint attribute")
        if not mimic.get("joint"):
            raise InputError(f"{where} has a <mimic> with an empty joint name")
        for attr in ("multiplier", "offset"):
            _attribute(mimic, attr, 1, f"mimic {attr}", where)
    for tag, needed, attributes in _JOINT_PARTS:
        if (el := sub.get(tag)) is None:
            continue
        if needed and not any(el.get(attr) is not None for attr in needed):
            raise InputError(
                f"{where}: <{tag}> has no {' or '.join(needed)} attribute (urdfdom refuses it)"
            )
        for attr in attributes:
            value = _attribute(el, attr, 1, f"{tag} {attr}", where, None)
            if value is not None and value[0] < 0.0 and (tag, attr) in _NOT_NEGATIVE:
                raise InputError(
                    f"{where}: {tag} {attr} {shown(el.get(attr))} is negative (urdfdom refuses it)"
                )


# The other elements of a joint that urdfdom reads: the attributes one of which it needs, and
# the attributes it reads as numbers
_JOINT_PARTS = (
    ("dynamics", ("damping", "friction"), ("damping", "friction")),
    (
        "safety_controller",
        ("k_velocity",),
        ("soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"),
    ),
    ("calibration", (), ("rising", "falling")),
)
_NOT_NEGATIVE = {("dynamics", "friction")}
# A <limit>'s attributes that URDF 1.2 adds, which urdfdom reads as numbers not below 0
_LIMITS_1_2 = ("acceleration", "deceleration", "jerk")


def _check_limit(limit: Any, jtype: str, where: str, version: tuple[int, int]) -> None:
    """A joint's ``<limit>`` as urdfdom (and Pinocchio) read it: its numbers; effort and velocity
    present (before URDF 1.2) and not negative (on a moving joint; on any, from 1.2); from 1.2,
    a revolute or prismatic joint's lower and upper present, lower not above upper, and
    acceleration, deceleration and jerk not negative."""
    bounds = []
    for attr in ("lower", "upper"):
        value = _attribute(limit, attr, 1, f"limit {attr}", where)
        if jtype == "revolute" and value is not None and abs(value[0]) > LARGEST_URDF_ANGLE:
            raise InputError(
                f"{where}: limit {attr} {shown(limit.get(attr))} is out of range for a "
                f"revolute joint (beyond ±{LARGEST_URDF_ANGLE:g} rad; a joint without limits "
                'is type="continuous")'
            )
        if value is not None:
            bounds.append(value[0])
        elif version >= (1, 2) and jtype in ("revolute", "prismatic"):
            raise InputError(
                f"{where}: <limit> has no {attr} attribute (urdfdom refuses a {jtype} joint's "
                "limit without lower and upper in a URDF of version 1.2)"
            )
    needed = ("effort", "velocity") if version < (1, 2) else ()  # read by urdfdom, not by us
    signed = version >= (1, 2) or jtype in MOVING_TYPES
    for attr in ("effort", "velocity", *(_LIMITS_1_2 if version >= (1, 2) else ())):
        text = limit.get(attr)
        if text is None:
            if attr in needed:
                raise InputError(
                    f"{where}: <limit> has no {attr} attribute (urdfdom refuses a limit without "
                    "effort and velocity)"
                )
            continue
        if numbers(text, 1, f"limit {attr}", where, None)[0] < 0.0 and signed:
            raise InputError(
                f"{where}: limit {attr} {shown(text)} is negative (urdfdom refuses it)"
            )
    if version >= (1, 2) and len(bounds) == 2 and bounds[0] > bounds[1]:
        raise InputError(
            f"{where}: limit lower {shown(limit.get('lower'))} is above upper "
            f"{shown(limit.get('upper'))} (urdfdom refuses it in a URDF of version 1.2)"
        )


def _check_version(root: Any, display: str) -> tuple[int, int]:
    """``<robot version>`` as urdfdom reads it (``URDFVersion``): two parts, each a whole
    ``strtol`` that is not negative, taken as an unsigned 32-bit number; 1.0 to 1.2. The version
    read (1.0 where none is given)."""
    text = root.get("version")
    if text is None:
        return (1, 0)
    parts = text.split(".")
    if len(parts) > 1 and not parts[-1]:
        parts.pop()  # urdfdom's split_string keeps no empty last part ("1.0." is 1.0)
    if len(parts) == 2 and all(_VERSION_PART.fullmatch(part) for part in parts):
        values = [int(part.lstrip(_LEADING)) for part in parts]
        major, minor = (min(v, 2**63 - 1) % 2**32 for v in values)
        if min(values) >= 0 and (major, minor) in _VERSIONS:
            return major, minor
    raise InputError(
        f"{display}: <robot version={shown(text)}> is not a version urdfdom reads (MAJOR.MINOR, "
        "1.0 to 1.2)"
    )


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
    version = _check_version(root, display)
    materials: set[str] = set()
    for el in root.iterchildren("material"):  # urdfdom keeps one material of each name
        name = el.get("name") or ""  # a material without a name is named "" to urdfdom
        if name in materials:
            raise InputError(
                f"{display}: material {shown(name)} is declared twice (urdfdom refuses it)"
            )
        materials.add(name)
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
        _check_joint(el, display, links, joints, version)
