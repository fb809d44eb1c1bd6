"""Planning the measurements: configurations that make the parameters of a level identifiable.

Each candidate configuration (drawn uniformly within the joint limits, seeded, or read from a
file) contributes the rows of the level's Jacobian at the nominal model (:mod:`.residuals`):
what its measurement would tell about each parameter, weighted by the noise levels. The
configurations are chosen one at a time to maximise the determinant of the information matrix
``J^T J`` (D-optimal design, greedily: Fedorov 1972, *Theory of Optimal Experiments*; the
observability indices of Sun & Hollerbach 2008 rank designs alike), which minimises the volume of
the parameters' confidence ellipsoid. With ``A`` the information so far, a candidate's rows
``J_c`` raise ``log det A`` by ``log det(I + J_c A^-1 J_c^T)``. Beyond a small plan each step
weighs a seeded draw of the candidates left (stochastic greedy, :func:`_greedy`), so that the
time grows linearly with the configurations asked for (and the candidates, 20 per
configuration). ``A`` starts as a small multiple of the identity (columns scaled to unit norm
over the candidates) so that the first choices, fewer than the parameters, are ranked too.

Fewer configurations than give one equation per parameter (6 per pose, 3 per marker) are
refused, naming the least; so are configurations that leave parameters undetermined, naming how
many the greedy choice needs to determine them all (:func:`minimum`).

The expected standard deviation of each parameter at the given noise is
``sqrt(diag((J^T J)^-1))`` over the chosen configurations (the linearised Gauss-Markov
covariance at the nominal; the measurements' own will differ as the robot differs from it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ..checks import check_configurations, check_count, check_instance, check_real, check_seed
from ..errors import InputError, shown
from ..escape import markdown_table, markdown_text
from ..model.poe import PoeModel
from ..tolerances import MAX_MARKERS
from .chart import Estimate, names
from .identifiable import redundant
from .levels import FULL, LEVELS, check_level
from .measure import marker_layout
from .residuals import evaluate, observed
from .solver import one_thread

__all__ = [
    "DEFAULT_NOISE_POS_M",
    "DEFAULT_NOISE_ROT",
    "MAX_CANDIDATES",
    "MAX_CONFIGURATIONS",
    "SAMPLED",
    "WHOLE",
    "Plan",
    "minimum",
    "plan",
]

Mat = NDArray[np.float64]

DEFAULT_NOISE_POS_M = 1e-4  # m: a laser tracker or a good camera, per coordinate
DEFAULT_NOISE_ROT = 1e-4  # rad
CANDIDATES_PER_CONFIGURATION = 20  # random candidates drawn per configuration chosen
MAX_CANDIDATES = 20_000  # candidates drawn, or read from a file, at most
MAX_CONFIGURATIONS = 10_000  # configurations planned at most (a few hundred identify a robot)
SAMPLED = 100  # candidates weighed at each step of the greedy choice, at least
_SHORTFALL = 0.01  # ... and candidates / configurations x ln(1 / this) (Mirzasoleiman 2015)
WHOLE = 200_000  # every candidate weighed at every step up to this many weighings (~1 s)
_RIDGE = 1e-6  # the information's start, x the identity (unit columns)


@dataclass(frozen=True)
class Plan:
    """Configurations to measure, and the parameter uncertainty they promise.

    Attributes
    ----------
    model
        The nominal's name.
    level
        The level planned for.
    pose
        Pose measurements (else positions of markers).
    markers
        Markers per configuration (position measurements).
    joints
        The joints' names (the columns of ``configurations``).
    configurations
        ``(N, n)`` the chosen configurations, in the order chosen.
    candidates
        How many candidates they were chosen from.
    noise_pos, noise_rot
        The noise levels of the expected uncertainty (length unit, rad).
    parameters
        The level's identified parameters.
    std
        ``(p,)`` their expected standard deviations (``inf``: not determined).
    random_std
        ``(p,)`` the same for as many random candidates (seeded), for comparison.
    length_unit
        The nominal's length unit.
    """

    model: str
    level: str
    pose: bool
    markers: int | None
    joints: tuple[str, ...]
    configurations: Mat
    candidates: int
    noise_pos: float
    noise_rot: float
    parameters: tuple[str, ...]
    std: Mat
    random_std: Mat
    length_unit: str

    def _repr_markdown_(self) -> str:
        """In a notebook: each parameter's expected standard deviation, planned and random, as
        a table (names escaped)."""
        kind = "poses" if self.pose else f"positions of {self.markers or 1} marker(s)"
        out = [
            f"**{markdown_text(self.model)}**: {len(self.configurations)} configurations for "
            f"{self.level} ({len(self.parameters)} parameters) chosen from {self.candidates} "
            f"candidates, measuring {kind}; noise {self.noise_pos:.3g} "
            f"{markdown_text(self.length_unit)}, {self.noise_rot:.3g} rad",
            "",
        ]
        rows = [
            [markdown_text(n), f"{s:.3g}", f"{r:.3g}"]
            for n, s, r in zip(self.parameters, self.std, self.random_std, strict=True)
        ]
        out += markdown_table(["parameter", "expected std", "random configurations"], rows)
        return "\n".join(out) + "\n"

    def __str__(self) -> str:
        """What ``urdf2dh plan`` prints."""
        return self.summary()

    def __repr__(self) -> str:
        return (
            f"<Plan {shown(self.model)}: {len(self.configurations)} configurations for "
            f"{self.level}, {len(self.parameters)} parameters>"
        )

    def summary(self) -> str:
        """What ``urdf2dh plan`` prints."""
        kind = "poses" if self.pose else f"positions of {self.markers or 1} marker(s)"
        unit = self.length_unit
        out = [
            f"plan for {self.model} ({self.level}, {len(self.parameters)} parameters): "
            f"{len(self.configurations)} configurations chosen from {self.candidates} "
            f"candidates, measuring {kind}",
            f"expected standard deviations at noise {self.noise_pos:.3g} {unit}"
            + (f" and {self.noise_rot:.3g} rad" if self.pose else "")
            + " per coordinate:",
        ]
        finite = np.isfinite(self.std)
        if not finite.all():
            lost = [n for n, f in zip(self.parameters, finite, strict=True) if not f]
            out.append(f"  not determined by these configurations: {', '.join(lost)}")
        for what, suffix in (("turn", "rad"), ("shift", unit), ("scale", "1"), ("offset", "")):
            picked = [
                (n, s)
                for n, s, r in zip(self.parameters, self.std, self.random_std, strict=True)
                if what in n.rsplit(".", 1)[1] and math.isfinite(s)
            ]
            if not picked:
                continue
            worst = max(picked, key=lambda x: x[1])
            shown_unit = suffix or ("rad or " + unit)
            out.append(
                f"  {what}s: largest {worst[1]:.3g} {shown_unit} ({worst[0]}), median "
                f"{float(np.median([s for _, s in picked])):.3g}"
            )
        ratio = _geometric_mean_ratio(self.std, self.random_std)
        if ratio is not None:
            out.append(
                f"  {ratio:.2g} times the deviations of as many random configurations "
                "(geometric mean)"
            )
        return "\n".join(out) + "\n"


def _geometric_mean_ratio(a: Mat, b: Mat) -> float | None:
    keep = np.isfinite(a) & np.isfinite(b) & (a > 0) & (b > 0)
    if not keep.any():
        return None
    return float(np.exp(np.mean(np.log(a[keep] / b[keep]))))


def _estimate(model: PoeModel, level: str, pose: bool, markers: int | None, seed: int) -> Estimate:
    """The nominal at ``level``, in its own base frame, with its free coordinates."""
    home, level_of = model.home.copy(), LEVELS[level]
    if pose:
        est = Estimate.of(model.joints, home, level=level_of)
    else:
        layout = marker_layout(model, markers, seed) if markers else {0: np.zeros(3)}
        local = np.array([layout[k] for k in sorted(layout)])
        est = Estimate.of(model.joints, home, local, level=level_of)
    carried = redundant(est, model.limits(), model.size())
    return replace(est, free=~carried)


def _rows(est: Estimate, q: Mat, sp: float, sr: float) -> Mat:
    """``(C, r, p)`` each candidate's weighted Jacobian rows (3 per marker, or 6 per pose)."""
    data = observed(est, q)
    _, jac = evaluate(est, data, sp, sr)
    return jac.reshape(len(q), len(est.markers) * data.rows, -1)


def _std(rows: Mat) -> Mat:
    """Expected standard deviations from the weighted rows ``(N, r, p)``."""
    flat = rows.reshape(-1, rows.shape[2])
    info = flat.T @ flat
    try:
        cov = np.linalg.inv(info)
        out: Mat = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    except np.linalg.LinAlgError:
        return np.full(rows.shape[2], math.inf)
    s = np.linalg.svd(flat, compute_uv=False)
    if len(s) < rows.shape[2] or s[-1] <= 1e-10 * s[0]:
        return np.full(rows.shape[2], math.inf)
    return out


def _gains(scaled: Mat, chol: Mat, which: NDArray[np.int64]) -> Mat:
    """``log det(I + J_c A^-1 J_c^T)`` of the candidates ``which`` (``A = L L^T``)."""
    from scipy.linalg import solve_triangular

    block = scaled[which]  # (k, r, p)
    k, r, p = block.shape
    half = solve_triangular(chol, block.reshape(k * r, p).T, lower=True)  # L^-1 J^T: (p, k r)
    half = half.T.reshape(k, r, p)
    inner = np.eye(r) + np.einsum("krp,ksp->krs", half, half)
    gains: Mat = np.linalg.slogdet(inner)[1]
    return gains


def _greedy(rows: Mat, count: int, seed: int = 0) -> list[int]:
    """D-optimal greedy choice of ``count`` candidates (module docstring), each step among a
    sample of the candidates left, drawn with ``numpy.random.default_rng((seed, 10))``: of
    ``candidates / count x ln 100`` of them (at least :data:`SAMPLED`), with which the
    "stochastic greedy" choice keeps the greedy choice's guarantee for a submodular gain such as
    ``log det`` to within 1% (Mirzasoleiman et al. 2015, "Lazier than lazy greedy"); its time
    grows with the candidates, not with the candidates times ``count``. Up to :data:`WHOLE`
    weighings in all, every candidate is weighed at every step (the greedy choice itself)."""
    norms = np.linalg.norm(rows.reshape(-1, rows.shape[2]), axis=0)
    norms[norms == 0.0] = 1.0
    scaled = rows / norms
    p = scaled.shape[2]
    info = _RIDGE * np.eye(p)
    rng = np.random.default_rng((seed, 10))
    available = np.ones(len(scaled), dtype=bool)
    chosen: list[int] = []
    sample = max(SAMPLED, math.ceil(len(scaled) / max(count, 1) * math.log(1.0 / _SHORTFALL)))
    if len(scaled) * count <= WHOLE:  # few: weigh every candidate at every step
        sample = len(scaled)
    for _ in range(count):
        left = np.flatnonzero(available)
        if len(left) > sample:
            left = np.sort(rng.choice(left, sample, replace=False))
        gains = _gains(scaled, np.asarray(np.linalg.cholesky(info), dtype=np.float64), left)
        best = int(left[np.argmax(gains)])
        chosen.append(best)
        available[best] = False
        info = info + scaled[best].T @ scaled[best]
    return chosen


def _too_few(
    seed: int,
    name: str,
    level: str,
    configs: int,
    rows: Mat,
    kind: str,
    parameters: tuple[str, ...],
) -> None:
    """Refuse ``configs`` configurations that leave parameters undetermined, naming how many
    the greedy choice needs to determine them all (or the parameters no candidate
    determines)."""
    more = _greedy(rows, min(len(rows), max(3 * configs, configs + 20)), seed)
    for k in range(configs + 1, len(more) + 1):
        if np.all(np.isfinite(_std(rows[more[:k]]))):
            raise InputError(
                f"{name}: {configs} configurations of {kind} leave some of the {level} level's "
                f"parameters undetermined; {k} determine them all: plan at least {k}"
            )
    lost = [n for n, s in zip(parameters, _std(rows[more]), strict=True) if not math.isfinite(s)]
    raise InputError(
        f"{name}: no configurations among the candidates determine {', '.join(lost[:6])}"
        + (f" ... ({len(lost)} in all)" if len(lost) > 6 else "")
        + f" at the {level} level: plan for a lower level, or give other candidates"
    )


def minimum(model: PoeModel, level: str, pose: bool, markers: int | None) -> tuple[int, int]:
    """The parameters ``level`` identifies and the configurations that give as many equations
    (each measures 6 for a pose, 3 per marker): fewer cannot determine them."""
    est = _estimate(model, level, pose, markers, 0)
    p = len(names(est))
    rows = 6 if pose and not markers else 3 * (markers or 1)
    return p, math.ceil(p / rows)


def plan(
    model: PoeModel,
    configs: int,
    level: str = FULL.name,
    pose: bool = True,
    markers: int | None = None,
    candidates: Mat | None = None,
    noise_pos: float | None = None,
    noise_rot: float | None = None,
    seed: int = 0,
) -> Plan:
    """Choose ``configs`` configurations that make ``level``'s parameters best identifiable
    (module docstring).

    Parameters
    ----------
    model
        The nominal model.
    configs
        How many configurations to choose.
    level
        The level planned for (:data:`.levels.LEVELS`).
    pose, markers
        Pose measurements, or positions of ``markers`` markers at seeded points of the tool (as
        ``urdf2dh measure --markers`` places them) or of the tool origin.
    candidates
        ``(C, n)`` configurations to choose among (default: drawn within the joint limits).
    noise_pos, noise_rot
        Noise levels of the expected uncertainty (default 0.1 mm in the model's unit, 1e-4 rad).
    seed
        Seeds the candidates, the random comparison and the markers.

    Returns
    -------
    Plan
        The chosen configurations ``(configs, n)`` and each parameter's expected standard
        deviation, beside that of as many random configurations.

    Raises
    ------
    TypeError, ValueError
        A wrong argument (an unknown level is a ``UsageError``).
    InputError
        More configurations asked than there are candidates, more candidates than
        :data:`MAX_CANDIDATES`, or too few configurations to determine the level's parameters
        (the message names how many would).
    """
    from .. import units

    check_instance(model, PoeModel, "plan: model", "urdf2dh.load(SOURCE) reads one")
    check_count(configs, "plan: configs", 1, MAX_CONFIGURATIONS)
    check_instance(level, str, "plan: level")
    check_level(level, "plan")
    if candidates is not None:
        n = model.dof
        candidates = check_configurations(candidates, n, "plan: candidates", True)
    for value, where in ((noise_pos, "plan: noise_pos"), (noise_rot, "plan: noise_rot")):
        if value is not None and check_real(value, where) <= 0.0:
            raise ValueError(f"{where} must be positive, not {value}")
    check_seed(seed, "plan: seed")
    if markers is not None:
        check_count(markers, "plan: markers", 1, MAX_MARKERS)
    pose = pose and not markers
    sp = (
        noise_pos
        if noise_pos is not None
        else DEFAULT_NOISE_POS_M / units.metres_per(model.length_unit)
    )
    sr = noise_rot if noise_rot is not None else DEFAULT_NOISE_ROT
    parameters, least = minimum(model, level, pose, markers)
    kind = "poses" if pose else "positions"
    if configs < least:
        raise InputError(
            f"{model.name}: the {level} level has {parameters} parameters, and {configs} "
            f"configuration{'s' if configs > 1 else ''} of {kind} give fewer equations: plan "
            f"at least {least}"
        )
    if candidates is None:
        count = min(max(CANDIDATES_PER_CONFIGURATION * configs, 500), MAX_CANDIDATES)
        candidates = model.sample(max(count, configs), (seed, 7))
    if len(candidates) > MAX_CANDIDATES:
        raise InputError(
            f"{len(candidates)} candidates, more than the {MAX_CANDIDATES} plan chooses among"
        )
    if configs > len(candidates):
        raise InputError(f"{configs} configurations asked for, from {len(candidates)} candidates")
    with one_thread():
        est = _estimate(model, level, pose, markers, seed)
        rows = _rows(est, candidates, sp, sr)
        chosen = _greedy(rows, configs, seed)
        random = np.random.default_rng((seed, 8)).choice(len(candidates), configs, replace=False)
        std, random_std = _std(rows[chosen]), _std(rows[random])
        if not np.all(np.isfinite(std)):
            _too_few(seed, model.name, level, configs, rows, kind, tuple(names(est)))
    return Plan(
        model.name,
        level,
        pose,
        markers,
        tuple(j.name for j in model.joints),
        candidates[chosen],
        len(candidates),
        sp,
        sr,
        tuple(names(est)),
        std,
        random_std,
        model.length_unit,
    )
