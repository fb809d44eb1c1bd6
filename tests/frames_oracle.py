"""Where a picture of a table's frames must put things, computed without :mod:`urdf2dh.emit`:
each frame's pose from the table's own forward kinematics (the table cut after row ``k``, with
an identity tool, at ``q = 0``)."""

from __future__ import annotations

import dataclasses
import re

import numpy as np

from urdf2dh.conventions.table import Table
from urdf2dh.emit.scene import ARROW, JOINT_AXIS, LABEL_GAP, TOOL_ARROW


def fk_frames(table: Table) -> dict[str, np.ndarray]:
    """Frame name (``0`` .. ``n``, ``tool``) -> its ``(4, 4)`` pose at home."""
    identity = type(table.tool)(**dict.fromkeys(table.tool.values(), 0.0))
    out = {}
    for k in range(table.n + 1):
        cut = dataclasses.replace(table, rows=table.rows[:k], tool=identity)
        out[str(k)] = cut.fk(np.zeros(cut.dof))
    out["tool"] = table.fk(np.zeros(table.dof))
    return out


def span(frames: dict[str, np.ndarray]) -> float:
    """The largest extent of the frame origins and the base link's origin."""
    points = np.array([np.zeros(3), *(f[:3, 3] for f in frames.values())])
    return float(np.ptp(points, axis=0).max())


def named(text: str) -> list[tuple[str, str]]:
    """What a label names: ``"x4, x6"`` -> ``[("x", "4"), ("x", "6")]``, ``"J2"`` ->
    ``[("J", "2")]``; other labels (the base link's name) name nothing of these."""
    out = []
    for part in text.split(", "):
        m = re.fullmatch(r"([xzJ])(\d+|tool)", part)
        if m:
            out.append((m[1], m[2]))
    return out


def on_ray(p: np.ndarray, start: np.ndarray, direction: np.ndarray) -> tuple[float, float]:
    """``p``'s distance along the ray from ``start`` in the unit ``direction``, and its
    distance from the ray's line."""
    along = float((p - start) @ direction)
    return along, float(np.linalg.norm(p - start - along * direction))


def anchor(table: Table, frames: dict[str, np.ndarray], what: str, which: str):
    """Where the label naming ``what`` (``x``, ``z``, ``J``) of ``which`` (a frame name, or a
    joint number) starts: ``(point, direction, distance)``, the anchor being ``point +
    distance * direction`` (a drawing may slide it further along ``direction``). An axis label
    starts beyond its arrow's tip (the arrow from the frame's origin along that axis); a
    joint's beyond the end of its axis line through the frame whose z axis it is, away from
    that z arrow."""
    size = span(frames) or table.size
    arrow = ARROW * size
    if what == "J":
        f = table.joint_frames()[int(which) - 1]
        return f[:3, 3], -f[:3, 2], JOINT_AXIS * size + LABEL_GAP * arrow
    f = frames[which]
    length = (TOOL_ARROW if which == "tool" else 1.0) * arrow
    return f[:3, 3], f[:3, "xyz".index(what)], length + LABEL_GAP * arrow
