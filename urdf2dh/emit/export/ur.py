"""Universal Robots: ``default_kinematics.yaml`` with the calibration hash of UR's client library.

The consumer
------------
``ur_macro.xacro`` of Universal_Robots_ROS2_Description reads ``kinematics:`` and places each
entry verbatim as a joint origin, ``<origin xyz="x y z" rpy="roll pitch yaw"/>``, with the joint
axis along that frame's z: ``shoulder`` -> ``shoulder_pan_joint``, ``upper_arm`` ->
``shoulder_lift_joint``, ``forearm`` -> ``elbow_joint``, ``wrist_1/2/3`` ->
``wrist_1/2/3_joint``. Around them the macro puts fixed frames of its own: ``base_link`` ->
``base_link_inertia`` is ``Rz(pi)`` (``base_link`` is REP-103 aligned, UR's base frame faces the
other way) and ``wrist_3_link`` -> ``flange`` -> ``tool0`` composes to the identity. URDF reads
``rpy`` as fixed-axis angles, ``R = Rz(yaw) Ry(pitch) Rx(roll)``.

Joint origins from the D-H table
--------------------------------
As UR's calibration tool (``ur_calibration``) splits them: each D-H row ``Rz(theta) Tz(d)
Rx(alpha) Tx(a)`` into ``Rz(theta) Tz(d)`` and ``Rx(alpha) Tx(a)``; joint 1's origin is
``Rz(theta_1) Tz(d_1)`` and joint k's (k = 2..6) is ``Rx(alpha_{k-1}) Tx(a_{k-1}) Rz(theta_k)
Tz(d_k)``. So ``wrist_3_link`` is D-H frame 6 (UR's tool flange), once the last row's
``Rx(alpha_6) Tx(a_6)`` and the table's tool transform are the identity, as UR's are. The tool's
correction of ``d_2``/``d_3`` for calibrated arms (``correctAxis``) is not applied: it changes no
forward kinematics and nothing at all for nominal tables.

The hash
--------
The client library (``urcl::primary_interface::KinematicsInfo::toHash``) writes ``theta, d, a,
alpha`` of joint 1, then of joint 2, ... joint 6 into a C++ stream with its default formatting
(``%g``, 6 significant digits), no separators, and hashes the text with
``std::hash<std::string>``; libstdc++ on 64-bit targets implements that as ``_Hash_bytes`` with
seed ``0xc70f6907``, a variant of MurmurHash64A (reproduced in
:func:`urdf2dh.io.urkinematics.hash_bytes`, with the file's reader). The driver compares
``calib_<hash>`` with the yaml's ``hash`` to tell whether the description matches the robot's
calibration.

Our tables are exact, so they carry round-off-sized values where UR's text has zeros (the
URDF's rounded pi/2 leaves theta = -4.9e-12 in UR10's), and lengths one ulp off their decimal
(0.11569999999999994); ``%g`` of those is not UR's text. Before hashing, every value is
rounded to :data:`~urdf2dh.tolerances.HASH_DECIMALS` decimals (1e-10: far below the 6 digits
the hash sees, far above round-off) and -0 becomes 0. The yaml shows the hashed table.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from numpy.typing import NDArray

from ... import units
from ...conventions import Params
from ...conventions.table import Table
from ...errors import ExportError, shown, visible
from ...escape import yaml_comment
from ...geometry.se3 import dh_matrix, rot_z, rpy
from ...io.urkinematics import LINKS, SEED, calibration_hash, hash_bytes, hash_text, hashed_rows
from ...tolerances import HASH_DECIMALS
from .common import (
    ExportOptions,
    Numbers,
    close_to,
    floats,
    header,
    require,
    require_convention,
    yaml_float,
)

__all__ = [
    "LINKS",
    "SEED",
    "calibration_hash",
    "hash_bytes",
    "hash_text",
    "hashed_rows",
    "joint_origins",
    "render",
]

Mat = NDArray[np.float64]

_MACRO_BASE = rot_z(math.pi)  # base_link -> base_link_inertia in ur_macro.xacro


def _check(table: Table, opts: ExportOptions) -> None:
    require_convention(table, "ur", ("dh",))
    if table.n != 6:
        raise ExportError(f"ur: a UR arm has 6 joints; this chain has {table.n}")
    require(table, "ur", ("dh",), ("revolute",))
    if not close_to(table, table.base_matrix, _MACRO_BASE, opts.tol):
        raise ExportError(
            f"ur: ur_macro.xacro puts UR's base frame at Rz(pi) from base_link, but this "
            f"chain's D-H frame 0 is elsewhere from {shown(table.base_link)} (base params "
            f"{_params(table.base)}); export from the UR description's base_link"
        )
    last = floats(table.rows[-1].params)
    flange = dh_matrix(0.0, 0.0, last["alpha"], last["a"]) @ table.tool_matrix
    if not close_to(table, flange, np.eye(4), opts.tol):
        raise ExportError(
            f"ur: ur_macro.xacro puts tool0 on D-H frame 6 (UR's flange), but "
            f"{shown(table.tip_link)} is elsewhere (last row alpha = "
            f"{math.degrees(last['alpha']):.6g} deg, a = {last['a']:.6g} "
            f"{visible(table.length_unit)}; tool "
            f"{_params(table.tool)}); export to the UR description's tool0"
        )


def _params(p: Params) -> str:
    kinds = type(p).quantities()
    return ", ".join(
        f"{k} = {math.degrees(v):.6g} deg" if kinds[k] == "angle" else f"{k} = {v:.6g}"
        for k, v in floats(p).items()
    )


def joint_origins(table: Table) -> list[Mat]:
    """The six joint origins (4x4, metres) of ``ur_macro.xacro``'s chain, split as
    ``ur_calibration`` splits the D-H rows."""
    k = units.factor(table.length_unit, "m")
    rows = [floats(r.params) for r in table.rows]
    out = [dh_matrix(rows[0]["theta"], k * rows[0]["d"], 0.0, 0.0)]
    for prev, cur in itertools.pairwise(rows):
        passive = dh_matrix(0.0, 0.0, prev["alpha"], k * prev["a"])
        out.append(passive @ dh_matrix(cur["theta"], k * cur["d"], 0.0, 0.0))
    return out


def render(table: Table, opts: ExportOptions) -> str:
    """``default_kinematics.yaml`` for ``ur_macro.xacro`` (see the module docstring)."""
    _check(table, opts)
    rows = hashed_rows(table)
    notes = header(table, "UR default_kinematics.yaml", "m")
    notes.append("Joint origins for Universal_Robots_ROS2_Description's ur_macro.xacro (metres,")
    notes.append("URDF rpy). The hash is the UR client library's, of this D-H table (rounded to")
    notes.append(f"{HASH_DECIMALS} decimals; theta, d, a, alpha per joint):")
    width = max(len(visible(r.name)) for r in table.rows)
    for r, values in zip(table.rows, rows, strict=True):
        pad = " " * (width - len(visible(r.name)))
        notes.append(f"  {r.name}{pad}  " + "  ".join(f"{v:>10g}" for v in values))
    lines = [yaml_comment(note) for note in notes]
    lines.append("kinematics:")
    metres = units.factor(table.length_unit, "m")
    numbers = Numbers(table.size * metres, opts.tol.written)  # origins are in metres
    for link, origin in zip(LINKS, joint_origins(table), strict=True):
        lines.append(f"  {link}:")
        xyz = (numbers.length(v) for v in origin[:3, 3])
        for key, value in zip(("x", "y", "z"), xyz, strict=True):
            lines.append(f"    {key}: {yaml_float(value)}")
        for key, value in zip(("roll", "pitch", "yaw"), rpy(origin), strict=True):
            lines.append(f"    {key}: {yaml_float(numbers.angle(value))}")
    lines.append(f"  hash: {calibration_hash(table)}")
    return "\n".join(lines) + "\n"
