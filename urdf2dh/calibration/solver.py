"""Levenberg-Marquardt on the chart of :mod:`.chart`, and the statistics of its solution.

Each iteration linearises the weighted residuals ``r`` at the current estimate (coordinates
``0`` of the chart centred there), scales the Jacobian's columns to unit norm
(``J_s = J D^-1``; lengths and angles then weigh alike), and takes the damped Gauss-Newton step

    ``(J_s^T J_s + lambda I) d_s = -J_s^T r``,  ``d = D^-1 d_s``

from the small ``p x p`` system (a step's precision only sets how fast the iteration
converges, not where to). A step that lowers
``|r|^2`` is kept and the chart re-centred on the new estimate (:func:`.chart.retract`), and
``lambda`` adapts by the gain ratio (Nielsen 1999; Madsen, Nielsen & Tingleff 2004, "Methods for
non-linear least squares problems", §3.2). Each step carries its geodesic acceleration
(Transtrum & Sethna 2012, "Improvements to the Levenberg-Marquardt algorithm for nonlinear
least-squares minimization", §3): the residuals' second derivative along the step ``v``, by a
finite difference at ``0.1 v``, solved through the same damped system, half of it added; a step
whose acceleration exceeds 0.75 of its size is refused as one that raised the cost. In the long
curved valleys of parameters the data barely see it turns hundreds of creeping iterations into
tens. It stops when the next step would move no modelled
tool point by more than ``CALIBRATION_STEP`` x size and no orientation by more than
``CALIBRATION_STEP`` rad, when it is predicted to lower ``|r|^2`` by no more than
``CALIBRATION_COST`` of it, or when the gradient vanishes (:mod:`urdf2dh.tolerances`). With a
prior (:mod:`.prior`) its rows join the measurements' (a :class:`Problem`).

The model is evaluated once per step tried, with the weights left out: its residuals (and the
prior's deviations) first, for the cost; the Jacobian (and the prior's tangent) from the same
frames only when the step is kept (a :class:`Linearisation`), which brings the next iteration's
Jacobian with it (beyond one chunk of measurements, :data:`.residuals.CHUNK`, the Jacobian is
made with the residuals). The solution's linearisation is what its statistics, the noise levels
and the prior's deviations of greatest evidence (:mod:`.evidence`), and the configurations left
out (:mod:`.select`) are computed from, under any weights, without evaluating the model again.
Products with the tall Jacobian go through BLAS on one thread (:func:`one_thread`: on a shared
two-core machine, OpenBLAS's threads waking for small matrices made the whole solve four to ten
times slower).

Statistics (Gauss-Markov, linearised at the solution): with ``m`` residuals and ``p``
coordinates, the variance factor ``s^2 = |r|^2 / (m - p)`` (about 1 when the noise levels used
as weights are right), the covariance ``s^2 (J^T J)^-1`` (through the SVD of the triangular
factor of ``J_s``'s QR factorisation, once; directions with singular values below
``RANK_RELATIVE`` x the largest are rank-deficient and their parameters get an infinite
deviation), the numerical rank and the
condition number of ``J_s``, and each residual's leverage (the diagonal of the hat matrix, for
variance-component estimation). With a prior, the covariance is the posterior's (its rows
included), but the rank, the condition number and the parameters not determined are the
measurements' alone (their rows' ``J_s``): what the prior holds, the measurements did not find.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..tolerances import (
    CALIBRATION_COST,
    CALIBRATION_GRADIENT,
    CALIBRATION_STEP,
    RANK_RELATIVE,
)
from .chart import Estimate, retract
from .prior import LinkErrors, Regulariser, Seen
from .residuals import Data, Evaluation, evaluate, measurement_errors, residuals

__all__ = [
    "Linearisation",
    "Problem",
    "Solution",
    "Statistics",
    "one_thread",
    "solve",
    "statistics",
]

Mat = NDArray[np.float64]

_DAMPING_START = 1e-6  # initial lambda (the scaled columns have unit norm)
_DAMPING_LIMIT = 1e16  # lambda beyond which no step can lower the cost
_PROBE = 0.1  # finite-difference step of the geodesic acceleration, x the step (Transtrum 2012)
_ACCELERATION_LIMIT = 0.75  # steps whose acceleration exceeds this x their size are refused


@lru_cache(maxsize=1)
def _controller() -> Any:
    """threadpoolctl's view of the BLAS libraries loaded (scipy's among them), found once."""
    import scipy.linalg  # noqa: F401  (loaded first, so that its BLAS is among them)
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


@contextmanager
def one_thread() -> Iterator[None]:
    """BLAS on one thread within: calibration's matrices are small, and BLAS threads only cost
    wake-ups (module docstring)."""
    with _controller().limit(limits=1, user_api="blas"):
        yield


@dataclass(frozen=True, slots=True)
class Linearisation:
    """A model linearised at an estimate, the weights left out (module docstring).

    Attributes
    ----------
    estimate
        Where.
    residuals, jacobian
        The measurements' residuals ``(m,)`` and their Jacobian ``(m, p)`` at unit noise
        levels (:func:`.residuals.evaluate`).
    rows
        Residuals per measurement (3 or 6).
    prior
        With a prior (:mod:`.prior`), its coordinates ``(k,)`` and their derivatives
        ``(k, p)`` (:meth:`.prior.LinkErrors.evaluate`), else ``None``.
    """

    estimate: Estimate
    residuals: Mat
    jacobian: Mat
    rows: int
    prior: tuple[Mat, Mat] | None = None

    @classmethod
    def at(cls, est: Estimate, data: Data, errors: LinkErrors | None = None) -> Linearisation:
        """The linearisation at ``est`` of the measurements ``data`` and, with ``errors``, of
        the prior's coordinates."""
        r, jac = evaluate(est, data, 1.0, 1.0)
        return cls(est, r, jac, data.rows, None if errors is None else errors.evaluate(est))

    def errors(self) -> Mat:
        """``(N, 1 or 2)``: :func:`.residuals.errors` at the estimate, of these residuals."""
        return measurement_errors(self.residuals, self.rows)


@dataclass(frozen=True, slots=True)
class Problem:
    """What a solve minimises: the measurements' weighted residuals and, with a prior, its rows.

    Attributes
    ----------
    data
        The measurements.
    sigma_pos, sigma_rot
        The noise levels that weigh position and rotation residuals.
    prior
        The prior's rows (:class:`.prior.Regulariser`), or ``None``.
    """

    data: Data
    sigma_pos: float
    sigma_rot: float
    prior: Regulariser | None = None
    _weights: Mat = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        w = np.full(self.data.rows, 1.0 / self.sigma_pos)
        w[3:] = 1.0 / self.sigma_rot
        w.setflags(write=False)
        object.__setattr__(self, "_weights", w)

    def linearise(self, est: Estimate) -> Linearisation:
        """The linearisation at ``est`` of what this problem weighs."""
        return Linearisation.at(est, self.data, None if self.prior is None else self.prior.errors)

    def weights(self) -> Mat:
        """``(rows,)`` each residual row's weight: ``1 / sigma`` of its kind (read-only)."""
        return self._weights

    def weighted(self, lin: Linearisation) -> tuple[Mat, Mat]:
        """The residuals (the measurements', then the prior's) and their Jacobian at ``lin``,
        weighed."""
        w = self.weights()
        m, p = lin.jacobian.shape
        k = 0 if self.prior is None else len(self.prior.whiten)  # the prior's rows, below
        r, jac = np.empty(m + k), np.empty((m + k, p))
        np.multiply(lin.residuals.reshape(-1, lin.rows), w, out=r[:m].reshape(-1, lin.rows))
        np.multiply(
            lin.jacobian.reshape(-1, lin.rows, p), w[:, None], out=jac[:m].reshape(-1, lin.rows, p)
        )
        if self.prior is not None:
            deviations, tangent = self.prior_part(self.prior, lin)
            np.matmul(self.prior.whiten, deviations, out=r[m:])
            np.matmul(self.prior.whiten, tangent, out=jac[m:])
        return r, jac

    def cost(self, lin: Linearisation) -> float:
        """The weighted sum of squares at ``lin``."""
        deviations = None if self.prior is None else self.prior_part(self.prior, lin)[0]
        return self._cost(lin.residuals, deviations)

    def _cost(self, residuals: Mat, deviations: Mat | None) -> float:
        """The weighted sum of squares of the measurements' ``residuals`` (unit noise levels)
        and, with a prior, of its ``deviations``."""
        r = residuals.reshape(-1, self.data.rows) * self.weights()
        total = float(np.sum(r * r))
        if self.prior is not None and deviations is not None:
            rp = self.prior.whiten @ deviations
            total += float(rp @ rp)
        return total

    def trial(self, est: Estimate) -> _Trial:
        """This problem's cost at ``est``; its linearisation there only when asked (the
        solver's refused steps cost no Jacobian)."""
        model = Evaluation.at(est, self.data)
        seen = None if self.prior is None else self.prior.errors.seen(est)
        return _Trial(
            model, seen, self._cost(model.residuals, None if seen is None else seen.values)
        )

    @staticmethod
    def prior_part(prior: Regulariser, lin: Linearisation) -> tuple[Mat, Mat]:
        """The prior's coordinates and tangent at ``lin`` (found there when it has none)."""
        return prior.errors.evaluate(lin.estimate) if lin.prior is None else lin.prior

    def residuals(self, est: Estimate) -> Mat:
        """The weighted residuals alone at ``est``."""
        r = residuals(est, self.data, self.sigma_pos, self.sigma_rot)
        if self.prior is None:
            return r
        return np.concatenate([r, self.prior.residuals(est)])

    @property
    def data_rows(self) -> int:
        return len(self.data) * self.data.rows

    def with_noise(self, sigma_pos: float, sigma_rot: float) -> Problem:
        return Problem(self.data, sigma_pos, sigma_rot, self.prior)


@dataclass(frozen=True, slots=True)
class _Trial:
    """A problem's cost at an estimate (:meth:`Problem.trial`)."""

    model: Evaluation
    prior: Seen | None
    cost: float

    def linearisation(self, problem: Problem) -> Linearisation:
        """The linearisation there (:meth:`Problem.linearise`), from the same evaluations (the
        prior's tangent from the line coordinates its deviations were read from)."""
        seen = self.prior
        prior = None if seen is None else (seen.values, seen.tangent())
        return Linearisation(
            self.model.estimate, self.model.residuals, self.model.jacobian(), problem.data.rows,
            prior,
        )  # fmt: skip


@dataclass(frozen=True, slots=True)
class Solution:
    """The end of a solve: the estimate, the iterations taken, whether it converged, the
    weighted residual norm reached, and the linearisation there."""

    estimate: Estimate
    iterations: int
    converged: bool
    cost: float
    lin: Linearisation


@dataclass(frozen=True, slots=True)
class Statistics:
    """Linearised statistics at a solution (module docstring)."""

    residuals: Mat
    rank: int
    condition: float
    variance_factor: float
    covariance: Mat
    std: Mat
    leverage: Mat


def _step_size(change: Mat, data: Data, sigma_pos: float, sigma_rot: float) -> tuple[float, float]:
    """Largest tool-point and orientation change (physical units) of a weighted change of the
    measurements' residuals."""
    squares = np.add.reduce(np.square(change.reshape(len(data), -1, 3)), axis=2)
    largest = np.sqrt(squares.max(axis=0, initial=0.0))  # position, then rotation
    return float(largest[0]) * sigma_pos, float(largest[1]) * sigma_rot if data.rows == 6 else 0.0


def solve(
    est: Estimate,
    problem: Problem,
    size: float,
    max_iterations: int,
    done: Callable[[int], None] | None = None,
    lin: Linearisation | None = None,
    first: Mat | None = None,
) -> Solution:
    """Minimise ``problem``'s residuals from ``est`` (module docstring). ``done`` is told each
    iteration's number (a progress display); ``lin`` is ``problem``'s linearisation at ``est``
    when the caller has it; ``first``, a step to try before any (a linearised model's
    solution: kept when it lowers the cost)."""
    lin = problem.linearise(est) if lin is None else lin
    cost = problem.cost(lin)
    if first is not None and len(first) and len(first) == lin.jacobian.shape[1]:
        moved = retract(est, first)
        tried = problem.trial(moved)
        if tried.cost < cost:
            est, lin, cost = moved, tried.linearisation(problem), tried.cost
    r, jac = problem.weighted(lin)
    lam = _DAMPING_START  # the columns have unit norm: diag(J_s^T J_s) = 1
    nu = 2.0
    m = problem.data_rows
    for it in range(1, max_iterations + 1):
        if not (math.isfinite(cost) and np.isfinite(jac).all()):  # beyond float's range
            return Solution(est, it - 1, False, math.sqrt(cost), lin)
        norms = _norms(jac)
        gram = (jac.T @ jac) / (norms[:, None] * norms)
        grad = (jac.T @ r) / norms
        if np.abs(grad).max(initial=0.0) <= CALIBRATION_GRADIENT * math.sqrt(cost):
            return Solution(est, it - 1, True, math.sqrt(cost), lin)
        if done is not None:
            done(it)
        while True:
            damped = gram.copy()
            np.einsum("ii->i", damped)[:] += lam  # + lam I
            ds = _solved(damped, -grad)
            if ds is None:  # no step at this damping: damp more
                lam *= nu
                nu *= 2.0
                if lam > _DAMPING_LIMIT:
                    return Solution(est, it, False, math.sqrt(cost), lin)
                continue
            predicted = -2.0 * float(ds @ grad) - float(ds @ gram @ ds)
            change = jac[:m] @ (ds / norms)
            pos, rot = _step_size(change, problem.data, problem.sigma_pos, problem.sigma_rot)
            if (pos <= CALIBRATION_STEP * size and rot <= CALIBRATION_STEP) or (
                0.0 <= predicted <= CALIBRATION_COST * cost
            ):
                # nothing left to gain above round-off: no point moves, or the cost is flat
                new = retract(est, ds / norms)
                tried = problem.trial(new)
                if tried.cost < cost:
                    est, lin, cost = new, tried.linearisation(problem), tried.cost
                return Solution(est, it, True, math.sqrt(cost), lin)
            accel = _acceleration(est, problem, r, jac, norms, ds, damped)
            step = None if accel is None else ds + 0.5 * accel
            if step is not None:
                new = retract(est, step / norms)
                tried = problem.trial(new)
                cost_new = tried.cost
            if step is not None and cost_new < cost and predicted > 0.0:
                gain = (cost - cost_new) / predicted
                est, lin, cost = new, tried.linearisation(problem), cost_new
                lam *= max(1.0 / 3.0, 1.0 - (2.0 * gain - 1.0) ** 3)
                nu = 2.0
                r, jac = problem.weighted(lin)
                break
            lam *= nu
            nu *= 2.0
            if lam > _DAMPING_LIMIT:
                return Solution(est, it, False, math.sqrt(cost), lin)
    return Solution(est, max_iterations, False, math.sqrt(cost), lin)


def _solved(a: Mat, b: Mat) -> Mat | None:
    """``a^-1 b``, or ``None`` where ``a`` is singular or the solution not finite."""
    try:
        x = np.asarray(np.linalg.solve(a, b), dtype=np.float64)
    except np.linalg.LinAlgError:
        return None
    return x if np.isfinite(x).all() else None


def _acceleration(
    est: Estimate, problem: Problem, r: Mat, jac: Mat, norms: Mat, ds: Mat, damped: Mat
) -> Mat | None:
    """The geodesic acceleration of the step ``ds`` (scaled), or ``None`` when it is too large
    for the step to be trusted (module docstring)."""
    probe = retract(est, _PROBE * ds / norms)
    r_probe = problem.residuals(probe)
    linear = jac @ (ds / norms)
    curvature = (2.0 / _PROBE) * ((r_probe - r) / _PROBE - linear)
    accel = _solved(damped, -(jac.T @ curvature) / norms)
    if accel is None:
        return None
    speed = math.sqrt(float(ds @ ds))
    if speed > 0.0 and 2.0 * math.sqrt(float(accel @ accel)) > _ACCELERATION_LIMIT * speed:
        return None
    return accel


def statistics(lin: Linearisation, problem: Problem, exact: bool = True) -> Statistics:
    """The linearised statistics of ``problem`` at its solution ``lin`` (module docstring).

    ``exact`` takes the SVD of the Jacobian's triangular factor, which resolves singular values
    down to round-off (the rank); otherwise the eigenproblem of ``J_s^T J_s`` gives them to
    about ``1e-8`` of the largest, enough for the leverages that weigh the noise levels.
    """
    r, jac = problem.weighted(lin)
    m, p = jac.shape
    if not (np.isfinite(r).all() and np.isfinite(jac).all()):  # beyond float's range
        return _undetermined(r, p)
    if p == 0:  # nothing identified
        factor = float(r @ r) / m if m else math.nan
        return Statistics(r, 0, 1.0, factor, np.zeros((0, 0)), np.zeros(0), np.zeros(m))
    norms = _norms(jac)
    jac /= norms  # J_s, in place (jac is this function's own)
    try:
        if exact:  # the SVD of J_s's triangular factor: the same singular values, to round-off
            _, s, vt = np.linalg.svd(_triangular(jac))
        else:  # from the small eigenproblem (see above)
            eig, v = np.linalg.eigh(jac.T @ jac)
            s = np.sqrt(np.maximum(eig[::-1], 0.0))
            vt = v[:, ::-1].T
    except np.linalg.LinAlgError:  # overflow on the way (columns of ~1e154 and more)
        return _undetermined(r, p)
    keep = s > RANK_RELATIVE * (s[0] if len(s) else 0.0)
    rank = int(np.sum(keep))
    condition = float(s[0] / s[-1]) if len(s) and s[-1] > 0.0 else math.inf
    factor = float(r @ r) / (m - p) if m > p else math.nan
    v = vt[keep].T / s[keep]
    covariance = factor * (v @ v.T) / np.outer(norms, norms)
    std = np.sqrt(np.diag(covariance))
    u = jac @ v  # J_s V S^-1: the left singular vectors
    leverage = np.einsum("ij,ij->i", u, u)
    if problem.prior is not None and exact:  # what the measurements alone determine
        _, s, vt = np.linalg.svd(_triangular(jac[: problem.data_rows]), full_matrices=True)
        s = np.append(s, np.zeros(p - len(s)))  # fewer rows than coordinates: the rest is 0
        keep = s > RANK_RELATIVE * s[0]
        rank = int(np.sum(keep))
        condition = float(s[0] / s[-1]) if s[-1] > 0.0 else math.inf
    if rank < p:  # parameters that move along an undetermined direction are not identified
        null = vt[~keep]
        std[np.abs(null).max(axis=0) > math.sqrt(RANK_RELATIVE)] = math.inf
    return Statistics(r, rank, condition, factor, covariance, std, leverage)


def _undetermined(r: Mat, p: int) -> Statistics:
    """The statistics of a solution beyond float's range: nothing determined."""
    nothing = np.full(p, math.inf)
    return Statistics(
        r, 0, math.inf, math.nan, np.full((p, p), math.nan), nothing, np.zeros(len(r))
    )


def _norms(jac: Mat) -> Mat:
    """Column norms ``D`` of ``J`` (``J_s = J D^-1``). A column that is zero up to round-off (a
    parameter the data cannot see) keeps its size: scaled to unit norm it would turn round-off
    into steps."""
    norms = np.sqrt(np.einsum("ij,ij->j", jac, jac))
    top = float(norms.max(initial=0.0)) or 1.0
    norms[norms <= RANK_RELATIVE * top] = top
    out: Mat = norms
    return out


def _triangular(a: Mat) -> Mat:
    """``R`` of ``a = Q R`` (``min(m, p) x p``), by LAPACK's Householder QR."""
    out: Mat = np.asarray(np.linalg.qr(a, mode="r"), dtype=np.float64)
    return out
