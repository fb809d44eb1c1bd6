"""POE model files (docs/formats/poe-file.md): YAML or JSON, twists ``[w, v]`` in the base
frame at home.

::

    format: poe
    name: puma560-actual
    length_unit: mm
    joints:
      - {name: j1, twist: [0.04, -0.02, 0.999, 0.02, 0.04, 0]}
      - {name: j2, twist: [0, -1.00002, 0, -0.02, 0, 0.05], type: revolute, limits: [-3, 3]}
    tool:
      twist: [0.02, -0.01, 0.01, 249, 51, -20.6]     # tool pose at home = exp(twist), or
      # matrix: [[...4x4...]]

Twists need not be normalised (Wu 2019 §II): ``|w|`` is the joint's scale and ``w.v/|w|^2`` its
pitch; ``w = 0`` makes a prismatic joint of scale ``|v|``. ``type`` is optional and must agree
with the twist. ``limits`` (optional, an extension) bounds ``q``. ``size`` (optional) is the
robot's size in ``length_unit`` (:meth:`~urdf2dh.model.poe.PoeModel.sized`); without it the model
takes the size of its own points.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import units
from ..errors import InputError, choices, shown
from ..geometry import se3
from ..model.poe import KINDS, PoeModel, joint_from_twist
from ..schemas import POE_FILE
from ..tolerances import DEFAULT, JOINT_SCALES, Tolerances
from .fields import (
    check_joint_count,
    check_leaders,
    check_name,
    check_number,
    read_mimic,
    read_size,
)
from .sources import Content, Reading, Source

__all__ = ["check_matrix", "poe_to_dict", "read_poe", "read_source"]


def _numbers(value: Any, count: int, where: str) -> NDArray[np.float64]:
    if not isinstance(value, list | tuple) or len(value) != count:
        raise InputError(f"{where} must be a list of {count} numbers")
    return np.array([check_number(v, where) for v in value])


def check_matrix(
    value: Any, where: str, tol: Tolerances = DEFAULT
) -> tuple[NDArray[np.float64], str | None]:
    """A 4x4 homogeneous transform from nested lists; a nearly orthonormal rotation (as typed
    with few decimals) is orthonormalised, with a note saying how much it moved."""
    if not isinstance(value, list | tuple) or len(value) != 4:
        raise InputError(f"{where} must be a 4x4 matrix")
    m = np.array([_numbers(r, 4, f"{where} row {i + 1}") for i, r in enumerate(value)])
    if not np.allclose(m[3], [0, 0, 0, 1], rtol=0, atol=0):
        raise InputError(f"{where}: last row must be [0, 0, 0, 1]")
    r = m[:3, :3]
    off = float(np.abs(r.T @ r - np.eye(3)).max())
    if off > tol.rotation_input:
        raise InputError(f"{where}: the 3x3 block is not a rotation (|R^T R - I| = {off:.2g})")
    if (det := float(np.linalg.det(r))) < 0:  # orthonormal, so det is -1
        raise InputError(
            f"{where}: the 3x3 block is a reflection (determinant {det:.3g}), not a rotation; "
            "a rotation's determinant is +1 (a left-handed frame? negate one axis)"
        )
    note = None
    if off > 0.0:
        u, _, vt = np.linalg.svd(r)
        fixed = u @ vt
        moved = float(np.abs(fixed - r).max())
        m[:3, :3] = fixed
        if moved > tol.noise:
            note = f"{where}: rotation orthonormalised (entries moved by up to {moved:.2g})"
    return m, note


def _known_unit(unit: str, where: str) -> None:
    """A length unit :mod:`urdf2dh.units` knows, or an error naming the field."""
    try:
        units.metres_per(unit)
    except InputError as e:
        raise InputError(f"{where}: {e}") from None


def read_poe(data: Any, display: str, tol: Tolerances = DEFAULT) -> PoeModel:
    """Build a :class:`PoeModel` from a parsed POE file, naming the joint at fault on error."""
    if not isinstance(data, dict) or data.get("format") != "poe":
        raise InputError(f"{display}: not a POE model file (needs 'format: poe')")
    if data.get("schema", POE_FILE) != POE_FILE:
        raise InputError(
            f"{display}: schema must be {POE_FILE} (or absent), not {shown(data['schema'])}"
        )
    unit = data.get("length_unit", "m")
    if not isinstance(unit, str) or not unit:
        raise InputError(f"{display}: length_unit must be a name such as m or mm")
    _known_unit(unit, f"{display}: length_unit")
    size = read_size(data, display, unit)
    raw = data.get("joints")
    if not isinstance(raw, list):
        raise InputError(f"{display}: 'joints' must be a list")
    check_joint_count(len(raw), display)
    joints, names = [], set()
    for i, entry in enumerate(raw, 1):
        if not isinstance(entry, dict):
            raise InputError(f"{display}: joint {i} must be a mapping with name and twist")
        name = check_name(entry.get("name", f"joint{i}"), f"{display}: joint {i} name")
        where = f"{display}: joint {shown(name)}"
        if name in names:
            raise InputError(f"{where} appears twice")
        names.add(name)
        xi = _numbers(entry.get("twist"), 6, f"{where} twist")
        if not np.any(xi):
            raise InputError(f"{where} has a zero twist")
        w, v = math.hypot(*xi[:3]), math.hypot(*xi[3:])  # no underflow of tiny entries
        scale = w if w > tol.noise else v
        if not JOINT_SCALES[0] <= scale <= JOINT_SCALES[1]:
            raise InputError(
                f"{where} twist has scale {scale:.3g} (|w|, or |v| where w = 0); a joint's scale "
                f"lies within [{JOINT_SCALES[0]:g}, {JOINT_SCALES[1]:g}]"
            )
        lower = upper = None
        if entry.get("limits") is not None:
            lower, upper = (float(x) for x in _numbers(entry["limits"], 2, f"{where} limits"))
            if not lower < upper:
                raise InputError(f"{where} limits must be [lower, upper] with lower < upper")
        joint = joint_from_twist(name, xi, tol.noise, lower, upper)
        declared = entry.get("type")
        if declared is not None:
            if declared not in KINDS:
                raise InputError(
                    f"{where} has unknown type {shown(declared)}; valid: {choices(KINDS)}"
                )
            if declared != joint.kind:
                detail = {
                    "prismatic": "w = 0 (a prismatic joint)",
                    "revolute": "zero pitch (a revolute joint)",
                    "helical": f"pitch {joint.pitch:.6g} {unit}/rad (a helical joint)",
                }[joint.kind]
                raise InputError(f"{where} is declared {declared} but its twist has {detail}")
        mimic = read_mimic(entry.get("mimic"), where)
        joints.append(joint if mimic is None else replace(joint, mimic=mimic))
    check_leaders(joints, display)
    tool = data.get("tool")
    warnings = []
    if not isinstance(tool, dict) or ("twist" in tool) == ("matrix" in tool):
        raise InputError(f"{display}: 'tool' must give either 'twist' or 'matrix'")
    if "twist" in tool:
        home = se3.twist_exp(_numbers(tool["twist"], 6, f"{display}: tool twist"))
    else:
        home, note = check_matrix(tool["matrix"], f"{display}: tool matrix", tol)
        if note:
            warnings.append(note)
    name = display if data.get("name") is None else check_name(data["name"], f"{display}: name")
    model = PoeModel(tuple(joints), home, str(name), display, "base", "tool", unit, tuple(warnings))
    return model if size is None else model.sized(size)


def read_source(content: Content, reading: Reading) -> Source:
    """The SOURCE of a POE model file (the ``poe`` entry of
    :data:`~urdf2dh.io.sources.READERS`)."""
    poe = read_poe(content.mapping, content.display, reading.tol)
    return Source("poe", content.display, content.name(poe.name), poe=poe,
                  bundled=content.bundled)  # fmt: skip


def poe_to_dict(model: PoeModel) -> dict[str, Any]:
    """A POE model file tree for ``model`` (tool as a matrix; limits where known; its
    :meth:`~urdf2dh.model.poe.PoeModel.size`, which a table's model takes from its source)."""
    joints = []
    for j in model.joints:
        xi = j.twist()
        if j.kind == "revolute":
            # v = p x w carries round-off along w relative to |p|, not to |v|: on an axis through
            # the origin (v ~ 1e-65 from a point 0.5 m along it) it would read back as a pitch
            w, v = xi[:3], xi[3:]
            xi = np.concatenate([w, v - (float(w @ v) / float(w @ w)) * w])
        entry: dict[str, Any] = {
            "name": j.name,
            "type": j.kind,
            "twist": [float(x) for x in xi],
        } | j.file_fields()
        joints.append(entry)
    return {
        "format": "poe",
        "schema": POE_FILE,
        "name": model.name,
        "length_unit": model.length_unit,
        "size": model.size(),
        "joints": joints,
        "tool": {"matrix": [[float(x) for x in row] for row in model.home]},
    }
