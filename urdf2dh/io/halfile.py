"""LinuxCNC genserkins HAL files as a SOURCE: what ``export --to linuxcnc`` writes, and a
configuration's own ``setp genserkins.*`` lines (docs/exports/linuxcnc.md; the writer:
:mod:`urdf2dh.emit.export.linuxcnc`).

genserkins evaluates six Craig links, link ``i`` being ``Rx(ALPHA-i) Tx(A-i) Rz(joint i)
Tz(D-i)``, ``A`` and ``D`` in the machine's length unit, ``ALPHA`` in radians. The reader takes

* ``setp genserkins.A-i``, ``ALPHA-i`` and ``D-i`` (0 where a line is absent, as genserkins
  starts);
* the joint zeros and directions of ``export --to linuxcnc``'s scale components: genserkins'
  angle of joint ``i`` is ``gain * q + offset`` of the arm's position ``q``
  (``setp urdf2dh-fb-i.gain``, ``.offset``, degrees);
* the chain the export names in its comments: ``# urdf2dh chain: {...}`` (the robot, its base
  and tip links, the length unit, genserkins' world frame ``Rz(theta) Tz(d)`` in the base link
  and the tip's turn ``Rx(alpha) Rz(theta)`` in genserkins' last frame, where the file has them)
  and ``# urdf2dh joint i: "name"`` (how many joints, their names).

A file without those comments is six joints ``joint_0`` ... ``joint_5`` in millimetres
(genserkins has no unit; the machine's INI file says it), with a warning saying so.
"""

from __future__ import annotations

import math
import re
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError, shown
from ..geometry import se3
from ..numerals import read_decimal
from ..units import metres_per
from .chaincomment import chain_links, decoded
from .fields import check_number

if TYPE_CHECKING:
    from ..model.poe import PoeModel
    from .sources import Content, Reading, Source

__all__ = ["is_hal", "read_hal", "read_source"]

LINKS = 6
_SETP = re.compile(r"^\s*setp\s+(\S+)\s+(\S+)\s*$")
_GENSER = re.compile(r"^genserkins\.(A|ALPHA|D)-([0-5])$")
_SCALE = re.compile(r"^urdf2dh-fb-([0-5])\.(gain|offset)$")
_CHAIN = re.compile(r"^#\s*urdf2dh chain: (.*)$")
_JOINT = re.compile(r"^#\s*urdf2dh joint ([0-5]): (.*)$")


def is_hal(data: bytes, suffix: str) -> bool:
    """Whether a file is a genserkins HAL file (``.hal``, or ``setp genserkins.`` lines)."""
    return suffix == ".hal" or b"setp genserkins." in data


def read_hal(text: str, display: str) -> PoeModel:
    """The chain of a genserkins HAL file (module docstring).

    Raises
    ------
    InputError
        A value that is not a number, a gain that is not +-1, a malformed chain comment, a
        length unit urdf2dh does not know; the message names the file and the line.
    """
    from ..model.poe import Joint, PoeModel

    links = np.zeros((LINKS, 3))  # A, ALPHA, D
    gains, offsets = np.ones(LINKS), np.zeros(LINKS)
    chain: dict[str, Any] = {}
    names: dict[int, str] = {}
    for number, line in _lines(text):
        where = f"{display}: line {number}"
        if (m := _CHAIN.match(line)) is not None:
            chain = decoded(m.group(1), where)
            if not isinstance(chain, dict):
                raise InputError(f"{where}: the chain comment must hold a mapping")
            continue
        if (m := _JOINT.match(line)) is not None:
            name = decoded(m.group(2), where)
            if not isinstance(name, str):
                raise InputError(f"{where}: a joint's name must be a string, not {shown(name)}")
            names[int(m.group(1))] = name
            continue
        m = _SETP.match(line)
        if m is None:
            continue
        pin, value = m.groups()
        if (g := _GENSER.match(pin)) is not None:
            column = ("A", "ALPHA", "D").index(g.group(1))
            links[int(g.group(2)), column] = _number(value, f"{where}: {pin}")
        elif (s := _SCALE.match(pin)) is not None:
            i, what = int(s.group(1)), s.group(2)
            x = _number(value, f"{where}: {pin}")
            if what == "gain":
                if x not in (1.0, -1.0):
                    raise InputError(f"{where}: {pin} must be 1 or -1 (a joint's direction)")
                gains[i] = x
            else:
                offsets[i] = math.radians(x)
    count = len(names) if names else LINKS
    if names and sorted(names) != list(range(count)):
        raise InputError(
            f"{display}: the joint comments number {sorted(names)}, not 0 .. {count - 1}"
        )
    unit = chain.get("unit", "mm")
    unit = {"inch": "in"}.get(unit, unit)
    if not isinstance(unit, str):
        raise InputError(f"{display}: the chain's unit must be a name such as mm")
    try:
        metres_per(unit)
    except InputError as e:
        raise InputError(f"{display}: {e}") from None
    frame = _world(chain.get("world"), display)
    joints = []
    for i in range(count):
        a, alpha, d = links[i]
        frame = frame @ se3.rot_x(alpha) @ se3.trans(a, 0.0, 0.0)
        name = names.get(i, f"joint_{i}")
        joints.append(Joint(name, "revolute", gains[i] * frame[:3, 2], frame[:3, 3].copy()))
        frame = frame @ se3.rot_z(offsets[i]) @ se3.trans(0.0, 0.0, d)
    for i in range(count, LINKS):  # links of joints held at 0
        a, alpha, d = links[i]
        frame = frame @ se3.rot_x(alpha) @ se3.trans(a, 0.0, 0.0) @ se3.trans(0.0, 0.0, d)
    turn = chain.get("tool_turn")
    if turn is not None:
        alpha, theta = _pair(turn, f"{display}: the chain's tool_turn")
        frame = frame @ se3.rot_x(alpha) @ se3.rot_z(theta)
    frame[3] = (0.0, 0.0, 0.0, 1.0)
    warnings: tuple[str, ...] = ()
    if not chain:
        warnings = (
            f"{display}: no urdf2dh chain comment: six joints joint_0 .. joint_5, lengths in mm "
            "(genserkins has no unit; the machine's INI file says it)",
        )
    robot, base_link, tip_link = chain_links(chain, display)
    return PoeModel(tuple(joints), frame, robot, display, base_link, tip_link, unit, warnings)


def _lines(text: str) -> list[tuple[int, str]]:
    """The file's lines with their numbers, a chain or joint comment whose JSON does not end on
    its line joined with the comment lines after it (:func:`~urdf2dh.escape.hal_comment` cuts
    lines of more than 1000 bytes: ``# `` starts each piece after the first)."""
    lines = text.splitlines()
    out, i = [], 0
    while i < len(lines):
        line, number = lines[i], i + 1
        i += 1
        m = _CHAIN.match(line) or _JOINT.match(line)
        while m is not None and not _whole(m.groups()[-1]) and i < len(lines):
            if not lines[i].startswith("# "):
                break
            line, i = line + lines[i][2:], i + 1
            m = _CHAIN.match(line) or _JOINT.match(line)
        out.append((number, line))
    return out


def _whole(text: str) -> bool:
    try:
        decoded(text, "")
    except InputError:
        return False
    return True


def _number(text: str, where: str) -> float:
    """A HAL value by the one number grammar (:mod:`urdf2dh.numerals`), within the bounds."""
    return check_number(read_decimal(text, where), where)


def _pair(value: Any, where: str) -> tuple[float, float]:
    if not isinstance(value, list) or len(value) != 2:
        raise InputError(f"{where} must be two numbers")
    return check_number(value[0], where), check_number(value[1], where)


def _world(value: Any, display: str) -> np.ndarray:
    """genserkins' world frame ``Rz(theta) Tz(d)`` in the base link (identity: none)."""
    if value is None:
        return np.eye(4)
    theta, d = _pair(value, f"{display}: the chain's world")
    out: np.ndarray = se3.rot_z(theta) @ se3.trans(0.0, 0.0, d)
    return out


def read_source(content: Content, reading: Reading) -> Source:
    """A genserkins HAL file as a SOURCE (the ``hal`` entry of
    :data:`~urdf2dh.io.sources.READERS`)."""
    return content.chain_source("LinuxCNC HAL", read_hal(content.text, content.display))
