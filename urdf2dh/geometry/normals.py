"""Lines in space: the common normal between a frame's z axis and the next joint axis.

This is the geometric core of Wu, Crawford & Roberts 2019, Lemmas 1-4: for a line (unit
direction ``u`` through point ``p``, both in the coordinates of a frame whose z axis is the
previous line), find ``H = Rz(theta) Tz(d) Rx(alpha) Tx(a)`` whose z axis is the line.

* Non-parallel (Lemma 1 case 2, eqs. 15-17): ``alpha = +-acos(u_z)`` with the sign chosen so that
  ``a >= 0``; ``d`` and ``a`` locate the common normal.
* Parallel (case 1): ``d = 0``; ``a`` is the distance between the lines.
* Tool z axis (Lemma 4, ``e^xi = H1 H2``): ``alpha`` in ``[0, pi]`` with ``a`` of either sign, and
  for a parallel tool axis the offset goes into ``d`` (the tool's own ``d`` is then 0), as in the
  paper's reference implementation; this is what reproduces Table II's last rows.

* Nearly parallel lines whose exact common normal lies far away meet the z axis at a pivot
  (``d = 0``, or the line's own point where that is on the z axis and the crossing is not: a
  joint's origin on the previous axis, its axis turned by a rounded angle), their direction
  kept, when they pass that close; otherwise they are treated as parallel.

The tolerance judgements (near-parallel treated as parallel, near-coincident as coincident,
round-off directions written as clean ones) are returned as :class:`Judgement` records so the
caller can report every one whose effect exceeds the exactness promised (``tol.report``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

from ..tolerances import Tolerances
from .frames import Vec3, angle, wrap_angle

__all__ = ["Judgement", "Limits", "LinkParams", "common_normal", "link_to_line"]


@dataclass(frozen=True, slots=True)
class Judgement:
    """One tolerance decision: which pair of lines, what was assumed, and how far off it was."""

    kind: Literal["parallel", "coincident"]
    first: str
    second: str
    angle: float  # radians the lines were from the assumed relation (0 if not angular)
    gap: float  # length the lines were from the assumed relation (0 if not a distance)
    source_angle: float | None = None  # the same angle between the lines in the source model
    pivot: float = 0.0  # distance from the base origin, at home, of the point the line turned on


@dataclass(frozen=True, slots=True)
class LinkParams:
    """``Rz(theta) Tz(d) Rx(alpha) Tx(a)``; ``parallel`` if the lines were (treated as)
    parallel, ``free`` if the new x axis was free (coincident lines) and ``theta = 0`` chosen."""

    theta: float
    d: float
    alpha: float
    a: float
    parallel: bool
    free: bool = False

    def turned(self) -> LinkParams:
        """The same frame turned by pi about its z: ``(theta + pi, d, -alpha, -a)``. Both are
        valid D-H links to the same line; conventions differ only in which they prefer."""
        alpha = math.pi if abs(self.alpha) == math.pi else -self.alpha + 0.0
        return LinkParams(
            wrap_angle(self.theta + math.pi),
            self.d,
            alpha,
            -self.a + 0.0,
            self.parallel,
            self.free,
        )


@dataclass(frozen=True, slots=True)
class Limits:
    """The thresholds of :func:`common_normal` for one robot, worked out once per conversion."""

    parallel: float  # treated as parallel within this angle (never below round-off)
    snap: float  # below this angle, parallel or meeting at the pivot is considered
    distance: float  # lines closer than this intersect
    far: float  # a common normal farther than this from the pivot is too far for D-H
    noise: float  # float round-off, as an angle
    sane: float  # beyond this |d| or |a| the lines are treated as parallel whatever the angle
    clean: float  # an angle within this of 0 or pi is written as that (tol.written)
    free: float  # a gap below this costs less than the exactness promised (tol.report x size)

    @classmethod
    def of(cls, tol: Tolerances, size: float) -> Limits:
        """The thresholds of ``tol`` for a robot of ``size``."""
        parallel = max(tol.parallel_angle, tol.noise)  # round-off is never geometry
        sane = tol.sane_factor * size if tol.sane_factor > 0.0 else math.inf
        return cls(
            parallel,
            max(parallel, tol.meet_angle),
            tol.distance(size),
            tol.far_factor * size,
            tol.noise,
            sane,
            tol.written,
            0.5 * tol.report * size,
        )


def _foot(u: Vec3, p: Vec3) -> float:
    """Where the exact common normal of the local z axis and a line (not parallel to it) meets
    the z axis: its ``d`` (Wu, eq. after (17))."""
    ux, uy, uz = u
    px, py, pz = p
    mx, my = py * uz - pz * uy, pz * ux - px * uz  # of the moment p x u
    return (ux * my - uy * mx) / (ux * ux + uy * uy)


def _far(u: Vec3, p: Vec3, pivot_d: float, far: float) -> bool:
    """Whether the exact common normal of nearly parallel lines lies farther than ``far``
    (``far_factor x size``) from the pivot: only then does D-H need the parallel judgement.
    (Lines tilted about their common perpendicular keep a near normal, and their exact table is
    sane.)"""
    return abs(_foot(u, p) - pivot_d) > far


def common_normal(
    u: Sequence[float],
    p: Sequence[float],
    tol: Tolerances,
    names: tuple[str, str],
    size: float,
    tool: bool = False,
) -> tuple[LinkParams, list[Judgement]]:
    """D-H parameters from the local z axis to the line through ``p`` along unit ``u``.

    ``tool=True`` applies the Lemma 4 rules for the tool's z axis (see module docstring).
    ``size`` is the robot's size, which scales the round-off floor of the distance tolerance.
    Returns the parameters and the tolerance judgements made (possibly none).
    """
    ux, uy, uz = (float(c) for c in u)
    px, py, pz = (float(c) for c in p)
    return link_to_line((ux, uy, uz), (px, py, pz), Limits.of(tol, size), names, tool)


def link_to_line(
    u: Vec3, p: Vec3, lim: Limits, names: tuple[str, str], tool: bool = False
) -> tuple[LinkParams, list[Judgement]]:
    """:func:`common_normal` of plain floats, with the thresholds worked out beforehand."""
    ux, uy, uz = u
    rho = math.hypot(ux, uy)
    off_parallel = math.atan2(rho, abs(uz))
    if rho == 0.0 or off_parallel <= lim.snap:
        # (Nearly) parallel. Pivot on the tool origin (the frame lands on it, the tool's own d
        # is 0), or on the line's crossing of the local xy plane (d = 0, Wu's parallel case),
        # or, where that crossing is off the z axis by more than the exactness promised and
        # the line's own point is not, on that point (a joint's origin on the previous axis,
        # its axis turned by a rounded angle: the lines meet there, not at d = 0).
        x, y, d = _pivot(u, p, tool)
        gap = math.hypot(x, y)
        if gap > lim.free and math.hypot(p[0], p[1]) <= lim.free:
            x, y, d = p
            gap = math.hypot(x, y)
        if gap <= lim.distance:
            # The lines meet at the pivot: a = 0 and the exact direction is kept, which is
            # exact however small the angle, where the common-normal formula is ill-conditioned.
            return _meet(u, d, gap, off_parallel, lim, names)
        if off_parallel <= lim.noise or (off_parallel <= lim.parallel and _far(u, p, d, lim.far)):
            return _parallel(u, (x, y, d), off_parallel, names)
    px, py, pz = p
    # the line's moment p x u; the same for any point p on the line
    mx, my, mz = py * uz - pz * uy, pz * ux - px * uz, px * uy - py * ux
    d = (ux * my - uy * mx) / (rho * rho) + 0.0  # Wu eq. after (17), h = 0 in the moment
    a_abs = abs(mz) / rho
    if max(abs(d), a_abs) > lim.sane and uz != 0.0:
        # exact, the table would reach kilometres away (d grows as offset / angle): treated as
        # parallel, with the deviation declared; D-H cannot be both exact and sane here
        return _parallel(u, _pivot(u, p, tool), off_parallel, names)
    if tool or a_abs <= lim.distance:
        # Tool (Lemma 4) or (nearly) intersecting lines: alpha > 0 and a keeps its exact,
        # possibly tiny negative, value. No judgement is needed: this is exact.
        sigma, a = 1.0, -mz / rho + 0.0
    else:  # Wu eq. (17): a sin(alpha) = -m_z; choose the sign of alpha that makes a >= 0
        sigma, a = (1.0, a_abs) if -mz > 0.0 else (-1.0, a_abs)
    alpha = angle(sigma * rho, uz)
    theta = angle(sigma * ux, -sigma * uy)  # Wu eq. (16)
    return LinkParams(theta, d, alpha, a, False), []


def _meet(
    u: Vec3, d: float, gap: float, off_parallel: float, lim: Limits, names: tuple[str, str]
) -> tuple[LinkParams, list[Judgement]]:
    """The link to a line taken to meet the local z axis at height ``d`` (``gap`` from it),
    its direction kept; within ``lim.clean`` of parallel it is made exactly parallel, a clean
    ``alpha`` of 0 or pi. Each departure from the line is a judgement."""
    ux, uy, uz = u
    judgements = [Judgement("coincident", *names, 0.0, gap)] if gap > 0.0 else []
    if off_parallel <= lim.clean:
        if off_parallel > 0.0:
            judgements.append(Judgement("parallel", *names, off_parallel, 0.0))
        return LinkParams(0.0, d, 0.0 if uz > 0.0 else math.pi, 0.0, True, True), judgements
    return LinkParams(angle(ux, -uy), d, angle(math.hypot(ux, uy), uz), 0.0, True), judgements


def _pivot(u: Vec3, p: Vec3, tool: bool) -> Vec3:
    """Where a frame treating the line as parallel lands: on the tool origin, or where the line
    crosses the local xy plane (``d = 0``)."""
    if tool:
        return p
    t = p[2] / u[2]
    return p[0] - t * u[0], p[1] - t * u[1], 0.0


def _parallel(
    u: Vec3, pivot: Vec3, off_parallel: float, names: tuple[str, str]
) -> tuple[LinkParams, list[Judgement]]:
    """The link to a line treated as parallel to the local z, through ``pivot``: ``alpha`` 0 or
    pi, ``a`` the distance, and the judgement (unless the angle is exactly 0)."""
    x, y, d = pivot
    judgements = [Judgement("parallel", *names, off_parallel, 0.0)] if off_parallel > 0.0 else []
    alpha = 0.0 if u[2] > 0.0 else math.pi
    return LinkParams(angle(y, x), d, alpha, math.hypot(x, y), True), judgements
