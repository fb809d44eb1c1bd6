"""Universal Robots' kinematics files as a SOURCE: ``default_kinematics.yaml``, what
``ur_calibration`` writes from a robot's factory calibration, and what ``export --to ur``
writes (docs/commands/index.md; the writer: :mod:`urdf2dh.emit.export.ur`).

The format, as ``ur_macro.xacro`` of Universal_Robots_ROS2_Description reads it::

    kinematics:
      shoulder:  {x, y, z, roll, pitch, yaw}     # shoulder_pan_joint's origin
      upper_arm: {...}                            # shoulder_lift_joint's
      forearm:   {...}                            # elbow_joint's
      wrist_1:   {...}  wrist_2: {...}  wrist_3: {...}
      hash: calib_<n>                             # the calibration's, from the robot

Each entry is a joint's ``<origin xyz rpy>`` verbatim (URDF's ``R = Rz(yaw) Ry(pitch)
Rx(roll)``), its axis along z. Around them the macro puts ``base_link`` -> ``base_link_inertia``
turned by pi about z (UR's base frame faces the other way), and ``wrist_3_link`` -> ``flange``
(rpy 0, -pi/2, -pi/2) -> ``tool0`` (rpy pi/2, 0, pi/2), which compose to the identity. The
model read is that chain, ``base_link`` -> ``tool0``, as the description built from the file is.

The hash. UR's client library hashes the robot's D-H table (``theta, d, a, alpha`` of each
joint, as a C++ stream writes doubles, no separators; libstdc++'s ``std::hash<std::string>``,
reproduced by :func:`hash_bytes`); the driver compares it with the file's to tell whether the
description is the robot's. The reader takes the D-H table of the file's joint origins (UR's
base frame to the flange, D-H frame 6), exact, and checks the file's hash against it, for each
of the choices a D-H table leaves (which way each common normal points), with the values as they
are and rounded to :data:`~urdf2dh.tolerances.HASH_DECIMALS` decimals (the round-off of an
exact table where UR writes 0). A hash that none gives is reported in the model's warnings.
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError, shown
from ..geometry import se3
from ..geometry.lie import log_so3
from ..tolerances import HASH_DECIMALS
from .fields import check_number

if TYPE_CHECKING:
    from ..conventions.table import Table
    from ..model.poe import PoeModel
    from .sources import Content, Reading, Source

__all__ = [
    "JOINTS",
    "LINKS",
    "SEED",
    "UrKinematics",
    "calibration_hash",
    "hash_bytes",
    "hash_text",
    "hashed_rows",
    "is_ur_kinematics",
    "read_source",
    "read_ur_kinematics",
]

Mat = NDArray[np.float64]
Rows = list[tuple[float, float, float, float]]

#: The file's entries, in chain order, and the joints ``ur_macro.xacro`` gives them to.
LINKS = ("shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3")
JOINTS = ("shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint",
          "wrist_2_joint", "wrist_3_joint")  # fmt: skip
KEYS = ("x", "y", "z", "roll", "pitch", "yaw")
BASE = se3.from_rpy((0.0, 0.0, 0.0), (0.0, 0.0, math.pi))  # base_link -> base_link_inertia
FLANGE = se3.from_rpy((0.0, 0.0, 0.0), (0.0, -math.pi / 2, -math.pi / 2))  # wrist_3 -> flange
TOOL0 = se3.from_rpy((0.0, 0.0, 0.0), (math.pi / 2, 0.0, math.pi / 2))  # flange -> tool0
SEED = 0xC70F6907  # libstdc++'s seed for std::hash<std::string>
_MUL = 0xC6A4A7935BD1E995  # MurmurHash64A's multiplier
_MASK = (1 << 64) - 1
_HASH = re.compile(r"calib_[0-9]{1,20}")


def _shift_mix(v: int) -> int:
    return v ^ (v >> 47)


def hash_bytes(data: bytes, seed: int = SEED) -> int:
    """libstdc++'s 64-bit ``_Hash_bytes``: MurmurHash64A over 8-byte little-endian words, with
    the tail bytes mixed in as one word and a final double shift-mix."""
    n = len(data)
    h = (seed ^ (n * _MUL)) & _MASK
    whole = n - n % 8
    for i in range(0, whole, 8):
        word = int.from_bytes(data[i : i + 8], "little")
        word = (_shift_mix((word * _MUL) & _MASK) * _MUL) & _MASK
        h = ((h ^ word) * _MUL) & _MASK
    if n % 8:
        h = ((h ^ int.from_bytes(data[whole:], "little")) * _MUL) & _MASK
    h = (_shift_mix(h) * _MUL) & _MASK
    return _shift_mix(h)


def hash_text(rows: Rows) -> str:
    """The text UR's client library hashes: every value as a C++ stream writes a double by
    default (``%g``), joint after joint, no separators."""
    return "".join(f"{v:g}" for row in rows for v in row)


def _calib(rows: Rows) -> str:
    return f"calib_{hash_bytes(hash_text(rows).encode('ascii'))}"


def hashed_rows(table: Table) -> Rows:
    """``(theta, d, a, alpha)`` per joint in metres and radians, rounded to :data:`HASH_DECIMALS`
    decimals (-0 turned into 0)."""
    from .. import units

    k = units.factor(table.length_unit, "m")
    rows = [r.params.scalars() for r in table.rows]
    return _rounded([(p["theta"], k * p["d"], k * p["a"], p["alpha"]) for p in rows])


def _rounded(rows: Rows) -> Rows:
    def snap(x: float) -> float:
        return round(x, HASH_DECIMALS) + 0.0

    return [(snap(t), snap(d), snap(a), snap(al)) for t, d, a, al in rows]


def calibration_hash(table: Table) -> str:
    """``calib_<n>`` for a UR-style table (see the module docstring)."""
    return _calib(hashed_rows(table))


@dataclass(frozen=True)
class UrKinematics:
    """A UR kinematics file as read: the six joint origins ``(6, 4, 4)`` (metres, each in its
    parent link's frame, as ``ur_macro.xacro`` reads them), the file's hash (``None`` where it
    has none), whether the D-H table of the origins gives it (``None`` without a hash), the hash
    they give, and a note where the hash holds for the angles read as ``ur_calibration`` writes
    them (Eigen's x-y-z angles) and not as URDF rpy."""

    display: str
    origins: Mat
    hash: str | None
    hash_checked: bool | None
    computed_hash: str
    note: str = ""

    def model(self, name: str = "ur") -> PoeModel:
        """The chain ``base_link`` -> ``tool0`` that ``ur_macro.xacro`` builds from the file."""
        from ..model.poe import Joint, PoeModel

        frame = BASE.copy()
        joints = []
        for joint_name, origin in zip(JOINTS, self.origins, strict=True):
            frame = frame @ origin
            joints.append(Joint(joint_name, "revolute", frame[:3, 2].copy(), frame[:3, 3].copy()))
        home = frame @ FLANGE @ TOOL0
        home[3] = (0.0, 0.0, 0.0, 1.0)
        warnings: tuple[str, ...] = ()
        if self.hash_checked is False:
            warnings = (self._hash_warning(),)
        elif self.note:
            warnings = (f"{self.display}: {self.note}",)
        return PoeModel(tuple(joints), home, name, self.display, "base_link", "tool0", "m",
                        warnings)  # fmt: skip

    def _hash_warning(self) -> str:
        return (
            f"{self.display}: hash {self.hash} is not that of the D-H table of its joint origins "
            f"({self.computed_hash}): the file was edited, or written by a tool that rounds "
            "otherwise; UR's driver compares the file's hash with the robot's"
        )


def is_ur_kinematics(tree: Any) -> bool:
    """Whether a parsed YAML tree is a UR kinematics file (``kinematics: {shoulder: ...}``)."""
    return (
        isinstance(tree, Mapping)
        and isinstance(tree.get("kinematics"), Mapping)
        and "shoulder" in tree["kinematics"]
    )


def read_ur_kinematics(tree: Any, display: str) -> UrKinematics:
    """A UR kinematics file's tree, checked: every entry with its six numbers, the hash
    ``calib_<digits>`` if there is one.

    Raises
    ------
    InputError
        A missing entry or number, a number that is not one, an unknown key, a malformed hash;
        the message names the file and the entry.
    """
    if not is_ur_kinematics(tree):
        raise InputError(f"{display}: not a UR kinematics file (kinematics: {{shoulder: ...}})")
    kin = tree["kinematics"]
    unknown = [k for k in kin if k not in (*LINKS, "hash")]
    if unknown:
        raise InputError(
            f"{display}: kinematics: unknown entry {shown(unknown[0])}; UR's are "
            f"{', '.join(LINKS)} and hash"
        )
    origins, eigen = [], []
    for link in LINKS:
        entry = kin.get(link)
        where = f"{display}: kinematics.{link}"
        if not isinstance(entry, Mapping):
            raise InputError(f"{where}: missing (x, y, z, roll, pitch, yaw)")
        extra = [k for k in entry if k not in KEYS]
        if extra:
            raise InputError(f"{where}: unknown key {shown(extra[0])}; valid: {', '.join(KEYS)}")
        missing = [k for k in KEYS if k not in entry]
        if missing:
            raise InputError(f"{where}: no {missing[0]}")
        x, y, z, roll, pitch, yaw = (check_number(entry[k], f"{where}.{k}") for k in KEYS)
        origins.append(se3.from_rpy((x, y, z), (roll, pitch, yaw)))
        eigen.append(se3.trans(x, y, z) @ se3.rot_x(roll) @ se3.rot_y(pitch) @ se3.rot_z(yaw))
    file_hash = kin.get("hash")
    if file_hash is not None and (not isinstance(file_hash, str) or not _HASH.fullmatch(file_hash)):
        raise InputError(
            f"{display}: kinematics.hash must be calib_<digits>, not {shown(file_hash)}"
        )
    stack = np.array(origins)
    computed = next(_hashes(stack))
    checked = None if file_hash is None else any(h == file_hash for h in _hashes(stack))
    note = ""
    if checked is False and any(h == file_hash for h in _hashes(np.array(eigen))):
        # ur_calibration writes Eigen's eulerAngles(0, 1, 2): R = Rx(roll) Ry(pitch) Rz(yaw)
        checked, note = True, _eigen_note(stack, np.array(eigen))
    return UrKinematics(display, stack, file_hash, checked, computed, note)


def _eigen_note(rpy: Mat, eigen: Mat) -> str:
    """What reading the angles as ``ur_macro.xacro`` does, not as ``ur_calibration`` wrote
    them, costs the description: the largest turn between the two readings of a joint origin."""
    turn = max(
        float(np.linalg.norm(log_so3(a[:3, :3].T @ b[:3, :3])))
        for a, b in zip(rpy, eigen, strict=True)
    )
    return (
        "the hash is that of the joint origins with their angles read as ur_calibration writes "
        "them (Eigen's x-y-z angles, R = Rx(roll) Ry(pitch) Rz(yaw)); ur_macro.xacro, and this "
        f"model, read them as URDF rpy: joint origins up to {turn:.2g} rad apart"
    )


def _hashes(origins: Mat) -> Iterator[str]:
    """The hashes the D-H tables of these joint origins give, the likeliest first: UR's base
    frame to the flange (D-H frame 6), the table of ``style='ur'`` (as ``export --to ur``
    writes it) and then each common normal either way, joints 2 to 4's offsets also a turn more
    or less (a controller keeps a calibration's large offset unwrapped, 7.13 rad), values as
    they are and rounded."""
    from ..conventions.convert import to_table
    from ..model.poe import Joint, PoeModel
    from ..tolerances import DEFAULT, EXACT

    frame = np.eye(4)
    joints = []
    for joint_name, origin in zip(JOINTS, origins, strict=True):
        frame = frame @ origin
        joints.append(Joint(joint_name, "revolute", frame[:3, 2].copy(), frame[:3, 3].copy()))
    model = PoeModel(tuple(joints), frame, "ur")
    turns = list(itertools.product((0, -1, 1), repeat=3))
    for tol in (DEFAULT, EXACT):
        table = to_table(model, "dh", tol, style="ur")
        rows = [(p["theta"], p["d"], p["a"], p["alpha"])
                for p in (r.params.scalars() for r in table.rows)]  # fmt: skip
        for flips in itertools.product((False, True), repeat=len(rows) - 1):
            turned = _turned(rows, flips)
            for extra in turns:
                unwrapped = [
                    (t + 2.0 * math.pi * extra[k - 1], d, a, al) if 1 <= k <= 3 else (t, d, a, al)
                    for k, (t, d, a, al) in enumerate(turned)
                ]
                yield _calib(_rounded(unwrapped))
                yield _calib(unwrapped)


def _turned(rows: Rows, flips: tuple[bool, ...]) -> Rows:
    """The same D-H table with the x axes of frames 1 .. n-1 turned round where ``flips``
    says: that frame's row gets ``theta + pi, -alpha, -a``, the next row ``theta - pi``."""
    out = [list(r) for r in rows]
    for k, flip in enumerate(flips):
        if flip:
            out[k][0] += math.pi
            out[k][2], out[k][3] = -out[k][2], -out[k][3]
            out[k + 1][0] -= math.pi
    return [(_wrap(t), d, a, _wrap(al)) for t, d, a, al in out]


def _wrap(angle: float) -> float:
    out = math.remainder(angle, 2.0 * math.pi)
    return math.pi if out == -math.pi else out + 0.0


def read_source(content: Content, reading: Reading) -> Source:
    """A UR kinematics file as a SOURCE (the ``ur`` entry of
    :data:`~urdf2dh.io.sources.READERS`): the chain ``base_link`` -> ``tool0`` of the
    description built from it."""
    from .sources import Source

    kinematics = read_ur_kinematics(content.mapping, content.display)
    model = kinematics.model(content.name(content.path.stem))
    return Source("UR kinematics", content.display, model.name, poe=replace(model),
                  bundled=content.bundled)  # fmt: skip
