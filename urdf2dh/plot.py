"""A picture of the arm at its home pose with its D-H frames, to check the frames by eye.

Drawn from a checked table: the links as a polyline through the frame origins, each joint's axis
as a dashed line (the z axis of the frame where the joint acts), and every D-H frame's x (red)
and z (blue) axes, labelled ``x0, z0, ..., xn, zn``, plus the tool frame. matplotlib is an
optional dependency, imported here only, with the Agg canvas (no display needed).
"""

from __future__ import annotations

import io
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import se3
from .errors import InputError, UsageError
from .export.escape import matplotlib_text
from .table import Table

__all__ = ["FORMATS", "dh_frames", "render"]

FORMATS = ("png", "svg", "pdf")
COLOURS = {"x": "#d62728", "y": "#2ca02c", "z": "#1f77b4", "joint": "#ff7f0e", "link": "#555555"}

Mat = NDArray[np.float64]


def dh_frames(table: Table) -> list[Mat]:
    """The table's frames ``0 .. n`` at the home pose (frame 0 is the base transform ``B``, frame
    ``i`` ends row ``i``), then the tool frame."""
    f = table.base_matrix
    out = [f]
    for row in table.rows:
        f = f @ se3.matrix_of(row.params.frame())
        out.append(f)
    out.append(f @ table.tool_matrix)
    return out


def _matplotlib(what: str) -> tuple[Any, Any]:
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError as e:
        raise InputError(
            f"{what} needs matplotlib; install it with: pip install matplotlib "
            "(or pip install 'urdf2dh[plot]')"
        ) from e
    return Figure, FigureCanvasAgg


def _arrow(ax: Any, origin: Mat, direction: Mat, length: float, colour: str, label: str,
           width: float = 1.8) -> None:
    tip = origin + length * direction
    ax.plot(*np.column_stack([origin, tip]), color=colour, linewidth=width)
    ax.text(*(origin + 1.15 * length * direction), label, color=colour, fontsize=8, usetex=False)


def render(table: Table, fmt: str = "png", title: str | None = None) -> bytes:
    """The drawing as ``png``, ``svg`` or ``pdf`` bytes."""
    if fmt not in FORMATS:
        raise UsageError(f"plot: unknown image format '{fmt}'; valid: {', '.join(FORMATS)}")
    figure_cls, canvas_cls = _matplotlib("urdf2dh plot")
    frames = dh_frames(table)
    points = np.array([np.zeros(3)] + [f[:3, 3] for f in frames])
    span = float(np.ptp(points, axis=0).max()) or 1.0
    arrow = 0.12 * span

    fig = figure_cls(figsize=(8, 8), dpi=100)
    canvas_cls(fig)
    ax = fig.add_subplot(projection="3d")
    ax.plot(*points.T, color=COLOURS["link"], linewidth=3, marker="o", markersize=4,
            label="links (frame origins)")
    for i, (row, f) in enumerate(zip(table.rows, table.frames()[:-1], strict=True)):
        z, p = f[:3, 2], f[:3, 3]
        ends = np.column_stack([p - 0.25 * span * z, p + 0.25 * span * z])
        ax.plot(*ends, color=COLOURS["joint"], linestyle="--", linewidth=1.2,
                label="joint axes" if i == 0 else None)
        ax.text(*(p + 0.27 * span * z), f"J{i + 1} {matplotlib_text(row.name)}",
                color=COLOURS["joint"], fontsize=7, usetex=False)
    for k, f in enumerate(frames[:-1]):
        _arrow(ax, f[:3, 3], f[:3, 0], arrow, COLOURS["x"], f"x{k}")
        _arrow(ax, f[:3, 3], f[:3, 2], arrow, COLOURS["z"], f"z{k}")
    tool = frames[-1]
    for axis, name in enumerate("xyz"):
        _arrow(ax, tool[:3, 3], tool[:3, axis], 0.7 * arrow, COLOURS[name],
               f"{name}tool" if name != "y" else "", width=1.0)
    world = np.eye(3)
    for axis, name in enumerate("xyz"):
        _arrow(ax, np.zeros(3), world[axis], 0.7 * arrow, "#000000",
               f"{name}_{matplotlib_text(table.base_link)}" if name == "x" and table.base_link
               else name,
               width=0.8)
    centre = (points.max(axis=0) + points.min(axis=0)) / 2
    half = 0.6 * span + arrow
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))
    unit = matplotlib_text(table.length_unit)
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.set_zlabel(f"z [{unit}]")
    name = table.spec.label
    robot = matplotlib_text(table.robot or "robot")
    chain = f"{matplotlib_text(table.base_link)} -> {matplotlib_text(table.tip_link)}"
    ax.set_title(title or f"{robot}: {name} frames at home\n{chain}" if table.base_link else
                 f"{robot}: {name} frames at home", fontsize=10, usetex=False)
    ax.legend(loc="upper left", fontsize=8)
    buf = io.BytesIO()
    fig.savefig(buf, format=fmt)
    return buf.getvalue()
