"""A picture of the arm at its home pose with its D-H frames, to check the frames by eye.

Drawn from a checked table: the links as a polyline through the frame origins, each joint's axis
as a dashed line (the z axis of the frame where the joint acts), and every D-H frame's x (red)
and z (blue) axes, labelled ``x0, z0, ..., xn, zn``, plus the tool frame. matplotlib is an
optional dependency, imported here only, with the Agg canvas (no display needed).
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import se3
from .errors import InputError, UsageError
from .export.escape import matplotlib_text
from .table import Table

__all__ = [
    "FORMATS",
    "LABEL_GAP",
    "Label",
    "apart",
    "box",
    "dh_frames",
    "layout",
    "place",
    "render",
]

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


LABEL_GAP = 2.0  # pixels between the boxes of two labels


def box(label: Label, xy: Mat) -> tuple[float, float, float, float]:
    """The pixels a label's text covers, drawn from ``xy`` (left, baseline): ``(x0, y0, x1,
    y1)``, from its font size (points at 100 dpi; a character is about 0.6 of the size wide)."""
    height = label.size * 100 / 72
    return (xy[0], xy[1] - 0.25 * height, xy[0] + 0.6 * height * len(label.text),
            xy[1] + height)  # fmt: skip


def apart(a: tuple[float, float, float, float], b: tuple[float, float, float, float]) -> bool:
    """Whether two boxes are at least :data:`LABEL_GAP` apart."""
    return (a[2] + LABEL_GAP <= b[0] or b[2] + LABEL_GAP <= a[0]
            or a[3] + LABEL_GAP <= b[1] or b[3] + LABEL_GAP <= a[1])  # fmt: skip


@dataclass(frozen=True, slots=True)
class Label:
    """A text near the tip of an arrow: where it starts, which way it may move if crowded."""

    text: str
    colour: str
    anchor: Mat
    direction: Mat
    step: float
    size: int = 8


def _arrow(ax: Any, labels: list[Label], origin: Mat, direction: Mat, length: float,
           colour: str, label: str, width: float = 1.8) -> None:  # fmt: skip
    tip = origin + length * direction
    ax.plot(*np.column_stack([origin, tip]), color=colour, linewidth=width)
    if label:
        labels.append(Label(label, colour, origin + 1.15 * length * direction, direction,
                            0.35 * length))  # fmt: skip


def place(ax: Any, labels: list[Label]) -> list[tuple[Label, Mat, Mat]]:
    """Each label's 3-D position and its place on the picture (pixels): at its arrow's tip, or
    moved on along the arrow, a step at a time, until its :func:`box` is apart from every label
    placed before it (frames that share an origin, such as a wrist's or the last joint's and the
    tool's, would otherwise print their names on top of each other)."""
    from mpl_toolkits.mplot3d import proj3d

    def pixels(p: Mat) -> Mat:
        x, y, _ = proj3d.proj_transform(p[0], p[1], p[2], ax.get_proj())
        return np.asarray(ax.transData.transform((x, y)))

    out: list[tuple[Label, Mat, Mat]] = []
    for label in labels:
        position = label.anchor
        for _ in range(40):
            xy = pixels(position)
            if all(apart(box(label, xy), box(other, at)) for other, _, at in out):
                break
            position = position + label.step * label.direction
        out.append((label, position, xy))
    return out


def layout(table: Table, title: str | None = None) -> tuple[Any, list[tuple[Label, Mat, Mat]]]:
    """The figure of :func:`render` and its labels as :func:`place` put them."""
    figure_cls, canvas_cls = _matplotlib("urdf2dh plot")
    frames = dh_frames(table)
    points = np.array([np.zeros(3)] + [f[:3, 3] for f in frames])
    span = float(np.ptp(points, axis=0).max()) or 1.0
    arrow = 0.12 * span

    fig = figure_cls(figsize=(8, 8), dpi=100)
    canvas_cls(fig)
    ax = fig.add_subplot(projection="3d")
    ax.plot(
        *points.T,
        color=COLOURS["link"],
        linewidth=3,
        marker="o",
        markersize=4,
        label="links (frame origins)",
    )
    labels: list[Label] = []
    for i, (row, f) in enumerate(zip(table.rows, table.frames()[:-1], strict=True)):
        z, p = f[:3, 2], f[:3, 3]
        ends = np.column_stack([p - 0.25 * span * z, p + 0.25 * span * z])
        ax.plot(
            *ends,
            color=COLOURS["joint"],
            linestyle="--",
            linewidth=1.2,
            label="joint axes" if i == 0 else None,
        )
        labels.append(Label(f"J{i + 1} {matplotlib_text(row.name)}", COLOURS["joint"],
                            p + 0.27 * span * z, z, 0.06 * span, 7))  # fmt: skip
    for k, f in enumerate(frames[:-1]):
        _arrow(ax, labels, f[:3, 3], f[:3, 0], arrow, COLOURS["x"], f"x{k}")
        _arrow(ax, labels, f[:3, 3], f[:3, 2], arrow, COLOURS["z"], f"z{k}")
    tool = frames[-1]
    for axis, name in enumerate("xyz"):
        _arrow(
            ax,
            labels,
            tool[:3, 3],
            tool[:3, axis],
            0.7 * arrow,
            COLOURS[name],
            f"{name}tool" if name != "y" else "",
            width=1.0,
        )
    world = np.eye(3)
    for axis, name in enumerate("xyz"):
        _arrow(
            ax,
            labels,
            np.zeros(3),
            world[axis],
            0.7 * arrow,
            "#000000",
            f"{name}_{matplotlib_text(table.base_link)}"
            if name == "x" and table.base_link
            else name,
            width=0.8,
        )
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
    ax.set_title(
        title or f"{robot}: {name} frames at home\n{chain}"
        if table.base_link
        else f"{robot}: {name} frames at home",
        fontsize=10,
        usetex=False,
    )
    ax.legend(loc="upper left", fontsize=8)
    placed = place(ax, labels)
    for label, position, _ in placed:
        ax.text(*position, label.text, color=label.colour, fontsize=label.size, usetex=False)
    return fig, placed


def render(table: Table, fmt: str = "png", title: str | None = None) -> bytes:
    """The drawing as ``png``, ``svg`` or ``pdf`` bytes."""
    if fmt not in FORMATS:
        raise UsageError(f"plot: unknown image format '{fmt}'; valid: {', '.join(FORMATS)}")
    fig, _ = layout(table, title)
    buf = io.BytesIO()
    fig.savefig(buf, format=fmt)
    return buf.getvalue()
