"""Where MJCF puts a frame: the compiler's settings, and an element's position and orientation.

MJCF gives a body's, frame's or site's orientation in one of five forms (MuJoCo's XML reference,
"Frame orientations"); quaternions are ``w x y z``:

* ``quat``: normalised as MuJoCo does (``1 -1 0 0`` is a quarter turn about -x);
* ``axisangle``: an axis (normalised) and an angle in the compiler's unit;
* ``euler``: three angles in the compiler's unit about the axes of ``<compiler eulerseq>``
  (default ``xyz``): a lowercase letter turns about the axis of the frame as turned so far
  (intrinsic, ``q = q r``), an uppercase one about the parent's fixed axis (extrinsic,
  ``q = r q``); the cases may mix;
* ``xyaxes``: the frame's x axis (normalised) and a y axis made perpendicular to it
  (Gram-Schmidt), z their cross product;
* ``zaxis``: the shortest turn taking the parent's z axis to the one given (half a turn about x
  when it points the other way);
* and for a site, ``fromto``: the frame halfway between the two points, its z axis the shortest
  turn to the direction from the second point to the first (MuJoCo's frame of a ``fromto``).

An element holds one of them at most (MuJoCo refuses more). Angles are in degrees unless
``<compiler angle="radian">``: degrees are MJCF's default. Every ``<compiler>`` of the document
counts, wherever it stands, a later one's attribute overriding an earlier one's (as MuJoCo reads
them). Numbers follow the URDF reader's grammar (:func:`urdf2dh.io.urdf.validate.numbers`):
decimal numbers only, finite, lengths within :data:`~urdf2dh.tolerances.LARGEST_URDF_NUMBER`.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...errors import InputError, choices, shown
from ...geometry.lie import rotation_of
from ...tolerances import LARGEST_URDF_NUMBER
from ..urdf.validate import numbers

__all__ = [
    "AXISANGLE_LENGTH",
    "EXTRINSIC_EULER",
    "ORIENTATIONS",
    "Compiler",
    "Lookup",
    "pose",
    "read_compiler",
]

Mat = NDArray[np.float64]
Quat = tuple[float, float, float, float]  # w x y z

#: The attributes that say an orientation (one of them at most on an element); ``fromto`` places
#: sites too.
ORIENTATIONS = ("quat", "axisangle", "euler", "xyaxes", "zaxis")
_EULER_LETTERS = "xyzXYZ"
_TINY = 1e-15  # MuJoCo's mjMINVAL: a vector shorter than this has no direction

#: What :func:`pose` notes of the forms it read (see :data:`urdf2dh.io.mjcf.tree.FEATURES`).
EXTRINSIC_EULER = "extrinsic-euler"
AXISANGLE_LENGTH = "axisangle-length"
_UNIT_LENGTH = 4 * sys.float_info.epsilon  # an axis this close to unit length is one

#: An attribute's value as an element (or its defaults) gives it: ``None`` where absent.
Lookup = Callable[[str], str | None]


@dataclass(frozen=True, slots=True)
class Compiler:
    """The ``<compiler>`` settings that change kinematics.

    Attributes
    ----------
    degree
        Angles in degrees (MJCF's default) rather than radians.
    eulerseq
        The axes of ``euler`` angles (default ``xyz``).
    autolimits
        A joint is limited where it has a range (default ``true``); otherwise ``limited``
        decides.
    """

    degree: bool = True
    eulerseq: str = "xyz"
    autolimits: bool = True

    def angle(self, value: float) -> float:
        """An angle of the document in radians."""
        return value * (math.pi / 180.0) if self.degree else value


def _keyword(el: Any, name: str, valid: tuple[str, ...], where: str) -> str | None:
    value: str | None = el.get(name)
    if value is not None and value not in valid:
        raise InputError(f"{where}: {name} {shown(value)} is not one of {choices(valid)}")
    return value


def read_compiler(root: Any, display: str) -> Compiler:
    """The settings of every ``<compiler>`` of the document, later ones overriding.

    Raises
    ------
    InputError
        A value MuJoCo does not take (``angle``, ``autolimits``, ``eulerseq`` of other than three
        of ``xyzXYZ``), or ``coordinate="global"``, which MuJoCo 2.3.3 dropped.
    """
    degree, eulerseq, autolimits = True, "xyz", True
    where = f"{display}: <compiler>"
    for el in root.iterchildren("compiler"):
        angle = _keyword(el, "angle", ("radian", "degree"), where)
        if angle is not None:
            degree = angle == "degree"
        limits = _keyword(el, "autolimits", ("true", "false"), where)
        if limits is not None:
            autolimits = limits == "true"
        if _keyword(el, "coordinate", ("local", "global"), where) == "global":
            raise InputError(
                f'{where}: coordinate="global" is not read (MuJoCo dropped global coordinates in '
                "2.3.3)"
            )
        seq = el.get("eulerseq")
        if seq is not None:
            if len(seq) != 3 or any(c not in _EULER_LETTERS for c in seq):
                raise InputError(
                    f"{where}: eulerseq {shown(seq)} is not three of the letters x, y, z "
                    "(intrinsic) and X, Y, Z (extrinsic)"
                )
            eulerseq = seq
    return Compiler(degree, eulerseq, autolimits)


# --------------------------------------------------------------------------- quaternions


def _product(a: Quat, b: Quat) -> Quat:
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    )


def _about(axis: tuple[float, float, float], angle: float) -> Quat:
    """The quaternion of ``angle`` about the unit ``axis``."""
    s = math.sin(angle / 2.0)
    return (math.cos(angle / 2.0), s * axis[0], s * axis[1], s * axis[2])


def _unit(v: list[float], what: str, where: str) -> tuple[float, ...]:
    norm = math.sqrt(sum(x * x for x in v))
    if not norm > _TINY or math.isinf(norm):
        raise InputError(f"{where}: {what} has no direction (its length is {norm:.3g})")
    return tuple(x / norm for x in v)


def _matrix(q: Quat, what: str, where: str) -> Mat:
    w, x, y, z = _unit(list(q), what, where)
    return rotation_of(np.array([x, y, z, w]))


def _euler(values: list[float], compiler: Compiler) -> Quat:
    q: Quat = (1.0, 0.0, 0.0, 0.0)
    for letter, value in zip(compiler.eulerseq, values, strict=True):
        axis = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}[letter.lower()]
        r = _about(axis, compiler.angle(value))
        q = _product(q, r) if letter.islower() else _product(r, q)
    return q


def _z_to(v: tuple[float, ...]) -> Quat:
    """The shortest turn taking ``(0, 0, 1)`` to the unit vector ``v``."""
    x, y, z = v
    axis = (-y, x, 0.0)  # (0, 0, 1) x v
    s = math.hypot(x, y)
    if s < _TINY:
        return (1.0, 0.0, 0.0, 0.0) if z > 0 else (0.0, 1.0, 0.0, 0.0)
    return _about((axis[0] / s, axis[1] / s, 0.0), math.atan2(s, z))


def _xyaxes(v: list[float], where: str) -> Mat:
    x = np.array(_unit(v[:3], "xyaxes x axis", where))
    y = np.array(v[3:])
    y = y - x * float(x @ y)
    y = np.array(_unit(y.tolist(), "xyaxes y axis (made perpendicular to x)", where))
    return np.column_stack([x, y, np.cross(x, y)])


def _orientation(get: Lookup, compiler: Compiler, where: str, noted: set[str]) -> Mat | None:
    """The rotation an element's orientation attribute gives, or ``None`` without one."""
    given = [name for name in ORIENTATIONS if get(name) is not None]
    if len(given) > 1:
        raise InputError(f"{where}: several orientations ({', '.join(given)}); MJCF takes one")
    if not given:
        return None
    name = given[0]
    text = get(name)
    assert text is not None
    if name == "quat":
        w, x, y, z = numbers(text, 4, name, where, LARGEST_URDF_NUMBER)
        return _matrix((w, x, y, z), f"quat {shown(text)}", where)
    if name == "axisangle":
        values = numbers(text, 4, name, where, LARGEST_URDF_NUMBER)
        axis = _unit(values[:3], f"axisangle {shown(text)}", where)
        if abs(math.sqrt(sum(x * x for x in values[:3])) - 1.0) > _UNIT_LENGTH:
            noted.add(AXISANGLE_LENGTH)
        q = _about((axis[0], axis[1], axis[2]), compiler.angle(values[3]))
        return _matrix(q, name, where)
    if name == "euler":
        if compiler.eulerseq != compiler.eulerseq.lower():
            noted.add(EXTRINSIC_EULER)
        return _matrix(_euler(numbers(text, 3, name, where, LARGEST_URDF_NUMBER), compiler),
                       name, where)  # fmt: skip
    if name == "xyaxes":
        return _xyaxes(numbers(text, 6, name, where, LARGEST_URDF_NUMBER), where)
    v = _unit(numbers(text, 3, name, where, LARGEST_URDF_NUMBER), f"zaxis {shown(text)}", where)
    return _matrix(_z_to(v), name, where)


def pose(
    get: Lookup, compiler: Compiler, where: str, fromto: bool = False, noted: set[str] | None = None
) -> Mat:
    """The ``(4, 4)`` pose an element's ``pos`` and orientation give (``fromto`` too, for a
    site), in its parent's frame.

    Parameters
    ----------
    get
        The element's attribute values (its own, or its defaults' where it takes them).
    compiler
        The document's compiler settings.
    where
        The file and element in messages.
    fromto
        Whether ``fromto`` places the element (sites).
    noted
        Where to note the forms read that an oracle may read otherwise
        (:data:`EXTRINSIC_EULER`, :data:`AXISANGLE_LENGTH`).
    """
    out = np.eye(4)
    if fromto and (text := get("fromto")) is not None:
        a, b = np.split(np.array(numbers(text, 6, "fromto", where, LARGEST_URDF_NUMBER)), 2)
        out[:3, 3] = (a + b) / 2.0
        z = _unit((a - b).tolist(), f"fromto {shown(text)}", where)  # as MuJoCo turns it
        out[:3, :3] = _matrix(_z_to(z), "fromto", where)
        return out
    if (text := get("pos")) is not None:
        out[:3, 3] = numbers(text, 3, "pos", where, LARGEST_URDF_NUMBER)
    rotation = _orientation(get, compiler, where, set() if noted is None else noted)
    if rotation is not None:
        out[:3, :3] = rotation
    return out
