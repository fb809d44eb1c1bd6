"""What a picture of a table's frames shows, whoever draws it (:mod:`.picture`, :mod:`.view`).

The arm at its home pose (``q = 0``), from a checked :class:`~urdf2dh.conventions.table.Table` in
any convention:

* the table's frames ``0 .. n`` (frame 0 is the base transform ``B``, frame ``k`` ends row
  ``k``) and the tool frame, each with its x (red) and z (blue) axis drawn as an arrow from its
  origin and labelled ``x0, z0, ..., xn, zn, xtool, ztool`` (the tool's y too, unlabelled);
* the links as a polyline through the frame origins, from the base link's origin;
* each joint's axis as a line through the frame whose z axis it is, labelled ``J1 .. Jn`` at
  its far end from that frame's z arrow;
* the base link's own axes, short and black;
* what hovering a frame shows: its row's parameters in the table's convention, with the
  units and decimals of the text table (:func:`urdf2dh.emit.formats.parameter_lines`).

Every label is attached to what it names: it starts :data:`LABEL_GAP` arrow lengths beyond
the end of its arrow (or joint axis), on that arrow's line, and a drawing may only slide it
further along that line (up to :attr:`Label.reach`) to keep it clear of other labels. Arrows
of frames that coincide share one label (``x5, x6``). The view (elevation, azimuth; z up) is
the one of a few dozen from which the labels stand farthest apart.

Bounds, so that no input takes minutes: a picture shows at most :data:`MAX_JOINTS` joints
(a longer chain is refused with one line; its frames could not be told apart anyway), and a
name is shown cut to :data:`NAME_CHARS` characters. Names are kept as text here; each drawing
escapes them for its language (:mod:`urdf2dh.escape`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ..conventions.grid import parameter_lines
from ..conventions.table import Table
from ..errors import InputError
from ..geometry import se3
from ..units import DECIMALS, fixed

__all__ = [
    "ARROW",
    "LABEL_GAP",
    "MAX_JOINTS",
    "NAME_CHARS",
    "TOOL_ARROW",
    "Arrow",
    "JointAxis",
    "Label",
    "Scene",
    "SceneFrame",
    "check_size",
    "choose_view",
    "frames_at_home",
    "scene",
    "screen_axes",
    "short",
]

Mat = NDArray[np.float64]

MAX_JOINTS = 200  # joints a picture shows; a longer chain is refused
NAME_CHARS = 40  # characters of a name a picture shows
ARROW = 0.12  # an axis arrow's length, per the span of the frame origins
TOOL_ARROW = 0.7  # the tool frame's arrows, per arrow length
JOINT_AXIS = 0.18  # a joint axis line's half length, per that span
WORLD_ARROW = 0.6  # the base link's axes, per arrow length
LABEL_GAP = 0.15  # from an arrow's tip to its label's anchor, per arrow length
SLIDE = 0.6  # how far a drawing may slide a label along its arrow, per arrow length
SAME_POINT = 1e-9  # anchors closer than this (per span) are one label's


def short(name: str, limit: int = NAME_CHARS) -> str:
    """``name`` as a picture shows it: cut to ``limit`` characters, the last one ``…``."""
    return name if len(name) <= limit else name[: limit - 1] + "…"


def check_size(joints: int) -> None:
    """Refuse a chain of more than :data:`MAX_JOINTS` joints: :class:`InputError`."""
    if joints > MAX_JOINTS:
        raise InputError(f"the chain has {joints} joints; a picture shows at most {MAX_JOINTS}")


@dataclass(frozen=True, slots=True)
class SceneFrame:
    """A frame of the table at home: ``name`` (``0`` .. ``n``, ``tool``), its ``(4, 4)``
    pose, and the lines hovering it shows (which record ends there and its parameters)."""

    name: str
    pose: Mat
    hover: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Arrow:
    """A frame's ``axis`` (``x``, ``y`` or ``z``) drawn from its origin; ``frame`` indexes
    :attr:`Scene.frames` (``-1``: the base link's axes)."""

    frame: int
    axis: str
    origin: Mat
    direction: Mat
    length: float

    @property
    def tip(self) -> Mat:
        return self.origin + self.length * self.direction


@dataclass(frozen=True, slots=True)
class JointAxis:
    """Joint ``number`` (1-based row) drawn as the segment ``ends`` ``(2, 3)`` of its axis."""

    number: int
    name: str
    kind: str
    ends: Mat


@dataclass(frozen=True, slots=True)
class Label:
    """A text attached to what it names.

    ``anchor`` is where it starts: :data:`LABEL_GAP` arrow lengths beyond the end of its arrow
    or axis, along ``direction`` (unit, the arrow's); a drawing may move it further along
    ``direction`` by at most ``reach``, never elsewhere. ``kind`` (``x``, ``z``, ``joint``,
    ``world``) picks its colour; ``hover`` is what hovering it shows.
    """

    text: str
    kind: str
    anchor: Mat
    direction: Mat
    reach: float
    hover: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Scene:
    """Everything a picture of a table's frames shows (see the module's description).

    Attributes
    ----------
    title, subtitle
        The robot and convention; the chain (``base -> tip``, empty for a POE model).
    unit
        The length unit of the coordinates.
    frames
        The table's frames ``0 .. n`` then the tool frame.
    links
        ``(n + 3, 3)``: the base link's origin, then every frame's origin.
    joints, arrows, labels
        What is drawn and named (labels in drawing order).
    arrow_length
        The length of a frame's axis arrow.
    lower, upper
        ``(3,)`` corners of a box holding everything drawn, labels slid as far as they may.
    elevation, azimuth
        The view, in degrees (z up; azimuth from x towards y, as matplotlib and plotly's
        camera eye take it).
    """

    title: str
    subtitle: str
    unit: str
    frames: tuple[SceneFrame, ...]
    links: Mat
    joints: tuple[JointAxis, ...]
    arrows: tuple[Arrow, ...]
    labels: tuple[Label, ...]
    arrow_length: float
    lower: Mat
    upper: Mat
    elevation: float
    azimuth: float


def frames_at_home(table: Table) -> list[Mat]:
    """The table's frames ``0 .. n`` at home (frame 0 is the base transform ``B``, frame ``k``
    ends row ``k``), then the tool frame, each ``(4, 4)``."""
    f = table.base_matrix
    out = [f]
    for row in table.rows:
        f = f @ se3.matrix_of(row.params.frame())
        out.append(f)
    out.append(f @ table.tool_matrix)
    return out


def _hover(table: Table, frames: list[Mat]) -> list[tuple[str, ...]]:
    unit = short(table.length_unit)
    out = []
    for k, f in enumerate(frames):
        if k == 0:
            head, params = ["frame 0: the base record"], table.base
        elif k <= table.n:
            row = table.rows[k - 1]
            head, params = [f"frame {k}: row {k}, joint {short(row.name)} ({row.kind})"], row.params
            if row.kind == "helical":
                head.append(f"pitch [{unit}/rad] = {row.pitch:.6g}")
            if row.scale != 1.0:
                head.append(f"scale = {row.scale:.8g}")
            if row.mimic is not None:
                m = row.mimic
                head.append(f"mimics {short(m.joint)}: q = {m.multiplier:g} q' + {m.offset:g}")
        else:
            head, params = ["tool frame: the tool record"], table.tool
        lines = parameter_lines(params, unit) or ["(no parameters: the last row's frame)"]
        origin = ", ".join(fixed(float(c), DECIMALS.get(table.length_unit, 6)) for c in f[:3, 3])
        out.append((*head, *lines, f"origin [{unit}] = ({origin})"))
    return out


def _merge(labels: list[Label], tolerance: float) -> list[Label]:
    """Labels of one kind whose anchors coincide as one label naming them all."""
    out: list[Label] = []
    for label in labels:
        for i, kept in enumerate(out):
            if kept.kind == label.kind and np.abs(kept.anchor - label.anchor).max() <= tolerance:
                text, hover = f"{kept.text}, {label.text}", (*kept.hover, "", *label.hover)
                out[i] = replace(kept, text=text, hover=hover)
                break
        else:
            out.append(label)
    return out


def _axes(frames: list[Mat], hovers: list[tuple[str, ...]], length: float,
          names: list[str]) -> tuple[list[Arrow], list[Label]]:  # fmt: skip
    """Every frame's x and z arrows (the tool's y too) and their labels, then the base
    link's axes."""
    arrows, labels = [], []
    for k, f in enumerate(frames):
        tool = k == len(frames) - 1
        for a, axis in enumerate("xyz"):
            if axis == "y" and not tool:
                continue
            arrow = Arrow(k, axis, f[:3, 3], f[:3, a], (TOOL_ARROW if tool else 1.0) * length)
            arrows.append(arrow)
            if axis != "y":
                labels.append(_label(f"{axis}{names[k]}", axis, arrow.tip, f[:3, a], length,
                                     hovers[k]))  # fmt: skip
    for a, axis in enumerate("xyz"):
        arrows.append(Arrow(-1, axis, np.zeros(3), np.eye(3)[a], WORLD_ARROW * length))
    return arrows, labels


def _joints(table: Table, span: float, length: float) -> tuple[list[JointAxis], list[Label]]:
    """Each joint's axis through the frame whose z axis it is, labelled at its far end from
    that frame's z arrow."""
    joints, labels = [], []
    for i, (row, f) in enumerate(zip(table.rows, table.joint_frames()[:-1], strict=True), 1):
        p, z = f[:3, 3], f[:3, 2]
        ends = np.array([p - JOINT_AXIS * span * z, p + JOINT_AXIS * span * z])
        joints.append(JointAxis(i, short(row.name), row.kind, ends))
        labels.append(_label(f"J{i}", "joint", ends[0], -z, length,
                             (f"joint {i}: {short(row.name)} ({row.kind})",)))  # fmt: skip
    return joints, labels


def scene(table: Table) -> Scene:
    """The picture of ``table``'s frames at home (see the module's description); a chain of
    more than :data:`MAX_JOINTS` joints is refused (:class:`InputError`)."""
    check_size(table.n)
    frames = frames_at_home(table)
    names = [str(k) for k in range(table.n + 1)] + ["tool"]
    hovers = _hover(table, frames)
    links = np.array([np.zeros(3)] + [f[:3, 3] for f in frames])
    span = float(np.ptp(links, axis=0).max())
    if not span > 0.0:
        span = table.size
    length = ARROW * span

    arrows, labels = _axes(frames, hovers, length, names)
    base = short(table.base_link) if table.base_link else "world"
    labels.append(_label(base, "world", arrows[-3].tip, np.eye(3)[0], length,
                         (f"the base link's frame: {base}",)))  # fmt: skip
    joints, joint_labels = _joints(table, span, length)
    labels = _merge(labels + joint_labels, SAME_POINT * span)

    anchors = np.array([lb.anchor for lb in labels])
    drawn = np.vstack(
        [links, *(np.array([a.origin, a.tip]) for a in arrows), *(j.ends for j in joints),
         anchors, [lb.anchor + lb.reach * lb.direction for lb in labels]]
    )  # fmt: skip
    elevation, azimuth = choose_view(anchors, drawn)
    robot = short(table.robot or "robot")
    chain = f"{short(table.base_link)} -> {short(table.tip_link)}" if table.base_link else ""
    return Scene(
        title=f"{robot}: {table.spec.label} frames at home",
        subtitle=chain,
        unit=short(table.length_unit),
        frames=tuple(SceneFrame(n, f, h) for n, f, h in zip(names, frames, hovers, strict=True)),
        links=links,
        joints=tuple(joints),
        arrows=tuple(arrows),
        labels=tuple(labels),
        arrow_length=length,
        lower=drawn.min(axis=0),
        upper=drawn.max(axis=0),
        elevation=elevation,
        azimuth=azimuth,
    )


def _label(text: str, kind: str, end: Mat, direction: Mat, length: float,
           hover: tuple[str, ...]) -> Label:  # fmt: skip
    return Label(text, kind, end + LABEL_GAP * length * direction, direction, SLIDE * length,
                 hover)  # fmt: skip


VIEWS = [(e, a) for e in (20.0, 30.0, 40.0) for a in range(-180, 180, 15)]
DEFAULT_VIEW = (30.0, -60.0)
CROWDED = 0.05  # anchors closer than this (per picture size) crowd each other


def screen_axes(elevation: float, azimuth: float) -> Mat:
    """``(3, 2)``: the screen's right and up directions for a view from (elevation, azimuth),
    z up (orthographic)."""
    e, a = np.radians(elevation), np.radians(azimuth)
    right = np.array([-np.sin(a), np.cos(a), 0.0])
    up = np.array([-np.sin(e) * np.cos(a), -np.sin(e) * np.sin(a), np.cos(e)])
    return np.column_stack([right, up])


def choose_view(anchors: Mat, drawn: Mat) -> tuple[float, float]:
    """The view (elevation, azimuth in degrees) among :data:`VIEWS` from which the label
    ``anchors`` ``(L, 3)`` crowd each other least on a picture fitting ``drawn`` ``(M, 3)``:
    the sum over pairs closer than :data:`CROWDED` of the picture of ``(1 - d / CROWDED)^2``;
    ties go to the view nearest matplotlib's default."""
    best, chosen = np.inf, DEFAULT_VIEW
    for view in VIEWS:
        screen = screen_axes(*view)
        box = drawn @ screen
        size = float(np.ptp(box, axis=0).max()) or 1.0
        p = anchors @ screen / size
        d2 = ((p[:, None, :] - p[None, :, :]) ** 2).sum(axis=2)
        i, j = np.nonzero(np.triu(d2 < CROWDED**2, 1))
        close = 1.0 - np.sqrt(d2[i, j]) / CROWDED
        far = abs(view[0] - DEFAULT_VIEW[0]) + abs((view[1] - DEFAULT_VIEW[1] + 180) % 360 - 180)
        score = float((close**2).sum()) + 1e-4 * far
        if score < best:
            best, chosen = score, view
    return chosen
