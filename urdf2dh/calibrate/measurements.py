"""Measurement files (issue 15, SPEC §5): CSV with a header row, read strictly, written exactly.

::

    j1,j2,j3,j4,j5,j6,x,y,z,qx,qy,qz,qw
    0.1,-0.5,1.2,0.3,0.2,0.1,412.7,85.3,-12.9,0.1,0.2,0.3,0.927

* one column per actuated joint, named as in the chain (radians for revolute and helical
  joints, the source's length unit for prismatic ones), in any order;
* ``x, y, z``: the tool point in the measuring device's frame (source length unit);
* for pose measurements ``qx, qy, qz, qw``: the tool orientation as a unit quaternion, scalar
  last (norm within :data:`~urdf2dh.tolerances.QUATERNION_NORM` of 1);
* optionally ``marker`` (integer >= 0): which of several points on the tool was measured, for
  position measurements.

Any fault (a NaN, a wrong field count, an unknown or missing column, a quaternion off unit
norm, a non-integer marker) is an :class:`~urdf2dh.errors.InputError` naming the file, the row
(data rows count from 1; the line number follows) and the column.

A *marker layout* file gives the markers' nominal positions on the tool, in the tool frame:
``marker,x,y,z``, one row per marker (:func:`read_layout`).
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError, choices, shown
from ..export.escape import csv_cell, csv_names
from ..files import read_file
from ..tolerances import QUATERNION_NORM

__all__ = [
    "POINT",
    "QUATERNION",
    "Measurements",
    "read_layout",
    "read_measurements",
    "write_layout",
    "write_measurements",
]

Mat = NDArray[np.float64]

POINT = ("x", "y", "z")
QUATERNION = ("qx", "qy", "qz", "qw")
MARKER = "marker"


@dataclass(frozen=True, slots=True)
class Measurements:
    """Joint positions and what the device measured at each.

    Attributes
    ----------
    joints
        Joint names, in the chain's order (the columns of ``q``).
    q
        ``(N, n)`` joint positions.
    points
        ``(N, 3)`` tool points in the device frame.
    quaternions
        ``(N, 4)`` unit quaternions ``[x, y, z, w]`` of the tool orientation, or ``None``.
    markers
        ``(N,)`` integer marker of each row (position measurements), or ``None``.
    source
        The file's name, for messages.
    """

    joints: tuple[str, ...]
    q: Mat
    points: Mat
    quaternions: Mat | None = None
    markers: NDArray[np.int64] | None = None
    source: str = ""

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

    def marker_ids(self) -> list[int]:
        """The distinct markers, ascending (``[0]`` without a marker column)."""
        return [0] if self.markers is None else sorted({int(m) for m in self.markers})

    def subset(self, rows: NDArray[np.int64]) -> Measurements:
        """The measurements at ``rows``."""
        return Measurements(
            self.joints,
            self.q[rows],
            self.points[rows],
            None if self.quaternions is None else self.quaternions[rows],
            None if self.markers is None else self.markers[rows],
            self.source,
        )


def _where(display: str, row: int, line: int, column: str | None = None) -> str:
    col = f", column {shown(column)}" if column is not None else ""
    return f"{display}: row {row} (line {line}){col}"


def _header(fields: list[str], joints: tuple[str, ...], display: str) -> None:
    seen: set[str] = set()
    for name in fields:
        if name in seen:
            raise InputError(f"{display}: column {shown(name)} appears twice in the header")
        seen.add(name)
    known = set(joints) | set(POINT) | set(QUATERNION) | {MARKER}
    unknown = [f for f in fields if f not in known]
    if unknown:
        raise InputError(
            f"{display}: column {shown(unknown[0])} is neither a joint of the chain "
            f"{choices(joints, limit=20)} nor one of x, y, z, qx, qy, qz, qw, marker"
        )
    missing = [j for j in (*joints, *POINT) if j not in seen]
    if missing:
        what = "joint" if missing[0] in joints else "column"
        raise InputError(f"{display}: the header has no column for {what} {shown(missing[0])}")
    quat = [c for c in QUATERNION if c in seen]
    if quat and len(quat) != 4:
        absent = next(c for c in QUATERNION if c not in seen)
        raise InputError(
            f"{display}: the header has {', '.join(quat)} but no {shown(absent)}; a "
            "pose needs all of qx, qy, qz, qw"
        )


def read_measurements(
    path: str | Path, joints: tuple[str, ...], display: str | None = None
) -> Measurements:
    """Read and check a measurement file against the chain's joint names."""
    display = display or str(path)
    data = read_file(Path(path), display)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        raise InputError(f"{display}: not a text (UTF-8) file") from e
    reader = csv.reader(io.StringIO(text, newline=""))
    header = next((r for r in reader if any(f.strip() for f in r)), None)
    if header is None:
        raise InputError(f"{display}: empty file (expected a header row and measurements)")
    fields = csv_names([f.strip() for f in header], joints)  # as written, or as csv_cell writes
    _header(fields, joints, display)
    col = {name: k for k, name in enumerate(fields)}
    has_quat, has_marker = "qw" in col, MARKER in col
    numeric = [*joints, *POINT, *(QUATERNION if has_quat else ())]
    rows: list[list[float]] = []
    marks: list[int] = []
    for raw in reader:
        if not any(f.strip() for f in raw):
            continue  # blank lines carry nothing
        row, line = len(rows) + 1, reader.line_num
        if len(raw) != len(fields):
            raise InputError(
                f"{_where(display, row, line)}: {len(raw)} fields, but the header has {len(fields)}"
            )
        values = []
        for name in numeric:
            text_value = raw[col[name]].strip()
            try:
                value = float(text_value)
            except ValueError:
                raise InputError(
                    f"{_where(display, row, line, name)}: {shown(text_value)} is not a number"
                ) from None
            if not math.isfinite(value):
                raise InputError(
                    f"{_where(display, row, line, name)}: {shown(text_value)} is not a finite "
                    "number"
                )
            values.append(value)
        if has_quat:
            norm = math.sqrt(math.fsum(v * v for v in values[-4:]))
            if abs(norm - 1.0) > QUATERNION_NORM:
                raise InputError(
                    f"{_where(display, row, line, 'qw')}: the quaternion (qx, qy, "
                    f"qz, qw) has norm {norm:.9g}, not 1 (within "
                    f"{QUATERNION_NORM:g})"
                )
        if has_marker:
            text_value = raw[col[MARKER]].strip()
            try:
                mark = int(text_value, 10)
            except ValueError:
                raise InputError(
                    f"{_where(display, row, line, MARKER)}: {shown(text_value)} is not an integer"
                ) from None
            if mark < 0:
                raise InputError(f"{_where(display, row, line, MARKER)}: {mark} is negative")
            marks.append(mark)
        rows.append(values)
    if not rows:
        raise InputError(f"{display}: no measurements after the header")
    table = np.array(rows, dtype=float)
    n = len(joints)
    return Measurements(
        joints,
        table[:, :n],
        table[:, n : n + 3],
        table[:, n + 3 :] if has_quat else None,
        np.array(marks, dtype=np.int64) if has_marker else None,
        display,
    )


def write_measurements(m: Measurements) -> str:
    """The CSV text of ``m`` (every number as the shortest text that reads back exactly, joint
    names as :func:`~urdf2dh.export.escape.csv_cell` writes them)."""
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


def read_layout(path: str | Path, display: str | None = None) -> dict[int, Mat]:
    """A marker layout file: ``marker,x,y,z`` rows, the markers' positions in the tool frame."""
    display = display or str(path)
    text = read_file(Path(path), display).decode("utf-8-sig", errors="replace")
    reader = csv.reader(io.StringIO(text, newline=""))
    header = [f.strip() for f in next(reader, [])]
    if header != [MARKER, *POINT]:
        raise InputError(f"{display}: a marker layout has the header 'marker,x,y,z'")
    out: dict[int, Mat] = {}
    for raw in reader:
        if not any(f.strip() for f in raw):
            continue
        row, line = len(out) + 1, reader.line_num
        if len(raw) != 4:
            raise InputError(f"{_where(display, row, line)}: {len(raw)} fields, not 4")
        try:
            mark = int(raw[0].strip(), 10)
        except ValueError:
            raise InputError(
                f"{_where(display, row, line, MARKER)}: {shown(raw[0].strip())} is not an integer"
            ) from None
        if mark in out:
            raise InputError(f"{_where(display, row, line, MARKER)}: marker {mark} appears twice")
        try:
            xyz = np.array([float(v) for v in raw[1:]])
        except ValueError:
            raise InputError(f"{_where(display, row, line)}: x, y, z must be numbers") from None
        if not np.all(np.isfinite(xyz)):
            raise InputError(f"{_where(display, row, line)}: x, y, z must be finite")
        out[mark] = xyz
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
