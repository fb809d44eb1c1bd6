"""The prior's deviations and the noise levels, estimated by the measurements' marginal
likelihood (empirical Bayes; MacKay, "Bayesian interpolation", Neural Computation 4(3), 1992).

At a linearisation of the level (:mod:`.prior`), the residuals of each kind ``g`` (positions,
rotations) are ``r_g(x) = r0_g + J_g x`` with noise ``sigma_g`` per coordinate, and the prior's
coordinates are ``y(x) = y0 + G x ~ N(0, M)``, ``M = sum_j t_j^2 M_j`` over the groups of
errors (each link's, the offsets', the scales'; ``M_j`` at unit deviation, lengths at the
robot's size per radian), every other coordinate free. Twice the negative log marginal
likelihood, the coordinates integrated out, is, up to a constant::

    2 f = min_x [sum_g |r_g(x)|^2 / sigma_g^2 + y(x)^T M^-1 y(x)]
          + log det H + log det M + sum_g n_g log sigma_g^2,
    H = sum_g J_g^T J_g / sigma_g^2 + G^T M^-1 G

(``n_g`` residuals of kind ``g``). It is minimised over the logarithms of the noise levels and
of the deviations by L-BFGS-B (scipy) with its analytic gradient: at the minimising ``x`` the
derivative of the first term is that of the objective alone, and ``d log det A = tr(A^-1 dA)``.
The deviations that maximise the evidence are those the measurements support: where they pin the
links down it is large and the prior hardly pulls; where they cannot tell a link's error from
noise it is small and the link keeps the nominal's geometry. The caller re-linearises at the new
solution until the estimates settle (:func:`.identify.solve_level`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .prior import LinkErrors

__all__ = ["Linearised", "maximise"]

Mat = NDArray[np.float64]

_LOWEST, _HIGHEST = 1e-9, 1.0  # the deviations searched, rad (and x the robot's size)
_RIDGE = 1e-12  # x the mean diagonal, added to H before its Cholesky factor


@dataclass(frozen=True)
class Linearised:
    """One level's model at a linearisation point.

    Attributes
    ----------
    gram, cross, square, count
        Per kind of residual (positions, then rotations): ``J_g^T J_g``, ``J_g^T r0_g``,
        ``|r0_g|^2`` and ``n_g``, at unit noise.
    shape, offset
        ``G`` ``(k, p)`` and ``y0`` ``(k,)``: the prior's projected coordinates.
    parts
        ``M_j`` ``(k, k)`` of each group of errors, at unit deviation.
    """

    gram: tuple[Mat, ...]
    cross: tuple[Mat, ...]
    square: tuple[float, ...]
    count: tuple[int, ...]
    shape: Mat
    offset: Mat
    parts: tuple[Mat, ...]


def linearised(
    residuals: Mat, jacobian: Mat, rows: int, errors: LinkErrors, tangent: Mat, deviations: Mat,
    parts: list[Mat],
) -> Linearised:  # fmt: skip
    """The level at a point: the measurements' unweighted residuals ``(N * rows,)`` and their
    Jacobian, the prior's :meth:`~.prior.LinkErrors.tangent` and
    :meth:`~.prior.LinkErrors.deviations` there, and its :meth:`~.prior.LinkErrors.parts`."""
    res = residuals.reshape(-1, rows)
    jac = jacobian.reshape(len(res), rows, -1)
    kinds = [slice(0, 3)] + ([slice(3, 6)] if rows == 6 else [])
    gram, cross, square, count = [], [], [], []
    for cols in kinds:
        j = jac[:, cols].reshape(-1, jac.shape[2])
        r = res[:, cols].ravel()
        gram.append(j.T @ j)
        cross.append(j.T @ r)
        square.append(float(r @ r))
        count.append(len(r))
    return Linearised(
        tuple(gram),
        tuple(cross),
        tuple(square),
        tuple(count),
        errors.project @ tangent,
        errors.project @ deviations,
        tuple(parts),
    )


def _objective(theta: Mat, lin: Linearised) -> tuple[float, Mat]:
    """``f`` and its gradient by ``theta``: the log noise levels, then the log deviations of
    the groups (module docstring)."""
    kinds = len(lin.gram)
    sigma2 = np.exp(2.0 * theta[:kinds])
    tau2 = np.exp(2.0 * theta[kinds:])
    m = sum(t * part for t, part in zip(tau2, lin.parts, strict=True))
    m = m + np.eye(len(m)) * (_RIDGE * float(np.trace(m)) / max(len(m), 1))
    lm = np.linalg.cholesky(m)
    minv_g = _cho_solve(lm, lin.shape)
    minv_y = _cho_solve(lm, lin.offset)
    h = sum(g / s for g, s in zip(lin.gram, sigma2, strict=True)) + lin.shape.T @ minv_g
    h = h + np.eye(len(h)) * (_RIDGE * float(np.trace(h)) / max(len(h), 1))
    b = sum(c / s for c, s in zip(lin.cross, sigma2, strict=True)) + lin.shape.T @ minv_y
    lh = np.linalg.cholesky(h)
    x = -_cho_solve(lh, b)
    errors = [
        sq + 2.0 * float(c @ x) + float(x @ g @ x)
        for sq, c, g in zip(lin.square, lin.cross, lin.gram, strict=True)
    ]
    v = lin.offset + lin.shape @ x
    minv_v = _cho_solve(lm, v)
    chi2 = sum(e / s for e, s in zip(errors, sigma2, strict=True)) + float(v @ minv_v)
    logdet = 2.0 * float(np.sum(np.log(np.diag(lh)))) + 2.0 * float(np.sum(np.log(np.diag(lm))))
    noise = sum(n * math.log(s) for n, s in zip(lin.count, sigma2, strict=True))
    value = 0.5 * (chi2 + logdet + noise)
    h_inv = _cho_solve(lh, np.eye(len(h)))
    grad = np.empty(len(theta))
    for g in range(kinds):
        grad[g] = 0.5 * (
            -2.0 * errors[g] / sigma2[g]
            - 2.0 * float(np.sum(h_inv * lin.gram[g])) / sigma2[g]
            + 2.0 * lin.count[g]
        )
    spread = minv_g @ h_inv @ minv_g.T  # M^-1 G H^-1 G^T M^-1
    m_inv = _cho_solve(lm, np.eye(len(m)))
    for k, (t, unit) in enumerate(zip(tau2, lin.parts, strict=True)):
        part = 2.0 * t * unit
        grad[kinds + k] = 0.5 * (
            -float(minv_v @ part @ minv_v)
            - float(np.sum(spread * part))
            + float(np.sum(m_inv * part))
        )
    return value, grad


def _cho_solve(factor: Mat, b: Mat) -> Mat:
    """``A^-1 b`` from the lower Cholesky factor of ``A``."""
    from scipy.linalg import cho_solve

    return cho_solve((factor, True), b, check_finite=False)


def maximise(
    lin: Linearised, noise: tuple[float, ...], deviations: Mat, floors: tuple[float, ...]
) -> tuple[tuple[float, ...], Mat]:
    """The noise levels (positions, then rotations) and the groups' deviations of greatest
    evidence, from ``noise`` and ``deviations``; the noise levels kept above ``floors`` (fixed
    where a floor is the level itself: given noise)."""
    from scipy.optimize import minimize

    kinds = len(lin.gram)
    theta0 = np.log(np.array([*noise, *np.clip(deviations, _LOWEST, _HIGHEST)], dtype=float))
    bounds = [
        (math.log(f), math.log(f) if f == level else None)
        for f, level in zip(floors, noise, strict=True)
    ] + [(math.log(_LOWEST), math.log(_HIGHEST))] * len(deviations)
    result = minimize(_objective, theta0, args=(lin,), jac=True, method="L-BFGS-B", bounds=bounds)
    return tuple(np.exp(result.x[:kinds]).tolist()), np.exp(result.x[kinds:])
