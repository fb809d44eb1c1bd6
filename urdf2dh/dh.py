"""POE -> standard Denavit-Hartenberg (Wu, Crawford & Roberts 2019), with base and tool frames.

Forward kinematics of a ``dh`` table (SPEC §2, Wu 2019 eq. 10)::

    T(q) = B . prod_i [ Q_i(s_i) . Rz(theta_i) Tz(d_i) Rx(alpha_i) Tx(a_i) ] . Rz(theta_T) Tz(d_T)

``B = Rz Tz Rx Tx`` puts frame 0's z on joint 1's axis (4 base parameters); row ``i`` carries the
link from joint ``i``'s axis to joint ``i+1``'s (the last row: to the tool's z axis); the tool
transform keeps 2 parameters (Lemma 4). The conversion follows eq. (18): each joint axis is
expressed in the frame built so far (the adjoint step) and Lemmas 1-3 give the next link.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import se3
from .lines import Judgement, Limits, LinkParams, angle, dh_frame, link_to_line
from .screws import PoeModel
from .tolerances import Tolerances

__all__ = [
    "BASE_PARAMS",
    "PARAMS",
    "STYLES",
    "TOOL_PARAMS",
    "base_frame",
    "links_from_poe",
    "row_frames",
    "tool_frame",
]

PARAMS = ("theta", "d", "alpha", "a")
BASE_PARAMS = ("theta", "d", "alpha", "a")
TOOL_PARAMS = ("theta", "d")

Mat = NDArray[np.float64]


def base_frame(p: dict[str, Any]) -> se3.Frame:
    """``B = Rz(theta) Tz(d) Rx(alpha) Tx(a)``."""
    return dh_frame(p["theta"], p["d"], p["alpha"], p["a"])


def row_frames(p: dict[str, Any]) -> tuple[se3.Frame | None, se3.Frame]:
    """(before ``Q_i``, after ``Q_i``): ``None`` and ``Rz Tz Rx Tx``."""
    return None, dh_frame(p["theta"], p["d"], p["alpha"], p["a"])


def tool_frame(p: dict[str, Any]) -> se3.Frame:
    """``T = Rz(theta) Tz(d)``."""
    return dh_frame(p["theta"], p["d"], 0.0, 0.0)


STYLES = ("wu", "ur", "zero")


def _prefer_small_theta(link: LinkParams) -> LinkParams:
    """Vendor style: of the two x directions along the common normal, the one with
    ``theta`` in ``(-pi/2, pi/2]`` (zero offsets where the geometry allows; a may be < 0)."""
    return link if -math.pi / 2 < link.theta <= math.pi / 2 else link.turned()


def links_from_poe(
    model: PoeModel, tol: Tolerances, style: str = "wu"
) -> tuple[list[LinkParams], tuple[float, float], list[Judgement]]:
    """The n + 1 D-H links (base->1, 1->2, ..., n->tool z) and the tool's ``(theta, d)``.

    ``style="wu"`` follows Wu 2019 §III (SPEC §3: ``a >= 0``). ``style="ur"`` prefers zero
    ``theta`` offsets, and where an x axis is free (coincident axes) turns it so that the next
    link's ``alpha`` is positive: Universal Robots' own sign choices; a free last x (the tool z
    on the last axis) is the tool's x, as UR's flange is D-H frame 6. ``style="zero"`` prefers
    zero ``theta`` offsets and leaves free x axes at ``theta = 0`` (the base's included), as
    controllers without offsets (LinuxCNC genserkins) need.

    Frames are built from the parameters as they will be evaluated (``F = F . H``), so the
    rounding of each row is seen by the next one and never accumulates unchecked.
    """
    home = se3.frame_of(model.home)
    limits = Limits.of(tol, model.size())
    lines: list[tuple[str, se3.Vec3, se3.Vec3 | None, bool]] = [
        (j.name, _vec(j.axis), None if j.point is None else _vec(j.point), False)
        for j in model.joints
    ]
    lines.append(("tool z", _column(home, 2), _column(home, 3), True))
    frames = [se3.IDENTITY]
    links: list[LinkParams] = []
    judgements: list[Judgement] = []
    names = ["base z"] + [line[0] for line in lines]
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
        u = se3.unit(se3.dir_into(frames[k], axis))
        # a prismatic axis with a free location passes through the current frame origin (SPEC §3)
        p = (0.0, 0.0, 0.0) if point is None else se3.point_into(frames[k], point)
        link, found = link_to_line(u, p, limits, (names[k], names[k + 1]), is_tool)
        if found:
            source = source_angle(k)
            found = [Judgement(j.kind, j.first, j.second, j.angle, j.gap, source) for j in found]
        return (_prefer_small_theta(link) if prefer_small_theta else link), found

    for k in range(len(lines)):
        link, found = link_to(k)
        if style == "ur" and k > 0 and links[-1].free and link.alpha < 0.0:
            links[-1] = links[-1].turned()  # UR: a free x is chosen for a positive next alpha
            prev = links[-1]
            frames[-1] = se3.compose(frames[-2], dh_frame(prev.theta, prev.d, prev.alpha, prev.a))
            link, found = link_to(k)
        links.append(link)
        judgements.extend(found)
        frames.append(se3.compose(frames[-1], dh_frame(link.theta, link.d, link.alpha, link.a)))
    g = se3.between(frames[-1], home)  # the tool transform Rz(theta) Tz(d) (Lemma 4)
    if style == "ur" and links[-1].free and g[1][0] != 0.0:
        # UR: the flange is D-H frame n, so a free last x (tool z on the last axis) is the
        # tool's own x and the tool transform is the identity
        last = links[-1]
        theta = angle(math.sin(last.theta + angle(g[1][0], g[0][0])),
                      math.cos(last.theta + angle(g[1][0], g[0][0])))
        links[-1] = last._replace(theta=theta)
        frames[-1] = se3.compose(frames[-2], dh_frame(theta, last.d, last.alpha, last.a))
        g = se3.between(frames[-1], home)
    return links, (angle(g[1][0], g[0][0]), g[2][3]), judgements


def _vec(a: Mat) -> se3.Vec3:
    x, y, z = a.tolist()
    return (x, y, z)


def _column(f: se3.Frame, k: int) -> se3.Vec3:
    return (f[0][k], f[1][k], f[2][k])
