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
derivative of the first term is that of the objective alone, and ``d log det A = tr(A^-1 dA)``
(the traces read from the lower triangle of the inverse that LAPACK leaves, :func:`_traced`).
The deviations that maximise the evidence are those the measurements support: where they pin the
links down it is large and the prior hardly pulls; where they cannot tell a link's error from
noise it is small and the link keeps the nominal's geometry. The caller re-linearises at the new
solution until the estimates settle (:func:`.identify.solve_level`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache, cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .prior import LinkErrors, ridged

__all__ = ["Linearised", "maximise"]

Mat = NDArray[np.float64]

_LOWEST, _HIGHEST = 1e-9, 1.0  # the deviations searched, rad (and x the robot's size)
_SETTLED = 1e-7  # L-BFGS-B stops when f changes by less than this x |f| (minimize's ftol,
# fmin_l_bfgs_b's factr times the machine epsilon, _EPSILON: a power of two); where the
# evidence is flat in a deviation (a few 1e-4 of f over a factor of ten in it) it stops short of
# the maximum there (where it stops then decides levels on real sets: TIAGo, TALOS)
_EPSILON = float(np.finfo(float).eps)
_COMPONENTS_ROUNDS = 100  # variance-component iterations at most (each ~halves the error)
_COMPONENTS_SETTLED = 1e-6  # ... stopping when no noise level changes by more than this


@dataclass(frozen=True)
class Linearised:
    """One level's model at a linearisation point.

    Attributes
    ----------
    gram, cross, square, count
        Per kind of residual (positions, then rotations): ``J_g^T J_g`` ``(kinds, p, p)``,
        ``J_g^T r0_g`` ``(kinds, p)``, ``|r0_g|^2`` and ``n_g`` ``(kinds,)``, at unit noise.
    shape, offset
        ``G`` ``(k, p)`` and ``y0`` ``(k,)``: the prior's projected coordinates.
    parts
        ``(groups, k, k)``: ``M_j`` of each group of errors, at unit deviation.
    """

    gram: Mat
    cross: Mat
    square: Mat
    count: Mat
    shape: Mat
    offset: Mat
    parts: Mat

    @cached_property
    def doubling(self) -> Mat:
        """``-2`` per noise level, then ``2`` per group: ``exp(doubling * theta)`` are the
        weights ``sigma_g^-2``, then the deviations squared."""
        return np.repeat([-2.0, 2.0], [len(self.count), len(self.parts)])

    @cached_property
    def hoisted(self) -> tuple[Mat, Mat]:
        """``shape`` in Fortran order (as LAPACK takes it), and ``2 cross``."""
        return np.asfortranarray(self.shape), 2.0 * self.cross

    @cached_property
    def traced(self) -> tuple[Mat, Mat]:
        """:func:`_traced` of ``gram`` and of ``parts``."""
        return _traced(self.gram), _traced(self.parts)


def _traced(a: Mat) -> Mat:
    """``(n, m * m)``: each symmetric ``a[i]`` as ``2 tril(a[i]) - diag(a[i])``, flattened: its
    product with the lower triangle of a symmetric ``B`` summed is ``tr(a[i] B)``, which is how
    the inverses LAPACK leaves in one triangle (:func:`_inverse`) are traced."""
    m = a.shape[1]
    out: Mat = (a * (2.0 * np.tri(m) - np.eye(m))).reshape(len(a), m * m)
    return out


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
    gram, cross, square = [], [], []
    for cols in kinds:
        j = jac[:, cols].reshape(-1, jac.shape[2])
        r = res[:, cols].ravel()
        gram.append(j.T @ j)
        cross.append(j.T @ r)
        square.append(float(r @ r))
    count = np.full(len(kinds), 3.0 * len(res))
    p = jac.shape[2]
    shape, offset, parts = np.zeros((0, p)), np.zeros(0), np.zeros((0, 0, 0))
    if prior is not None:
        errors, tangent, deviations, unit = prior
        shape, offset, parts = errors.project @ tangent, errors.project @ deviations, np.array(unit)
    return Linearised(
        np.array(gram), np.array(cross), np.array(square), count, shape, offset, parts
    )


def _objective(theta: Mat, lin: Linearised) -> tuple[float, Mat]:
    """``f`` and its gradient by ``theta``: the log noise levels, then the log deviations of
    the groups (module docstring; :func:`_evaluated`)."""
    value, grad, _ = _evaluated(theta, lin)
    return value, grad


def _evaluated(theta: Mat, lin: Linearised) -> tuple[float, Mat, Mat]:
    """:func:`_objective` and the minimising ``x``, from one factorisation of ``M`` and one
    of ``H``. With ``w_g = sigma_g^-2``, ``u = M^-1 y(x)`` and ``K = M^-1 G``, the gradient
    by ``log sigma_g`` is ``n_g - w_g (|r_g(x)|^2 + tr(H^-1 J_g^T J_g))`` and by ``log t_j``
    it is ``t_j^2 tr(M_j (M^-1 - K H^-1 K^T - u u^T))``, ``K H^-1 K^T = W^T W`` with ``W =
    L_H^-1 K^T``. LAPACK's Cholesky routines directly: the matrices are small and called for
    often."""
    kinds = len(lin.count)
    if not len(lin.offset):
        return _noise_only(np.exp(-2.0 * theta), lin)
    scales = np.exp(lin.doubling * theta)
    weight, tau2 = scales[:kinds], scales[kinds:]
    lm, k_mat, lh, x = _posterior(weight, tau2, lin)
    errors = _errors(lin, x)
    v = lin.offset + lin.shape @ x
    u = _solve(lm, v)
    chi2 = float(weight @ errors) + float(v @ u)
    logdet = 2.0 * float(np.log(lh.diagonal()).sum() + np.log(lm.diagonal()).sum())
    noise = 2.0 * float(lin.count @ theta[:kinds])
    value = 0.5 * (chi2 + logdet + noise)
    gram, parts = lin.traced
    w_mat = _forward(lh, k_mat.T)
    rest = _inverse(lm) - w_mat.T @ w_mat - u[:, None] * u
    by_noise = lin.count - weight * (errors + gram @ _inverse(lh).ravel())
    return value, np.concatenate((by_noise, tau2 * (parts @ rest.ravel()))), x


def _noise_only(weight: Mat, lin: Linearised) -> tuple[float, Mat, Mat]:
    """:func:`_evaluated` without a prior, at the weights ``sigma_g^-2``."""
    lh, x = _without_prior(lin, weight)
    errors = _errors(lin, x)
    logdet = 2.0 * float(np.log(lh.diagonal()).sum())
    value = 0.5 * (float(weight @ errors) + logdet - float(lin.count @ np.log(weight)))
    grad = lin.count - weight * (errors + _traces(lin, lh))
    return value, grad, x


def _posterior(weight: Mat, tau2: Mat, lin: Linearised) -> tuple[Mat, Mat, Mat, Mat]:
    """At the weights ``sigma_g^-2`` and the deviations squared: the Cholesky factor of ``M``,
    ``K = M^-1 G``, the Cholesky factor of ``H`` and the minimising ``x``."""
    lm = _factor(ridged(_summed(tau2, lin.parts)))
    k_mat = _solve(lm, lin.hoisted[0])
    lh = _factor(ridged(_summed(weight, lin.gram) + lin.shape.T @ k_mat))
    x = -_solve(lh, weight @ lin.cross + k_mat.T @ lin.offset)
    return lm, k_mat, lh, x


def _summed(scales: Mat, terms: Mat) -> Mat:
    """``sum_i scales[i] terms[i]`` ``(m, m)`` of the square ``terms`` ``(n, m, m)``."""
    m = terms.shape[1]
    out: Mat = (scales @ terms.reshape(len(terms), -1)).reshape(m, m)
    return out


def _without_prior(lin: Linearised, weight: Mat) -> tuple[Mat, Mat]:
    """Without a prior, at the weights ``sigma_g^-2``: the Cholesky factor of ``H`` and the
    minimising ``x``."""
    lh = _factor(ridged(_summed(weight, lin.gram)))
    return lh, -_solve(lh, weight @ lin.cross)


def _traces(lin: Linearised, lh: Mat) -> Mat:
    """``tr(H^-1 J_g^T J_g)`` per kind from ``H``'s Cholesky factor."""
    out: Mat = lin.traced[0] @ _inverse(lh).ravel()
    return out


def _errors(lin: Linearised, x: Mat) -> Mat:
    """Each kind's ``|r_g(x)|^2`` at unit noise."""
    out: Mat = lin.square + (lin.hoisted[1] + lin.gram @ x) @ x
    return out


@cache
def _lapack() -> Any:
    """scipy's LAPACK wrappers, imported on first use."""
    from scipy.linalg import lapack

    return lapack


def _factor(a: Mat) -> Mat:
    """The lower Cholesky factor of the symmetric positive definite ``a``."""
    factor, info = _lapack().dpotrf(a, lower=1, clean=1)
    if info:
        raise np.linalg.LinAlgError("not positive definite")
    out: Mat = factor
    return out


def _solve(factor: Mat, b: Mat) -> Mat:
    """``A^-1 b`` from the lower Cholesky factor of ``A``."""
    out: Mat = _lapack().dpotrs(factor, b, lower=1)[0]
    return out


def _forward(factor: Mat, b: Mat) -> Mat:
    """``L^-1 b`` from the lower Cholesky factor ``L``."""
    out: Mat = _lapack().dtrtrs(factor, b, lower=1)[0]
    return out


def _inverse(factor: Mat) -> Mat:
    """The lower triangle of ``A^-1`` from the lower Cholesky factor of ``A`` (the upper
    triangle zero: :func:`_traced` reads the lower one)."""
    out: Mat = _lapack().dpotri(factor, lower=1)[0]
    return out


class _Search:
    """:func:`_evaluated` for L-BFGS-B, which asks for the value and then the gradient at each
    point: one evaluation serves both, and the minimising ``x`` of the last point is kept for
    the step from the search's end."""

    __slots__ = ("_at", "_grad", "_lin", "_x")

    def __init__(self, lin: Linearised) -> None:
        self._lin = lin
        self._at = b""
        self._grad = self._x = np.zeros(0)

    def _evaluate(self, theta: Mat) -> float:
        value, self._grad, self._x = _evaluated(theta, self._lin)
        self._at = theta.tobytes()
        return value

    def value(self, theta: Mat) -> float:
        return self._evaluate(theta)

    def gradient(self, theta: Mat) -> Mat:
        if theta.tobytes() != self._at:
            self._evaluate(theta)
        return self._grad

    def step(self, theta: Mat) -> Mat:
        """The minimising ``x`` at ``theta``."""
        if theta.tobytes() != self._at:
            self._evaluate(theta)
        return self._x


def maximise(
    lin: Linearised, noise: tuple[float, ...], deviations: Mat, floors: tuple[float, ...]
) -> tuple[tuple[float, ...], Mat, Mat]:
    """The noise levels (positions, then rotations) and the groups' deviations of greatest
    evidence, from ``noise`` and ``deviations``; the noise levels kept above ``floors`` (fixed
    where a floor is the level itself: given noise); and the linearised model's solution with
    them (a Gauss-Newton step from the linearisation point: where the solve starts). Without a
    prior, the noise levels alone: variance components (:func:`_components`)."""
    from scipy.optimize import fmin_l_bfgs_b

    kinds = len(lin.count)
    if not len(lin.offset):
        levels = _components(lin, noise, floors)
        theta = np.log(np.array(levels))
        weight = np.exp(-2.0 * theta)
        return levels, np.zeros(0), _without_prior(lin, weight)[1]
    theta0 = np.log(np.array([*noise, *np.clip(deviations, _LOWEST, _HIGHEST)], dtype=float))
    search = _Search(lin)
    found = fmin_l_bfgs_b(
        search.value,
        theta0,
        search.gradient,
        bounds=_bounds(noise, floors, len(deviations)),
        factr=_SETTLED / _EPSILON,
    )[0]
    return tuple(np.exp(found[:kinds]).tolist()), np.exp(found[kinds:]), search.step(found)


def _bounds(
    noise: tuple[float, ...], floors: tuple[float, ...], groups: int
) -> list[tuple[float, float | None]]:
    """L-BFGS-B's bounds on ``theta``: each log noise level above its floor's (fixed where the
    floor is the level itself), each log deviation within the deviations searched."""
    return [
        (math.log(f), math.log(f) if f == level else None)
        for f, level in zip(floors, noise, strict=True)
    ] + [(math.log(_LOWEST), math.log(_HIGHEST))] * groups


def _components(
    lin: Linearised, noise: tuple[float, ...], floors: tuple[float, ...]
) -> tuple[float, ...]:
    """The noise levels of greatest evidence without a prior: where the gradient of
    :func:`_noise_only` vanishes, ``sigma_g^2 = e_g / (n_g - tr(H^-1 J_g^T J_g / sigma_g^2))``
    (Förstner's variance components), iterated from ``noise`` until no level changes by more
    than :data:`_COMPONENTS_SETTLED`; each kept above its floor (fixed where the floor is the
    level itself: given noise)."""
    levels = np.array(noise, dtype=float)
    given = [f == v for f, v in zip(floors, noise, strict=True)]
    for _ in range(_COMPONENTS_ROUNDS):
        weight = levels**-2
        lh, x = _without_prior(lin, weight)
        error = _errors(lin, x).tolist()
        redundancy = (lin.count - weight * _traces(lin, lh)).tolist()
        old = levels.tolist()
        new = [
            level
            if fixed
            else max(math.sqrt(e / r if r > 0.0 and e > 0.0 else level * level), floor)
            for level, fixed, floor, e, r in zip(old, given, floors, error, redundancy, strict=True)
        ]
        levels = np.array(new)
        if all(abs(n / o - 1.0) <= _COMPONENTS_SETTLED for n, o in zip(new, old, strict=True)):
            break
    return tuple(levels.tolist())
