"""Calibration on real models: Wu 2019's PUMA 560 from its nominal to its
actual model, noise at the noise floor with honest standard deviations, position-only
measurements with one and three markers, SCARA and Stanford (prismatic) arms, helical joints,
and a UR5 identified into a file UR's description takes."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from consumers import ur_description_urdf

import urdf2dh
from urdf2dh import DEFAULT, Joint, PoeModel, calibrate, to_table
from urdf2dh.calibration.chart import Estimate, line_point, local_coordinates
from urdf2dh.calibration.identify import identify, moved
from urdf2dh.calibration.measure import marker_layout, perturb, synthesize
from urdf2dh.calibration.measurements import Measurements
from urdf2dh.calibration.report import to_dict
from urdf2dh.calibration.start import FitOptions, placement
from urdf2dh.check.papers import agrees
from urdf2dh.emit.export import ExportOptions, export_table
from urdf2dh.geometry.lie import quaternion_of
from urdf2dh.geometry.se3 import pose_errors, twist_exp
from urdf2dh.io.catalog import our_robots_dir

NOISE_POS, NOISE_ROT = 0.01, 1e-5  # mm and rad


@pytest.fixture(scope="module")
def puma():
    return urdf2dh.load("puma560-nominal"), urdf2dh.load("puma560-actual")


def fk_error(model: PoeModel, truth: PoeModel, seed: int = 11) -> tuple[float, float]:
    q = truth.sample(1000, seed)
    return pose_errors(model.fk_batch(q), truth.fk_batch(q))


def param(params, name: str) -> float:
    """A table parameter, whether ``params`` is a dict (today) or a dataclass (refactor)."""
    return params[name] if isinstance(params, dict) else getattr(params, name)


def dh_cells(table) -> list[float]:
    """Table II's cells of a dh table, in the paper's units (deg, mm, mm/deg)."""

    def four(p):
        return [
            math.degrees(param(p, "theta")),
            param(p, "d"),
            math.degrees(param(p, "alpha")),
            param(p, "a"),
        ]

    cells = four(table.base)
    for row in table.rows:
        cells += [*four(row.params), row.pitch * math.pi / 180.0, row.scale]
    return [*cells, math.degrees(param(table.tool, "theta")), param(table.tool, "d")]


def test_puma_from_60_noise_free_poses_is_the_actual_model_and_table_ii(puma):
    nominal, actual = puma
    m = synthesize(actual, 60, seed=1)
    result = identify(nominal, m, FitOptions(helical=("all",)))
    assert result.solution.converged and result.stats.rank == 42
    position, rotation = fk_error(result.model, actual)
    assert position <= 1e-9 * actual.size() and rotation <= 1e-9, (position, rotation)
    assert [j.kind for j in result.model.joints] == [j.kind for j in actual.joints]
    printed = yaml.safe_load((our_robots_dir() / "wu2019-table2.yaml").read_text())
    ref = printed["puma560-actual"]
    texts = [*ref["base"], *(c for row in ref["rows"] for c in row), *ref["tool"]]
    ours = dh_cells(to_table(result.model, "dh"))
    assert len(ours) == len(texts) == 42
    bad = [(v, t) for v, t in zip(ours, texts, strict=True) if not agrees(v, t)]
    assert bad == []


def test_noisy_poses_leave_the_noise_floor_on_held_out_poses(puma):
    nominal, actual = puma
    m = synthesize(actual, 250, NOISE_POS, NOISE_ROT, seed=2)
    cal = calibrate(nominal, m, helical=("all",), holdout=0.2, seed=3, convention="poe")
    assert cal.level == "full" and cal.chosen_by == "cross-validation"
    tree = to_dict(cal)
    assert tree["counts"]["fit"] == 200 and tree["counts"]["held_out"] == 50
    held = tree["residuals"]["after"]["held_out"]
    floor_pos, floor_rot = math.sqrt(3) * NOISE_POS, math.sqrt(3) * NOISE_ROT
    assert held["rms_position"] <= 1.2 * floor_pos, held
    assert held["rms_rotation"] <= 1.2 * floor_rot, held
    # the noise levels were estimated from the fit (variance components): near the truth
    assert tree["noise"]["given"] is False
    assert abs(tree["noise"]["position"] / NOISE_POS - 1) < 0.15
    assert abs(tree["noise"]["rotation"] / NOISE_ROT - 1) < 0.15
    before = tree["residuals"]["before"]["held_out"]
    assert before["rms_position"] > 1000 * held["rms_position"]


def test_standard_deviations_cover_the_errors_over_50_seeds(puma):
    """Each fit's parameter errors, as local coordinates of the chart centred on the truth (the
    chart the covariance is expressed in, up to second order), against twice the reported
    deviation: a Gaussian puts 95.4% within; we require 90%."""
    nominal, actual = puma
    truth = Estimate.of(
        tuple(
            Joint(j.name, "helical", j.axis, line_point(j.axis, j.point), j.pitch, j.scale)
            for j in actual.joints
        ),
        home=actual.home,
    )
    inside, factors = [], []
    for seed in range(50):
        m = synthesize(actual, 200, NOISE_POS, NOISE_ROT, seed=100 + seed)
        result = identify(
            nominal, m, FitOptions(helical=("all",), noise_pos=NOISE_POS, noise_rot=NOISE_ROT)
        )
        error = local_coordinates(truth, result.estimate)
        inside.append(np.abs(error) <= 2.0 * result.stats.std)
        factors.append(result.stats.variance_factor)
    coverage = float(np.mean(inside))
    assert coverage >= 0.90, coverage
    assert 0.9 < float(np.mean(factors)) < 1.1  # the given noise levels are right


def test_three_markers_identify_the_full_model(puma):
    nominal, actual = puma
    layout = marker_layout(actual, 3, seed=4)
    m = synthesize(actual, 60, seed=4, layout=layout, pose=False)
    result = identify(nominal, m, FitOptions(pose=False, helical=("all",), layout=layout))
    assert result.stats.rank == len(result.names) == 36 + 9
    position, rotation = fk_error(result.model, actual)
    assert position <= 1e-9 * actual.size() and rotation <= 1e-9
    for k, point in layout.items():
        assert np.allclose(result.markers_on_tool[k], point, atol=1e-9 * actual.size())


def test_one_marker_identifies_the_chain_and_the_point_not_the_tool_rotation(puma):
    """The documented reduced set: every joint screw and scale and the marker's point (the tool
    origin when no layout is given); the tool rotation is kept from the nominal as placed in the
    device frame by the start fit."""
    nominal, actual = puma
    m = synthesize(actual, 60, seed=5, pose=False)
    opts = FitOptions(pose=False, helical=("all",))
    result = identify(nominal, m, opts)
    assert result.stats.rank == len(result.names) == 36 + 3
    assert np.allclose(result.model.twists(), actual.twists(), atol=1e-9)
    q = actual.sample(1000, 6)
    ours, theirs = result.model.fk_batch(q), actual.fk_batch(q)
    assert np.abs(ours[:, :3, 3] - theirs[:, :3, 3]).max() <= 1e-9 * actual.size()
    # as placed in the device frame by the rigid fit and the base-tool level's base motion
    placed = result.before.base_motion() @ placement(nominal, m, opts, [0]) @ nominal.home
    assert np.allclose(result.model.home[:3, :3], placed[:3, :3], atol=1e-15)
    assert pose_errors(ours, theirs)[1] > 1e-3  # and so the tool's orientation is the nominal's


@pytest.mark.parametrize("robot", ["scara", "stanford"])
def test_scara_and_stanford_calibrate(robot):
    nominal = urdf2dh.load(robot)
    size = nominal.size()
    actual = perturb(nominal, 7, 0.01, 0.005 * size, scale=1e-3)
    m = synthesize(actual, 80, seed=8)
    result = identify(nominal, m, FitOptions())
    assert result.stats.rank == len(result.names)
    position, rotation = fk_error(result.model, actual)
    assert position <= 1e-9 * size and rotation <= 1e-9
    noisy = synthesize(actual, 250, 1e-5, 1e-5, seed=9)
    cal = calibrate(nominal, noisy, holdout=0.2, convention="cpc")
    held = cal.comparison("held_out")
    assert held is not None and held.after.rms_rotation is not None
    assert held.after.rms_position <= 1.2 * math.sqrt(3) * 1e-5
    assert held.after.rms_rotation <= 1.2 * math.sqrt(3) * 1e-5
    for convention in ("dh", "mdh", "cpc"):  # every writer takes the identified model
        assert to_table(cal.model, convention).check.max_position_error < 1e-10 * size


def test_helical_pitch_is_identified(puma):
    """The actual PUMA's joints 3 to 6 are helical (Wu 2019 Table I); identified as such from a
    nominal whose joints are all revolute, their pitches come out as the actual's, and joints 1
    and 2 stay revolute."""
    nominal, actual = puma
    helical = tuple(j.name for j in actual.joints if j.kind == "helical")
    assert helical == ("j3", "j4", "j5", "j6")
    result = identify(nominal, synthesize(actual, 60, seed=10), FitOptions(helical=helical))
    assert [j.kind for j in result.model.joints] == [j.kind for j in actual.joints]
    for ours, theirs in zip(result.model.joints, actual.joints, strict=True):
        assert ours.pitch == pytest.approx(theirs.pitch, rel=1e-6, abs=1e-12)


def test_ur5_identified_in_its_base_frame_exports_to_ur():
    """An as-built UR5 (flange on its last axis) measured by a device 2 m away: with the scales
    and the tool's placement on the last axis kept, and the model anchored on joint 1's axis in
    the nominal base frame, the UR export takes it, and UR's description built from that yaml
    moves as the identified model does."""
    import pinocchio as pin

    nominal = urdf2dh.load("ur5")
    actual = perturb(nominal, 3, 0.002, 0.001, tool_on_axis=True)
    device = twist_exp(np.array([0.1, -0.2, 0.7, 1.5, -0.8, 0.3]))
    seen = PoeModel(moved(actual.joints, device), device @ actual.home, "as-built")
    m = synthesize(seen, 200, 1e-5, 1e-5, seed=12)
    result = identify(nominal, m, FitOptions(keep_scale=True, keep_tool_axis=True, frame="nominal"))
    assert len(result.names) == 4 * 6 + 2 and result.stats.rank == 26
    first, nominal_first = result.model.joints[0], nominal.joints[0]
    assert np.allclose(first.axis, nominal_first.axis, atol=1e-14)
    assert np.allclose(first.point, line_point(nominal_first.axis, nominal_first.point), atol=1e-14)
    # identified vs the truth, both in the device frame: within a few noise levels
    position, rotation = fk_error(result.device_model, seen)
    assert position < 1e-4 and rotation < 1e-4
    table = to_table(result.model, "dh", style="ur")
    text = export_table(table, "ur", ExportOptions(None, DEFAULT))
    kin = yaml.safe_load(text)["kinematics"]
    urdf = ur_description_urdf(kin)
    robot = pin.buildModelFromXML(urdf)
    data = robot.createData()
    frame = robot.getFrameId("tool0")
    q = result.model.sample(50, 13)
    for qk in q:
        pin.framesForwardKinematics(robot, data, qk)
        ours = result.model.fk(qk)
        assert np.allclose(data.oMf[frame].homogeneous, ours, atol=1e-9)


def test_nominal_frame_anchors_a_prismatic_first_joint_by_its_direction():
    """tiago-arm starts with its prismatic torso lift: --frame nominal puts the identified lift
    direction on the nominal's and fits the rest; the reported base pose maps the model back
    into the device frame exactly."""
    nominal = urdf2dh.load("tiago-arm")
    actual = perturb(nominal, 2, 0.003, 0.002)
    device = twist_exp(np.array([0.3, 0.1, -0.5, 1.0, 2.0, -0.4]))
    seen = PoeModel(moved(actual.joints, device), device @ actual.home, "seen")
    result = identify(nominal, synthesize(seen, 100, seed=3), FitOptions(frame="nominal"))
    assert result.model.joints[0].kind == "prismatic"
    assert np.allclose(result.model.joints[0].axis, nominal.joints[0].axis, atol=1e-14)
    q = nominal.sample(500, 1)
    position, rotation = pose_errors(
        result.base_in_device @ result.model.fk_batch(q), seen.fk_batch(q)
    )
    assert position <= 1e-12 and rotation <= 1e-12


def test_a_joint_that_never_moves_is_reported_not_identified_with_the_cause():
    """A joint held at one position throughout shows nothing of how its line lies or how far it
    scales: those are not determined, the report says so and why, and the rest is found."""
    nominal = urdf2dh.load("ur5")
    actual = perturb(nominal, 4, 0.002, 0.001)
    m = synthesize(actual, 60, seed=5)
    q = m.q.copy()
    q[:, 3] = 0.0  # wrist_1 held at zero throughout
    poses = actual.fk_batch(q)
    frozen = Measurements(
        m.joints, q, poses[:, :3, 3], quaternion_of(poses[:, :3, :3]), None, "frozen.csv"
    )
    cal = calibrate(nominal, frozen, level="full")
    assert cal.counts.rank == 36 - 5 and cal.counts.parameters == 36
    lost = [p.name for p in cal.parameters if p.std is None]
    assert lost == [f"wrist_1_joint.{k}" for k in ("turn1", "turn2", "shift1", "shift2", "scale")]
    assert all("barely moved (0 rad)" in (p.flag or "") for p in cal.parameters if p.std is None)
    assert cal.barely_moved == (("wrist_1_joint", 0.0),)
    assert any(
        "determine 31 of the 36 parameters" in w and "barely moved (wrist_1_joint)" in w
        for w in cal.warnings
    )
    # the rest is still found: the model matches the robot wherever wrist_1 is at zero
    fresh = actual.sample(200, 6)
    fresh[:, 3] = 0.0
    position, _ = pose_errors(cal.model.fk_batch(fresh), actual.fk_batch(fresh))
    assert position <= 1e-9 * actual.size()
