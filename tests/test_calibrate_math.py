"""Calibration's mathematics on real models: the Lie helpers, the chart and its inverse, the
analytic Jacobian against finite differences, and identifiability by numerical rank (Wu 2019
§V: eq. 23 for poses; the count for positions with K markers)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import urdf2dh
from urdf2dh import Joint, PoeModel, to_table
from urdf2dh.calibration import residuals as residuals_module
from urdf2dh.calibration.chart import (
    Estimate,
    absorbed,
    all_names,
    count,
    line_point,
    local_coordinates,
    normal_basis,
    retract,
    tool_screws,
)
from urdf2dh.calibration.levels import BASE_TOOL, FULL, GEOMETRY, OFFSETS
from urdf2dh.calibration.residuals import Data, Evaluation, evaluate, model_poses, residuals
from urdf2dh.geometry.lie import (
    exp_so3,
    left_jacobian,
    left_jacobian_inverse,
    log_se3,
    log_so3,
    quaternion_of,
    rotation_of,
)
from urdf2dh.geometry.se3 import twist_exp
from urdf2dh.model.identifiability import Identifiability


def param(params, name: str) -> float:
    """A table parameter, whether ``params`` is a dict (today) or a dataclass (refactor)."""
    return params[name] if isinstance(params, dict) else getattr(params, name)


def estimate(model: PoeModel, helical: bool = False, **kw) -> Estimate:
    """A pose estimate of ``model`` (points as feet of perpendiculars)."""
    joints = tuple(
        Joint(
            j.name,
            "helical" if helical and j.kind == "revolute" else j.kind,
            j.axis,
            None
            if j.point is None
            else (j.point if j.kind == "prismatic" else line_point(j.axis, j.point)),
            j.pitch,
            j.scale,
        )
        for j in model.joints
    )
    return Estimate.of(joints, home=model.home.copy(), **kw)


@pytest.mark.parametrize("angle", [0.0, 1e-9, 1e-5, 0.05, 0.3, 2.0, np.pi - 1e-4, np.pi - 1e-9])
def test_so3_exp_log_and_quaternions_round_trip(angle):
    rng = np.random.default_rng(1)
    axis = rng.normal(size=(20, 3))
    w = axis / np.linalg.norm(axis, axis=1, keepdims=True) * angle
    r = exp_so3(w)
    assert np.allclose(r @ np.swapaxes(r, 1, 2), np.eye(3), atol=1e-15)
    back = log_so3(r)
    same = np.linalg.norm(back - w, axis=1)
    flipped = np.linalg.norm(back + w, axis=1)  # at pi, w and -w are one rotation
    assert np.all(np.minimum(same, flipped if angle > 3 else same) <= 1e-12 * max(angle, 1)), back
    q = quaternion_of(r)
    assert np.allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-15) and np.all(q[:, 3] >= 0)
    assert np.allclose(rotation_of(q), r, atol=2e-15)


def test_left_jacobians_are_inverse_and_match_differences():
    rng = np.random.default_rng(2)
    for angle in (1e-7, 0.05, 0.099, 0.101, 1.0, 3.0):
        w = rng.normal(size=3)
        w *= angle / np.linalg.norm(w)
        assert np.allclose(left_jacobian(w) @ left_jacobian_inverse(w), np.eye(3), atol=1e-14)
        # exp([d]) exp([w]) = exp([w + J^-1 d]) to first order
        h = 1e-7
        numeric = np.array(
            [
                (log_so3(exp_so3(h * e) @ exp_so3(w)) - log_so3(exp_so3(-h * e) @ exp_so3(w)))
                / (2 * h)
                for e in np.eye(3)
            ]
        ).T
        assert np.allclose(numeric, left_jacobian_inverse(w), atol=1e-7)
    xi = np.array([0.3, -0.2, 0.5, 0.1, 0.4, -0.7])
    assert np.allclose(log_se3(twist_exp(xi)), xi, atol=1e-15)


@pytest.mark.parametrize("robot", ["puma560-actual", "stanford", "scara", "ur5"])
def test_chart_retraction_and_local_coordinates_are_inverse(robot):
    est = estimate(urdf2dh.load(robot), helical=robot == "puma560-actual")
    rng = np.random.default_rng(3)
    delta = rng.normal(size=count(est)) * 1e-3
    assert np.allclose(local_coordinates(est, retract(est, delta)), delta, atol=1e-12)
    assert np.allclose(local_coordinates(est, est), 0.0, atol=1e-12)


def _numeric_jacobian(est, data, sp, sr, h=1e-6):
    cols = []
    for k in range(count(est)):
        d = np.zeros(count(est))
        d[k] = h
        plus = residuals(retract(est, d), data, sp, sr)
        minus = residuals(retract(est, -d), data, sp, sr)
        cols.append((plus - minus) / (2 * h))
    return np.array(cols).T


CASES = [
    "pose",
    "tool-axis",
    "position",
    "prismatic",
    "no-scale",
    "offsets",
    "base-tool",
    "offsets-position",
    "some-fixed",
    "markers-fixed",
]


def _case(case: str) -> tuple[Estimate, Data, float, float]:
    """An estimate (every level; joint lines, pitches, scales; base, offsets; tool and markers,
    some coordinates held fixed) and measurements far from it (``J_l^-1`` matters)."""
    model = urdf2dh.load("stanford" if case in ("prismatic", "offsets") else "puma560-actual")
    rng = np.random.default_rng(4)
    q = model.sample(15, 5)
    level = {
        "no-scale": GEOMETRY,
        "offsets": OFFSETS,
        "offsets-position": OFFSETS,
        "base-tool": BASE_TOOL,
    }.get(case, FULL)
    if case in ("position", "offsets-position", "markers-fixed"):
        base = estimate(model, helical=case != "offsets-position")
        est = Estimate.of(
            base.joints,
            model.home.copy(),
            np.array([[200.0, 60.0, -10.0], [260.0, 30, 5]]),
            level=level,
            offsets=rng.normal(size=model.n) * 0.1 if level.offsets else None,
        )
        if case == "markers-fixed":
            free = np.ones(count(est), dtype=bool)
            free[[3, 10, -1, -5]] = False
            est = replace(est, free=free)
        data = Data(q, rng.normal(size=(15, 3)) * 100, rng.integers(0, 2, 15))
    else:
        est = estimate(
            model,
            helical=case not in ("prismatic", "offsets", "base-tool"),
            keep_tool_axis=case == "tool-axis",
            level=level,
        )
        if level.offsets:
            est = replace(est, offsets=rng.normal(size=model.n) * 0.1)
        if case == "some-fixed":
            free = np.ones(count(est), dtype=bool)
            free[[0, 7, 20, -2]] = False
            est = replace(est, free=free)
        poses = model_poses(est, q)
        turn = exp_so3(rng.normal(size=(15, 3)) * 0.2)  # residuals far from 0: J_l^-1 matters
        data = Data.poses(q, poses[:, :3, 3] + rng.normal(size=(15, 3)), poses[:, :3, :3] @ turn)
    return est, data, 0.5, 0.01


@pytest.mark.parametrize("case", CASES)
def test_analytic_jacobian_equals_finite_differences(case):
    """Every level's Jacobian against central differences of the residuals."""
    est, data, sp, sr = _case(case)
    _, jac = evaluate(est, data, sp, sr)
    numeric = _numeric_jacobian(est, data, sp, sr)
    assert jac.shape == numeric.shape == (len(data) * data.rows, count(est))
    scale = np.abs(jac).max(axis=0)
    assert np.all(np.abs(jac - numeric).max(axis=0) <= 1e-6 * scale), np.abs(jac - numeric).max(0)


def _adjoint(p: np.ndarray) -> np.ndarray:
    r, t = p[:3, :3], p[:3, 3]
    skew = np.cross(np.eye(3), t)  # [t]: row i is e_i x t
    return np.block([[r, np.zeros((3, 3))], [skew @ r, r]])


def _reference(est: Estimate, data: Data, sp: float, sr: float) -> tuple[np.ndarray, np.ndarray]:
    """The residuals and Jacobian of residuals.py's module docstring, one configuration and one
    coordinate at a time: products of :func:`twist_exp`, ``6 x 6`` adjoints."""
    chain, n = est.chain, est.n
    offsets = est.joint_offsets()
    names = [name.split(".") for name in all_names(est)]
    res, rows = [], []
    for q, seen, k, measured in zip(
        data.q,
        data.points,
        data.markers,
        data.rotations if data.rotations is not None else [None] * len(data),
        strict=True,
    ):
        frames, hats = [np.eye(4)], []
        for i in range(n):
            u, p = chain.axis[i], chain.point[i]
            if chain.kinds[i] == "prismatic":
                hat = np.concatenate([np.zeros(3), u])
            else:
                hat = np.concatenate([u, np.cross(p, u) + chain.pitch[i] * u])
            hats.append(hat)
            frames.append(frames[-1] @ twist_exp(hat * chain.scale[i] * (q[i] + offsets[i])))
        tool = frames[-1] @ est.home
        x = tool[:3, :3] @ est.markers[k] + tool[:3, 3]
        phi = None if measured is None else log_so3(tool[:3, :3] @ measured.T)
        res.append(np.concatenate([(x - seen) / sp, [] if phi is None else phi / sr]))
        cols = []
        for (who, what), free in zip(
            names, est.free if est.free is not None else [True] * len(names), strict=True
        ):
            if not free:
                continue
            dx = None
            if who == "base":
                d = np.eye(6)[["rx", "ry", "rz", "x", "y", "z"].index(what)]
            elif who == "tool" and est.keep_tool_axis:
                d = _adjoint(tool) @ tool_screws(est)[:, ["turn", "slide"].index(what)]
            elif who == "tool":
                d = _adjoint(tool) @ np.eye(6)[["rx", "ry", "rz", "x", "y", "z"].index(what)]
            elif who.startswith("marker"):
                d = np.zeros(6)
                shift = np.eye(3)["xyz".index(what)]
                dx = frames[-1][:3, :3] @ shift if int(who[6:]) == k else np.zeros(3)
            else:
                i = chain.names.index(who)
                u, p = chain.axis[i], chain.point[i]
                before, after = _adjoint(frames[i]), _adjoint(frames[i + 1])
                e1, e2 = normal_basis(u)
                motion = q[i] + offsets[i]
                if what in ("turn1", "turn2", "shift1", "shift2"):
                    e = e1 if what.endswith("1") else e2
                    if what.startswith("shift"):
                        eta = np.concatenate([np.zeros(3), e])
                    elif chain.kinds[i] == "prismatic":
                        eta = np.concatenate([e, np.zeros(3)])
                    else:
                        eta = np.concatenate([e, np.cross(p, e)])
                    last = est.keep_tool_axis and i == n - 1
                    d = before @ eta - (0.0 if last else after @ eta)
                elif what == "pitch":
                    d = before @ np.concatenate([np.zeros(3), u]) * chain.scale[i] * motion
                elif what == "offset":
                    d = before @ hats[i] * chain.scale[i]
                else:  # scale
                    d = before @ hats[i] * motion
            if dx is None:
                dx = d[3:] + np.cross(d[:3], x)
            rot = [] if phi is None else left_jacobian_inverse(phi) @ d[:3] / sr
            cols.append(np.concatenate([dx / sp, rot]))
        rows.append(np.array(cols).T.reshape(data.rows, -1))
    return np.concatenate(res), np.concatenate(rows)


@pytest.mark.parametrize("case", CASES)
def test_residuals_and_jacobian_equal_a_plain_reference(case):
    """The batched residuals and Jacobian (every level, pose and position measurements, fixed
    coordinates) equal the module docstring's formulas evaluated one configuration and one
    coordinate at a time, to round-off."""
    est, data, sp, sr = _case(case)
    r, jac = evaluate(est, data, sp, sr)
    r_ref, jac_ref = _reference(est, data, sp, sr)
    size = np.abs(data.points).max() / sp  # residuals are differences of positions of this size
    assert np.abs(r - r_ref).max() <= 1e-13 * size
    assert np.abs(jac - jac_ref).max() <= 1e-13 * np.abs(jac_ref).max()
    assert np.array_equal(residuals(est, data, sp, sr), r)


@pytest.mark.parametrize("case", ["position", "some-fixed"])
def test_measurements_beyond_one_chunk_evaluate_as_one(case, monkeypatch):
    """Beyond :data:`~urdf2dh.calibration.residuals.CHUNK` measurements the model is evaluated a
    chunk at a time, and a solver's evaluation makes its Jacobian in the same pass: the
    residuals and Jacobian are those of one pass over all of them, bit for bit."""
    est, data, sp, sr = _case(case)
    r, jac = evaluate(est, data, 1.0, 1.0)
    monkeypatch.setattr(residuals_module, "CHUNK", 4)  # 15 measurements: four chunks
    chunked = Evaluation.at(est, data)
    assert isinstance(chunked.made, np.ndarray)  # the Jacobian, made with the residuals
    assert np.array_equal(chunked.residuals, r) and np.array_equal(chunked.jacobian(), jac)
    r_w, jac_w = evaluate(est, data, sp, sr)  # weighted, chunked
    monkeypatch.setattr(residuals_module, "CHUNK", 1024)
    one = evaluate(est, data, sp, sr)
    assert np.array_equal(one[0], r_w) and np.array_equal(one[1], jac_w)


@pytest.mark.parametrize("robot", ["puma560-actual", "stanford"])
def test_offsets_are_absorbed_into_the_same_motion(robot):
    """A model with joint offsets and the same model with them absorbed by the lines and the
    tool (chart.absorbed) move alike at every configuration."""
    model = urdf2dh.load(robot)
    rng = np.random.default_rng(9)
    est = replace(estimate(model), level=OFFSETS, offsets=rng.normal(size=model.n) * 0.3)
    flat = absorbed(est)
    q = model.sample(50, 10)
    assert np.allclose(model_poses(est, q), model_poses(flat, q), atol=1e-12 * model.size())


def _rank(jac: np.ndarray, relative: float = 1e-7) -> int:
    jac = jac / np.linalg.norm(jac, axis=0).clip(min=1e-300)
    s = np.linalg.svd(jac, compute_uv=False)
    return int(np.sum(s > relative * s[0]))


@pytest.mark.parametrize("robot", ["puma560-actual", "ur5", "stanford", "scara", "panda"])
def test_pose_count_is_wu_eq_23_and_the_jacobian_has_that_rank(robot):
    """Our coordinates are exactly 5h + 4r + 2t + n + 6 (eq. 23); the Jacobian over 30 random
    configurations has that rank; and joint offsets (q_i -> q_i + dq_i) and a base transform
    added as further parameters leave the rank unchanged: the model absorbs them."""
    model = urdf2dh.load(robot)
    est = estimate(model)
    assert count(est) == Identifiability.of(j.kind for j in model.joints).maximum
    q = model.sample(30, 6)
    poses = model_poses(est, q)
    data = Data.poses(q, poses[:, :3, 3], poses[:, :3, :3])
    _, jac = evaluate(est, data, 1.0, 1.0 / model.size())
    assert _rank(jac) == count(est)

    def pose_rows(offsets: np.ndarray, base: np.ndarray) -> np.ndarray:
        t = twist_exp(base) @ model_poses(est, q + offsets)
        return np.concatenate(
            [
                t[:, :3, 3],
                log_so3(t[:, :3, :3] @ np.swapaxes(poses[:, :3, :3], 1, 2)) * model.size(),
            ],
            axis=1,
        ).ravel()

    extra, h = [], 1e-6
    for k in range(model.n + 6):
        e = np.zeros(model.n + 6)
        e[k] = h
        plus = pose_rows(e[: model.n], e[model.n :])
        minus = pose_rows(-e[: model.n], -e[model.n :])
        extra.append((plus - minus) / (2 * h))
    both = np.hstack([jac, np.array(extra).T])  # rows alike: rotation x size in both
    assert _rank(both) == count(est)


@pytest.mark.parametrize(
    "markers, layout_known, expected_tool",
    [
        (1, False, 0),
        (3, False, 0),
        (1, True, 3),
        (2, True, 5),
        (3, True, 6),
    ],
)
def test_position_measurements_identify_the_chain_and_what_markers_fix(
    markers, layout_known, expected_tool
):
    """Positions of K markers: the chain (5h + 4r + 2t + n) and each marker's point, 3K, are
    identifiable; the tool frame M is not (only M m_k is seen). With the markers' positions on
    the tool known, M's identifiable part is 3 with one marker (its position: the tool turns
    about the point unseen), 5 with two (the turn about their line is unseen), all 6 with three.
    """
    model = urdf2dh.load("puma560-actual")
    est = estimate(model, helical=True)
    chain = count(est) - 6
    rng = np.random.default_rng(7)
    local = rng.normal(size=(markers, 3)) * 30.0
    q = model.sample(40, 8)

    def points(x: np.ndarray) -> np.ndarray:
        moved = retract(est, x[: count(est)])
        m = local + (0 if layout_known else x[count(est) :].reshape(-1, 3))
        t = model_poses(moved, q)
        return (np.einsum("nij,kj->nki", t[:, :3, :3], m) + t[:, None, :3, 3]).ravel()

    size = count(est) + (0 if layout_known else 3 * markers)
    jac = []
    for k in range(size):
        e = np.zeros(size)
        e[k] = 1e-5
        jac.append((points(e) - points(-e)) / 2e-5)
    rank = _rank(np.array(jac).T)
    if layout_known:
        assert rank == chain + expected_tool
    else:  # M and the markers' positions on the tool trade off: 3K of their 6 + 3K
        assert rank == chain + 3 * markers


def test_style_ur_puts_a_free_last_x_on_the_tool():
    """dh --style ur: when the tool z lies exactly on the last axis, its turn about the axis goes
    into the last row's theta and the tool transform is the identity (UR's flange is D-H frame
    6); other styles keep it in the tool."""
    ur5 = urdf2dh.load("ur5")
    last = ur5.joints[-1]
    axis = last.axis
    turn = twist_exp(np.r_[axis, np.cross(last.point, axis)] * 0.3)
    joints = (*ur5.joints[:-1], Joint(last.name, last.kind, axis, last.point))
    home = turn @ ur5.home
    home[:3, 2] = axis  # the tool z exactly on the axis (the URDF has 5e-12 rad of round-off)
    home[:3, 0] -= (home[:3, 0] @ axis) * axis
    home[:3, 0] /= np.linalg.norm(home[:3, 0])
    home[:3, 1] = np.cross(axis, home[:3, 0])
    model = PoeModel(joints, home, "ur5-turned")
    ur = to_table(model, "dh", style="ur")
    assert abs(param(ur.tool, "theta")) < 1e-15 and abs(param(ur.tool, "d")) < 1e-15
    wu = to_table(model, "dh")
    assert abs(param(wu.tool, "theta")) > 0.1
