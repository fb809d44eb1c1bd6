"""The prior as errors of a robot's links, the deviations of greatest evidence, and the levels
judged by leaving configurations out: each against an independent computation (finite
differences, refits), and on robots whose errors are known."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.optimize import approx_fprime

import urdf2dh
from urdf2dh.calibration.calibration import calibrate
from urdf2dh.calibration.chart import count, local_coordinates, retract
from urdf2dh.calibration.evidence import _objective, linearised, maximise
from urdf2dh.calibration.fit import fit_before, joint_locations, level_start, solve_level
from urdf2dh.calibration.levels import GEOMETRY
from urdf2dh.calibration.measure import perturb, synthesize
from urdf2dh.calibration.prior import Deviations, Prior, Regulariser, link_errors
from urdf2dh.calibration.residuals import evaluate, residuals
from urdf2dh.calibration.select import left_out_errors
from urdf2dh.calibration.solver import solve
from urdf2dh.calibration.start import FitOptions, to_data
from urdf2dh.geometry.se3 import pose_errors, twist_exp
from urdf2dh.model.poe import PoeModel

NOISE = 1e-4  # m and rad


@pytest.fixture(scope="module")
def ur5():
    return urdf2dh.load("ur5")


def _geometry(nominal: PoeModel, m, level: str = "geometry"):
    """The level's start from the base-and-tool fit, the joints' locations, the data."""
    opts = FitOptions(pose=m.quaternions is not None, level=level)
    ids = m.marker_ids()
    _, before = fit_before(nominal, m, opts, ids)
    start, _, _ = level_start(nominal, before.solution.estimate, opts, ids)
    where = joint_locations(nominal, m, opts, ids, before.solution.estimate)
    return opts, before, start, where, to_data(m, opts.pose, ids)


@pytest.mark.parametrize("level", ["offsets", "geometry", "full"])
def test_the_prior_s_coordinates_and_their_derivatives(ur5, level):
    """The deviations the prior sees are the chart's coordinates from its centre, and their
    derivatives equal central differences through the chart's retraction."""
    m = synthesize(perturb(ur5, 2, 0.002, 0.002), 20, NOISE, NOISE, seed=3)
    _, _, start, where, _ = _geometry(ur5, m, level)
    errors = link_errors(start, where)
    assert errors is not None
    est = retract(start, np.random.default_rng(4).normal(0.0, 2e-3, count(start)))
    assert np.allclose(errors.deviations(est), local_coordinates(start, est)[errors.at], atol=1e-14)
    tangent = errors.tangent(est)
    step = 1e-6
    for k in range(count(est)):
        move = np.zeros(count(est))
        move[k] = step
        plus = errors.deviations(retract(est, move))
        minus = errors.deviations(retract(est, -move))
        assert np.allclose(tangent[:, k], (plus - minus) / (2 * step), atol=1e-7), k


def test_a_link_s_error_moves_every_later_joint_and_the_base_is_free(ur5):
    """The prior's metric is the links': a rigid motion of the whole robot (the base) costs
    nothing to first order; the elbow's link turned by 1 mrad (everything after it moves)
    costs one deviation squared, the same turn of a single line alone far more (it is not a
    link's error)."""
    m = synthesize(ur5, 20, NOISE, NOISE, seed=5)
    _, _, start, where, _ = _geometry(ur5, m)
    errors = link_errors(start, where)
    assert errors is not None and errors.links == 5
    dev = Deviations((1e-3,) * 5, 1e-3, 1e-3, 1.0)
    prior = Regulariser.of(errors, dev)

    def cost(g_index: int, twist: np.ndarray) -> float:
        """Every joint from ``g_index`` on moved by ``twist`` (about the device origin)."""
        chain = start.chain
        g = twist_exp(twist)
        axis, point = chain.axis.copy(), chain.point.copy()
        axis[g_index:] = axis[g_index:] @ g[:3, :3].T
        point[g_index:] = point[g_index:] @ g[:3, :3].T + g[:3, 3]
        point[g_index:] -= (
            np.sum(point[g_index:] * axis[g_index:], axis=1)[:, None] * axis[g_index:]
        )
        moved = replace(start, chain=replace(chain, axis=axis, point=point))
        r = prior.residuals(moved)
        return float(r @ r)

    # the base moved: free to first order (the cost is of fourth order in the motion, where
    # any first-order part would make it of second order)
    base = np.array([1e-3, 2e-3, -1e-3, 5e-3, 0.0, 1e-3])
    assert cost(0, base) < 1e-3 and cost(0, base / 10) < 3e-4 * cost(0, base)
    # the link before the elbow turned about the elbow's location, normal to its axis
    elbow = 2
    u = start.chain.axis[elbow]
    normal = np.cross(u, [0.0, 0.0, 1.0])
    normal /= np.linalg.norm(normal)
    turn = 1e-3 * normal
    link = cost(elbow, np.concatenate([turn, np.cross(where[elbow], turn)]))
    assert link == pytest.approx(1.0, rel=1e-3)
    # the elbow's line alone turned the same (the later joints left behind): a larger cost
    single = replace(start, chain=start.chain)
    axis = start.chain.axis.copy()
    axis[elbow] = axis[elbow] + np.cross(turn, axis[elbow])
    axis[elbow] /= np.linalg.norm(axis[elbow])
    alone = replace(single, chain=replace(start.chain, axis=axis))
    r = prior.residuals(alone)
    assert float(r @ r) > 2.0 * link


@pytest.fixture(scope="module")
def ur10_full():
    """The full level of the UR10's real poses linearised at its start, with its prior's link
    errors: the evidence's linearisation and what it was made of."""
    from pathlib import Path

    data_dir = Path(__file__).resolve().parents[1] / "examples" / "calibration-data"
    from urdf2dh.calibration.measurements import read_measurements

    nominal = urdf2dh.load(str(data_dir / "ur10" / "ur10_robot.urdf"), tip="wrist_3_link")
    joints = tuple(j.name for j in nominal.joints)
    m = read_measurements(data_dir / "ur10" / "ur10_pose_fit.csv", joints)
    _, _, start, where, data = _geometry(nominal, m, "full")
    errors = link_errors(start, where)
    assert errors is not None
    r0, jac = evaluate(start, data, 1.0, 1.0)
    assert jac is not None
    here = (errors, errors.tangent(start), errors.deviations(start), errors.parts(nominal.size()))
    return linearised(r0, jac, data.rows, here), r0, jac


_THETA = np.log(np.array([2e-3, 4e-3, 1e-3, 3e-3, 2e-4, 1e-3, 5e-3, 1e-3, 2e-3]))


def test_the_evidence_gradient_equals_finite_differences(ur10_full):
    """The marginal likelihood's analytic gradient (noise levels and every group's deviation)
    against central differences, on the UR10's real poses."""
    lin = ur10_full[0]
    assert len(_THETA) == 2 + len(lin.parts)
    value, grad = _objective(_THETA, lin)
    numeric = approx_fprime(_THETA, lambda t: _objective(t, lin)[0], 1e-6)
    assert math.isfinite(value)
    assert np.allclose(grad, numeric, rtol=1e-4, atol=1e-4 * np.abs(grad).max())


def test_the_evidence_equals_the_gaussian_marginal_likelihood(ur10_full):
    """The objective against the restricted likelihood written out with dense matrices
    (Harville 1974): the measurements and the prior's coordinates ``z = (r0, y0)`` with design
    ``X = (J, G)`` and covariance ``V = diag(sigma_g^2 I, M)``, twice ``f`` being ``log det V +
    log det X^T V^-1 X + z^T P z``, ``P = V^-1 - V^-1 X (X^T V^-1 X)^-1 X^T V^-1``; at
    several noise levels and deviations, on the UR10's real poses."""
    lin, r0, jac = ur10_full
    positions = (np.arange(len(r0)) % 6) < 3
    for scale in (0.3, 1.0, 4.0):
        theta = _THETA + np.log(scale) * np.arange(len(_THETA)) / len(_THETA)
        sigma2, tau2 = np.exp(2.0 * theta[:2]), np.exp(2.0 * theta[2:])
        m = np.einsum("g,gij->ij", tau2, lin.parts)
        v = np.zeros((len(r0) + len(m),) * 2)
        v[: len(r0), : len(r0)] = np.diag(np.where(positions, sigma2[0], sigma2[1]))
        v[len(r0) :, len(r0) :] = m
        x = np.vstack([jac, lin.shape])
        z = np.concatenate([r0, lin.offset])
        v_inv = np.linalg.inv(v)
        h = x.T @ v_inv @ x
        p = v_inv - v_inv @ x @ np.linalg.solve(h, x.T @ v_inv)
        dense = np.linalg.slogdet(v)[1] + np.linalg.slogdet(h)[1] + z @ p @ z
        assert _objective(theta, lin)[0] == pytest.approx(0.5 * dense, rel=1e-9, abs=1e-6)


@pytest.mark.parametrize("fixed", [False, True])
def test_the_evidence_search_is_scipy_s_l_bfgs_b_on_the_objective(ur10_full, fixed):
    """The search for the greatest evidence goes where scipy.optimize.minimize's L-BFGS-B goes
    on :func:`_objective` (the value and gradient from one evaluation, its stopping rule, its
    bounds), bit for bit, on the UR10's real poses: the levels, the deviations and the step
    (the linearised model's solution there); with both noise levels free, and with the
    positions' given (its floor is the level: a fixed bound)."""
    from scipy.optimize import minimize

    from urdf2dh.calibration.evidence import _SETTLED, _bounds, _posterior

    lin = ur10_full[0]
    noise, deviations = (2e-3, 4e-3), np.exp(_THETA[2:])
    floors = (2e-3 if fixed else 1e-9, 1e-9)
    levels, found, step = maximise(lin, noise, deviations, floors)
    theta0 = np.log(np.array([*noise, *deviations]))
    reference = minimize(
        _objective, theta0, args=(lin,), jac=True, method="L-BFGS-B",
        bounds=_bounds(noise, floors, len(deviations)),
        options={"ftol": _SETTLED},
    )  # fmt: skip
    assert reference.nit > 3 and (abs(levels[0] / 2e-3 - 1.0) < 1e-15) == fixed
    assert levels == tuple(np.exp(reference.x[:2]).tolist())
    assert np.array_equal(found, np.exp(reference.x[2:]))
    weight, tau2 = np.exp(-2.0 * reference.x[:2]), np.exp(2.0 * reference.x[2:])
    assert np.array_equal(step, _posterior(weight, tau2, lin)[3])


def test_the_noise_levels_without_a_prior_are_where_the_evidence_is_greatest(ur5):
    """Without a prior the noise levels of greatest evidence come from variance components
    iterated to their fixed point: there the evidence's gradient vanishes, and it is a minimum
    of its negative (no nearby levels do better)."""
    m = synthesize(ur5, 25, 3e-4, 1e-3, seed=8)  # base and tool explain it but for the noise
    _, before, _, _, data = _geometry(ur5, m, "offsets")
    r0, jac = evaluate(before.solution.estimate, data, 1.0, 1.0)
    assert jac is not None
    lin = linearised(r0, jac, data.rows)
    levels, deviations, _ = maximise(lin, (1.0, 1.0), np.zeros(0), (1e-9, 1e-9))
    assert len(deviations) == 0 and 1e-4 < levels[0] < 1e-3 and 3e-4 < levels[1] < 3e-3
    theta = np.log(np.array(levels))
    value, grad = _objective(theta, lin)
    assert np.allclose(grad, 0.0, atol=1e-4)
    for move in ([0.01, 0.0], [0.0, 0.01], [-0.01, 0.0], [0.0, -0.01]):
        assert _objective(theta + np.array(move), lin)[0] > value


def test_the_link_that_was_made_wrong_is_the_one_the_evidence_frees(ur5):
    """A UR5 whose only error is the link before its elbow, turned by 3 mrad about the elbow
    (everything from the elbow on moved), measured at 40 configurations: the deviation of
    greatest evidence of that link is near its error and the others' far smaller, and the
    robot is found to the noise."""
    elbow = 2
    turn = 3e-3 * np.array([0.0, 0.0, 1.0])  # normal to the elbow's axis
    g = twist_exp(np.concatenate([turn, np.cross(ur5.joints[elbow].point, turn)]))
    joints = tuple(
        j
        if i < elbow
        else replace(j, axis=g[:3, :3] @ j.axis, point=g[:3, :3] @ j.point + g[:3, 3])
        for i, j in enumerate(ur5.joints)
    )
    actual = PoeModel(joints, g @ ur5.home, "bent")
    m = synthesize(actual, 40, NOISE, NOISE, seed=7)
    cal = calibrate(ur5, m, level="geometry")
    prior = cal.selection.score("geometry").prior
    assert prior is not None
    links = np.array(prior.links)  # the links before joints 2, 3, ...: the elbow's is 1
    assert int(np.argmax(links)) == elbow - 1
    assert 1e-3 < links.max() < 1e-2 and np.sort(links)[-2] < 0.3 * links.max()
    fresh = ur5.sample(200, 9)
    position, _ = pose_errors(cal.model.fk_batch(fresh), actual.fk_batch(fresh))
    assert position < 10 * NOISE


def test_leaving_each_configuration_out_agrees_with_refits(ur5):
    """The grouped deleted residuals of the geometry level with a stated prior against the
    level solved again without each configuration: the same prediction errors."""
    actual = perturb(ur5, 10, 0.002, 0.002)
    layout_free = synthesize(actual, 18, NOISE, NOISE, seed=11)
    opts, before, start, where, data = _geometry(ur5, layout_free)
    opts = replace(opts, prior=Prior(1e-3, 1e-3))
    noise = (before.sigma_pos, before.sigma_rot)
    fit = solve_level(start, data, opts, ur5.size(), start, noise, where)
    problem = fit.problem(data)
    index, configurations = layout_free.configurations()
    predicted = left_out_errors(problem, fit.solution.lin, index)
    assert predicted is not None
    refits = []
    for c in range(configurations):
        keep = index != c
        part = replace(problem, data=to_data(layout_free.subset(np.flatnonzero(keep)), True, []))
        again = solve(fit.solution.estimate, part, ur5.size(), 200)
        assert again.converged
        held = to_data(layout_free.subset(np.flatnonzero(~keep)), True, [])
        r = residuals(again.estimate, held, 1.0, 1.0)
        refits.append([float(r[:3] @ r[:3]), float(r[3:] @ r[3:])])
    refits = np.array(refits)
    assert np.allclose(predicted, refits, rtol=0.05, atol=1e-3 * NOISE**2)
    assert math.sqrt(np.mean(predicted[:, 0])) == pytest.approx(
        math.sqrt(np.mean(refits[:, 0])), rel=0.01
    )


def test_the_default_chooses_the_level_with_the_prior_of_greatest_evidence(ur5):
    """The report's selection: every level's left-out error, the prior's deviations at the
    geometry and full levels (none below), and the choice."""
    m = synthesize(perturb(ur5, 12, 0.002, 0.002), 30, NOISE, NOISE, seed=13)
    cal = calibrate(ur5, m)
    sel = cal.selection
    assert sel is not None and sel.seed is None and sel.folds == 30 == sel.configurations
    priors = {s.level: s.prior for s in sel.scores}
    assert priors["base-tool"] is None and priors["offsets"] is None
    assert priors["geometry"] is not None and len(priors["geometry"].links) == 5
    assert cal.level in ("geometry", "full")
    with_none = calibrate(ur5, m, prior="none")
    assert all(s.prior is None for s in with_none.selection.scores)
    assert GEOMETRY.lines
