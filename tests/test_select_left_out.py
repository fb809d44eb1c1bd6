"""Leaving configurations out of a level's fit (:mod:`urdf2dh.calibration.select`): the grouped
deleted residuals and the fit moved without some measurements, each against a plain reference
on a seeded UR5's level fits (poses, and positions of three markers; with and without a prior;
each configuration or folds of them left out), by both of the module's factorisations of the
hat matrix; and the levels some configuration alone determines refused."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import urdf2dh
from urdf2dh.calibration import select
from urdf2dh.calibration.measure import marker_layout, perturb, synthesize
from urdf2dh.calibration.problem import CalibrationProblem, Options, fit_options
from urdf2dh.calibration.select import (
    fold_of_configurations,
    hat_basis,
    judge_levels,
    left_out_errors,
    without_rows,
)
from urdf2dh.calibration.solver import Linearisation, Problem
from urdf2dh.calibration.start import to_data

NOISE = 1e-4  # m and rad


@pytest.fixture(scope="module", params=["poses", "positions"])
def fitted(request):
    """Each level's problem and linearisation at its solution, and each measurement's
    configuration, on a perturbed UR5 measured at 14 configurations."""
    ur5 = urdf2dh.load("ur5")
    actual = perturb(ur5, 4, 0.002, 0.002)
    pose = request.param == "poses"
    layout = None if pose else marker_layout(ur5, 3, seed=2)
    m = synthesize(actual, 14, NOISE, NOISE, seed=5, layout=layout, pose=pose)
    problem = CalibrationProblem.of(ur5, m, pose, (None, None), layout, 0.0, 0, None)
    first = judge_levels(problem, Options(fit_options(problem)))
    data = to_data(problem.fit, pose, problem.markers)
    at = {lv: (f.problem(data), f.solution.lin) for lv, f in first.fits.items()}
    assert {p.prior is None for p, _ in at.values()} == {True, False}  # with and without
    return at, problem.fit.configurations()


def _deleted(problem: Problem, lin: Linearisation, group: np.ndarray) -> np.ndarray:
    """The reference: ``(I - H_cc)^-1 e_c`` for each group ``c``, ``H = Q Q^T`` from a QR
    factorisation of the weighted Jacobian (the prior's rows included), as squared position
    (and rotation) errors in the physical units."""
    r, jac = problem.weighted(lin)
    m, rows = problem.data_rows, lin.rows
    q = np.linalg.qr(jac)[0][:m]
    out = np.empty(m)
    for c in range(int(group.max()) + 1):
        mine = np.flatnonzero(np.repeat(group == c, rows))
        block = np.eye(len(mine)) - q[mine] @ q[mine].T
        out[mine] = np.linalg.solve(block, r[mine])
    each = out.reshape(-1, rows)
    squared = [np.sum(each[:, :3] ** 2, axis=1) * problem.sigma_pos**2]
    if rows == 6:
        squared.append(np.sum(each[:, 3:] ** 2, axis=1) * problem.sigma_rot**2)
    return np.stack(squared, axis=1)


def _path(path: str, monkeypatch: pytest.MonkeyPatch) -> list[bool]:
    """The hat matrix's basis by the eigenvectors alone (``eigen``), or by the Cholesky factor
    where it is taken (``cholesky``): whether it was, at each call."""
    taken: list[bool] = []
    factor = select._inverse_factor

    def chosen(normal: np.ndarray) -> np.ndarray | None:
        out = None if path == "eigen" else factor(normal)
        taken.append(out is not None)
        return out

    monkeypatch.setattr(select, "_inverse_factor", chosen)
    return taken


@pytest.mark.parametrize("path", ["cholesky", "eigen"])
@pytest.mark.parametrize("folds", [None, 4])
def test_left_out_errors_are_the_deleted_residuals(fitted, folds, path, monkeypatch):
    """Every level's left-out errors equal the reference formula to round-off, by the Cholesky
    factor (every direction kept) and by the eigenvectors; the blocks of single pose
    configurations have Frobenius norms below 1, the folds' and the markers' do not (their
    ``I - H_cc`` factored to show it invertible)."""
    at, (index, configurations) = fitted
    taken = _path(path, monkeypatch)
    group = fold_of_configurations(configurations, folds, 7)[index]
    for problem, lin in at.values():
        mine = left_out_errors(problem, lin, group)
        assert mine is not None
        assert np.allclose(mine, _deleted(problem, lin, group), rtol=1e-10, atol=0.0)
    assert taken == [path == "cholesky"] * len(at)  # well-conditioned: the bound shows it


@pytest.mark.parametrize("path", ["cholesky", "eigen"])
def test_a_fit_without_some_measurements_is_the_least_squares_step(fitted, path, monkeypatch):
    """:func:`~urdf2dh.calibration.select.without_rows` moves each level's solution by the
    least-squares step on the rows kept (the prior's among them), by either path, and gives
    the moved fit's hat matrix's basis."""
    at, _ = fitted
    _path(path, monkeypatch)
    for problem, lin in at.values():
        keep = np.setdiff1d(np.arange(len(problem.data)), [1, 6])
        part, moved, basis = without_rows(problem, lin, keep)
        assert np.array_equal(basis, hat_basis(part.weighted(moved)[1]))  # the moved fit's
        r, jac = problem.weighted(lin)
        kept = (keep[:, None] * lin.rows + np.arange(lin.rows)).ravel()
        fitted_rows = np.r_[kept, np.arange(problem.data_rows, len(r))]
        step = np.linalg.lstsq(jac[fitted_rows], -r[fitted_rows], rcond=None)[0]
        expected = lin.residuals[kept] + lin.jacobian[kept] @ step
        assert len(part.data) == len(keep) and part.prior is problem.prior
        assert np.allclose(moved.residuals, expected, rtol=0.0, atol=1e-10 * np.abs(expected).max())
        if problem.prior is not None:  # the moved fit is at the least-squares solution
            r_moved, jac_moved = part.weighted(moved)
            assert np.abs(jac_moved.T @ r_moved).max() < 1e-9 * np.abs(jac_moved).max()


def test_a_level_some_configuration_alone_determines_is_not_judged(fitted):
    """A parameter only one configuration's rows see: ``None``; seen by no configuration (a
    rank-deficient Jacobian, the eigenvector path), the others are judged as without it."""
    at, (index, _) = fitted
    problem, lin = next((p, lin) for p, lin in at.values() if p.prior is None)
    alone = lin.jacobian.copy()
    alone[np.repeat(index, lin.rows) != 3, 0] = 0.0
    assert left_out_errors(problem, replace(lin, jacobian=alone), index) is None
    unseen = lin.jacobian.copy()
    unseen[:, 0] = 0.0
    without = replace(lin, jacobian=lin.jacobian[:, 1:])
    mine = left_out_errors(problem, replace(lin, jacobian=unseen), index)
    assert mine is not None
    assert np.allclose(mine, _deleted(problem, without, index), rtol=1e-10, atol=0.0)
