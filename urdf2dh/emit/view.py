"""The interactive view: a :class:`~.scene.Scene` as a plotly 3-D figure on an offline page.

Turn it with the mouse, zoom with the wheel, hover a frame's origin (or a label) to read the
parameters of the record that ends there. The figure's traces, in order, each named (the
legend shows the names and hides or shows a trace on a click):

``links``        the polyline through the frame origins
``joint axes``   each joint's axis (hover: the joint)
``x axes``, ``z axes``, ``tool y``, ``base axes``
                 arrows: a line from the frame's origin and a cone ending at its tip
``frames``       a marker at each frame's origin (hover: its record's parameters)
``labels``       every label at its scene anchor, its text and colour per point

Every text from the source reaches the figure through
:func:`urdf2dh.escape.html_text` (plotly reads text as HTML).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..escape import html_text
from .html import offline_page, plotly_objects
from .picture import COLOURS
from .scene import Arrow, Scene, screen_axes

__all__ = ["HEAD", "figure", "page"]

Mat = NDArray[np.float64]

HEAD = 0.25  # an arrow's cone, per arrow length
ARROWS: tuple[tuple[str, Callable[[Arrow], bool], str], ...] = (  # trace name, which, colour
    ("x axes", lambda a: a.frame >= 0 and a.axis == "x", COLOURS["x"]),
    ("z axes", lambda a: a.frame >= 0 and a.axis == "z", COLOURS["z"]),
    ("tool y", lambda a: a.frame >= 0 and a.axis == "y", COLOURS["y"]),
    ("base axes", lambda a: a.frame < 0, COLOURS["world"]),
)
CAMERA_DISTANCE = 2.6  # plotly's camera eye, in units of the scene's half size


def _hover(lines: tuple[str, ...]) -> str:
    return "<br>".join(html_text(line) for line in lines)


def _xyz(points: Mat) -> dict[str, Mat]:
    """A trace's ``x``, ``y``, ``z`` from ``(k, 3)`` points."""
    return dict(zip("xyz", np.asarray(points, dtype=float).T, strict=True))


def _polylines(segments: list[Mat]) -> dict[str, list[float | None]]:
    """A trace's ``x``, ``y``, ``z`` for several polylines, ``None`` between them (plotly's
    gaps)."""
    xyz: dict[str, list[float | None]] = {"x": [], "y": [], "z": []}
    for segment in segments:
        for c, values in enumerate(xyz.values()):
            values.extend([*map(float, segment[:, c]), None])
    return xyz


def _arrows(go: Any, name: str, arrows: list[Arrow], colour: str) -> list[Any]:
    """A line from each arrow's origin to its tip, and a cone ending at the tip."""
    line = go.Scatter3d(
        **_polylines([np.array([a.origin, a.tip]) for a in arrows]),
        mode="lines",
        name=name,
        legendgroup=name,
        hoverinfo="skip",
        line={"color": colour, "width": 5},
    )
    heads = np.array([HEAD * a.length * a.direction for a in arrows])
    cone = go.Cone(
        **_xyz(np.array([a.tip for a in arrows])),
        u=heads[:, 0],
        v=heads[:, 1],
        w=heads[:, 2],
        anchor="tip",
        sizemode="raw",
        sizeref=1.0,
        colorscale=[[0, colour], [1, colour]],
        showscale=False,
        name=name,
        legendgroup=name,
        showlegend=False,
        hoverinfo="skip",
    )
    return [line, cone]


def _traces(go: Any, scene: Scene) -> list[Any]:
    traces = [
        go.Scatter3d(
            **_xyz(scene.links),
            mode="lines+markers",
            name="links",
            hoverinfo="skip",
            line={"color": COLOURS["link"], "width": 7},
            marker={"size": 3, "color": COLOURS["link"]},
        )
    ]
    if scene.joints:
        hover = [_hover((f"joint {j.number}: {j.name} ({j.kind})",)) for j in scene.joints]
        traces.append(
            go.Scatter3d(
                **_polylines([j.ends for j in scene.joints]),
                mode="lines",
                name="joint axes",
                hovertext=[t for h in hover for t in (h, h, None)],
                hoverinfo="text",
                line={"color": COLOURS["joint"], "width": 3, "dash": "dash"},
            )
        )
    for name, chosen, colour in ARROWS:
        arrows = [a for a in scene.arrows if chosen(a)]
        if arrows:
            traces.extend(_arrows(go, name, arrows, colour))
    traces.append(
        go.Scatter3d(
            **_xyz(np.array([f.pose[:3, 3] for f in scene.frames])),
            mode="markers",
            name="frames",
            text=[f.name for f in scene.frames],
            hovertext=[_hover(f.hover) for f in scene.frames],
            hoverinfo="text",
            marker={"size": 5, "color": "#222222", "symbol": "diamond"},
        )
    )
    traces.append(
        go.Scatter3d(
            **_xyz(np.array([lb.anchor for lb in scene.labels])),
            mode="text",
            name="labels",
            text=[html_text(lb.text) for lb in scene.labels],
            textposition="middle center",
            textfont={"color": [COLOURS[lb.kind] for lb in scene.labels], "size": 13},
            hovertext=[_hover(lb.hover) for lb in scene.labels],
            hoverinfo="text",
        )
    )
    return traces


def figure(scene: Scene) -> Any:
    """The plotly figure of ``scene``."""
    go = plotly_objects("the interactive view")
    unit = html_text(scene.unit)
    title = html_text(scene.title)
    if scene.subtitle:
        title += "<br><sub>" + html_text(scene.subtitle) + "</sub>"
    screen = screen_axes(scene.elevation, scene.azimuth)
    eye = CAMERA_DISTANCE * np.cross(screen[:, 0], screen[:, 1])  # right x up: to the viewer
    axes = {f"{c}axis": {"title": {"text": f"{c} [{unit}]"}, "showspikes": False} for c in "xyz"}
    camera = {
        "eye": dict(zip("xyz", map(float, eye), strict=True)),
        "up": {"x": 0, "y": 0, "z": 1},
        "projection": {"type": "orthographic"},
    }
    layout = go.Layout(
        title={"text": title, "x": 0.5},
        scene={"aspectmode": "data", "camera": camera, **axes},
        hoverlabel={"font": {"family": "monospace"}, "align": "left"},
        legend={"itemsizing": "constant"},
        margin={"l": 0, "r": 0, "t": 60, "b": 0},
    )
    return go.Figure(data=_traces(go, scene), layout=layout)


def page(scene: Scene) -> str:
    """The interactive view of ``scene`` as a self-contained HTML page."""
    title = scene.title + (f" ({scene.subtitle})" if scene.subtitle else "")
    return offline_page(figure(scene), title)
