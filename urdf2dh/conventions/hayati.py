"""Hayati: D-H rows where they are well conditioned, Hayati's rows where axes are (nearly)
parallel (Hayati & Mirmirani 1985).

Forward kinematics of a ``hayati`` table (docs/conventions/hayati.md)::

    T(q) = B . prod_i [ Q_i(s_i) . H_i ] . Rz(theta_T) Tz(d_T)

where each ``H`` (the base's ``B`` too) is either a D-H link ``Rz(theta) Tz(d) Rx(alpha)
Tx(a)`` (params ``theta, d, alpha, a``) or a Hayati link ``Rz(theta) Tx(a) Rx(alpha)
Ry(beta)`` (params ``theta, a, alpha, beta``: no ``d``). The tool is the standard one (Lemma 4).

Why: a D-H link puts the next frame on the common normal of two axes, which for axes ``angle``
apart lies about ``offset / angle`` away: ``d`` of hundreds of metres for a few milliradians, and
no D-H table of that geometry is both exact and sane. A Hayati link puts the next frame where
the next axis crosses the current frame's xy plane instead, and turns onto the axis by
``Rx(alpha) Ry(beta)``: near parallel axes that crossing is near, and the link is as well
conditioned as the geometry.

The rule, for each line in turn (joint 1's axis from the base z, ..., the tool's z from the last
joint's axis), in the frames as evaluated so far: compute the exact D-H link (Wu 2019 Lemmas 1-4, no
tolerance judgement: :mod:`urdf2dh.geometry.normals` with exact tolerances, lines meeting only
within what costs less than the exactness promised) and the Hayati link; take the Hayati link when
its ``|a|`` is smaller than the D-H link's larger length ``max(|d|, |a|)`` by more than that
distance (over ``sin(alpha)`` for a common normal, which is known to that only), or when the D-H
link could only be had by a judgement beyond round-off (axes 1e-15 to 1e-13 rad from parallel,
whose exact common normal is far away) and the Hayati link needs none, or when the D-H link's
common normal is itself set by round-off (axes 1e-13 to 2.4e-7 rad from parallel); the D-H link
otherwise (so exactly parallel axes keep Wu's ``d = 0`` row, and an axis in the xy plane, which
the Hayati link cannot reach, a D-H one). Every table is exact, every length stays within the
geometry's own distances, and no row's form is decided by round-off: converting the table's POE
model again gives the same rows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, ClassVar

from ..geometry import frames
from ..geometry.frames import Frame, Vec3
from ..geometry.normals import Judgement, Limits, LinkParams, link_to_line
from .base import Conversion, Params, Style, angle, length
from .dh import DhLink, RzTz, chain_lines

if TYPE_CHECKING:
    from ..model.poe import PoeModel
    from ..tolerances import Tolerances

__all__ = ["HAYATI", "HayatiConvention", "HayatiLink", "hayati_link"]


@dataclass(frozen=True, slots=True)
class HayatiLink(Params):
    """A Hayati link: ``Rz(theta) Tx(a) Rx(alpha) Ry(beta)``."""

    form: ClassVar[str] = "Hayati"

    theta: float = angle()
    a: float = length()
    alpha: float = angle()
    beta: float = angle()

    def frame(self) -> Frame:
        ct, st = math.cos(self.theta), math.sin(self.theta)
        ca, sa = math.cos(self.alpha), math.sin(self.alpha)
        cb, sb = math.cos(self.beta), math.sin(self.beta)
        # Rx(alpha) Ry(beta), then turned by Rz(theta) and moved by Tx(a) along the new x
        r = ((cb, 0.0, sb), (sa * sb, ca, -sa * cb), (-ca * sb, sa, ca * cb))
        return (
            (ct * r[0][0] - st * r[1][0], ct * r[0][1] - st * r[1][1],
             ct * r[0][2] - st * r[1][2], self.a * ct),
            (st * r[0][0] + ct * r[1][0], st * r[0][1] + ct * r[1][1],
             st * r[0][2] + ct * r[1][2], self.a * st),
            (r[2][0], r[2][1], r[2][2], 0.0),
        )  # fmt: skip


def hayati_link(u: Vec3, p: Vec3, lim: Limits) -> tuple[HayatiLink, float] | None:
    """The Hayati link from the local z axis to the line through ``p`` along unit ``u``, and the
    gap it closed: the new origin where the line crosses the local xy plane, turned onto ``u``
    by ``Rx(alpha) Ry(beta)``; ``None`` for a line parallel to that plane, which never crosses
    it. A crossing within ``lim.distance`` of the origin is taken as the origin (``a = 0``, the
    gap); there the x axis is free and is laid across ``u`` (``beta = 0``), as D-H lays it for
    lines that meet, or kept (``theta = 0``) where ``u`` is the z axis up to round-off."""
    ux, uy, uz = u
    if uz == 0.0:
        return None
    t = p[2] / uz
    x, y = p[0] - t * ux, p[1] - t * uy  # the crossing
    a = math.hypot(x, y)
    if a <= lim.distance:
        rho = math.hypot(ux, uy)
        if math.atan2(rho, abs(uz)) <= lim.clean:
            return HayatiLink(0.0, 0.0, 0.0 if uz > 0.0 else math.pi, 0.0), a
        return HayatiLink(frames.angle(ux, -uy), 0.0, frames.angle(rho, uz), 0.0), a
    theta = frames.angle(y, x)
    c, s = math.cos(theta), math.sin(theta)
    vx, vy = c * ux + s * uy, c * uy - s * ux  # u in the turned frame: Rz(-theta) u
    beta = math.asin(max(-1.0, min(1.0, vx)))
    alpha = frames.angle(-vy, uz)
    return HayatiLink(theta, a, alpha, beta), 0.0


def _shorter(u: Vec3, link: LinkParams, hayati: HayatiLink, lim: Limits) -> bool:
    """Whether the Hayati link is the shorter one by more than round-off.

    A D-H link that pivots (parallel or meeting lines) is known to ``lim.distance``; one on the
    common normal of lines ``alpha`` apart to ``lim.distance / sin(alpha)`` only (the ``d`` of
    intersecting axes is a few 1e-17 m of round-off on a mm chain), so the Hayati link must be
    shorter by that much; and where the lines are ``rho =
    sin(angle)`` from parallel, crossing the local xy plane at ``c``, the foot ``d = -c.e / rho``
    moves by ``|c| delta / rho^2`` for a round-off ``delta`` of ``u``: more than ``|c|`` itself
    where ``rho^2 <= lim.noise``, and which link is longer is round-off there, so the Hayati
    link, as well conditioned as the geometry, is taken. Either way the choice holds when the
    table is converted again."""
    rho = math.hypot(u[0], u[1])
    if link.parallel:  # a pivot's d and a, not a common normal's
        margin = lim.distance
    elif rho * rho <= lim.noise:
        return True
    else:
        margin = lim.distance / abs(math.sin(link.alpha))
    return hayati.a + margin < max(abs(link.d), abs(link.a))


class HayatiConvention:
    """The ``hayati`` convention."""

    name = "hayati"
    label = "Hayati (D-H and Hayati rows)"
    title = (
        "Hayati: B . prod[Q_i H_i] . Rz Tz, H = Rz(theta) Tz(d) Rx(alpha) Tx(a) (D-H) "
        "or Rz(theta) Tx(a) Rx(alpha) Ry(beta) (Hayati)"
    )
    formula = (
        "T(q) = B . prod_i [Rz(q_i) H_i] . T,  H = Rz(theta) Tz(d) Rx(alpha) Tx(a) or "
        "Rz(theta) Tx(a) Rx(alpha) Ry(beta)  (Hayati)"
    )
    base_types: tuple[type[Params], ...] = (DhLink, HayatiLink)
    row_types: tuple[type[Params], ...] = (DhLink, HayatiLink)
    tool_types: tuple[type[Params], ...] = (RzTz,)
    styles: tuple[str, ...] = ("wu",)
    guided = False

    def from_poe(self, model: PoeModel, tol: Tolerances, style: Style) -> Conversion:
        """Each line's link by the rule of the module docstring, in frames built from the
        parameters as they will be evaluated."""
        # no judgement beyond the exactness promised: every row exact
        limits = Limits.of(tol.with_exact(), model.size())
        limits = replace(limits, distance=min(limits.distance, limits.free))
        names = ["base z", *(line[0] for line in chain_lines(model))]
        frame = frames.IDENTITY
        records: list[Params] = []
        judgements: list[Judgement] = []
        for k, (_, axis, point, is_tool) in enumerate(chain_lines(model)):
            u = frames.unit(frames.dir_into(frame, axis))
            p = (0.0, 0.0, 0.0) if point is None else frames.point_into(frame, point)
            link, found = link_to_line(u, p, limits, (names[k], names[k + 1]), is_tool)
            record: Params = DhLink(link.theta, link.d, link.alpha, link.a)
            hayati = hayati_link(u, p, limits)
            judged = any(j.angle > limits.clean or j.gap > limits.free for j in found)
            if hayati is not None and (
                _shorter(u, link, hayati[0], limits) or (judged and hayati[1] == 0.0)
            ):
                record = hayati[0]
                if hayati[1] > 0.0:  # round-off only: the limits are exact
                    found = [Judgement("coincident", names[k], names[k + 1], 0.0, hayati[1])]
                else:
                    found = []
            judgements.extend(found)
            records.append(record)
            frame = frames.compose(frame, record.frame())
        g = frames.between(frame, frames.frame_of(model.home))  # the tool: Rz(theta) Tz(d)
        tool = RzTz(frames.angle(g[1][0], g[0][0]), g[2][3])
        return Conversion(records[0], tuple(records[1:]), tool, (1.0,) * model.n,
                          tuple(judgements))  # fmt: skip


HAYATI = HayatiConvention()
