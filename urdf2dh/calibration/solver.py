"""Levenberg-Marquardt on the chart of :mod:`.chart`, and the statistics of its solution.

Each iteration linearises the weighted residuals ``r`` at the current estimate (coordinates
``0`` of the chart centred there), scales the Jacobian's columns to unit norm
(``J_s = J D^-1``; lengths and angles then weigh alike), and takes the damped Gauss-Newton step

    ``(J_s^T J_s + lambda I) d_s = -J_s^T r``,  ``d = D^-1 d_s``

from the small ``p x p`` system (a step's precision only sets how fast the iteration
converges, not where to). Products with the tall ``J_s`` are taken by ``einsum``, not BLAS, and
no tall factorisation is made: OpenBLAS wakes its threads for those, and on a busy two-core
machine their spinning made the whole solve four to ten times slower. A step that lowers
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

Statistics (Gauss-Markov, linearised at the solution): with ``m`` residuals and ``p``
coordinates, the variance factor ``s^2 = |r|^2 / (m - p)`` (about 1 when the noise levels used
as weights are right), the covariance ``s^2 (J^T J)^-1`` (through the SVD of ``J_s``'s
triangular factor, once; directions with singular values below ``RANK_RELATIVE`` x the largest
are rank-deficient and their parameters get an infinite deviation), the numerical rank and the
condition number of ``J_s``, and each residual's leverage (the diagonal of the hat matrix, for
variance-component estimation). With a prior, the covariance is the posterior's (its rows
included), but the rank, the condition number and the parameters not determined are the
measurements' alone (their rows' ``J_s``): what the prior holds, the measurements did not find.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..tolerances import (
    CALIBRATION_COST,
    CALIBRATION_GRADIENT,
    CALIBRATION_STEP,
    RANK_RELATIVE,
)
from .chart import Estimate, retract
from .prior import Regulariser
from .residuals import Data, evaluate, residuals

__all__ = ["Problem", "Solution", "Statistics", "solve", "statistics"]

Mat = NDArray[np.float64]

_DAMPING_START = 1e-6  # initial lambda (the scaled columns have unit norm)
_DAMPING_LIMIT = 1e16  # lambda beyond which no step can lower the cost
_PROBE = 0.1  # finite-difference step of the geodesic acceleration, x the step (Transtrum 2012)
_ACCELERATION_LIMIT = 0.75  # steps whose acceleration exceeds this x their size are refused


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

    def evaluate(self, est: Estimate) -> tuple[Mat, Mat]:
        """Residuals (the measurements', then the prior's) and their Jacobian."""
        r, jac = evaluate(est, self.data, self.sigma_pos, self.sigma_rot)
        if self.prior is None:
            return r, jac
        rp, jp = self.prior.rows(est)
        return np.concatenate([r, rp]), np.concatenate([jac, jp])

    def residuals(self, est: Estimate) -> Mat:
        """The residuals alone (:meth:`evaluate`)."""
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
class Solution:
    """The end of a solve: the estimate, the iterations taken, whether it converged, and the
    weighted residual norm reached."""

    estimate: Estimate
    iterations: int
    converged: bool
    cost: float


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
    rows = change.reshape(len(data), data.rows)
    pos = float(np.linalg.norm(rows[:, :3], axis=1).max(initial=0.0)) * sigma_pos
    rot = (
        float(np.linalg.norm(rows[:, 3:], axis=1).max(initial=0.0)) * sigma_rot
        if data.rows == 6
        else 0.0
    )
    return pos, rot


def solve(
    est: Estimate,
    problem: Problem,
    size: float,
    max_iterations: int,
    done: Callable[[int], None] | None = None,
) -> Solution:
    """Minimise ``problem``'s residuals from ``est`` (module docstring). ``done`` is told each
    iteration's number (a progress display)."""
    r, jac = problem.evaluate(est)
    cost = float(r @ r)
    lam = _DAMPING_START  # the columns have unit norm: diag(J_s^T J_s) = 1
    nu = 2.0
    m = problem.data_rows
    for it in range(1, max_iterations + 1):
        if not (math.isfinite(cost) and np.all(np.isfinite(jac))):  # beyond float's range
            return Solution(est, it - 1, False, math.sqrt(cost))
        norms = _norms(jac)
        gram = np.einsum("ij,ik->jk", jac, jac) / np.outer(norms, norms)  # no BLAS: see above
        grad = np.einsum("ij,i->j", jac, r) / norms
        if np.abs(grad).max(initial=0.0) <= CALIBRATION_GRADIENT * math.sqrt(cost):
            return Solution(est, it - 1, True, math.sqrt(cost))
        if done is not None:
            done(it)
        while True:
            damped = gram + lam * np.eye(len(gram))
            ds = _solved(damped, -grad)
            if ds is None:  # no step at this damping: damp more
                lam *= nu
                nu *= 2.0
                if lam > _DAMPING_LIMIT:
                    return Solution(est, it, False, math.sqrt(cost))
                continue
            predicted = -2.0 * float(ds @ grad) - float(ds @ gram @ ds)
            change = np.einsum("ij,j->i", jac[:m], ds / norms)
            pos, rot = _step_size(change, problem.data, problem.sigma_pos, problem.sigma_rot)
            if (pos <= CALIBRATION_STEP * size and rot <= CALIBRATION_STEP) or (
                0.0 <= predicted <= CALIBRATION_COST * cost
            ):
                # nothing left to gain above round-off: no point moves, or the cost is flat
                new = retract(est, ds / norms)
                cost_new = float(np.sum(problem.residuals(new) ** 2))
                if cost_new < cost:
                    est, cost = new, cost_new
                return Solution(est, it, True, math.sqrt(cost))
            accel = _acceleration(est, problem, r, jac, norms, ds, damped)
            step = None if accel is None else ds + 0.5 * accel
            if step is not None:
                new = retract(est, step / norms)
                r_new = problem.residuals(new)
                cost_new = float(r_new @ r_new)
            if step is not None and cost_new < cost and predicted > 0.0:
                gain = (cost - cost_new) / predicted
                est, cost = new, cost_new
                lam *= max(1.0 / 3.0, 1.0 - (2.0 * gain - 1.0) ** 3)
                nu = 2.0
                r, jac = problem.evaluate(est)
                break
            lam *= nu
            nu *= 2.0
            if lam > _DAMPING_LIMIT:
                return Solution(est, it, False, math.sqrt(cost))
    return Solution(est, max_iterations, False, math.sqrt(cost))


def _solved(a: Mat, b: Mat) -> Mat | None:
    """``a^-1 b``, or ``None`` where ``a`` is singular or the solution not finite."""
    try:
        x = np.asarray(np.linalg.solve(a, b), dtype=np.float64)
    except np.linalg.LinAlgError:
        return None
    return x if np.all(np.isfinite(x)) else None


def _acceleration(
    est: Estimate, problem: Problem, r: Mat, jac: Mat, norms: Mat, ds: Mat, damped: Mat
) -> Mat | None:
    """The geodesic acceleration of the step ``ds`` (scaled), or ``None`` when it is too large
    for the step to be trusted (module docstring)."""
    probe = retract(est, _PROBE * ds / norms)
    r_probe = problem.residuals(probe)
    linear = np.einsum("ij,j->i", jac, ds / norms)
    curvature = (2.0 / _PROBE) * ((r_probe - r) / _PROBE - linear)
    accel = _solved(damped, -np.einsum("ij,i->j", jac, curvature) / norms)
    if accel is None:
        return None
    speed = float(np.linalg.norm(ds))
    if speed > 0.0 and 2.0 * float(np.linalg.norm(accel)) > _ACCELERATION_LIMIT * speed:
        return None
    return accel


def statistics(est: Estimate, problem: Problem, exact: bool = True) -> Statistics:
    """The linearised statistics of ``est`` as a solution (module docstring).

    ``exact`` takes the SVD of the Jacobian's triangular factor, which resolves singular values
    down to round-off (the rank); otherwise the eigenproblem of ``J_s^T J_s`` gives them to
    about ``1e-8`` of the largest, enough for the leverages that weigh the noise levels.
    """
    r, jac = problem.evaluate(est)
    m, p = jac.shape
    if not (np.all(np.isfinite(r)) and np.all(np.isfinite(jac))):  # beyond float's range
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
            eig, v = np.linalg.eigh(np.einsum("ij,ik->jk", jac, jac))
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
    u = np.einsum("ij,jk->ik", jac, v)  # J_s V S^-1: the left singular vectors, no BLAS
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
    """``R`` of ``a = Q R`` (``p x p``) by Householder reflections written with ``einsum``: the
    tall factorisation without BLAS (LAPACK's wakes OpenBLAS's threads, see above)."""
    a = a.copy()
    m, p = a.shape
    for k in range(min(m, p)):
        v = a[k:, k].copy()
        norm = math.sqrt(float(np.einsum("i,i->", v, v)))
        if norm == 0.0:
            continue
        v[0] += math.copysign(norm, v[0])
        w = np.einsum("i,ij->j", v, a[k:, k:]) * (2.0 / float(np.einsum("i,i->", v, v)))
        a[k:, k:] -= np.multiply.outer(v, w)
    return np.triu(a[:p])
