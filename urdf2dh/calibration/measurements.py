"""Measurement files: CSV with a header row, read strictly, written exactly.

::

    j1,j2,j3,j4,j5,j6,x,y,z,qx,qy,qz,qw
    0.1,-0.5,1.2,0.3,0.2,0.1,412.7,85.3,-12.9,0.1,0.2,0.3,0.927

* one column per actuated joint, named as in the chain (radians for revolute and helical
  joints, the nominal's length unit for prismatic ones, unless :class:`Reading` says otherwise),
  in any order;
* ``x, y, z``: the tool point in the measuring device's frame;
* for pose measurements, the tool orientation, either as a unit quaternion ``qx, qy, qz, qw``
  (scalar last; norm within :data:`~urdf2dh.tolerances.QUATERNION_NORM` of 1) or as three angles
  ``roll, pitch, yaw``: by default URDF's fixed-axis angles, ``R = Rz(yaw) Ry(pitch) Rx(roll)``
  (scipy's extrinsic ``"xyz"``), or any sequence :attr:`Reading.euler` names;
* optionally ``marker`` (integer >= 0): which of several points on the tool a row measured, for
  position measurements.

FIGAROH's files read as they are: ``x1, y1, z1`` for the point and ``phix1, phiy1, phiz1`` for
its fixed-axis angles (FIGAROH's ``R = Rz Ry Rx``, the same as ``roll, pitch, yaw``); several
points on one row, ``x1, y1, z1, x2, y2, z2, ...``, are markers 1, 2, ... (one row each here).

:class:`Reading` renames and ignores columns (names or shell-style patterns), and says the
file's units (angles in degrees, lengths in another unit). A configuration is a distinct row of
joint values (:meth:`Measurements.configurations`): held-out sets and cross-validation folds
keep a configuration's rows together.

Any fault (a NaN, a wrong field count, an unknown or missing column, a quaternion off unit
norm, a non-integer marker, more than :data:`MAX_MEASUREMENTS` rows) is an
:class:`~urdf2dh.errors.InputError` naming the file, the row (data rows count from 1; the line
number follows) and the column.

A *marker layout* file gives the markers' nominal positions on the tool, in the tool frame:
``marker,x,y,z``, one row per marker (:func:`read_layout`).
"""

from __future__ import annotations

import csv
import fnmatch
import io
import math
import re
from collections.abc import Callable, Hashable, Iterator
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, TypeVar, cast

import numpy as np
from numpy.typing import NDArray

from .. import units
from ..errors import InputError, UsageError, choices, shown, visible
from ..escape import csv_cell, csv_names, markdown_table, markdown_text, text_table
from ..io.files import read_file
from ..numerals import decimal, integer, read_decimal, why_not
from ..tolerances import MEASUREMENT_BYTES, QUATERNION_NORM

__all__ = [
    "EULER",
    "MAX_MEASUREMENTS",
    "POINT",
    "QUATERNION",
    "AsRead",
    "Measurements",
    "Reading",
    "check_noise",
    "euler_quaternions",
    "read_configurations",
    "read_layout",
    "read_measurements",
    "write_layout",
    "write_measurements",
]

Mat = NDArray[np.float64]
T = TypeVar("T")

POINT = ("x", "y", "z")
QUATERNION = ("qx", "qy", "qz", "qw")
EULER = ("roll", "pitch", "yaw")
FIGAROH_EULER = ("phix1", "phiy1", "phiz1")
MARKER = "marker"

# Measurement rows read at most (a row is one pose, or one marker's position): a few hundred
# well-spread configurations identify a robot (``urdf2dh plan`` picks them), and the
# identification holds the Jacobian, rows x parameters, in memory: 10^5 poses of a 7-joint arm
# take about 0.3 GB.
MAX_MEASUREMENTS = 100_000

_WIDE = re.compile(r"([xyz])([1-9][0-9]*)\Z")


@dataclass(frozen=True, slots=True)
class Reading:
    """How to read a measurement file whose columns or units differ from urdf2dh's own.

    Attributes
    ----------
    rename
        ``(old, new)`` pairs: the file's column ``old`` is read as ``new`` (a joint's name,
        ``x``, ``qw``, ``roll`` ...).
    ignore
        Column names or shell-style patterns (``t``, ``x[2-4]``) that are skipped.
    degrees
        Revolute and helical joint values and orientation angles are in degrees.
    length_unit
        The file's length unit (positions and prismatic joints), converted to the nominal's;
        ``None``: already the nominal's.
    euler
        The rotation sequence of the three angle columns (``roll, pitch, yaw`` or FIGAROH's
        ``phix1, phiy1, phiz1``, in that order), in scipy's notation: lower case for axes fixed
        in space (extrinsic), upper case for axes that move (intrinsic). ``"xyz"`` is URDF's
        and ROS's ``R = Rz(yaw) Ry(pitch) Rx(roll)``; ``"ZYX"`` is the same rotation.
    """

    rename: tuple[tuple[str, str], ...] = ()
    ignore: tuple[str, ...] = ()
    degrees: bool = False
    length_unit: str | None = None
    euler: str = "xyz"

    def __post_init__(self) -> None:
        seq = self.euler
        if not (
            len(seq) == 3
            and (set(seq) <= set("xyz") or set(seq) <= set("XYZ"))
            and seq[0] != seq[1] != seq[2]
        ):
            raise UsageError(
                f"rotation sequence {shown(seq)}: three axes from x, y, z, all lower case "
                "(fixed axes) or all upper case (moving axes), no axis twice in a row, e.g. "
                "xyz (URDF's roll, pitch, yaw) or ZYZ"
            )
        if self.length_unit is not None:
            units.metres_per(self.length_unit)
        news = [new for _, new in self.rename]
        twice = next((n for n in news if news.count(n) > 1), None)
        if twice is not None:
            raise UsageError(f"two columns are renamed to {shown(twice)}")


@dataclass(frozen=True, slots=True)
class AsRead:
    """How a file was read: the facts a diagnosis needs to read it differently
    (:mod:`.diagnosis`), and the length unit its user works in.

    Attributes
    ----------
    reading
        The :class:`Reading` it was read with.
    model_unit
        The length unit its lengths were converted into (the nominal's), or ``None`` when they
        were kept as the file holds them.
    joint_columns
        The file's header name read as each joint (the chain's order).
    point_columns
        The file's header names read as ``x, y, z`` (one point per row), else ``()``.
    orientation_columns
        The file's header names read as ``qx, qy, qz, qw``, or as the three angles (in the order
        :attr:`Reading.euler` takes them), else ``()``.
    angles
        ``(N, 3)`` the three angle columns as the file holds them (rows as the measurements'),
        or ``None``.
    """

    reading: Reading
    model_unit: str | None
    joint_columns: tuple[str, ...]
    point_columns: tuple[str, ...] = ()
    orientation_columns: tuple[str, ...] = ()
    angles: Mat | None = None

    @property
    def length_unit(self) -> str | None:
        """The file's length unit, when its lengths were converted from it (else ``None``)."""
        if self.model_unit is None:
            return None
        return self.reading.length_unit

    def subset(self, rows: NDArray[np.int64]) -> AsRead:
        """The same, for the measurements at ``rows``."""
        if self.angles is None:
            return self
        return AsRead(
            self.reading, self.model_unit, self.joint_columns, self.point_columns,
            self.orientation_columns, self.angles[rows],
        )  # fmt: skip


SHOWN_ROWS = 10  # the rows of measurements a notebook shows


@dataclass(frozen=True, slots=True)
class Measurements:
    """Joint positions and what the device measured at each.

    Attributes
    ----------
    joints
        Joint names, in the chain's order (the columns of ``q``).
    q
        ``(N, n)`` joint positions (radians; the nominal's length unit for sliding joints).
    points
        ``(N, 3)`` tool points in the device frame (the nominal's length unit).
    quaternions
        ``(N, 4)`` unit quaternions ``[x, y, z, w]`` of the tool orientation, or ``None``.
    markers
        ``(N,)`` integer marker of each row (position measurements), or ``None``.
    source
        The file's name, for messages.
    layout
        Where the markers sit: marker -> ``(3,)`` point in the tool frame (length unit), when
        known (synthetic measurements: :func:`~.measure.measure`); ``None`` otherwise.
        :func:`~urdf2dh.calibrate` takes it as ``layout=`` to hold the markers there.
    read_as
        How they were read from a file (:func:`read_measurements`), or ``None``.

    Like every value here they are not changed once made (their arrays are not written to):
    what is found from them alone is found once (:meth:`remembered`).
    """

    joints: tuple[str, ...]
    q: Mat
    points: Mat
    quaternions: Mat | None = None
    markers: NDArray[np.int64] | None = None
    source: str = ""
    layout: dict[int, Mat] | None = None
    read_as: AsRead | None = None
    _memo: dict[Hashable, Any] = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        n = len(self.q)
        if self.q.shape != (n, len(self.joints)) or self.points.shape != (n, 3):
            raise ValueError("q must be (N, joints) and points (N, 3)")
        if self.quaternions is not None and self.quaternions.shape != (n, 4):
            raise ValueError("quaternions must be (N, 4)")
        if self.markers is not None and self.markers.shape != (n,):
            raise ValueError("markers must be (N,)")

    def __len__(self) -> int:
        return len(self.q)

    def __getstate__(self) -> tuple[object, ...]:
        """The fields to pickle: the memo is not among them (it is made again)."""
        return tuple(getattr(self, f.name) for f in fields(self) if f.init)

    def __setstate__(self, state: tuple[object, ...]) -> None:
        for f, value in zip((f for f in fields(self) if f.init), state, strict=True):
            object.__setattr__(self, f.name, value)
        object.__setattr__(self, "_memo", {})

    def remembered(self, key: Hashable, make: Callable[[], T]) -> T:
        """``make()``, made once for these measurements: ``key`` names what it finds from them
        (with any argument it takes besides them). Every step of a calibration asks for the
        same views of its measurements (:meth:`configurations`, :func:`.start.to_data`); their
        arrays are made read-only, since every later asker shares them."""
        if key not in self._memo:
            self._memo[key] = make()
        return cast(T, self._memo[key])

    @property
    def length_unit(self) -> str | None:
        """The length unit of the file they were read from, when it was converted into the
        nominal's (``Reading.length_unit``); ``None``: the nominal's."""
        return None if self.read_as is None else self.read_as.length_unit

    def _repr_markdown_(self) -> str:
        """In a notebook: how many rows of what, and the first rows as a table (names
        escaped)."""
        title, head, body, more = self._layout(markdown_text)
        return "\n".join([title, "", *markdown_table(head, body, texts=0), *more]) + "\n"

    def __str__(self) -> str:
        """How many rows of what, and the first rows as a table."""
        title, head, body, more = self._layout(visible)
        return "\n".join([title, "", *text_table(head, body, texts=0), *more]) + "\n"

    def __repr__(self) -> str:
        kind = "poses" if self.quaternions is not None else "positions"
        where = f" from {shown(self.source)}" if self.source else ""
        return f"<Measurements: {len(self)} {kind} of {len(self.joints)} joints{where}>"

    def _layout(
        self, text: Callable[[str], str]
    ) -> tuple[str, list[str], list[list[str]], list[str]]:
        """The title, the first rows' table and what follows it, names as ``text`` writes
        them."""
        kind = "poses" if self.quaternions is not None else "positions"
        markers = "" if self.markers is None else f" of {len(self.marker_ids())} markers"
        _, configs = self.configurations()
        where = f" from {text(self.source)}" if self.source else ""
        head = [*map(text, self.joints), "x", "y", "z"]
        if self.quaternions is not None:
            head += ["qx", "qy", "qz", "qw"]
        if self.markers is not None:
            head.insert(0, "marker")
        body = []
        for i in range(min(len(self), SHOWN_ROWS)):
            cells = [f"{v:.6g}" for v in self.q[i]] + [f"{v:.6g}" for v in self.points[i]]
            if self.quaternions is not None:
                cells += [f"{v:.6g}" for v in self.quaternions[i]]
            if self.markers is not None:
                cells.insert(0, str(int(self.markers[i])))
            body.append(cells)
        title = f"{len(self)} measured {kind}{markers} at {configs} configurations{where}"
        more = ["", f"... {len(self) - SHOWN_ROWS} more rows"] if len(self) > SHOWN_ROWS else []
        return title, head, body, more

    def marker_ids(self) -> list[int]:
        """The distinct markers, ascending (``[0]`` without a marker column)."""
        return [0] if self.markers is None else sorted({int(m) for m in self.markers})

    def configurations(self) -> tuple[NDArray[np.int64], int]:
        """Each row's configuration (a distinct row of joint values, numbered in the order of
        their first row; read-only, found once: :meth:`remembered`) and how many there are."""
        return self.remembered("configurations", self._configurations)

    def _configurations(self) -> tuple[NDArray[np.int64], int]:
        if len(self) == 0:
            return np.zeros(0, dtype=np.int64), 0
        order = np.lexsort(self.q.T[::-1])  # the rows sorted, equal rows in file order
        ranked = self.q[order]
        starts = np.empty(len(order), dtype=bool)  # where a sorted row differs from the last
        starts[0] = True
        np.any(ranked[1:] != ranked[:-1], axis=1, out=starts[1:])
        first = order[starts]  # each configuration's first row
        number = np.empty(len(first), dtype=np.int64)
        number[np.argsort(first)] = np.arange(len(first))  # numbered in file order
        out = np.empty(len(order), dtype=np.int64)
        out[order] = number[np.cumsum(starts) - 1]
        out.setflags(write=False)
        return out, len(first)

    def subset(self, rows: NDArray[np.int64]) -> Measurements:
        """The measurements at ``rows``."""
        return Measurements(
            self.joints,
            self.q[rows],
            self.points[rows],
            None if self.quaternions is None else self.quaternions[rows],
            None if self.markers is None else self.markers[rows],
            self.source,
            self.layout,
            None if self.read_as is None else self.read_as.subset(rows),
        )

    def of_configurations(self, chosen: NDArray[np.int64]) -> Measurements:
        """The rows of the configurations numbered ``chosen`` (:meth:`configurations`)."""
        index, count = self.configurations()
        keep = np.zeros(count, dtype=bool)
        keep[chosen] = True
        return self.subset(np.flatnonzero(keep[index]))


def check_noise(
    noise_pos: float | None,
    noise_rot: float | None,
    size: float,
    unit: str,
    exact: bool = False,
) -> None:
    """Refuse a noise level that is not a number > 0 (>= 0 with ``exact``: synthetic
    measurements may be exact), or that is as large as the robot (``size``, in ``unit``) or a
    radian: no measurement is exact, and one that noisy tells nothing."""
    for what, value, bound, bound_text in (
        ("position", noise_pos, size, f"the robot's size ({size:.3g} {unit})"),
        ("rotation", noise_rot, 1.0, "1 rad"),
    ):
        if value is None:
            continue
        if not (math.isfinite(value) and (value > 0.0 or (exact and value == 0.0))):
            least = ">= 0" if exact else "> 0 (measurements are never exact)"
            raise InputError(f"the {what} noise must be a number {least}, not {value:g}")
        if value >= bound:
            raise InputError(
                f"a {what} noise of {value:g} is not below {bound_text}: such measurements "
                "tell nothing about the robot"
            )


def _where(display: str, row: int, line: int, column: str | None = None) -> str:
    col = f", column {shown(column)}" if column is not None else ""
    return f"{display}: row {row} (line {line}){col}"


@dataclass(frozen=True, slots=True)
class _Layout:
    """Where each quantity sits in a file's rows."""

    joints: tuple[int, ...]  # column of each chain joint
    points: tuple[tuple[int, int, int], ...]  # x, y, z columns of each point on a row
    point_ids: tuple[int | None, ...]  # the marker of each (None: no marker)
    quaternion: tuple[int, ...] | None
    euler: tuple[int, ...] | None
    marker: int | None

    @property
    def rows_per_line(self) -> int:
        return len(self.points)


def _renamed(fields: list[str], reading: Reading, display: str) -> list[str | None]:
    """The header's names after renaming; ``None`` for an ignored column."""
    rename = dict(reading.rename)
    unknown = [old for old in rename if old not in fields]
    if unknown:
        raise InputError(
            f"{display}: no column {shown(unknown[0])} to rename; the header has "
            f"{choices(fields, limit=20, quoted=True)}"
        )
    out: list[str | None] = []
    for name in fields:
        if any(fnmatch.fnmatchcase(name, pattern) for pattern in reading.ignore):
            out.append(None)
        else:
            out.append(rename.get(name, name))
    return out


def _layout(names: list[str | None], joints: tuple[str, ...], display: str) -> _Layout:
    seen: dict[str, int] = {}
    for k, name in enumerate(names):
        if name is None:
            continue
        if name in seen:
            raise InputError(f"{display}: column {shown(name)} appears twice in the header")
        seen[name] = k
    wide: dict[int, dict[str, int]] = {}
    for name, k in seen.items():
        match = _WIDE.match(name)
        if match:
            wide.setdefault(int(match.group(2)), {})[match.group(1)] = k
    known = set(joints) | set(POINT) | set(QUATERNION) | set(EULER) | set(FIGAROH_EULER)
    known |= {MARKER}
    unknown = [n for n in seen if n not in known and not (_WIDE.match(n) and int(n[1:]) in wide)]
    if unknown:
        raise InputError(
            f"{display}: column {shown(unknown[0])} is neither a joint of the chain "
            f"{choices(joints, limit=20)} nor one of x, y, z, qx, qy, qz, qw, roll, pitch, "
            "yaw, marker (or FIGAROH's x1, y1, z1, ..., phix1, phiy1, phiz1); rename or "
            "ignore it"
        )
    missing = [j for j in joints if j not in seen]
    if missing:
        raise InputError(f"{display}: the header has no column for joint {shown(missing[0])}")
    points: list[tuple[int, int, int]] = []
    ids: list[int | None] = []
    if wide and any(c in seen for c in POINT):
        raise InputError(
            f"{display}: the header has both x, y, z and numbered points "
            f"(x{min(wide)}, ...); one or the other"
        )
    if wide:
        for marker in sorted(wide):
            cols = wide[marker]
            absent = next((c for c in POINT if c not in cols), None)
            if absent is not None:
                raise InputError(
                    f"{display}: the header has {', '.join(f'{c}{marker}' for c in cols)} but "
                    f"no {absent}{marker}"
                )
            points.append((cols["x"], cols["y"], cols["z"]))
            ids.append(marker if len(wide) > 1 else None)
    else:
        absent = next((c for c in POINT if c not in seen), None)
        if absent is not None:
            raise InputError(f"{display}: the header has no column for {shown(absent)}")
        points.append((seen["x"], seen["y"], seen["z"]))
        ids.append(None)
    quat = _group(seen, QUATERNION, "a pose", display)
    euler = _group(seen, EULER, "roll, pitch, yaw", display)
    figaroh = _group(seen, FIGAROH_EULER, "FIGAROH's angles", display)
    orientations = [g for g in (quat, euler, figaroh) if g is not None]
    if len(orientations) > 1:
        raise InputError(
            f"{display}: the header gives the orientation twice (quaternion and angles); "
            "ignore one of them"
        )
    orientation = orientations[0] if orientations else None
    if orientation is not None and len(points) > 1:
        raise InputError(
            f"{display}: an orientation goes with one point per row (a pose), not "
            f"{len(points)} markers"
        )
    marker_column = seen.get(MARKER)
    if marker_column is not None and len(points) > 1:
        raise InputError(
            f"{display}: a 'marker' column goes with one point per row, not numbered points"
        )
    return _Layout(
        tuple(seen[j] for j in joints),
        tuple(points),
        tuple(ids),
        quat,
        euler if euler is not None else figaroh,
        marker_column,
    )


def _group(
    seen: dict[str, int], names: tuple[str, ...], what: str, display: str
) -> tuple[int, ...] | None:
    present = [c for c in names if c in seen]
    if not present:
        return None
    if len(present) != len(names):
        absent = next(c for c in names if c not in seen)
        raise InputError(
            f"{display}: the header has {', '.join(present)} but no {shown(absent)}; "
            f"{what} needs all of {', '.join(names)}"
        )
    return tuple(seen[c] for c in names)


def _rows(text: str, display: str) -> Iterator[tuple[int, list[str]]]:
    """The CSV's non-blank rows with their line numbers; a row the csv module cannot read (a
    cell beyond its field limit, a stray quote at the end) is an error naming its line."""
    reader = csv.reader(io.StringIO(text, newline=""))
    while True:
        try:
            raw = next(reader)
        except StopIteration:
            return
        except csv.Error as e:
            raise InputError(f"{display}, line {reader.line_num}: not a CSV row ({e})") from e
        if any(f.strip() for f in raw):
            yield reader.line_num, raw


def _number(raw: list[str], k: int, name: str, where: str) -> float:
    """The cell's number, by the one grammar of urdf2dh's files (:mod:`urdf2dh.numerals`);
    spaces and tabs around it are allowed."""
    return read_decimal(raw[k].strip(" \t"), f"{where}, column {shown(name)}")


def _text(path: str | Path, display: str) -> str:
    data = read_file(Path(path), display, limit=MEASUREMENT_BYTES)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        raise InputError(f"{display}: not a text (UTF-8) file") from e


def read_measurements(
    path: str | Path,
    joints: tuple[str, ...],
    display: str | None = None,
    reading: Reading | None = None,
    sliding: tuple[str, ...] = (),
    length_unit: str | None = None,
) -> Measurements:
    """Read and check a measurement file against the chain's joint names (module docstring).

    Parameters
    ----------
    path
        The CSV file.
    joints
        The chain's actuated joints, in order.
    display
        The file's name in messages (default ``path``).
    reading
        Renamed and ignored columns, the file's units and rotation sequence.
    sliding
        The prismatic joints among ``joints`` (their values are lengths, the others angles).
    length_unit
        The nominal's length unit, into which :attr:`Reading.length_unit` converts.

    Raises
    ------
    InputError
        Any fault of the file, naming the row and column.
    """
    display = display or str(path)
    reading = reading or Reading()
    rows = _rows(_text(path, display), display)
    first = next(rows, None)
    if first is None:
        raise InputError(f"{display}: empty file (expected a header row and measurements)")
    fields = [f.strip() for f in first[1]]
    renamed = _renamed(fields, reading, display)
    # a name as written, or as csv_cell writes it
    names = [None if n is None else csv_names([n], joints)[0] for n in renamed]
    layout = _layout(names, joints, display)
    shown_names = [n if n is not None else "" for n in names]
    q_rows: list[list[float]] = []
    point_rows: list[list[float]] = []
    orient_rows: list[list[float]] = []
    marks: list[int] = []
    per_line = layout.rows_per_line
    for count, (line, raw) in enumerate(rows, start=1):
        where = _where(display, count, line)
        if len(raw) != len(fields):
            raise InputError(f"{where}: {len(raw)} fields, but the header has {len(fields)}")
        if len(point_rows) + per_line > MAX_MEASUREMENTS:
            raise InputError(
                f"{display}: more than {MAX_MEASUREMENTS} measurements; calibration reads at "
                "most that many (a few hundred well-spread configurations identify a robot: "
                "urdf2dh plan picks them)"
            )
        q = [_number(raw, k, shown_names[k], where) for k in layout.joints]
        orient: list[float] = []
        if layout.quaternion is not None:
            orient = [_number(raw, k, shown_names[k], where) for k in layout.quaternion]
            norm = math.sqrt(math.fsum(v * v for v in orient))
            if abs(norm - 1.0) > QUATERNION_NORM:
                raise InputError(
                    f"{where}, column 'qw': the quaternion (qx, qy, qz, qw) has norm "
                    f"{norm:.9g}, not 1 (within {QUATERNION_NORM:g})"
                )
        elif layout.euler is not None:
            orient = [_number(raw, k, shown_names[k], where) for k in layout.euler]
        mark = None
        if layout.marker is not None:
            text_value = raw[layout.marker].strip(" \t")
            mark = integer(text_value)
            if mark is None:
                raise InputError(f"{where}, column 'marker': {shown(text_value)} is not an integer")
            if mark < 0:
                raise InputError(f"{where}, column 'marker': {mark} is negative")
        for cols, marker in zip(layout.points, layout.point_ids, strict=True):
            q_rows.append(q)
            point_rows.append([_number(raw, k, shown_names[k], where) for k in cols])
            if orient:
                orient_rows.append(orient)
            if marker is not None or mark is not None:
                marks.append(marker if marker is not None else int(mark))  # type: ignore[arg-type]
    if not q_rows:
        raise InputError(f"{display}: no measurements after the header")
    q_all = np.array(q_rows, dtype=float)
    points = np.array(point_rows, dtype=float)
    if reading.length_unit is not None and length_unit is not None:
        factor = units.factor(reading.length_unit, length_unit)
        points *= factor
        for k, name in enumerate(joints):
            if name in sliding:
                q_all[:, k] *= factor
    if reading.degrees:
        for k, name in enumerate(joints):
            if name not in sliding:
                q_all[:, k] = np.radians(q_all[:, k])
    quats, angles = None, None
    orientation = layout.quaternion if layout.quaternion is not None else layout.euler
    if layout.quaternion is not None:
        quats = np.array(orient_rows, dtype=float)
        quats /= np.linalg.norm(quats, axis=1, keepdims=True)
    elif layout.euler is not None:
        angles = np.array(orient_rows, dtype=float)
        quats = euler_quaternions(angles, reading.euler, reading.degrees)
    read_as = AsRead(
        reading,
        length_unit,
        tuple(fields[k] for k in layout.joints),
        tuple(fields[k] for k in layout.points[0]) if len(layout.points) == 1 else (),
        tuple(fields[k] for k in orientation) if orientation is not None else (),
        angles,
    )
    return Measurements(
        joints,
        q_all,
        points,
        quats,
        np.array(marks, dtype=np.int64) if marks else None,
        display,
        read_as=read_as,
    )


def euler_quaternions(angles: Mat, sequence: str, degrees: bool) -> Mat:
    """``(N, 4)`` unit quaternions ``[x, y, z, w]`` of the angles ``(N, 3)`` in ``sequence``
    (scipy's notation, :attr:`Reading.euler`)."""
    from scipy.spatial.transform import Rotation

    out: Mat = Rotation.from_euler(sequence, angles, degrees=degrees).as_quat()
    return out


def read_configurations(
    path: str | Path,
    joints: tuple[str, ...],
    display: str | None = None,
    degrees: bool = False,
    sliding: tuple[str, ...] = (),
) -> Mat:
    """``(N, n)`` joint values from a CSV file with a column per joint (others are skipped):
    candidate configurations for :func:`urdf2dh.calibration.plan.plan`, or its own output."""
    display = display or str(path)
    rows = _rows(_text(path, display), display)
    first = next(rows, None)
    if first is None:
        raise InputError(f"{display}: empty file (expected a header row and configurations)")
    fields = csv_names([f.strip() for f in first[1]], joints)
    missing = [j for j in joints if j not in fields]
    if missing:
        raise InputError(f"{display}: the header has no column for joint {shown(missing[0])}")
    cols = [fields.index(j) for j in joints]
    out = []
    for count, (line, raw) in enumerate(rows, start=1):
        where = _where(display, count, line)
        if len(raw) != len(fields):
            raise InputError(f"{where}: {len(raw)} fields, but the header has {len(fields)}")
        if count > MAX_MEASUREMENTS:
            raise InputError(f"{display}: more than {MAX_MEASUREMENTS} configurations")
        out.append([_number(raw, k, fields[k], where) for k in cols])
    if not out:
        raise InputError(f"{display}: no configurations after the header")
    q = np.array(out, dtype=float)
    if degrees:
        for k, name in enumerate(joints):
            if name not in sliding:
                q[:, k] = np.radians(q[:, k])
    return q


def write_measurements(m: Measurements) -> str:
    """The CSV text of ``m`` (every number as the shortest text that reads back exactly, joint
    names as :func:`~urdf2dh.escape.csv_cell` writes them)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    header = [*(csv_cell(j) for j in m.joints), *POINT]
    if m.quaternions is not None:
        header += QUATERNION
    if m.markers is not None:
        header.append(MARKER)
    out.write(",".join(header) + "\n")  # names as csv_cell writes them
    for k in range(len(m)):
        row = [repr(float(v) + 0.0) for v in (*m.q[k], *m.points[k])]
        if m.quaternions is not None:
            row += [repr(float(v) + 0.0) for v in m.quaternions[k]]
        if m.markers is not None:
            row.append(str(int(m.markers[k])))
        writer.writerow(row)
    return out.getvalue()


def write_configurations(joints: tuple[str, ...], q: Mat) -> str:
    """The CSV text of configurations: a column per joint (names as
    :func:`~urdf2dh.escape.csv_cell` writes them)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    out.write(",".join(csv_cell(j) for j in joints) + "\n")
    for row in q:
        writer.writerow([repr(float(v) + 0.0) for v in row])
    return out.getvalue()


def read_layout(path: str | Path, display: str | None = None) -> dict[int, Mat]:
    """A marker layout file: ``marker,x,y,z`` rows, the markers' positions in the tool frame."""
    display = display or str(path)
    text = read_file(Path(path), display).decode("utf-8-sig", errors="replace")
    rows = _rows(text, display)
    first = next(rows, None)
    header = [] if first is None else [f.strip() for f in first[1]]
    if header != [MARKER, *POINT]:
        raise InputError(f"{display}: a marker layout has the header 'marker,x,y,z'")
    out: dict[int, Mat] = {}
    for row, (line, raw) in enumerate(rows, start=1):
        if len(raw) != 4:
            raise InputError(f"{_where(display, row, line)}: {len(raw)} fields, not 4")
        mark = integer(raw[0].strip(" \t"))
        if mark is None:
            raise InputError(
                f"{_where(display, row, line, MARKER)}: {shown(raw[0].strip())} is not an integer"
            )
        if mark in out:
            raise InputError(f"{_where(display, row, line, MARKER)}: marker {mark} appears twice")
        values = [decimal(v.strip(" \t")) for v in raw[1:]]
        if any(v is None for v in values):
            bad = next(v for v in raw[1:] if decimal(v.strip(" \t")) is None)
            reason = why_not(bad.strip(" \t"))
            problem = "must be finite" if reason == "not finite" else "must be numbers"
            raise InputError(
                f"{_where(display, row, line)}: x, y, z {problem} ({shown(bad)}: {reason})"
            )
        xyz = np.array(values, dtype=float)
        out[mark] = xyz
        if len(out) > MAX_MEASUREMENTS:
            raise InputError(f"{display}: more than {MAX_MEASUREMENTS} markers")
    if not out:
        raise InputError(f"{display}: no markers after the header")
    return out


def write_layout(layout: dict[int, Mat]) -> str:
    """The text of a marker layout file."""
    lines = ["marker,x,y,z"]
    lines += [
        f"{k}," + ",".join(repr(float(v) + 0.0) for v in xyz) for k, xyz in sorted(layout.items())
    ]
    return "\n".join(lines) + "\n"
