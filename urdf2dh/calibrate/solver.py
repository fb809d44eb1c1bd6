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
non-linear least squares problems", §3.2). It stops when the next step would move no modelled
tool point by more than ``CALIBRATION_STEP`` x size and no orientation by more than
``CALIBRATION_STEP`` rad, or when the gradient vanishes (:mod:`urdf2dh.tolerances`).

Statistics (Gauss-Markov, linearised at the solution): with ``m`` residuals and ``p``
coordinates, the variance factor ``s^2 = |r|^2 / (m - p)`` (about 1 when the noise levels used
as weights are right), the covariance ``s^2 (J^T J)^-1`` (through the SVD of ``J_s``'s
triangular factor, once; directions with singular values below ``RANK_RELATIVE`` x the largest
are rank-deficient and their parameters get an infinite deviation), the numerical rank and the
condition number of ``J_s``, and each residual's leverage (the diagonal of the hat matrix, for
variance-component estimation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..tolerances import CALIBRATION_GRADIENT, CALIBRATION_STEP, RANK_RELATIVE
from .chart import Estimate, retract
from .residuals import Data, evaluate

__all__ = ["Solution", "Statistics", "solve", "statistics"]

Mat = NDArray[np.float64]

_DAMPING_START = 1e-6  # initial lambda (the scaled columns have unit norm)
_DAMPING_LIMIT = 1e16  # lambda beyond which no step can lower the cost


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


def _scaled(jac: Mat) -> tuple[Mat, Mat]:
    """Column norms ``D`` and ``J D^-1``. A column that is zero up to round-off (a parameter the
    data cannot see) keeps its size: scaled to unit norm it would turn round-off into steps."""
    norms = np.linalg.norm(jac, axis=0)
    top = float(norms.max(initial=0.0)) or 1.0
    norms[norms <= RANK_RELATIVE * top] = top
    return norms, jac / norms


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


def _step_size(change: Mat, data: Data, sigma_pos: float, sigma_rot: float) -> tuple[float, float]:
    """Largest tool-point and orientation change (physical units) of a weighted change."""
    rows = change.reshape(len(data), data.rows)
    pos = float(np.linalg.norm(rows[:, :3], axis=1).max(initial=0.0)) * sigma_pos
    rot = (
        float(np.linalg.norm(rows[:, 3:], axis=1).max(initial=0.0)) * sigma_rot
        if data.rows == 6
        else 0.0
    )
    return pos, rot


def solve(
    est: Estimate, data: Data, sigma_pos: float, sigma_rot: float, size: float, max_iterations: int
) -> Solution:
    """Minimise the weighted residuals from ``est`` (module docstring)."""
    r, jac = evaluate(est, data, sigma_pos, sigma_rot)
    cost = float(r @ r)
    lam: float | None = None
    nu = 2.0
    for it in range(1, max_iterations + 1):
        assert jac is not None
        norms, js = _scaled(jac)
        gram = np.einsum("ij,ik->jk", js, js)  # no BLAS: see above
        grad = np.einsum("ij,i->j", js, r)
        if lam is None:
            lam = _DAMPING_START  # the columns have unit norm: diag(J_s^T J_s) = 1
        if np.abs(grad).max(initial=0.0) <= CALIBRATION_GRADIENT * math.sqrt(cost):
            return Solution(est, it - 1, True, math.sqrt(cost))
        while True:
            ds = np.linalg.solve(gram + lam * np.eye(len(gram)), -grad)
            change = np.einsum("ij,j->i", js, ds)
            predicted = -2.0 * float(ds @ grad) - float(change @ change)
            pos, rot = _step_size(change, data, sigma_pos, sigma_rot)
            new = retract(est, ds / norms)
            r_new, _ = evaluate(new, data, sigma_pos, sigma_rot, jacobian=False)
            cost_new = float(r_new @ r_new)
            if pos <= CALIBRATION_STEP * size and rot <= CALIBRATION_STEP:
                # nothing left to gain above round-off
                if cost_new < cost:
                    est, cost = new, cost_new
                return Solution(est, it, True, math.sqrt(cost))
            if cost_new < cost and predicted > 0.0:
                gain = (cost - cost_new) / predicted
                est, cost = new, cost_new
                lam *= max(1.0 / 3.0, 1.0 - (2.0 * gain - 1.0) ** 3)
                nu = 2.0
                r, jac = evaluate(est, data, sigma_pos, sigma_rot)
                break
            lam *= nu
            nu *= 2.0
            if lam > _DAMPING_LIMIT:
                return Solution(est, it, False, math.sqrt(cost))
    return Solution(est, max_iterations, False, math.sqrt(cost))


def statistics(
    est: Estimate, data: Data, sigma_pos: float, sigma_rot: float, exact: bool = True
) -> Statistics:
    """The linearised statistics of ``est`` as a solution (module docstring).

    ``exact`` takes the SVD of the Jacobian's triangular factor, which resolves singular values
    down to round-off (the rank); otherwise the eigenproblem of ``J_s^T J_s`` gives them to
    about ``1e-8`` of the largest, enough for the leverages that weigh the noise levels.
    """
    r, jac = evaluate(est, data, sigma_pos, sigma_rot)
    assert jac is not None
    m, p = jac.shape
    norms, js = _scaled(jac)
    if exact:  # the SVD of J_s's triangular factor: the same singular values, to round-off
        _, s, vt = np.linalg.svd(_triangular(js))
    else:  # from the small eigenproblem (see above)
        eig, v = np.linalg.eigh(np.einsum("ij,ik->jk", js, js))
        s = np.sqrt(np.maximum(eig[::-1], 0.0))
        vt = v[:, ::-1].T
    uq = np.einsum("ij,kj->ik", js, vt) / np.where(s > 0.0, s, 1.0)
    keep = s > RANK_RELATIVE * (s[0] if len(s) else 0.0)
    rank = int(np.sum(keep))
    condition = float(s[0] / s[-1]) if len(s) and s[-1] > 0.0 else math.inf
    factor = float(r @ r) / (m - p) if m > p else math.nan
    v = vt[keep].T / s[keep]
    covariance = factor * (v @ v.T) / np.outer(norms, norms)
    std = np.sqrt(np.diag(covariance))
    if rank < p:  # parameters that move along an undetermined direction are not identified
        null = vt[~keep]
        std[np.abs(null).max(axis=0) > math.sqrt(RANK_RELATIVE)] = math.inf
    leverage = np.sum(uq[:, keep] ** 2, axis=1)
    return Statistics(r, rank, condition, factor, covariance, std, leverage)
