"""What every export target shares: number text, the header, the checks that refuse a table.

A target is generated from a checked :class:`~urdf2dh.conventions.table.Table` only; these helpers
never change a parameter, they format it or refuse it with the reason.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from ...conventions import Params, get
from ...conventions.analytic import pi_text
from ...conventions.base import written_angle, written_length
from ...conventions.grid import summary
from ...conventions.table import Table
from ...errors import ExportError, Remedy, UsageError, shown
from ...geometry.se3 import pose_errors
from ...model.mimic import Followed
from ...tolerances import DECIMAL_ROUND_OFF, DEFAULT, Tolerances

__all__ = [
    "ExportOptions",
    "Numbers",
    "close_to",
    "floats",
    "header",
    "matlab_matrix",
    "num",
    "require",
    "require_convention",
    "require_joint_kinds",
    "require_unit_scale",
    "yaml_float",
]


@dataclass(frozen=True, slots=True)
class ExportOptions:
    """What a user may choose beyond the table (:func:`urdf2dh.export`).

    Attributes
    ----------
    units
        The length unit of targets that fix one (``mm`` or ``inch`` for ``linuxcnc``, ``mm`` or
        ``m`` for ``ikdh``; ``None``: the target's default, ``mm``).
    tol
        The tolerances that decide what counts as zero, and the table's self-check.
    """

    units: str | None = None
    tol: Tolerances = DEFAULT


def close_to(table: Table, a: np.ndarray, b: np.ndarray, tol: Tolerances) -> bool:
    """Whether two transforms agree within the exactness a table promises (``check_position``
    x robot size, ``check_rotation``): what a target may drop without the user noticing."""
    pos, rot = pose_errors(np.asarray(a)[None], np.asarray(b)[None])
    return pos <= tol.check_position * table.size and rot <= tol.check_rotation


def floats(params: Params) -> dict[str, float]:
    """A D-H record's parameters by name (every target here reads D-H tables only)."""
    if params.vectors():
        raise ExportError(f"{type(params).__name__} is not a D-H record; targets take D-H tables")
    return params.scalars()


def num(x: float) -> str:
    """The shortest text that reads back as exactly ``x`` (Python ``repr``), without ``-0``.

    Valid as a number literal in Python, MATLAB and YAML 1.2 alike.
    """
    x = float(x) + 0.0
    if not math.isfinite(x):
        raise ExportError(f"non-finite parameter {x!r}")
    return repr(x)


def yaml_float(x: float) -> str:
    """A float's :func:`num` text as YAML 1.1 (PyYAML, xacro's and ROS 1's loaders) reads a
    float: ``1e-12`` would be a string there, ``1.0e-12`` is a float in YAML 1.1 and 1.2."""
    text = num(x)
    mantissa, _, exponent = text.partition("e")
    if exponent and "." not in mantissa:
        text = f"{mantissa}.0e{exponent}"
    return text


def _shortest(x: float, within: float) -> float:
    """The number with the fewest significant digits within ``within`` of ``x`` (``x`` itself
    when none is)."""
    for digits in range(1, 16):
        y = float(f"{x:.{digits}g}")
        if abs(y - x) <= within:
            return y + 0.0
    return float(f"{x:.15g}") + 0.0


@dataclass(frozen=True, slots=True)
class Numbers:
    """How a target writes a table's numbers: round-off snapped as the table files snap it
    (:func:`~urdf2dh.conventions.base.written_angle`, :func:`~.written_length`: a length within
    ``written x size`` of 0, an angle within ``written`` of a multiple of pi/2, as that); then
    a length as the shortest decimal within the arithmetic's round-off
    (:data:`~urdf2dh.tolerances.DECIMAL_ROUND_OFF` x size) and an angle to 15 significant
    digits. So files carry ``0``, ``0.39225`` and ``-0.035`` where the arithmetic left
    ``1.2e-16``, ``0.39225000000000004`` and ``-0.03500000000000005``, and read the same on
    every platform; genuine values (a rounded pi/2 leaving 4.9e-12 rad, a length 2.8e-13 m off
    its decimal, 600 mm as 23.6220472440945 inch) are kept."""

    size: float
    written: float
    length_scale: float = 1.0

    @classmethod
    def of(cls, table: Table, tol: Tolerances, length_scale: float = 1.0) -> Numbers:
        return cls(table.size * length_scale, tol.written, length_scale)

    def angle(self, x: float) -> float:
        return float(f"{written_angle(x, self.written):.15g}") + 0.0

    def length(self, x: float) -> float:
        """A length of the table, in the target's unit (times ``length_scale``)."""
        x = written_length(x * self.length_scale, self.written * self.size)
        return _shortest(x, DECIMAL_ROUND_OFF * self.size)

    def ang(self, x: float) -> str:
        """An angle's text."""
        return num(self.angle(x))

    def pi_angle(self, x: float) -> float:
        """The angle :meth:`pi_ang` writes, to the last bit: a multiple of pi/2 (up to the
        files' round-off) as float64 holds it, any other angle as the table holds it."""
        return written_angle(x, self.written)

    def pi_ang(self, x: float) -> str:
        """An angle's text, exact: a multiple of pi/2 as ``pi/2``, ``pi``, ... (where the reader
        defines ``pi``: Python with ``from math import pi``, MATLAB, ikdh's robot file), any
        other angle with the digits that read back as it (:func:`num`)."""
        value = self.pi_angle(x)
        return pi_text(value) or num(value)

    def lin(self, x: float) -> str:
        """A length's text, in the target's unit."""
        return num(self.length(x))

    def position(self, kind: str) -> Callable[[float], str]:
        """The text of a joint position of a ``kind`` of joint: an angle for a revolute
        joint (:meth:`turn`), a length for a prismatic one (limits, home positions)."""
        return self.turn if kind == "revolute" else self.lin

    def turn(self, x: float) -> str:
        """A joint angle's text (a limit): as :meth:`ang`, but a multiple of pi/2 is not
        wrapped into [-pi, pi], so that a limit of 4 pi stays 4 pi."""
        return num(float(f"{written_angle(x, self.written, wrap=False):.15g}"))

    def matrix(self, m: np.ndarray) -> list[list[float]]:
        """A 4x4 transform's entries: rotation as angles, translation as lengths."""
        return [
            [self.length(m[i, j]) if j == 3 and i < 3 else self.angle(m[i, j]) for j in range(4)]
            for i in range(4)
        ]


def matlab_matrix(m: np.ndarray, numbers: Numbers) -> str:
    """A 4x4 transform as a MATLAB matrix literal ``[r11 r12 r13 x; ...; 0 0 0 1]``."""
    return "[" + "; ".join(" ".join(repr(v) for v in row) for row in numbers.matrix(m)) + "]"


def _chain(table: Table) -> str:
    where = table.source or table.robot or "the source"
    if table.base_link or table.tip_link:
        where += f": {table.base_link} -> {table.tip_link}"
    return where


def header(table: Table, what: str, unit: str | None = None) -> list[str]:
    """Comment lines (without the comment marker) naming the robot, the chain, the convention's
    FK formula, the unit of the file's lengths (``unit``: the target's, where it writes another
    than the table's) and the table's own check. Names are as the source spells them: every
    target writes these lines through its language's comment function (:mod:`.escape`)."""
    lines = [f"{what} for {table.robot or 'robot'} ({_chain(table)}), generated by urdf2dh."]
    lines.append(table.spec.formula)
    lines.append(f"Lengths in {unit or table.length_unit} unless stated, angles in radians.")
    lines.extend(summary(table))
    return lines


def require(
    table: Table,
    target: str,
    conventions: Iterable[str],
    kinds: Iterable[str] = ("revolute", "prismatic"),
) -> None:
    """What every target checks first: the table's convention, its joint kinds, unit scales,
    and no coupled (mimic) joints."""
    require_convention(table, target, conventions)
    require_joint_kinds(table, target, kinds)
    require_unit_scale(table, target)
    require_uncoupled(table.rows, target)


def require_uncoupled(joints: Iterable[Followed], target: str) -> None:
    """Refuse joints that mimic another: no target but the URDF writer holds a coupling."""
    coupled = [f"{shown(j.name)} (mimics {shown(j.mimic.joint)})" for j in joints if j.mimic]
    if coupled:
        raise ExportError(
            f"{target}: joints {', '.join(coupled)} follow another joint; {target} has no coupled "
            "joints (the urdf format keeps the coupling)",
            remedy=Remedy("ignore_mimic", "; {} treats them as independent"),
        )


def require_joint_kinds(table: Table, target: str, allowed: Iterable[str]) -> None:
    """Refuse joints whose kind the target has no joint type for (e.g. helical)."""
    allowed = tuple(allowed)
    bad = [f"{shown(r.name)} ({r.kind})" for r in table.rows if r.kind not in allowed]
    if bad:
        raise ExportError(
            f"{target}: joints {', '.join(bad)} cannot be written; {target} has "
            f"{' and '.join(allowed)} joints only"
        )


def require_unit_scale(table: Table, target: str) -> None:
    """Refuse joints whose table variable is a scaled URDF position (``s = scale q``)."""
    bad = [f"{shown(r.name)} (scale {r.scale:g})" for r in table.rows if r.scale != 1.0]
    if bad:
        raise ExportError(
            f"{target}: joints {', '.join(bad)} move by a multiple of their position; "
            f"{target} has no joint scale"
        )


def require_convention(table: Table, target: str, allowed: Iterable[str]) -> None:
    """Refuse a table in a convention the target does not read, naming the first row whose
    form none of them has."""
    allowed = tuple(allowed)
    if table.convention in allowed:
        return
    known = {cls for name in allowed for cls in get(name).row_types}
    odd = next((r for r in table.rows if type(r.params) not in known), None)
    row = "" if odd is None else (
        f" (row {shown(odd.name)} is a {odd.params.form or table.convention} row: "
        f"{', '.join(odd.params.values())})")  # fmt: skip
    raise UsageError(
        f"{target} takes {' or '.join(allowed)} tables, not {table.convention}{row}",
        remedy=Remedy("convention", "; export with {}", allowed[0]),
    )
