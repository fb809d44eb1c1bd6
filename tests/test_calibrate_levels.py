"""How much calibration identifies, and what it says about it, on synthetic robots whose errors
are known: the nested levels and their choice by cross-validation, fixed parameters and the
prior, held-out configurations and validation files, outliers, the flags and warnings, the
refusals of impossible input, and the pictures."""

from __future__ import annotations

import json
import math
import re
from dataclasses import replace

import numpy as np
import pytest

import urdf2dh
from urdf2dh import PoeModel, calibrate
from urdf2dh.calibration.chart import Estimate, absorbed
from urdf2dh.calibration.levels import OFFSETS
from urdf2dh.calibration.measure import marker_layout, perturb, synthesize
from urdf2dh.calibration.measurements import MAX_MEASUREMENTS, Measurements, write_measurements
from urdf2dh.calibration.plot import plot_calibration
from urdf2dh.calibration.prior import Prior
from urdf2dh.calibration.residuals import model_poses
from urdf2dh.cli import main
from urdf2dh.errors import InputError, UsageError
from urdf2dh.geometry.se3 import pose_errors

NOISE = 1e-4  # m and rad


@pytest.fixture(scope="module")
def ur5():
    return urdf2dh.load("ur5")


def with_offsets(model: PoeModel, offsets: np.ndarray) -> PoeModel:
    """``model`` with joint offsets added (absorbed into its lines and tool)."""
    est = Estimate.of(model.joints, home=model.home, level=OFFSETS, offsets=offsets)
    flat = absorbed(est)
    assert flat.home is not None
    return PoeModel(flat.joints, flat.home, "with-offsets", length_unit=model.length_unit)


@pytest.mark.parametrize(
    "error, expected",
    [("none", "base-tool"), ("offsets", "offsets"), ("geometry", "geometry"), ("scales", "full")],
)
def test_cross_validation_chooses_the_level_of_the_robot_s_errors(ur5, error, expected):
    """A UR5 whose only errors are at one level, measured with noise at 40 configurations: the
    default identifies that level, neither less nor more."""
    if error == "none":
        actual = ur5
    elif error == "offsets":
        actual = with_offsets(ur5, np.array([0.0, 0.004, -0.003, 0.005, -0.004, 0.0]))
    elif error == "geometry":
        actual = perturb(ur5, 1, 0.003, 0.003)
    else:
        geometry = perturb(ur5, 1, 0.003, 0.003)
        scaled = tuple(
            type(j)(
                j.name, j.kind, j.axis, j.point, j.pitch, 1.0 + 0.01 * (-1) ** i, j.lower, j.upper
            )
            for i, j in enumerate(geometry.joints)
        )
        actual = PoeModel(scaled, geometry.home, "scaled")
    m = synthesize(actual, 40, NOISE, NOISE, seed=2)
    cal = calibrate(ur5, m)
    assert cal.level == expected, [(s.level, s.rms_position) for s in cal.selection.scores]
    fresh = ur5.sample(300, 3)
    position, _ = pose_errors(cal.model.fk_batch(fresh), actual.fk_batch(fresh))
    assert position < 10 * NOISE


def test_a_level_asked_for_and_what_is_carried(ur5):
    actual = with_offsets(ur5, np.array([0.0, 0.004, -0.003, 0.005, -0.004, 0.0]))
    m = synthesize(actual, 30, NOISE, NOISE, seed=4)
    cal = calibrate(ur5, m, level="offsets")
    assert cal.level == "offsets" and cal.chosen_by == "option"
    names = [p.name for p in cal.parameters]
    # joint 1's offset is the base's turn about its axis, joint 6's the tool's: carried
    assert "shoulder_pan_joint.offset" not in names and "wrist_3_joint.offset" not in names
    carried = {h.name for h in cal.held if "carry" in h.reason}
    assert carried == {"shoulder_pan_joint.offset", "wrist_3_joint.offset"}
    offset = next(p for p in cal.parameters if p.name == "elbow_joint.offset")
    assert offset.value == pytest.approx(-0.003, abs=5 * offset.std)


def test_fixed_parameters_and_a_bad_name(ur5):
    actual = perturb(ur5, 5, 0.002, 0.002)
    m = synthesize(actual, 40, NOISE, NOISE, seed=6)
    cal = calibrate(ur5, m, level="full", fixed=("*.scale", "wrist_3_joint.*"))
    names = [p.name for p in cal.parameters]
    assert not any(n.endswith(".scale") or n.startswith("wrist_3_joint") for n in names)
    held = {h.name: h.reason for h in cal.held}
    assert held["elbow_joint.scale"] == "fixed as asked" and "wrist_3_joint.turn1" in held
    with pytest.raises(InputError, match=r"no parameter is named 'elbow\.scale'"):
        calibrate(ur5, m, fixed=("elbow.scale",))


def test_a_tight_prior_keeps_the_nominal_and_a_loose_one_changes_nothing(ur5):
    actual = perturb(ur5, 7, 0.003, 0.003)
    m = synthesize(actual, 30, NOISE, NOISE, seed=8)
    free = calibrate(ur5, m, level="geometry", prior="none")
    loose = calibrate(ur5, m, level="geometry", prior=Prior(1.0, 1.0))
    tight = calibrate(ur5, m, level="geometry", prior=Prior(1e-7, 1e-7))
    q = ur5.sample(200, 9)
    assert pose_errors(loose.model.fk_batch(q), free.model.fk_batch(q))[0] < 1e-7
    joints = [p for p in tight.parameters if not p.name.startswith(("tool", "base"))]
    assert max(abs(p.change) for p in joints) < 1e-5
    assert max(abs(p.change) for p in free.parameters if p in joints or True) > 1e-3


def test_markers_of_a_configuration_stay_on_one_side_of_the_holdout(ur5):
    layout = marker_layout(ur5, 3, seed=1)
    m = synthesize(ur5, 30, NOISE, 0.0, seed=1, layout=layout, pose=False)
    cal = calibrate(ur5, m, holdout=0.3, layout=layout)
    fit, held = cal.comparison("fit"), cal.comparison("held_out")
    assert fit is not None and held is not None
    assert len(held.configurations) == 9 and not set(fit.configurations) & set(held.configurations)
    assert held.after.count == 27 and cal.counts.held_out == 27


def test_a_validation_file_is_judged(ur5, tmp_path, capsys):
    actual = perturb(ur5, 9, 0.002, 0.002)
    fit, more = tmp_path / "fit.csv", tmp_path / "more.csv"
    fit.write_text(write_measurements(synthesize(actual, 40, NOISE, NOISE, seed=10)))
    more.write_text(write_measurements(synthesize(actual, 20, NOISE, NOISE, seed=11)))
    report = tmp_path / "r.json"
    code = main(["calibrate", "ur5", str(fit), "--validate", str(more), "--report", str(report)])
    _, err = capsys.readouterr()
    assert code == 0, err
    tree = json.loads(report.read_text())
    valid = tree["residuals"]["after"]["validation"]
    assert valid["count"] == 20 and valid["rms_position"] < 3 * math.sqrt(3) * NOISE
    assert "after, validation" in err


def test_an_outlier_is_listed_and_rejected_when_it_spoils_the_others(ur5):
    """A wrong measurement drags the fit: without it the other configurations are predicted
    far better, so the default rejects it; asked, it is kept, or rejected."""
    actual = perturb(ur5, 11, 0.002, 0.002)
    m = synthesize(actual, 60, NOISE, NOISE, seed=12)
    points = m.points.copy()
    points[17] += [0.02, -0.01, 0.0]  # 22 mm off: a wrong measurement
    bad = Measurements(m.joints, m.q, points, m.quaternions, None, "bad.csv")
    kept = calibrate(ur5, bad, reject=False)
    assert [s.row for s in kept.suspects] == [17] and not kept.rejected
    assert kept.suspects[0].position > 0.01 and kept.suspects[0].chance < 1e-6
    assert any("row 18" in w and "cannot explain (kept as asked" in w for w in kept.warnings)
    rejected = calibrate(ur5, bad, reject=True)
    assert rejected.rejected and rejected.counts.rejected == 1
    assert any("rejected 1 outlier (as asked): row 18" in w for w in rejected.warnings)
    default = calibrate(ur5, bad)
    assert default.rejected and default.counts.rejected == 1
    assert any(
        "rejected 1 outlier (without them the other configurations are predicted better" in w
        for w in default.warnings
    )
    q = ur5.sample(200, 13)
    better = pose_errors(default.model.fk_batch(q), actual.fk_batch(q))[0]
    worse = pose_errors(kept.model.fk_batch(q), actual.fk_batch(q))[0]
    assert better < worse and better < 10 * NOISE


def test_joints_that_barely_move_and_poorly_identified_parameters_are_named(ur5):
    actual = perturb(ur5, 13, 0.002, 0.002)
    q = ur5.sample(40, 14)
    q[:, 4] = 0.3 + 0.01 * np.sin(np.arange(40))  # wrist_2 within 0.02 rad
    poses = actual.fk_batch(q)
    m = synthesize(actual, 40, NOISE, NOISE, seed=15, configurations=q)
    assert np.allclose(m.q, q) and poses.shape == (40, 4, 4)
    cal = calibrate(ur5, m, level="full")
    assert cal.barely_moved[0][0] == "wrist_2_joint" and cal.barely_moved[0][1] < 0.03
    assert any(w.startswith("barely moved") and "wrist_2_joint" in w for w in cal.warnings)
    flagged = {p.name for p in cal.parameters if p.flag and "barely moved" in p.flag}
    assert flagged == {
        f"wrist_2_joint.{k}" for k in ("turn1", "turn2", "shift1", "shift2", "scale")
    }
    offset_free = calibrate(ur5, m, level="offsets")
    offset = next(p for p in offset_free.parameters if p.name == "wrist_2_joint.offset")
    assert offset.flag is None or "barely moved" not in offset.flag  # an offset shows anyway


def test_position_measurements_without_rotation_noise_identify_everything(ur5):
    """Poses whose rotations are exact (measure's default --noise-rot 0): weights from the
    noise levels alone would drown the positions (21 of 36 parameters seen). The weights are
    bounded, every parameter is identified, and a given level that would drown them is named."""
    actual = perturb(ur5, 15, 0.002, 0.002)
    m = synthesize(actual, 60, NOISE, 0.0, seed=16)
    cal = calibrate(ur5, m, level="full")
    assert cal.counts.rank == cal.counts.parameters == 36
    assert not any("determine" in w for w in cal.warnings)
    given = calibrate(ur5, m, level="full", noise_pos=NOISE, noise_rot=1e-15)
    assert given.counts.rank == 36
    assert any("would weigh rotations" in w and "drown" in w for w in given.warnings)


@pytest.mark.parametrize(
    "noise_pos, noise_rot, fragment",
    [
        (0.0, NOISE, "--noise-pos 0: the position noise must be a number > 0"),
        (NOISE, 0.0, "--noise-rot 0: the rotation noise must be a number > 0"),
        (NOISE, float("nan"), "--noise-rot nan: the rotation noise must be a number > 0"),
        (1e300, NOISE, "--noise-pos 1e+300: a position noise of 1e+300 is not below the robot"),
        (NOISE, 10.0, "--noise-rot 10: a rotation noise of 10 is not below 1 rad"),
    ],
)
def test_degenerate_noise_levels_are_refused(tmp_path, capsys, noise_pos, noise_rot, fragment):
    path, out = tmp_path / "m.csv", tmp_path / "out.txt"
    path.write_text(write_measurements(synthesize(urdf2dh.load("ur5"), 20, seed=1)))
    argv = ["calibrate", "ur5", str(path), "-o", str(out)]
    code = main([*argv, "--noise-pos", str(noise_pos), "--noise-rot", str(noise_rot)])
    _, err = capsys.readouterr()
    assert code == 2 and err.count("\n") == 1 and fragment in err, err
    assert not out.exists()


def test_impossible_joint_values_and_points_are_refused(tmp_path, capsys):
    m = synthesize(urdf2dh.load("ur5"), 20, seed=1)
    for column, value, fragment in (
        (2, 1e300, "row 4, joint 'elbow_joint': 1e+300 is beyond any joint's travel"),
        (7, -1e300, "row 4: a measured point 1e+300 m from the device's origin"),
    ):
        table = np.hstack([m.q, m.points, m.quaternions])
        table[3, column] = value
        bad = Measurements(m.joints, table[:, :6], table[:, 6:9], table[:, 9:], None, "bad.csv")
        path = tmp_path / "bad.csv"
        path.write_text(write_measurements(bad))
        code = main(["calibrate", "ur5", str(path)])
        _, err = capsys.readouterr()
        assert code == 2 and err.count("\n") == 1 and fragment in err, err


def test_measurements_are_bounded(tmp_path, capsys):
    code = main(["measure", "ur5", "--configs", "2000", "--markers", "100", "-o", "/dev/null"])
    _, err = capsys.readouterr()
    assert code == 2 and err.count("\n") == 1
    assert "2000 configurations x 100 markers are 200000 measurements, more than the" in err
    joints = [j.name for j in urdf2dh.load("ur5").joints]
    head = ",".join([*joints, "x", "y", "z"]) + "\n"
    row = "0,0,0,0,0,0,0.1,0.2,0.3\n"
    path = tmp_path / "many.csv"
    path.write_text(head + row * (MAX_MEASUREMENTS + 1))
    code = main(["calibrate", "ur5", str(path)])
    _, err = capsys.readouterr()
    assert (
        code == 2 and err.count("\n") == 1 and f"more than {MAX_MEASUREMENTS} measurements" in err
    )


def test_plots_are_a_png_and_one_self_contained_page(ur5):
    actual = perturb(ur5, 17, 0.002, 0.002)
    m = synthesize(actual, 40, NOISE, NOISE, seed=18)
    cal = calibrate(ur5, m, holdout=0.25)
    png = plot_calibration(cal, "png")
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 20_000
    html = plot_calibration(cal, "html").decode()
    assert "<html" in html and "plotly" in html and "held out" in html
    assert "Content-Security-Policy" in html  # the shared offline page
    # plotly.js is in the page (megabytes of it), and no script is fetched from anywhere
    assert len(html) > 1_000_000 and not re.findall(r"<script[^>]*\bsrc\s*=", html)
    with pytest.raises(UsageError):
        plot_calibration(cal, "gif")


def test_the_levels_show_a_progress_bar_on_a_terminal(tmp_path):
    import fcntl
    import os
    import pty
    import struct
    import subprocess
    import sys
    import termios
    from pathlib import Path

    path = tmp_path / "m.csv"
    path.write_text(
        write_measurements(
            synthesize(perturb(urdf2dh.load("ur5"), 1, 0.002, 0.002), 30, NOISE, NOISE, seed=1)
        )
    )
    main_fd, sub = pty.openpty()
    fcntl.ioctl(sub, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))
    root = Path(__file__).resolve().parents[1]
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "urdf2dh.cli",
            "calibrate",
            "ur5",
            str(path),
            "-o",
            str(tmp_path / "o.txt"),
        ],
        stdout=subprocess.PIPE,
        stderr=sub,
        cwd=root,
    )
    os.close(sub)
    drawn = b""
    try:
        while chunk := os.read(main_fd, 65536):
            drawn += chunk
    except OSError:
        pass
    os.close(main_fd)
    proc.communicate(timeout=120)
    assert proc.returncode == 0
    assert b"calibrate: levels:" in drawn and b"/4" in drawn


def test_the_model_poses_of_an_estimate_with_offsets_move_as_the_absorbed_model(ur5):
    est = Estimate.of(ur5.joints, home=ur5.home, level=OFFSETS, offsets=np.full(6, 0.01))
    q = ur5.sample(20, 1)
    assert np.allclose(model_poses(est, q), model_poses(absorbed(est), q), atol=1e-14)


def test_planned_configurations_identify_better_than_random_ones(ur5):
    """Over five robots as built: 15 configurations planned for the full model (D-optimal)
    against 15 random ones, the same noise: the planned ones leave smaller errors, at new
    configurations and in the parameters (the geometric mean of their deviations)."""
    from urdf2dh.calibration.identify import identify
    from urdf2dh.calibration.plan import plan
    from urdf2dh.calibration.start import FitOptions

    chosen = plan(ur5, 15, level="full", noise_pos=NOISE, noise_rot=NOISE, seed=0)
    assert chosen.configurations.shape == (15, 6) and chosen.candidates >= 500
    lim = ur5.limits()
    assert np.all(chosen.configurations >= lim[:, 0]) and np.all(chosen.configurations <= lim[:, 1])
    assert np.all(np.isfinite(chosen.std)) and np.all(chosen.std < chosen.random_std * 10)
    assert "expected standard deviations" in chosen.summary()
    fresh = ur5.sample(500, 21)
    wins, ratios = 0, []
    for seed in range(5):
        actual = perturb(ur5, 30 + seed, 0.003, 0.003)
        errors = []
        for q in (chosen.configurations, ur5.sample(15, (seed, 99))):
            m = synthesize(actual, 15, NOISE, NOISE, seed=40 + seed, configurations=q)
            result = identify(ur5, m, FitOptions(level="full", noise_pos=NOISE, noise_rot=NOISE))
            model, truth = result.model.fk_batch(fresh), actual.fk_batch(fresh)
            errors.append(float(np.sqrt(np.mean(np.sum((model - truth)[:, :3, 3] ** 2, axis=1)))))
        wins += errors[0] < errors[1]
        ratios.append(errors[0] / errors[1])
    assert wins >= 4 and float(np.exp(np.mean(np.log(ratios)))) < 0.8, ratios


def test_plan_writes_configurations_that_measure_reads(tmp_path, capsys):
    out, meas = tmp_path / "plan.csv", tmp_path / "m.csv"
    code = main(["plan", "ur5", "--configs", "12", "--identify", "offsets", "-o", str(out)])
    printed, err = capsys.readouterr()
    assert code == 0, err
    assert "12 configurations chosen" in printed and "offsets" in printed
    lines = out.read_text().splitlines()
    assert lines[0].startswith("shoulder_pan_joint,") and len(lines) == 13
    code = main(["measure", "ur5", "--configurations", str(out), "-o", str(meas)])
    assert code == 0, capsys.readouterr().err
    assert len(meas.read_text().splitlines()) == 13


def test_left_out_errors_are_the_refits_and_refuse_a_configuration_that_alone_sees_a_parameter():
    """On a linear problem, at the fit's solution, the grouped deleted residuals equal refits
    without each configuration; a parameter only one configuration's rows see makes the level
    unjudgeable (``None``), the same parameter seen by two configurations does not."""
    from urdf2dh.calibration.residuals import Data
    from urdf2dh.calibration.select import left_out_errors
    from urdf2dh.calibration.solver import Linearisation, Problem

    rng = np.random.default_rng(11)
    configurations, rows = 6, 3
    data = Data(
        np.zeros((configurations, 1)),
        np.zeros((configurations, 3)),
        np.zeros(configurations, dtype=np.int64),
    )
    problem = Problem(data, 0.5, 1.0)
    group = np.arange(configurations)
    jac = rng.normal(size=(configurations * rows, 3))
    res = rng.normal(size=configurations * rows)
    res -= jac @ np.linalg.lstsq(jac, res, rcond=None)[0]  # at the fit's solution
    lin = Linearisation(Estimate.__new__(Estimate), res, jac, rows)
    squared = left_out_errors(problem, lin, group)
    assert squared is not None
    for c in range(configurations):
        mine = slice(c * rows, (c + 1) * rows)
        others = np.ones(len(res), dtype=bool)
        others[mine] = False
        x = np.linalg.lstsq(jac[others], -res[others], rcond=None)[0]
        refit = res[mine] + jac[mine] @ x
        assert squared[c, 0] == pytest.approx(float(refit @ refit), rel=1e-10)
    seen_once = jac.copy()
    seen_once[rows:, 2] = 0.0  # only configuration 0 sees the third parameter
    assert left_out_errors(problem, replace(lin, jacobian=seen_once), group) is None
    seen_twice = jac.copy()
    seen_twice[2 * rows :, 2] = 0.0  # configurations 0 and 1 see it
    assert left_out_errors(problem, replace(lin, jacobian=seen_twice), group) is not None
