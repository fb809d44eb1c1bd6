"""OPW parameter files as a SOURCE: ROS-Industrial's ``opw_parameters_*.yaml``, a MoveIt group's
OPW entries, and what ``export --to opw`` writes (docs/exports/opw.md; the model:
:mod:`urdf2dh.conventions.opw`).

::

    opw_kinematics_geometric_parameters: {a1, a2, b, c1, c2, c3, c4}   # metres
    opw_kinematics_joint_offsets: [6 radians]      # or rosparam's deg(-90.0), rad(...)
    opw_kinematics_joint_sign_corrections: [6 of 1 or -1]

The same keys may stand under one group's name (a MoveIt ``kinematics.yaml``). What OPW cannot
hold, ``export --to opw`` writes beside them and the reader takes back: ``urdf2dh_base_transform``
and ``urdf2dh_tool_transform`` (``xyz``, URDF ``rpy``: ``pose = B . F . T``) and the comment
``# urdf2dh chain: {...}`` (JSON: the robot, its base and tip links, its joints' names; names
are in comments only, as everywhere in the file). A file without them is OPW's own frames, its
joints ``joint_1`` ... ``joint_6``. Offsets and signs default to 0 and 1 where absent, as the
consumers take them.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError, shown
from ..geometry import se3
from ..numerals import DECIMAL, read_decimal
from .chaincomment import chain_links, find_chain
from .fields import check_number, check_vector

if TYPE_CHECKING:
    from ..model.poe import PoeModel
    from .sources import Content, Reading, Source

__all__ = ["GEOMETRY_KEY", "is_opw", "read_opw", "read_source"]

GEOMETRY_KEY = "opw_kinematics_geometric_parameters"
OFFSETS_KEY = "opw_kinematics_joint_offsets"
SIGNS_KEY = "opw_kinematics_joint_sign_corrections"
EXTRA = ("urdf2dh_base_transform", "urdf2dh_tool_transform")
_ROSPARAM = re.compile(rf"^\s*(deg|rad)\s*\(\s*({DECIMAL})\s*\)\s*$")


def _block(tree: Any) -> Mapping[str, Any] | None:
    """The mapping holding the OPW keys: the file's, or its one group's."""
    if not isinstance(tree, Mapping):
        return None
    if GEOMETRY_KEY in tree:
        return tree
    groups = [v for v in tree.values() if isinstance(v, Mapping) and GEOMETRY_KEY in v]
    return groups[0] if len(groups) == 1 else None


def is_opw(tree: Any) -> bool:
    """Whether a parsed YAML tree is an OPW parameter file."""
    return _block(tree) is not None


def _angle(value: Any, where: str) -> float:
    """A number, or rosparam's ``deg(x)`` / ``rad(x)``."""
    if isinstance(value, str):
        match = _ROSPARAM.match(value)
        if match is None:
            raise InputError(f"{where} must be a number, deg(x) or rad(x), not {shown(value)}")
        x = check_number(read_decimal(match.group(2), where), where)
        return math.radians(x) if match.group(1) == "deg" else x
    return check_number(value, where)


def _six(tree: Mapping[str, Any], key: str, default: float, display: str) -> list[Any]:
    values = tree.get(key, [default] * 6)
    if not isinstance(values, list) or len(values) != 6:
        raise InputError(f"{display}: {key} must be a list of six, not {shown(values)}")
    return values


def _transform(tree: Mapping[str, Any], key: str, display: str) -> np.ndarray:
    raw = tree.get(key)
    if raw is None:
        return np.eye(4)
    where = f"{display}: {key}"
    if not isinstance(raw, Mapping) or set(raw) - {"xyz", "rpy"}:
        raise InputError(f"{where} must be a mapping of xyz and rpy")
    xyz = check_vector(raw.get("xyz", [0.0, 0.0, 0.0]), f"{where}.xyz")
    rpy = check_vector(raw.get("rpy", [0.0, 0.0, 0.0]), f"{where}.rpy")
    return se3.from_rpy(xyz, rpy)


def read_opw(tree: Any, display: str, text: str = "") -> PoeModel:
    """The chain of an OPW parameter file (module docstring).

    Raises
    ------
    InputError
        A missing or non-numeric length, offsets or signs that are not six (signs not +-1),
        a malformed transform or chain block; the message names the file and the key.
    """
    from ..conventions.opw import GEOMETRY, JOINT_NAMES, OpwParameters, opw_to_poe

    block = _block(tree)
    if block is None:
        raise InputError(f"{display}: not an OPW parameter file (no {GEOMETRY_KEY})")
    geometry = block[GEOMETRY_KEY]
    if not isinstance(geometry, Mapping):
        raise InputError(f"{display}: {GEOMETRY_KEY} must be a mapping of {', '.join(GEOMETRY)}")
    unknown = [k for k in geometry if k not in GEOMETRY and k != "dof"]
    if unknown:
        raise InputError(f"{display}: {GEOMETRY_KEY}: unknown key {shown(unknown[0])}")
    missing = [k for k in GEOMETRY if k not in geometry]
    if missing:
        raise InputError(f"{display}: {GEOMETRY_KEY}: no {missing[0]}")
    if geometry.get("dof", 6) != 6 or block.get("dof", 6) != 6:
        raise InputError(f"{display}: a five-axis OPW arm (dof 5) is not read; six joints only")
    lengths = [check_number(geometry[k], f"{display}: {GEOMETRY_KEY}.{k}") for k in GEOMETRY]
    offsets = tuple(
        _angle(v, f"{display}: {OFFSETS_KEY}[{i}]")
        for i, v in enumerate(_six(block, OFFSETS_KEY, 0.0, display))
    )
    signs = _six(block, SIGNS_KEY, 1, display)
    if any(isinstance(s, bool) or s not in (1, -1) for s in signs):
        raise InputError(f"{display}: {SIGNS_KEY} must be six of 1 or -1, not {shown(signs)}")
    base = _transform(block, EXTRA[0], display)
    tool = _transform(block, EXTRA[1], display)
    chain = find_chain(text, display)
    names = chain.get("joints", list(JOINT_NAMES))
    if not isinstance(names, list) or len(names) != 6 or not all(isinstance(n, str) for n in names):
        raise InputError(f"{display}: the urdf2dh chain comment's joints must be six names")
    robot, base_link, tip_link = chain_links(chain, display)
    a1, a2, b, c1, c2, c3, c4 = lengths
    params = OpwParameters(a1, a2, b, c1, c2, c3, c4, offsets, tuple(int(s) for s in signs),
                           base, tool)  # fmt: skip
    return opw_to_poe(params, tuple(names), robot, display, base_link, tip_link)


def read_source(content: Content, reading: Reading) -> Source:
    """An OPW parameter file as a SOURCE (the ``opw`` entry of
    :data:`~urdf2dh.io.sources.READERS`)."""
    return content.chain_source("OPW", read_opw(content.mapping, content.display, content.text))
