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

from .prior import LinkErrors, ridged

__all__ = ["Linearised", "maximise"]

Mat = NDArray[np.float64]

_LOWEST, _HIGHEST = 1e-9, 1.0  # the deviations searched, rad (and x the robot's size)
_SETTLED = 1e-7  # L-BFGS-B stops when f changes by less than this x |f| (its ftol): far below
# what moves a deviation by a per cent
_COMPONENTS_ROUNDS = 100  # variance-component iterations at most (each ~halves the error)
_COMPONENTS_SETTLED = 1e-6  # ... stopping when no noise level changes by more than this


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
        ``(groups, k, k)``: ``M_j`` of each group of errors, at unit deviation.
    """

    gram: tuple[Mat, ...]
    cross: tuple[Mat, ...]
    square: tuple[float, ...]
    count: tuple[int, ...]
    shape: Mat
    offset: Mat
    parts: Mat


def linearised(
    residuals: Mat,
    jacobian: Mat,
    rows: int,
    prior: tuple[LinkErrors, Mat, Mat, list[Mat]] | None = None,
) -> Linearised:
    """The level at a point: the measurements' unweighted residuals ``(N * rows,)`` and their
    Jacobian and, with a prior, its link errors with their
    :meth:`~.prior.LinkErrors.tangent` and :meth:`~.prior.LinkErrors.deviations` there and
    their :meth:`~.prior.LinkErrors.parts` (without one, only the noise levels are left to
    estimate: Förstner's variance components, reached at once)."""
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
    if prior is None:
        p = jac.shape[2]
        return Linearised(
            tuple(gram), tuple(cross), tuple(square), tuple(count),
            np.zeros((0, p)), np.zeros(0), np.zeros((0, 0, 0)),
        )  # fmt: skip
    errors, tangent, deviations, parts = prior
    return Linearised(
        tuple(gram),
        tuple(cross),
        tuple(square),
        tuple(count),
        errors.project @ tangent,
        errors.project @ deviations,
        np.array(parts),
    )


def _objective(theta: Mat, lin: Linearised) -> tuple[float, Mat]:
    """``f`` and its gradient by ``theta``: the log noise levels, then the log deviations of
    the groups (module docstring). With ``u = M^-1 y(x)`` and ``P_j = M_j``, the gradient by
    ``log t_j`` is ``t_j^2 sum(P_j * (M^-1 - M^-1 G H^-1 G^T M^-1 - u u^T))``. LAPACK's
    Cholesky routines directly: the matrices are small and called for often."""
    kinds = len(lin.gram)
    sigma2 = np.exp(2.0 * theta[:kinds])
    if not len(lin.offset):
        return _noise_only(sigma2, lin)
    tau2 = np.exp(2.0 * theta[kinds:])
    lm = _factor(_prior_covariance(tau2, lin))
    minv_g = _solve(lm, lin.shape)
    gram = _weighted(lin.gram, sigma2)
    h = ridged(_total(gram) + lin.shape.T @ minv_g)
    b = _total(_weighted(lin.cross, sigma2))
    b = b + minv_g.T @ lin.offset
    lh = _factor(h)
    x = -_solve(lh, b)
    errors = _errors(lin, x)
    v = lin.offset + lin.shape @ x
    u = _solve(lm, v)
    chi2 = sum(e / s for e, s in zip(errors, sigma2, strict=True)) + float(v @ u)
    logdet = 2.0 * float(np.sum(np.log(np.diag(lh)))) + 2.0 * float(np.sum(np.log(np.diag(lm))))
    noise = sum(n * math.log(s) for n, s in zip(lin.count, sigma2, strict=True))
    value = 0.5 * (chi2 + logdet + noise)
    h_inv = _inverse(lh)
    spread = minv_g @ h_inv @ minv_g.T
    rest = _inverse(lm) - spread - np.outer(u, u)
    grad = np.empty(len(theta))
    for g in range(kinds):
        grad[g] = -errors[g] / sigma2[g] - float(np.sum(h_inv * gram[g])) + lin.count[g]
    grad[kinds:] = tau2 * np.einsum("gij,ij->g", lin.parts, rest)
    return value, grad


def _noise_only(sigma2: Mat, lin: Linearised) -> tuple[float, Mat]:
    """:func:`_objective` without a prior."""
    gram, lh, x = _without_prior(lin, sigma2)
    errors = _errors(lin, x)
    chi2 = sum(e / s for e, s in zip(errors, sigma2, strict=True))
    noise = sum(n * math.log(s) for n, s in zip(lin.count, sigma2, strict=True))
    value = 0.5 * (chi2 + 2.0 * float(np.sum(np.log(np.diag(lh)))) + noise)
    h_inv = _inverse(lh)
    grad = np.array(
        [
            -e / s - float(np.sum(h_inv * g)) + n
            for e, s, g, n in zip(errors, sigma2, gram, lin.count, strict=True)
        ]
    )
    return value, grad


def _weighted(terms: tuple[Mat, ...], sigma2: Mat) -> list[Mat]:
    """Each kind's term over its noise variance."""
    return [t / s for t, s in zip(terms, sigma2, strict=True)]


def _total(terms: list[Mat]) -> Mat:
    """The sum of ``terms``, a new array."""
    total: Mat = sum(terms, np.zeros_like(terms[0]))
    return total


def _prior_covariance(tau2: Mat, lin: Linearised) -> Mat:
    """``M = sum_j t_j^2 M_j``, ridged."""
    return ridged(np.einsum("g,gij->ij", tau2, lin.parts))


def _without_prior(lin: Linearised, sigma2: Mat) -> tuple[list[Mat], Mat, Mat]:
    """Without a prior, at the noise variances ``sigma2``: the weighted Gram matrices, the
    Cholesky factor of ``H`` and the minimising ``x``."""
    gram = _weighted(lin.gram, sigma2)
    lh = _factor(ridged(_total(gram)))
    x = -_solve(lh, _total(_weighted(lin.cross, sigma2)))
    return gram, lh, x


def _errors(lin: Linearised, x: Mat) -> list[float]:
    """Each kind's ``|r_g(x)|^2`` at unit noise."""
    return [
        sq + 2.0 * float(c @ x) + float(x @ g @ x)
        for sq, c, g in zip(lin.square, lin.cross, lin.gram, strict=True)
    ]


def _factor(a: Mat) -> Mat:
    """The lower Cholesky factor of the symmetric positive definite ``a``."""
    from scipy.linalg.lapack import dpotrf

    factor, info = dpotrf(a, lower=1, clean=1)
    if info:
        raise np.linalg.LinAlgError("not positive definite")
    out: Mat = factor
    return out


def _solve(factor: Mat, b: Mat) -> Mat:
    """``A^-1 b`` from the lower Cholesky factor of ``A``."""
    from scipy.linalg.lapack import dpotrs

    out: Mat = dpotrs(factor, b, lower=1)[0]
    return out


def _inverse(factor: Mat) -> Mat:
    """``A^-1`` from the lower Cholesky factor of ``A``."""
    from scipy.linalg.lapack import dpotri

    low = dpotri(factor, lower=1)[0]
    out: Mat = np.tril(low) + np.tril(low, -1).T
    return out


def maximise(
    lin: Linearised, noise: tuple[float, ...], deviations: Mat, floors: tuple[float, ...]
) -> tuple[tuple[float, ...], Mat, Mat]:
    """The noise levels (positions, then rotations) and the groups' deviations of greatest
    evidence, from ``noise`` and ``deviations``; the noise levels kept above ``floors`` (fixed
    where a floor is the level itself: given noise); and the linearised model's solution with
    them (a Gauss-Newton step from the linearisation point: where the solve starts). Without a
    prior, the noise levels alone: variance components (:func:`_components`)."""
    from scipy.optimize import minimize

    kinds = len(lin.gram)
    if not len(lin.offset):
        levels = _components(lin, noise, floors)
        theta = np.log(np.array(levels))
        return levels, np.zeros(0), _step(theta, lin)
    theta0 = np.log(np.array([*noise, *np.clip(deviations, _LOWEST, _HIGHEST)], dtype=float))
    bounds = [
        (math.log(f), math.log(f) if f == level else None)
        for f, level in zip(floors, noise, strict=True)
    ] + [(math.log(_LOWEST), math.log(_HIGHEST))] * len(deviations)
    result = minimize(
        _objective, theta0, args=(lin,), jac=True, method="L-BFGS-B", bounds=bounds,
        options={"ftol": _SETTLED},
    )  # fmt: skip
    return (
        tuple(np.exp(result.x[:kinds]).tolist()),
        np.exp(result.x[kinds:]),
        _step(result.x, lin),
    )


def _components(
    lin: Linearised, noise: tuple[float, ...], floors: tuple[float, ...]
) -> tuple[float, ...]:
    """The noise levels of greatest evidence without a prior: where the gradient of
    :func:`_noise_only` vanishes, ``sigma_g^2 = e_g / (n_g - tr(H^-1 J_g^T J_g / sigma_g^2))``
    (Förstner's variance components), iterated from ``noise`` until no level changes by more
    than :data:`_COMPONENTS_SETTLED`; each kept above its floor (fixed where the floor is the
    level itself: given noise)."""
    levels = np.array(noise, dtype=float)
    fixed = np.array([f == v for f, v in zip(floors, noise, strict=True)])
    low = np.array(floors, dtype=float)
    for _ in range(_COMPONENTS_ROUNDS):
        gram, lh, x = _without_prior(lin, levels**2)
        h_inv = _inverse(lh)
        new = levels.copy()
        for g, (error, n) in enumerate(zip(_errors(lin, x), lin.count, strict=True)):
            redundancy = n - float(np.sum(h_inv * gram[g]))
            if redundancy > 0.0 and error > 0.0:
                new[g] = math.sqrt(error / redundancy)
        new = np.where(fixed, levels, np.maximum(new, low))
        settled = bool(np.all(np.abs(new / levels - 1.0) <= _COMPONENTS_SETTLED))
        levels = new
        if settled:
            break
    return tuple(levels.tolist())


def _step(theta: Mat, lin: Linearised) -> Mat:
    """The minimising ``x`` of the linearised objective at ``theta``."""
    kinds = len(lin.gram)
    sigma2 = np.exp(2.0 * theta[:kinds])
    h = _total(_weighted(lin.gram, sigma2))
    b = _total(_weighted(lin.cross, sigma2))
    if len(lin.offset):
        minv_g = _solve(_factor(_prior_covariance(np.exp(2.0 * theta[kinds:]), lin)), lin.shape)
        h = h + lin.shape.T @ minv_g
        b = b + minv_g.T @ lin.offset
    return -_solve(_factor(ridged(h)), b)
