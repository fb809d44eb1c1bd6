"""ikdh robot files as a SOURCE: what ``export --to ikdh`` writes, and ikdh's own robot files
(``ikdh/robots/*.yaml``, RoboDK's arms) (docs/exports/ikdh.md; the writer:
:mod:`urdf2dh.emit.export.ikdh`).

::

    name: ...
    dh:
      a: [6 lengths]
      d: [6 lengths]
      alpha: [6 angles]   # radians: a number, pi, pi/N, pi*N, with a leading -
      theta: [6 angles]
    limits:
      J1: [lower, upper]  # degrees
      ...
    base: [4 rows of 4]   # urdf2dh's, which ikdh does not read
    tool: [4 rows of 4]

The chain is ikdh's standard D-H: ``pose(q) = base . prod_i Rz(theta_i + q_i) Tz(d_i)
Tx(a_i) Rx(alpha_i) . tool``, joint ``i`` turning about the z axis of frame ``i - 1``. The
export names its chain in its last line, ``# urdf2dh chain: {...}`` (:mod:`.chaincomment`: the
robot, its links, its joints' names, the length unit, and the joints whose limits it made up
because the table has none), and the reader takes it back. A file without it is six joints
``J1`` ... ``J6`` in metres, as ikdh's own robot files write them (ikdh has no unit), which a
warning says; ``base`` and ``tool`` default to the identity.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError, shown
from ..geometry import se3
from ..numerals import read_decimal
from .chaincomment import chain_links, find_chain
from .fields import check_number

if TYPE_CHECKING:
    from ..model.poe import PoeModel
    from .sources import Content, Reading, Source

__all__ = ["is_ikdh", "read_ikdh", "read_source"]

JOINTS = 6
COLUMNS = ("a", "d", "alpha", "theta")
UNITS = ("mm", "m")
_PI = re.compile(r"^(-?)\s*pi\s*(?:([/*])\s*([0-9]+(?:\.[0-9]*)?))?$")


def is_ikdh(tree: Any) -> bool:
    """Whether a parsed YAML tree is an ikdh robot file (a ``dh`` mapping of the four
    columns)."""
    if not isinstance(tree, Mapping) or "schema" in tree or "format" in tree:
        return False
    dh = tree.get("dh")
    return isinstance(dh, Mapping) and all(k in dh for k in COLUMNS)


def _value(value: Any, angle: bool, where: str) -> float:
    """A number, or for an angle ikdh's ``pi``, ``pi/N``, ``pi*N`` (a leading ``-``)."""
    if isinstance(value, str) and angle:
        m = _PI.match(value.strip())
        if m is None:
            raise InputError(f"{where} must be a number, pi, pi/N or pi*N, not {shown(value)}")
        sign, op, n = m.groups()
        k = 1.0 if n is None else read_decimal(n, where)
        if op == "/" and k == 0.0:
            raise InputError(f"{where}: {shown(value)} divides by zero")
        x = math.pi / k if op == "/" else math.pi * k
        return check_number(-x if sign else x, where)
    return check_number(value, where)


def _matrix(tree: Mapping[str, Any], key: str, display: str) -> np.ndarray:
    """``base`` or ``tool`` (4 rows of 4, a rigid transform), the identity where absent."""
    value = tree.get(key)
    if value is None:
        return np.eye(4)
    where = f"{display}: {key}"
    if not isinstance(value, list) or len(value) != 4:
        raise InputError(f"{where} must be 4 rows of 4 numbers")
    rows = []
    for i, row in enumerate(value):
        if not isinstance(row, list) or len(row) != 4:
            raise InputError(f"{where} must be 4 rows of 4 numbers")
        rows.append([check_number(x, f"{where}[{i}]") for x in row])
    m = np.array(rows)
    r = m[:3, :3]
    if not np.allclose(m[3], (0, 0, 0, 1)) or not np.allclose(r.T @ r, np.eye(3), atol=1e-9):
        raise InputError(f"{where} is not a rigid transform (a rotation and a translation)")
    return m


def _limits(tree: Mapping[str, Any], display: str) -> list[tuple[float, float] | None]:
    """Each joint's limits in radians (``limits: Jk: [lower, upper]`` in degrees), or None."""
    block = tree.get("limits")
    if block is None:
        return [None] * JOINTS
    if not isinstance(block, Mapping):
        raise InputError(f"{display}: limits must be a mapping J1 .. J6 -> [lower, upper]")
    out: list[tuple[float, float] | None] = []
    for k in range(1, JOINTS + 1):
        value = block.get(f"J{k}")
        if value is None:
            out.append(None)
            continue
        where = f"{display}: limits.J{k}"
        if not isinstance(value, list) or len(value) != 2:
            raise InputError(f"{where} must be [lower, upper] in degrees")
        lo, hi = (math.radians(check_number(x, where)) for x in value)
        out.append((lo, hi))
    return out


def read_ikdh(tree: Any, display: str, text: str = "") -> PoeModel:
    """The chain of an ikdh robot file (module docstring).

    Raises
    ------
    InputError
        A column that is not six values, a value that is not a number (or ``pi`` form), a base
        or tool that is not a rigid transform, a malformed chain comment; the message names the
        file and the entry.
    """
    from ..model.poe import Joint, PoeModel

    if not is_ikdh(tree):
        raise InputError(f"{display}: not an ikdh robot file (no dh: a, d, alpha, theta)")
    dh = tree["dh"]
    columns = {}
    for key in COLUMNS:
        values = dh[key]
        if not isinstance(values, list) or len(values) != JOINTS:
            raise InputError(f"{display}: dh.{key} must be a list of {JOINTS} values")
        columns[key] = [
            _value(v, key in ("alpha", "theta"), f"{display}: dh.{key}[{i}]")
            for i, v in enumerate(values)
        ]
    chain = find_chain(text, display)
    robot, base_link, tip_link = chain_links(chain, display)
    names = chain.get("joints", [f"J{k}" for k in range(1, JOINTS + 1)])
    if (
        not isinstance(names, list)
        or len(names) != JOINTS
        or not all(isinstance(n, str) for n in names)
    ):
        raise InputError(f"{display}: the urdf2dh chain comment's joints must be six names")
    unit = chain.get("unit", "m")
    if unit not in UNITS:
        raise InputError(f"{display}: the urdf2dh chain's unit must be mm or m, not {shown(unit)}")
    unlimited = chain.get("unlimited", [])
    if not isinstance(unlimited, list) or not all(
        isinstance(i, int) and not isinstance(i, bool) and 0 <= i < JOINTS for i in unlimited
    ):
        raise InputError(f"{display}: the urdf2dh chain's unlimited must be joint indices 0 .. 5")
    limits = _limits(tree, display)
    frame = _matrix(tree, "base", display)
    joints = []
    for i in range(JOINTS):
        limit = None if i in unlimited else limits[i]
        lower, upper = (None, None) if limit is None else limit
        joints.append(Joint(names[i], "revolute", frame[:3, 2].copy(), frame[:3, 3].copy(),
                            lower=lower, upper=upper))  # fmt: skip
        a, d, alpha, theta = (columns[k][i] for k in COLUMNS)
        frame = frame @ se3.dh_matrix(theta, d, alpha, a)
    home = frame @ _matrix(tree, "tool", display)
    home[3] = (0.0, 0.0, 0.0, 1.0)
    warnings: tuple[str, ...] = ()
    if not chain:
        warnings = (
            f"{display}: no urdf2dh chain comment: joints J1 .. J6, lengths in m as ikdh's own "
            "robot files write them (ikdh has no unit)",
        )
    name = robot or (tree["name"] if isinstance(tree.get("name"), str) else "")
    return PoeModel(tuple(joints), home, name, display, base_link, tip_link, unit, warnings)


def read_source(content: Content, reading: Reading) -> Source:
    """An ikdh robot file as a SOURCE (the ``ikdh`` entry of
    :data:`~urdf2dh.io.sources.READERS`)."""
    return content.chain_source("ikdh", read_ikdh(content.mapping, content.display, content.text))
