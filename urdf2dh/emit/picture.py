"""The picture for papers: a :class:`~.scene.Scene` drawn by matplotlib (png, svg, pdf).

An orthographic view (parallel axes stay parallel) at equal scale on every axis, from the
scene's view, on a figure as wide as the arm looks from there. Every label is drawn at its
anchor or slid along its own arrow (never elsewhere, :attr:`~.scene.Label.reach` at most), set
on the side its arrow points to on the picture or else around it. Labels are placed one by one,
each at the first of these places where its text covers no label placed before it and no
line, or else where it covers the fewest pixels of other labels and of the figure's edge,
then the fewest lines. Labels are drawn over the lines, on a light backing. matplotlib is an
optional dependency, imported here only, with the Agg canvas (no display needed).
"""

from __future__ import annotations

import io
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import UsageError, choices, missing
from ..escape import matplotlib_text
from .scene import Label, Scene, screen_axes

__all__ = ["COLOURS", "FORMATS", "LABEL_SPACE", "Placed", "draw", "picture"]

FORMATS = ("png", "svg", "pdf")
COLOURS = {
    "x": "#d62728",
    "y": "#2ca02c",
    "z": "#1f77b4",
    "joint": "#e07000",
    "link": "#555555",
    "world": "#000000",
}
FONT_SIZE = {"x": 8, "z": 8, "joint": 7, "world": 7}  # points
LABEL_SPACE = 2.0  # pixels kept between two labels' texts
SLIDES = (0.0, 0.2, 0.4, 0.6, 0.8, 1.0)  # where along its arrow a label tries, per its reach
LINE_STEP = 3.0  # pixels between the points of a drawn line that labels keep off
PNG_DPI = 150
ZOOM = 1.0  # of the 3-D box in its axes (matplotlib leaves room for ticks around it)
TICKS = 5  # at most, on each axis
BACKING = {"facecolor": "white", "alpha": 0.75, "edgecolor": "none", "pad": 0.3}  # under a label
HEIGHT = 8.0  # inches
WIDTHS = (6.0, 12.0)  # inches

Mat = NDArray[np.float64]
Box = tuple[float, float, float, float]
Placed = tuple[Label, Any, Box]  # a label, its matplotlib text, the pixels it covers


def matplotlib_figure(what: str = "the picture") -> tuple[Any, Any]:
    """matplotlib's ``Figure`` and its Agg canvas (no display needed), or the
    :class:`~urdf2dh.errors.InputError` saying how to install matplotlib (``what``: the feature
    that needs it)."""
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError as e:
        raise missing(what, "matplotlib", "plot") from e
    return Figure, FigureCanvasAgg


def _limits(scene: Scene) -> tuple[Mat, Mat]:
    """Equal-scale limits around everything drawn: a margin of 4 %, and no side shorter than
    a third of the longest (a planar arm's picture keeps some depth)."""
    centre = (scene.upper + scene.lower) / 2
    half = np.maximum((scene.upper - scene.lower) / 2, 1e-12)
    half = np.maximum(half, half.max() / 3) * 1.04
    return centre - half, centre + half


def _size(lower: Mat, upper: Mat, scene: Scene) -> tuple[float, float]:
    """The figure's size (inches): :data:`HEIGHT` high, as wide as the box ``lower .. upper``
    looks from the scene's view (within :data:`WIDTHS`), with room for the title and legend."""
    corners = np.array([[(lower, upper)[(k >> i) & 1][i] for i in range(3)] for k in range(8)])
    seen = np.ptp(corners @ screen_axes(scene.elevation, scene.azimuth), axis=0)
    width = HEIGHT * 0.84 * seen[0] / seen[1] + 1.6
    return float(np.clip(width, *WIDTHS)), HEIGHT


ALIGNMENTS = {  # (ha, va) -> which way the text lies from its anchor
    (ha, va): np.array([dx, dy]) / np.hypot(dx, dy)
    for ha, dx in (("left", 1.0), ("center", 0.0), ("right", -1.0))
    for va, dy in (("bottom", 1.0), ("center", 0.0), ("top", -1.0))
    if dx or dy
}


def _candidates(screen: Mat) -> list[tuple[str, str]]:
    """The alignments (ha, va) of a label's text, the side ``screen`` (its arrow's direction on
    the picture, pixels) points to first, the side back onto the arrow last."""
    return sorted(ALIGNMENTS, key=lambda align: -float(ALIGNMENTS[align] @ screen))


def _box(xy: Mat, size: tuple[float, float], align: tuple[str, str]) -> Box:
    w, h = size
    x0 = xy[0] - {"left": 0.0, "center": w / 2, "right": w}[align[0]]
    y0 = xy[1] - {"bottom": 0.0, "center": h / 2, "top": h}[align[1]]
    return (x0, y0, x0 + w, y0 + h)


class _Crowd:
    """What is already on the picture, in pixels: the labels placed so far (boxes) and the
    drawn lines (as a summed-area table of their points, :data:`LINE_STEP` apart, so that
    counting the points in a box takes four look-ups)."""

    def __init__(self, lines: Mat, width: float, height: float) -> None:
        self.frame = (0.0, 0.0, width, height)
        shape = (int(height) + 2, int(width) + 2)
        ij = np.floor(lines[:, ::-1]).astype(int) + 1
        keep = (ij >= 1).all(axis=1) & (ij[:, 0] < shape[0]) & (ij[:, 1] < shape[1])
        grid = np.zeros(shape)
        np.add.at(grid, (ij[keep, 0], ij[keep, 1]), 1.0)
        self.table = grid.cumsum(axis=0).cumsum(axis=1)
        self.boxes = np.zeros((0, 4))

    def _points(self, x0: float, y0: float, x1: float, y1: float) -> int:
        rows, cols = self.table.shape
        i0, i1 = (min(max(int(v), 0), rows - 1) for v in (y0, y1 + 1))
        j0, j1 = (min(max(int(v), 0), cols - 1) for v in (x0, x1 + 1))
        t = self.table
        return round(float(t[i1, j1] - t[i0, j1] - t[i1, j0] + t[i0, j0]))

    def cost(self, box: Box) -> tuple[float, int]:
        """What ``box`` (grown by :data:`LABEL_SPACE`) covers: the pixels of placed labels and
        of the figure's outside, then the points of drawn lines."""
        s = LABEL_SPACE
        x0, y0, x1, y1 = box[0] - s, box[1] - s, box[2] + s, box[3] + s
        b = self.boxes
        w = np.clip(np.minimum(x1, b[:, 2]) - np.maximum(x0, b[:, 0]), 0.0, None)
        h = np.clip(np.minimum(y1, b[:, 3]) - np.maximum(y0, b[:, 1]), 0.0, None)
        f = self.frame
        inside = max(0.0, min(x1, f[2]) - max(x0, f[0])) * max(0.0, min(y1, f[3]) - max(y0, f[1]))
        outside = (x1 - x0) * (y1 - y0) - inside
        return float((w * h).sum()) + outside, self._points(x0, y0, x1, y1)

    def add(self, box: Box) -> None:
        self.boxes = np.vstack([self.boxes, box])


def _segments(scene: Scene) -> list[tuple[Mat, Mat]]:
    """Every line drawn: links, joint axes, arrows."""
    out = list(zip(scene.links[:-1], scene.links[1:], strict=True))
    out += [(j.ends[0], j.ends[1]) for j in scene.joints]
    out += [(a.origin, a.tip) for a in scene.arrows]
    return out


def _place(ax: Any, fig: Any, scene: Scene) -> list[Placed]:
    """Draw the scene's labels, each at the first free place along its arrow."""
    from mpl_toolkits.mplot3d import proj3d

    renderer = fig.canvas.get_renderer()
    proj = ax.get_proj()

    def pixels(p: Mat) -> Mat:
        x, y, _ = proj3d.proj_transform(p[0], p[1], p[2], proj)
        return np.asarray(ax.transData.transform((x, y)))

    points = []
    for a, b in _segments(scene):
        pa, pb = pixels(a), pixels(b)
        steps = min(int(float(np.linalg.norm(pb - pa)) // LINE_STEP), 1000) + 2
        points.append(pa + np.linspace(0.0, 1.0, steps)[:, None] * (pb - pa))
    crowd = _Crowd(np.vstack(points), fig.bbox.width, fig.bbox.height)
    placed: list[Placed] = []
    for label in scene.labels:
        text = ax.text(*label.anchor, matplotlib_text(label.text), color=COLOURS[label.kind],
                       fontsize=FONT_SIZE[label.kind], usetex=False, zorder=5,
                       bbox=BACKING)  # fmt: skip
        extent = text.get_window_extent(renderer)
        size = (extent.width, extent.height)
        start = pixels(label.anchor)
        screen = pixels(label.anchor + scene.arrow_length * label.direction) - start
        tried = []
        for slide in SLIDES:
            position = label.anchor + slide * label.reach * label.direction
            xy = pixels(position)
            for align in _candidates(screen):
                box = _box(xy, size, align)
                tried.append((crowd.cost(box), position, align, box))
                if tried[-1][0] == (0.0, 0):
                    break
            if tried[-1][0] == (0.0, 0):
                break
        _, position, align, box = min(tried, key=lambda t: t[0])
        text.set_position_3d(position)
        text.set_horizontalalignment(align[0])
        text.set_verticalalignment(align[1])
        placed.append((label, text, box))
        crowd.add(box)
    return placed


def draw(scene: Scene) -> tuple[Any, Any, list[Placed]]:
    """The matplotlib figure of ``scene``, its 3-D axes, and its labels as placed."""
    figure_cls, canvas_cls = matplotlib_figure()
    from matplotlib.ticker import MaxNLocator

    lower, upper = _limits(scene)
    fig = figure_cls(figsize=_size(lower, upper, scene), dpi=100)
    canvas_cls(fig)
    ax = fig.add_axes((0.0, 0.08, 1.0, 0.84), projection="3d", computed_zorder=False)
    ax.set_proj_type("ortho")

    ax.plot(*scene.links.T, color=COLOURS["link"], linewidth=2.5, marker="o", markersize=3.5,
            label="links (frame origins)")  # fmt: skip
    for k, joint in enumerate(scene.joints):
        ax.plot(*joint.ends.T, color=COLOURS["joint"], linestyle="--", linewidth=1.1,
                label="joint axes" if k == 0 else None)  # fmt: skip
    for axis in "xyz":
        for colour, world in ((COLOURS[axis], False), (COLOURS["world"], True)):
            arrows = [a for a in scene.arrows if a.axis == axis and (a.frame < 0) == world]
            if not arrows:
                continue
            start = np.array([a.origin for a in arrows])
            vector = np.array([a.length * a.direction for a in arrows])
            ax.quiver(*start.T, *vector.T, color=colour, arrow_length_ratio=0.18,
                      linewidth=0.8 if world else 1.6,
                      label=None if world or axis == "y" else f"{axis} axes")  # fmt: skip

    ax.set_xlim(lower[0], upper[0])
    ax.set_ylim(lower[1], upper[1])
    ax.set_zlim(lower[2], upper[2])
    ax.set_box_aspect(tuple(upper - lower), zoom=ZOOM)
    ax.view_init(elev=scene.elevation, azim=scene.azimuth)
    unit = matplotlib_text(scene.unit)
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.set_zlabel(f"z [{unit}]")
    ax.tick_params(labelsize=7)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(TICKS))
    title = matplotlib_text(scene.title)
    if scene.subtitle:
        title += "\n" + matplotlib_text(scene.subtitle)
    fig.suptitle(title, fontsize=10, y=0.97)
    fig.legend(loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.canvas.draw()  # the layout, so that the labels are placed on the final picture
    return fig, ax, _place(ax, fig, scene)


def picture(scene: Scene, fmt: str = "png") -> bytes:
    """The drawing of ``scene`` as ``png``, ``svg`` or ``pdf`` bytes."""
    if fmt not in FORMATS:
        raise UsageError(f"unknown image format '{fmt}'; valid: {choices(FORMATS)}")
    fig, _, _ = draw(scene)
    buf = io.BytesIO()
    fig.savefig(buf, format=fmt, dpi=PNG_DPI if fmt == "png" else "figure")
    return buf.getvalue()
