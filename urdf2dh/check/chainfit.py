"""One chain laid onto another: the joint directions, zero offsets and base and tool transforms
that make a table's forward kinematics equal a source's (docs/commands/match.md).

Two chains ``A`` (the table) and ``S`` (the source) describe the same robot when

    T_S(q) = B . T_A(sigma * scale * q + delta) . E   for every q,

with ``sigma_i = +-1`` (the table's joint ``i`` turns the same way or the other), ``delta_i``
its zero offset, and ``B``, ``E`` rigid transforms. The search is structured, not blind:

1. Each chain is a sequence of z-frames, one on each joint axis (:meth:`PoeModel.link_form`:
   ``T = G_0 Q_1 G_1 ... Q_n G_n``). Matching the chains means finding, on each source axis,
   where the table's frame sits: ``K_i^-1 B J_i(delta) = Rz(phi_i) Tz(t_i) F(sigma_i)``, a turn
   about and a slide along the axis, flipped by ``F(-1) = Rx(pi)``.
2. Link ``i`` (axis ``i`` to axis ``i + 1``) then reads ``Rz(psi) Tz(tau) G'_i = H_i Rz(phi')
   Tz(t')`` with ``G'_i = F_i G_i F_(i+1)``: two links that agree up to a screw about each end's
   axis. Both are split as D-H links (``Rz Tz Rx(alpha) Tx(a) Rz Tz``): they agree when their
   ``alpha`` and ``a`` do (the angle and distance between the axes), and then the screws follow
   in closed form: fixed for skew axes, a relation along the axis for parallel ones, a relation
   in both for coincident ones (:func:`link_equations`).
3. The directions ``sigma`` are searched link by link (a beam of the best partial chains), the
   angles follow link by link, and the slides of the whole chain are solved together by least
   squares (parallel axes leave a slide free until a later link fixes it).

The remaining freedoms are fixed as follows: a turn of the base about joint 1's axis is the
same as joint 1's offset, and a turn of the tool about the last axis the same as the last
joint's; those two offsets are 0 and the base and tool take the turns. The slide along a
prismatic joint is its offset likewise.

A prismatic joint's axis is a direction, not a line: links next to one compare angles only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ..geometry.frames import wrap_angle
from ..model.poe import PoeModel
from ..tolerances import DIFF_PARALLEL_DEG

__all__ = [
    "BEAM",
    "DISAGREEING",
    "Fit",
    "LinkEquation",
    "Mismatch",
    "Tolerance",
    "fit_lines",
    "link_equations",
]

Mat = NDArray[np.float64]

#: Partial chains kept at each link of the search (the best by mismatch).
BEAM = 128
#: Fits returned where no way of laying the chains agrees (the best by their links' mismatch).
DISAGREEING = 4
# A free slide is pulled towards 0 with this weight (against 1 for the links' equations), so
# that it is 0 where nothing fixes it and anything where something does.
_WEAK = 1e-6
# ... and a prismatic joint's offset with this one: where a slide of the base or tool along
# parallel axes is the same as the offset, the base or tool takes it.
_PREFER = 1e-3
_FLIP = np.diag([1.0, -1.0, -1.0, 1.0])  # Rx(pi)
# Axes this close to (anti-)parallel (rad) in a link where the chains disagree anyway are
# compared as parallel ones (where each crosses the plane normal to the first axis), not along
# their common normal: that normal runs off far away for nearly parallel axes (a calibrated
# robot's: d of hundreds of metres), and with it every angle the link equations give.
_NEAR_PARALLEL = math.radians(DIFF_PARALLEL_DEG)
# The refinement's finite-difference step (rad, and x robot size), and the RMS difference below
# which it stops (float64 forward kinematics is itself good to a few 1e-16).
_STEP = 1e-7
_ROUND_OFF = 1e-15


@dataclass(frozen=True, slots=True)
class Tolerance:
    """How far a link's angle (rad) and distance (source length unit) may differ and still
    agree: the precision the table is written to, with a floor of round-off."""

    angle: float
    length: float


@dataclass(frozen=True, slots=True)
class Mismatch:
    """A place where the chains disagree: link ``link`` (between joints ``link`` and
    ``link + 1``, 0-based) or joint ``link`` for an ``offset`` (the slide along its axis) or a
    ``turn`` (a prismatic joint's angle); the table's and the source's value."""

    link: int
    what: str  # "angle", "distance", "offset", "turn", "kind"
    table: float
    source: float

    @property
    def difference(self) -> float:
        d = self.table - self.source
        return abs(wrap_angle(d)) if self.what in ("angle", "turn") else abs(d)


@dataclass(frozen=True, slots=True)
class LinkEquation:
    """What link ``i`` says of the screws at its two ends (module docstring, step 2).

    ``kind`` is ``skew`` (``psi``, ``tau``, ``phi``, ``t`` each fixed), ``parallel`` (``psi``
    and ``phi`` fixed, ``t = eps tau + slide``), ``coincident`` (``phi = eps psi + turn``,
    ``t = eps tau + slide``); ``positions`` is False next to a prismatic joint (no slides).
    """

    kind: str
    psi: float
    tau: float
    phi: float
    t: float
    eps: float
    positions: bool
    alpha: tuple[float, float]  # table's, source's
    a: tuple[float, float]

    def mismatch(self, tol: Tolerance) -> float:
        """The disagreement in units of the tolerance (at most 1: they agree)."""
        angle = abs(wrap_angle(self.alpha[0] - self.alpha[1])) / tol.angle
        length = abs(self.a[0] - self.a[1]) / tol.length if self.positions else 0.0
        return max(angle, length)


@dataclass(frozen=True, slots=True)
class Fit:
    """One way of laying the table's chain onto the source's.

    ``signs`` and ``offsets``: the table's joint ``i`` is at ``signs_i * scale_i * q_i +
    offsets_i`` (``scale`` the source joint's); ``base`` ``B`` and ``tool`` ``E`` (4x4,
    source units); ``mismatches`` what disagrees beyond the tolerance; ``cost`` the total
    disagreement in units of the tolerance.
    """

    signs: tuple[int, ...]
    offsets: tuple[float, ...]
    base: Mat
    tool: Mat
    mismatches: tuple[Mismatch, ...] = ()
    cost: float = 0.0
    equations: tuple[LinkEquation, ...] = field(default=(), repr=False, compare=False)


def _rz_tz(theta: float, d: float) -> Mat:
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, 0.0, 0.0], [s, c, 0.0, 0.0], [0.0, 0.0, 1.0, d], [0, 0, 0, 1.0]])


def _dh(theta: float, d: float, alpha: float, a: float) -> Mat:
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st],
                     [0.0, sa, ca, d], [0.0, 0.0, 0.0, 1.0]])  # fmt: skip


def _remainder(x: Mat, theta: float, d: float, alpha: float, a: float) -> tuple[float, float]:
    """``(theta', d')`` with ``x = Rz(theta) Tz(d) Rx(alpha) Tx(a) Rz(theta') Tz(d')``."""
    y = np.linalg.solve(_dh(theta, d, alpha, a), x)
    return math.atan2(y[1, 0], y[0, 0]), float(y[2, 3])


def _off_parallel(u: Mat) -> float:
    return math.atan2(math.hypot(u[0], u[1]), abs(u[2]))


def _crossing(x: Mat) -> Mat:
    """Where the (nearly parallel) line of ``x``'s z axis crosses the plane z = 0."""
    u, p = x[:3, 2], x[:3, 3]
    out: Mat = p - (p[2] / u[2]) * u
    return out


def _skew_parts(x: Mat) -> list[tuple[float, float, float, float]]:
    """The two D-H links ``(theta, d, alpha, a)`` from the z axis to ``x``'s z axis (skew or
    intersecting lines): along the common normal one way and the other."""
    ux, uy, uz = (float(c) for c in x[:3, 2])
    px, py, pz = (float(c) for c in x[:3, 3])
    rho = math.hypot(ux, uy)
    if rho == 0.0:  # parallel to z (only where the other link is not: a mismatch anyway)
        return [(0.0, 0.0, math.atan2(0.0, uz), math.hypot(px, py))] * 2
    nx, ny = -uy / rho, ux / rho  # the common normal z x u
    mx, my = py * uz - pz * uy, pz * ux - px * uz  # the line's moment p x u
    d = (ux * my - uy * mx) / (rho * rho)
    a = px * nx + py * ny
    theta = math.atan2(ny, nx)
    alpha = math.atan2(rho, uz)
    return [(theta, d, alpha, a), (wrap_angle(theta + math.pi), d, -alpha, -a)]


def link_equations(g: Mat, h: Mat, tol: Tolerance, positions: bool = True) -> LinkEquation:
    """Link equations of the table's link ``g`` against the source's ``h`` (module docstring,
    step 2): both split as D-H links, the table's split chosen nearest the source's."""
    ug, uh = g[:3, 2], h[:3, 2]
    alpha_g = math.atan2(math.hypot(ug[0], ug[1]), ug[2])  # the angle between the axes
    alpha_h = math.atan2(math.hypot(uh[0], uh[1]), uh[2])
    off = max(_off_parallel(ug), _off_parallel(uh))
    if off <= tol.angle or (off <= _NEAR_PARALLEL and abs(alpha_g - alpha_h) > tol.angle):
        eps = math.copysign(1.0, uh[2])
        flip_g, flip_h = (0.0 if ug[2] > 0 else math.pi), (0.0 if eps > 0 else math.pi)
        cg, ch = _crossing(g), _crossing(h)
        ag, ah = math.hypot(cg[0], cg[1]), math.hypot(ch[0], ch[1])
        if not positions or min(ag, ah) <= tol.length:
            tg, dg = _remainder(g, 0.0, 0.0, flip_g, 0.0)
            th, dh = _remainder(h, 0.0, 0.0, flip_h, 0.0)
            return LinkEquation("coincident", 0.0, 0.0, wrap_angle(tg - th), dg - dh, eps,
                                positions, (alpha_g, alpha_h), (ag, ah))  # fmt: skip
        theta_g, theta_h = math.atan2(cg[1], cg[0]), math.atan2(ch[1], ch[0])
        tg, dg = _remainder(g, theta_g, 0.0, flip_g, ag)
        th, dh = _remainder(h, theta_h, 0.0, flip_h, ah)
        return LinkEquation("parallel", wrap_angle(theta_h - theta_g), 0.0,
                            wrap_angle(tg - th), dg - dh, eps, positions,
                            (alpha_g, alpha_h), (ag, ah))  # fmt: skip
    parts_g, parts_h = _skew_parts(g), _skew_parts(h)
    if positions:
        # the source's split with a >= 0 (alpha in (0, pi) for intersecting axes); the table's
        # of its two nearest that
        part_h = parts_h[1] if parts_h[0][3] < -tol.length else parts_h[0]

        def distance(p: tuple[float, float, float, float]) -> float:
            angle = abs(wrap_angle(p[2] - part_h[2])) / tol.angle
            return angle + abs(p[3] - part_h[3]) / tol.length

        part_g = min(parts_g, key=distance)
    else:  # directions only: the normal along z x u for both (alpha in (0, pi))
        part_g, part_h = parts_g[0], parts_h[0]
    t2g, d2g = _remainder(g, *part_g)
    t2h, d2h = _remainder(h, *part_h)
    return LinkEquation("skew", wrap_angle(part_h[0] - part_g[0]), part_h[1] - part_g[1],
                        wrap_angle(t2g - t2h), d2g - d2h, 1.0, positions,
                        (part_g[2], part_h[2]), (part_g[3], part_h[3]))  # fmt: skip


def _level(cost: float) -> float:
    """A disagreement to 9 significant digits: costs equal but for round-off (a flipped joint
    whose links' angles and distances are the same, as a right angle's are) tie, and the
    fewer flips win."""
    return float(f"{cost:.9g}")


@dataclass(frozen=True, slots=True)
class _Partial:
    signs: tuple[int, ...]
    equations: tuple[LinkEquation, ...]
    cost: float


def fit_lines(table: PoeModel, source: PoeModel, tol: Tolerance, beam: int = BEAM) -> list[Fit]:
    """The ways of laying ``table`` onto ``source`` (same number of joints), best first: every
    one whose links all agree within ``tol``, or else the :data:`DISAGREEING` best found (by
    their links' disagreement: directions that differ little there, as near-parallel axes'
    do, are told apart by the refinement's residual).

    Each :class:`Fit` holds directions, offsets, base and tool solved in closed form and by
    linear least squares from the link equations (the module docstring); it is exact where
    the chains agree exactly, and a starting point for a refinement where they agree within
    the tolerance.
    """
    n = source.n
    if table.n != n:
        raise ValueError(f"fit_lines: the table has {table.n} joints, the source {n}")
    ga, _ = table.link_form()
    gs, _ = source.link_form()
    prismatic = [j.kind == "prismatic" for j in source.joints]
    flips = {1: np.eye(4), -1: _FLIP}
    partials = [_Partial((s,), (), 0.0) for s in (1, -1)]
    for i in range(1, n):
        grown = []
        for p in partials:
            for s in (1, -1):
                g = flips[p.signs[-1]] @ ga[i] @ flips[s]
                eq = link_equations(g, gs[i], tol, not (prismatic[i - 1] or prismatic[i]))
                cost = p.cost + max(eq.mismatch(tol) - 1.0, 0.0)
                grown.append(_Partial((*p.signs, s), (*p.equations, eq), cost))
        grown.sort(key=lambda p: (_level(p.cost), sum(s < 0 for s in p.signs)))
        partials = grown[:beam]
    agreeing = [p for p in partials if p.cost == 0.0] or partials[:DISAGREEING]
    fits = [_solve(p, ga, gs, source, tol, flips) for p in agreeing]
    fits.sort(key=lambda f: (_level(f.cost), sum(s < 0 for s in f.signs)))
    return [f for f in fits if f.cost == 0.0] or fits


def _solve(
    p: _Partial, ga: Mat, gs: Mat, source: PoeModel, tol: Tolerance, flips: dict[int, Mat]
) -> Fit:
    """Angles link by link, slides by least squares, then the offsets, base and tool."""
    n = len(p.signs)
    prismatic = [j.kind == "prismatic" for j in source.joints]
    mismatches = [
        m
        for i, eq in enumerate(p.equations)
        for m in _link_mismatches(i, eq, tol)
    ]  # fmt: skip
    # angles: phi (where the table's frame sits on axis i, arriving) and psi (leaving)
    phi = [0.0] * n
    psi = [0.0] * n
    for i in range(n):
        eq = p.equations[i] if i < n - 1 else None
        pinned = eq is not None and eq.kind in ("skew", "parallel")
        if i == 0:
            psi[0] = eq.psi if pinned and eq is not None else 0.0
            phi[0] = psi[0]  # joint 1's offset is 0: the base takes the turn
        elif pinned and eq is not None:
            psi[i] = eq.psi
            if prismatic[i] and abs(wrap_angle(psi[i] - phi[i])) > tol.angle:
                mismatches.append(Mismatch(i, "turn", psi[i], phi[i]))
        else:
            psi[i] = phi[i]  # nothing fixes it: offset 0
        if eq is not None:
            phi[i + 1] = eq.phi if pinned else wrap_angle(eq.eps * psi[i] + eq.phi)
    slides, slide_mismatches = _slides(p.equations, prismatic, tol)
    mismatches += slide_mismatches
    t, tau = slides
    signs = p.signs
    offsets = []
    for i in range(n):
        if prismatic[i]:
            offsets.append(signs[i] * (tau[i] - t[i]))
        else:
            offsets.append(signs[i] * wrap_angle(psi[i] - phi[i]))
    base = gs[0] @ _rz_tz(phi[0], t[0]) @ flips[signs[0]] @ np.linalg.inv(ga[0])
    last = _rz_tz(psi[-1], tau[-1]) @ flips[signs[-1]] @ ga[n]
    tool = np.linalg.solve(last, gs[n])
    base[3], tool[3] = (0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 1.0)
    cost = p.cost + sum(m.difference / (tol.length if m.what == "offset" else tol.angle) - 1.0
                        for m in slide_mismatches)  # fmt: skip
    return Fit(signs, tuple(offsets), base, tool, tuple(mismatches), cost, p.equations)


def _link_mismatches(i: int, eq: LinkEquation, tol: Tolerance) -> list[Mismatch]:
    out = []
    if abs(wrap_angle(eq.alpha[0] - eq.alpha[1])) > tol.angle:
        out.append(Mismatch(i, "angle", *eq.alpha))
    if eq.positions and abs(eq.a[0] - eq.a[1]) > tol.length:
        out.append(Mismatch(i, "distance", *eq.a))
    return out


def _slides(
    equations: tuple[LinkEquation, ...], prismatic: list[bool], tol: Tolerance
) -> tuple[tuple[list[float], list[float]], list[Mismatch]]:
    """Each joint's slide arriving (``t``) and leaving (``tau``), by least squares over the
    links' equations (one slide per revolute joint; a prismatic joint's two differ by its
    offset), and the joints where the links' equations disagree."""
    n = len(prismatic)
    index: list[tuple[int, int]] = []  # (arriving, leaving) variable of each joint
    count = 0
    for i in range(n):
        if prismatic[i]:
            index.append((count, count + 1))
            count += 2
        else:
            index.append((count, count))
            count += 1
    rows: list[tuple[dict[int, float], float, float, int]] = []  # coefficients, rhs, weight, joint
    for i, eq in enumerate(equations):
        if not eq.positions:
            continue
        leave, arrive = index[i][1], index[i + 1][0]
        if eq.kind == "skew":
            rows.append(({leave: 1.0}, eq.tau, 1.0, i))
            rows.append(({arrive: 1.0}, eq.t, 1.0, i + 1))
        else:
            coefficients = {arrive: 1.0}
            coefficients[leave] = coefficients.get(leave, 0.0) - eq.eps
            rows.append((coefficients, eq.t, 1.0, i + 1))
    for i in range(n):
        arrive, leave = index[i]
        if arrive != leave:  # a prismatic joint: offset 0 at the ends, else preferably 0
            weight = 1.0 if i in (0, n - 1) else _PREFER
            rows.append(({leave: 1.0, arrive: -1.0}, 0.0, weight, -1))
    for v in range(count):
        rows.append(({v: 1.0}, 0.0, _WEAK, -1))
    a = np.zeros((len(rows), count))
    b = np.zeros(len(rows))
    for r, (coefficients, rhs, weight, _) in enumerate(rows):
        for v, c in coefficients.items():
            a[r, v] = weight * c
        b[r] = weight * rhs
    x = np.linalg.lstsq(a, b, rcond=None)[0]
    residual = a @ x - b
    mismatches = []
    for r, (_, _, weight, joint) in enumerate(rows):
        if weight == 1.0 and joint >= 0 and abs(residual[r]) > tol.length:
            mismatches.append(Mismatch(joint, "offset", float(residual[r]), 0.0))
    t = [float(x[index[i][0]]) for i in range(n)]
    tau = [float(x[index[i][1]]) for i in range(n)]
    return (t, tau), mismatches


def positions(fit: Fit, source: PoeModel, q: Mat) -> Mat:
    """The table's joint positions ``(N, n)`` at the source's configurations ``q``: ``signs *
    scale * q + offsets``."""
    scales = np.array([j.scale for j in source.joints])
    out: Mat = np.asarray(q) * (np.array(fit.signs) * scales) + np.array(fit.offsets)
    return out


def poses(fit: Fit, table: PoeModel, source: PoeModel, q: Mat) -> Mat:
    """``B . T_A(positions) . E`` ``(N, 4, 4)``: the table's poses at the source's ``q``."""
    out: Mat = fit.base @ table.fk_batch(positions(fit, source, q)) @ fit.tool
    return out


def _errors(a: Mat, b: Mat, size: float) -> Mat:
    """Stacked position (over ``size``) and rotation differences of two pose stacks."""
    position = (a[:, :3, 3] - b[:, :3, 3]) / size
    m = np.einsum("nji,njk->nik", b[:, :3, :3], a[:, :3, :3])
    rotation = 0.5 * np.stack([m[:, 2, 1] - m[:, 1, 2], m[:, 0, 2] - m[:, 2, 0],
                               m[:, 1, 0] - m[:, 0, 1]], axis=1)  # fmt: skip
    out: Mat = np.concatenate([position.ravel(), rotation.ravel()])
    return out


def place(table: PoeModel, source: PoeModel, fit: Fit, q: Mat) -> Fit:
    """``fit`` with the base's and tool's translations and the prismatic joints' directions
    and offsets solved by linear least squares over the positions at configurations ``q``, its
    rotations and revolute offsets kept. With those fixed, a position is affine in the sliding
    joints' positions, and so linear in the translations, in each sliding joint's gain on the
    source's ``q`` (its direction: the sign) and in its offset. The link equations leave these
    loose: a prismatic joint's axis is a direction, not a line, and turning it round changes no
    angle."""
    sliding = [i for i, j in enumerate(source.joints) if j.kind == "prismatic"]
    target = source.fk_batch(q)[:, :3, 3]
    at = positions(fit, source, q)
    at[:, sliding] = 0.0
    still = table.fk_batch(at)
    rb = fit.base[:3, :3]
    columns = [np.broadcast_to(np.eye(3), (len(q), 3, 3)), rb @ still[:, :3, :3]]
    for i in sliding:  # each sliding joint's direction at these configurations
        moved = at.copy()
        moved[:, i] = 1.0
        v = (rb @ (table.fk_batch(moved)[:, :3, 3] - still[:, :3, 3]).T).T
        drive = source.joints[i].scale * q[:, i]
        columns += [(v * drive[:, None])[..., None], v[..., None]]
    a = np.concatenate(columns, axis=2).reshape(-1, 6 + 2 * len(sliding))
    b = (target - (rb @ still[:, :3, 3].T).T).ravel()
    x = np.linalg.lstsq(a, b, rcond=None)[0]
    base, tool = fit.base.copy(), fit.tool.copy()
    base[:3, 3], tool[:3, 3] = x[:3], x[3:6]
    signs, offsets = list(fit.signs), list(fit.offsets)
    for k, i in enumerate(sliding):
        signs[i] = 1 if x[6 + 2 * k] >= 0.0 else -1
        offsets[i] = float(x[7 + 2 * k])
    return Fit(tuple(signs), tuple(offsets), base, tool, fit.mismatches, fit.cost, fit.equations)


def refine(
    table: PoeModel,
    source: PoeModel,
    fit: Fit,
    q: Mat,
    held: frozenset[int] = frozenset(),
    iterations: int = 40,
) -> Fit:
    """``fit`` with its base, tool and offsets moved to the least squares of the pose
    differences at configurations ``q`` (Levenberg-Marquardt; joint 1's and the last joint's
    offsets stay 0, the base and tool take them, and so do the joints in ``held``): where the
    chains agree only to the table's written precision, the closed-form fit of one link's
    equations is not the best fit of all."""
    from ..geometry.se3 import twist_exp

    n, size = len(fit.signs), source.size()
    target = source.fk_batch(q)
    free = [i for i in range(1, n - 1) if i not in held]

    def moved(x: Mat) -> Fit:
        offsets = np.array(fit.offsets)
        offsets[free] += x[12:]
        base = twist_exp(x[:6]) @ fit.base
        tool = fit.tool @ twist_exp(x[6:12])
        return Fit(fit.signs, tuple(offsets.tolist()), base, tool, fit.mismatches, fit.cost,
                   fit.equations)  # fmt: skip

    def residual(x: Mat) -> Mat:
        return _errors(poses(moved(x), table, source, q), target, size)

    x = np.zeros(12 + len(free))
    r = residual(x)
    cost, damping = float(r @ r), 1e-3
    floor = r.size * _ROUND_OFF**2  # below this, steps only chase round-off
    for _ in range(iterations):
        if cost <= floor:
            break
        jac = np.empty((r.size, x.size))
        for k in range(x.size):
            e = np.zeros(x.size)
            e[k] = _STEP
            jac[:, k] = (residual(x + e) - r) / _STEP
        normal = jac.T @ jac
        gradient = jac.T @ r
        while damping < 1e12:
            dx = np.linalg.solve(normal + damping * np.diag(np.diag(normal) + 1e-30), -gradient)
            trial = residual(x + dx)
            trial_cost = float(trial @ trial)
            if trial_cost < cost:
                break
            damping *= 5.0
        else:
            break  # no step lowers the cost: a minimum
        gain = cost - trial_cost
        x, r, cost, damping = x + dx, trial, trial_cost, max(damping / 3.0, 1e-12)
        if gain <= 1e-12 * (cost + gain):
            break
    return moved(x)
