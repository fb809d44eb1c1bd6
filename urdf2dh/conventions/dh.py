"""Standard Denavit-Hartenberg, from a POE model by Wu, Crawford & Roberts 2019.

Forward kinematics of a ``dh`` table (Wu 2019 eq. 10; docs/conventions/dh.md)::

    T(q) = B . prod_i [ Q_i(s_i) . Rz(theta_i) Tz(d_i) Rx(alpha_i) Tx(a_i) ] . Rz(theta_T) Tz(d_T)

``B = Rz Tz Rx Tx`` puts frame 0's z on joint 1's axis (4 base parameters); row ``i`` carries the
link from joint ``i``'s axis to joint ``i+1``'s (the last row: to the tool's z axis); the tool
transform keeps 2 parameters (Lemma 4). The conversion follows eq. (18): each joint axis is
expressed in the frame built so far (the adjoint step) and Lemmas 1-3
(:mod:`urdf2dh.geometry.normals`) give the next link.

Styles choose among the equally exact tables (for each common normal, which of its two
directions is the x axis): ``wu`` follows Wu 2019 §III (``a >= 0``; docs/conventions/dh.md);
``ur`` prefers
zero ``theta`` offsets and turns a free x axis (coincident axes) so that the next ``alpha`` is
positive, as Universal Robots' own tables do, and a free last x (the tool z on the last axis)
is the tool's own x, as UR's flange is D-H frame 6; ``zero`` prefers zero ``theta`` offsets
and leaves free x axes at ``theta = 0``, the base's included (what controllers without
offsets, such as LinuxCNC's genserkins, need).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, ClassVar

from ..errors import shown
from ..geometry import frames
from ..geometry.frames import Frame, Vec3
from ..geometry.normals import Judgement, Limits, LinkParams, link_to_line
from .base import Conversion, Guide, Params, Style, angle, length

if TYPE_CHECKING:
    from ..model.poe import PoeModel
    from ..tolerances import Tolerances

__all__ = [
    "DH",
    "STYLES",
    "DhLink",
    "RzTz",
    "StandardDH",
    "chain_lines",
    "far_rows",
    "links_from_poe",
]

STYLES = ("wu", "ur", "zero")


@dataclass(frozen=True, slots=True)
class DhLink(Params):
    """A standard D-H link: ``Rz(theta) Tz(d) Rx(alpha) Tx(a)`` (rows and the base)."""

    form: ClassVar[str] = "D-H"

    theta: float = angle()
    d: float = length()
    alpha: float = angle()
    a: float = length()

    def frame(self) -> Frame:
        return frames.dh_frame(self.theta, self.d, self.alpha, self.a)


@dataclass(frozen=True, slots=True)
class RzTz(Params):
    """``Rz(theta) Tz(d)``: the standard tool (Lemma 4), and the modified D-H base."""

    theta: float = angle()
    d: float = length()

    def frame(self) -> Frame:
        return frames.dh_frame(self.theta, self.d, 0.0, 0.0)


def _link(p: LinkParams) -> DhLink:
    return DhLink(p.theta, p.d, p.alpha, p.a)


def far_rows(
    name: str, model: PoeModel, rows: tuple[Params, ...], tol: Tolerances
) -> tuple[str, ...]:
    """A warning for each row whose ``|d|`` or ``|a|`` lies beyond ``far_factor`` x the robot's
    size: nearly parallel axes whose exact common normal is far away (``--exact``)."""
    far, unit = tol.far_factor * model.size(), model.length_unit
    out = []
    for joint, params in zip(model.joints, rows, strict=True):
        values = {k: getattr(params, k) for k in ("d", "a")}
        big = [k for k in values if abs(values[k]) > far]
        if big:
            lengths = ", ".join(f"|{k}| = {abs(values[k]):.3g} {unit}" for k in big)
            out.append(
                f"{name}: row {shown(joint.name)} has {lengths}, far beyond the robot's size "
                f"({model.size():.3g} {unit}): nearly parallel axes put the common "
                "normal far away and D-H loses precision there; --convention hayati (or cpc, or "
                "the POE model) describes this geometry without it, while mdh shares the common "
                "normals"
            )
    return tuple(out)


class StandardDH:
    """The ``dh`` convention."""

    name = "dh"
    label = "standard D-H"
    title = "standard D-H (Wu 2019): B . prod[Q_i Rz(theta) Tz(d) Rx(alpha) Tx(a)] . Rz Tz"
    formula = (
        "T(q) = B . prod_i [Rz(q_i + theta_i) Tz(d_i) Rx(alpha_i) Tx(a_i)] . T  (standard D-H)"
    )
    base_types: tuple[type[Params], ...] = (DhLink,)
    row_types: tuple[type[Params], ...] = (DhLink,)
    tool_types: tuple[type[Params], ...] = (RzTz,)
    styles: tuple[str, ...] = STYLES
    guided = True

    def from_poe(self, model: PoeModel, tol: Tolerances, style: Style) -> Conversion:
        links, (theta, d), judgements = links_from_poe(model, tol, style)
        rows = tuple(_link(p) for p in links[1:])
        return Conversion(
            _link(links[0]),
            rows,
            RzTz(theta, d),
            (1.0,) * model.n,
            tuple(judgements),
            far_rows(self.name, model, rows, tol),
        )


DH = StandardDH()


def _nearest(link: LinkParams, exact: bool, target: Frame) -> LinkParams:
    """Of the links equally exact to ``link``'s line, the one whose frame is nearest
    ``target`` (given in the frame the link starts from): its x axis the common normal's
    direction nearer the target's x; on coincident lines the target's turn and height, on
    (exactly) parallel ones the target's height."""
    if link.free:  # any turn about and slide along the line
        turn = frames.angle(target[1][0], target[0][0])
        return replace(link, theta=turn, d=target[2][3] + 0.0)
    if link.parallel and exact:
        link = replace(link, d=target[2][3] + 0.0)
    turned = link.turned()

    def along(p: LinkParams) -> float:
        return math.cos(p.theta) * target[0][0] + math.sin(p.theta) * target[1][0]

    return turned if along(turned) > along(link) else link


def _prefer_small_theta(link: LinkParams) -> LinkParams:
    """Of the two x directions along the common normal, the one with ``theta`` in
    ``(-pi/2, pi/2]`` (zero offsets where the geometry allows; ``a`` may be < 0)."""
    return link if -math.pi / 2 < link.theta <= math.pi / 2 else link.turned()


def links_from_poe(
    model: PoeModel, tol: Tolerances, style: Style = "wu"
) -> tuple[list[LinkParams], tuple[float, float], list[Judgement]]:
    """The n + 1 D-H links (base->1, 1->2, ..., n->tool z), the tool's ``(theta, d)`` and the
    tolerance judgements made, in ``style`` (module docstring), or nearest a
    :class:`~urdf2dh.conventions.base.Guide`'s frames.

    Frames are built from the parameters as they will be evaluated (``F = F . H``), so the
    rounding of each row is seen by the next one and never accumulates unchecked.
    """
    home = frames.frame_of(model.home)
    limits = Limits.of(tol, model.size())
    lines = chain_lines(model)
    built = [frames.IDENTITY]
    links: list[LinkParams] = []
    judgements: list[Judgement] = []
    names = ["base z"] + [line[0] for line in lines]
    guide = style if isinstance(style, Guide) else None
    prefer_small_theta = style in ("ur", "zero")

    def source_angle(k: int) -> float:
        """Angle from parallel between line k and the one before it, in the source (after
        an earlier judgement, the frames are off by that much too: not a new judgement)."""
        ax, ay, az = (0.0, 0.0, 1.0) if k == 0 else lines[k - 1][1]
        bx, by, bz = lines[k][1]
        cross = math.hypot(ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx)
        return math.atan2(cross, abs(ax * bx + ay * by + az * bz))

    def link_to(k: int) -> tuple[LinkParams, list[Judgement]]:
        _, axis, point, is_tool = lines[k]
        u = frames.unit(frames.dir_into(built[k], axis))
        # a prismatic axis with a free location passes through the current frame origin
        p = (0.0, 0.0, 0.0) if point is None else frames.point_into(built[k], point)
        link, found = link_to_line(u, p, limits, (names[k], names[k + 1]), is_tool)
        if found:
            source = source_angle(k)
            # the line was turned (or moved) onto one through the new frame's origin
            origin = frames.compose(built[k], frames.dh_frame(link.theta, link.d, 0.0, link.a))
            pivot = math.hypot(origin[0][3], origin[1][3], origin[2][3])
            found = [replace(j, source_angle=source, pivot=pivot) for j in found]
        if guide is not None:
            return _nearest(link, not found, frames.between(built[k], guide.frames[k])), found
        return (_prefer_small_theta(link) if prefer_small_theta else link), found

    for k in range(len(lines)):
        link, found = link_to(k)
        if style == "ur" and k > 0 and links[-1].free and link.alpha < 0.0:
            links[-1] = links[-1].turned()  # UR: a free x is chosen for a positive next alpha
            prev = links[-1]
            built[-1] = frames.compose(
                built[-2], frames.dh_frame(prev.theta, prev.d, prev.alpha, prev.a)
            )
            link, found = link_to(k)
        links.append(link)
        judgements.extend(found)
        built.append(
            frames.compose(built[-1], frames.dh_frame(link.theta, link.d, link.alpha, link.a))
        )
    g = frames.between(built[-1], home)  # the tool transform Rz(theta) Tz(d) (Lemma 4)
    if style == "ur" and links[-1].free and g[1][0] != 0.0:
        # UR: the flange is D-H frame n, so a free last x (tool z on the last axis) is the
        # tool's own x and the tool transform is the identity
        last = links[-1]
        turn = last.theta + frames.angle(g[1][0], g[0][0])
        links[-1] = replace(last, theta=frames.angle(math.sin(turn), math.cos(turn)))
        built[-1] = frames.compose(
            built[-2], frames.dh_frame(links[-1].theta, last.d, last.alpha, last.a)
        )
        g = frames.between(built[-1], home)
    return links, (frames.angle(g[1][0], g[0][0]), g[2][3]), judgements


Line = tuple[str, Vec3, Vec3 | None, bool]  # name, direction, a point (or None), is the tool z


def chain_lines(model: PoeModel) -> list[Line]:
    """The lines a D-H-like table puts its frames' z axes on, after the base z: each joint's
    axis, then the tool's z (a prismatic joint's free line has no point)."""
    home = frames.frame_of(model.home)
    lines: list[Line] = [
        (j.name, _vec(j.axis.tolist()), None if j.point is None else _vec(j.point.tolist()), False)
        for j in model.joints
    ]
    lines.append(("tool z", _column(home, 2), _column(home, 3), True))
    return lines


def _vec(v: list[float]) -> Vec3:
    x, y, z = v
    return (x, y, z)


def _column(f: Frame, k: int) -> Vec3:
    return (f[0][k], f[1][k], f[2][k])
