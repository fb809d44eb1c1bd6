"""Calibration that cannot mislead: the reproducers of what went wrong (an optimistic noise figure
crashing the outlier re-fit, --noise-pos read in metres beside --length-unit mm, a helical PUMA
reported as noise, files in degrees, millimetres or another quaternion order written as models,
noise no robot has, plan's time and its too few configurations, a report in metres) and what
each does now: a model, or exit 3 with one line naming the cause and the option that fixes it,
nothing written."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import urdf2dh
from urdf2dh.calibration.calibration import calibrate
from urdf2dh.calibration.diagnosis import misread, rotation_misfit
from urdf2dh.calibration.measure import perturb, synthesize
from urdf2dh.calibration.measurements import Measurements, Reading, read_measurements
from urdf2dh.calibration.plan import plan
from urdf2dh.calibration.start import FitOptions
from urdf2dh.calibration.userunits import UserUnits
from urdf2dh.cli import main
from urdf2dh.errors import Implausible, InputError
from urdf2dh.geometry.lie import rotation_of

UR5_JOINTS = tuple(j.name for j in urdf2dh.load("ur5").joints)


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def refused(capsys, tmp_path, *argv, code=3):
    """Run ``argv`` with ``-o`` and ``--report``: refused with ``code``, one line, no output;
    the line."""
    out, report = tmp_path / "out.txt", tmp_path / "report.json"
    got, _, err = run(capsys, *argv, "-o", out, "--report", report)
    assert got == code, err
    assert err.startswith("urdf2dh: error: ") and err.count("\n") == 1, err
    assert "internal error" not in err and not out.exists() and not report.exists()
    return err


@pytest.fixture(scope="module")
def u40(tmp_path_factory):
    """The issue's UR5: 40 poses with 0.1 mm and 0.1 mrad of noise, seed 3."""
    path = tmp_path_factory.mktemp("u40") / "u40.csv"
    argv = ["measure", "ur5", "--configs", "40", "--noise-pos", "1e-4", "--noise-rot", "1e-4"]
    assert main([*argv, "--seed", "3", "-o", str(path)]) == 0
    return path


@pytest.fixture(scope="module")
def puma(tmp_path_factory):
    """The README's measurements of the PUMA 560 as Wu 2019 measured it (helical joints)."""
    path = tmp_path_factory.mktemp("puma") / "m.csv"
    argv = ["measure", "puma560-actual", "--configs", "100", "--noise-pos", "0.01"]
    assert main([*argv, "--noise-rot", "1e-5", "-o", str(path)]) == 0
    return path


def test_an_optimistic_noise_figure_is_named_not_a_crash(u40, capsys, tmp_path):
    """Every measurement beyond a noise ten times too small: they are not outliers (the re-fit
    without them all crashed); refused naming the noise and the options."""
    err = refused(capsys, tmp_path, "calibrate", "ur5", u40, "--noise-pos", "1e-5",
                  "--noise-rot", "1e-5")  # fmt: skip
    assert "40 of the 40 fitted measurements lie beyond what the noise given explains" in err
    assert "--noise-pos and --noise-rot" in err and "--accept-implausible" in err
    # stated as it is, the same file calibrates
    code, _, err = run(capsys, "calibrate", "ur5", u40, "--noise-pos", "1e-4", "--noise-rot",
                       "1e-4", "-o", tmp_path / "ok.txt")  # fmt: skip
    assert code == 0, err


def test_the_readmes_puma_with_its_true_noise_calibrates(puma, capsys, tmp_path):
    code, _, err = run(capsys, "calibrate", "puma560-nominal", puma, "--helical", "all",
                       "--noise-pos", "0.01", "--noise-rot", "1e-5", "--report",
                       tmp_path / "r.json", "-o", tmp_path / "p.txt")  # fmt: skip
    assert code == 0, err
    tree = json.loads((tmp_path / "r.json").read_text())
    assert tree["noise"]["given"] and tree["noise"]["position"] == pytest.approx(0.01)
    assert tree["residuals"]["after"]["fit"]["rms_position"] < 3 * math.sqrt(3) * 0.01


def test_a_helical_puma_is_not_reported_as_noise(puma, capsys, tmp_path):
    """Without --helical the positions leave millimetres that the rotations (1e-5 rad) deny:
    refused, naming the joints whose pitch explains them; estimated or given noise alike."""
    err = refused(capsys, tmp_path, "calibrate", "puma560-nominal", puma)
    assert "the positions carry the model's error" in err and "--helical" in err
    err = refused(capsys, tmp_path, "calibrate", "puma560-nominal", puma, "--noise-pos", "0.01",
                  "--noise-rot", "1e-5")  # fmt: skip
    assert "times the noise given" in err and "--helical" in err
    helical = err.split("--helical ")[1].split(";")[0]
    code, _, err = run(capsys, "calibrate", "puma560-nominal", puma, "--helical", helical,
                       "-o", tmp_path / "p.txt")  # fmt: skip
    assert code == 0, err  # the remedy named is one that works


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    """A UR5 as built measured in millimetres and degrees, joints named A1..A6."""
    ur5 = urdf2dh.load("ur5")
    m = synthesize(perturb(ur5, 3, 0.002, 0.001), 40, 3e-5, 5e-5, seed=4)
    path = tmp_path_factory.mktemp("lab") / "lab.csv"
    head = [f"A{k}" for k in range(1, 7)] + ["x", "y", "z", "qx", "qy", "qz", "qw"]
    assert m.quaternions is not None
    rows = np.hstack([np.degrees(m.q), m.points * 1000, m.quaternions])
    path.write_text(
        ",".join(head) + "\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows) + "\n"
    )
    rename = ",".join(f"A{k}={j}" for k, j in enumerate(UR5_JOINTS, start=1))
    return path, ("--rename", rename), m


def test_noise_pos_is_in_the_files_length_unit(lab, capsys, tmp_path):
    """--length-unit mm --noise-pos 0.03 is a tracker's 0.03 mm (it was read as 0.03 m, the fit
    held at the nominal's and nothing said); the report and its text speak millimetres."""
    path, rename, _ = lab
    report = tmp_path / "r.json"
    code, text, err = run(capsys, "calibrate", "ur5", path, *rename, "--degrees",
                          "--length-unit", "mm", "--noise-pos", "0.03", "--noise-rot", "5e-5",
                          "--report", report, "-o", tmp_path / "cal.txt")  # fmt: skip
    assert code == 0, err
    tree = json.loads(report.read_text())
    assert tree["units"]["length"] == "mm"
    assert tree["noise"]["position"] == pytest.approx(0.03)
    fit = tree["residuals"]["after"]["fit"]
    assert 0.02 < fit["rms_position"] < 0.1  # millimetres: about sqrt(3) x 0.03
    assert tree["model"]["length_unit"] == "m"  # the model keeps the nominal's unit
    assert "noise position 0.03 mm" in text and " mm " in text
    # the same noise in metres contradicts the residuals: named, with the unit it is read in
    err = refused(capsys, tmp_path, "calibrate", "ur5", path, *rename, "--degrees",
                  "--length-unit", "mm", "--noise-pos", "3e-5", "--noise-rot", "5e-5")  # fmt: skip
    assert "times the noise given" in err and " mm per coordinate" in err
    # and 30 mm for a file that shows a few hundredths (0.03 in metres, read as millimetres)
    err = refused(capsys, tmp_path, "calibrate", "ur5", path, *rename, "--degrees",
                  "--length-unit", "mm", "--noise-pos", "30", "--noise-rot", "5e-5")  # fmt: skip
    assert "over-stated" in err and "position noise is in mm" in err
    with pytest.raises(SystemExit):
        main(["calibrate", "-h"])
    assert "in the measurement file's length unit" in " ".join(capsys.readouterr().out.split())


@pytest.mark.parametrize(
    "change, expected",
    [
        (("--length-unit", "mm"), "the joint values are in degrees, not radians"),
        (("--degrees",), "the file's lengths are in mm, not m"),
    ],
    ids=["degrees", "millimetres"],
)
def test_units_a_file_does_not_state_are_named(lab, capsys, tmp_path, change, expected):
    path, rename, _ = lab
    err = refused(capsys, tmp_path, "calibrate", "ur5", path, *rename, *change)
    assert expected in err
    option = "--degrees" if "degrees" in expected else "--length-unit mm"
    assert f"read them with {option}" in err


def test_a_quaternion_in_another_order_is_named(lab, capsys, tmp_path):
    """w, x, y, z under the header qx, qy, qz, qw: the rename that reads it is named."""
    path, rename, _ = lab
    text = path.read_text().splitlines()
    rows = [line.split(",") for line in text[1:]]
    swapped = [[*r[:9], r[12], r[9], r[10], r[11]] for r in rows]
    bad = tmp_path / "wxyz.csv"
    bad.write_text("\n".join([text[0], *(",".join(r) for r in swapped)]) + "\n")
    err = refused(capsys, tmp_path, "calibrate", "ur5", bad, *rename, "--degrees",
                  "--length-unit", "mm")  # fmt: skip
    assert "the columns read as qx, qy, qz, qw hold w, x, y, z" in err
    fix = err.split("read them with --rename ")[1].split(";")[0]
    code, _, err = run(capsys, "calibrate", "ur5", bad, *rename, "--rename", fix, "--degrees",
                       "--length-unit", "mm", "-o", tmp_path / "ok.txt")  # fmt: skip
    assert code == 0, err


def test_joint_values_far_beyond_the_limits_as_radians(capsys, tmp_path):
    """A SCARA's joints in degrees (values of 145 against limits of +-2.6 rad): named."""
    scara = urdf2dh.load("scara")
    m = synthesize(perturb(scara, 5, 0.002, 0.001), 40, 1e-4, 1e-4, seed=6)
    turning = [k for k, j in enumerate(scara.joints) if j.kind != "prismatic"]
    q = m.q.copy()
    q[:, turning] = np.degrees(q[:, turning])
    assert np.abs(q).max() > 100
    path = tmp_path / "scara.csv"
    from urdf2dh.calibration.measurements import write_measurements

    path.write_text(write_measurements(Measurements(m.joints, q, m.points, m.quaternions)))
    err = refused(capsys, tmp_path, "calibrate", "scara", path)
    assert "the joint values are in degrees" in err and "--degrees" in err


def test_the_python_api_raises_with_the_facts_and_accepts_on_purpose(u40):
    ur5 = urdf2dh.load("ur5")
    m = read_measurements(u40, UR5_JOINTS)
    with pytest.raises(Implausible) as e:
        calibrate(ur5, m, noise_pos=1e-5, noise_rot=1e-5)
    assert e.value.exit_code == 3 and "outliers-everywhere" in e.value.causes
    assert e.value.remedy is not None and e.value.remedy.argument == "noise_pos, noise_rot"
    assert "--" not in str(e.value)  # the library names no option; the command line does
    assert e.value.result is not None and e.value.result.noise.given
    cal = calibrate(ur5, m, noise_pos=1e-5, noise_rot=1e-5, accept=True)
    assert cal.warnings[0].startswith("accepted all the same: 40 of the 40")


def test_degenerate_measurements_never_crash():
    """Measurements that leave nothing to fit, or that the fit cannot follow: refused with a
    message, never an internal error."""
    ur5 = urdf2dh.load("ur5")
    m = synthesize(ur5, 4, 1e-4, 1e-4, seed=1)
    same = Measurements(m.joints, np.repeat(m.q[:1], 4, 0), m.points, m.quaternions, None, "a")
    for kwargs in (
        {"holdout": 0.9},  # holds every configuration out
        {"level": "full", "prior": "none"},  # fewer equations than parameters
    ):
        with pytest.raises(InputError):
            calibrate(ur5, m, **kwargs)
    with pytest.raises((InputError, Implausible)):
        calibrate(ur5, same)  # four poses at one configuration
    with pytest.raises((InputError, Implausible)):
        calibrate(ur5, m, noise_pos=1e-12, noise_rot=1e-12, level="base-tool")


def test_measure_refuses_noise_no_robot_has(capsys):
    code, _, err = run(capsys, "measure", "ur5", "--configs", "3", "--noise-pos", "1e300")
    assert code == 2 and "is not below the robot's size" in err and err.count("\n") == 1
    code, _, err = run(capsys, "measure", "ur5", "--configs", "3", "--noise-rot", "2")
    assert code == 2 and "is not below 1 rad" in err
    with pytest.raises(InputError, match="not below the robot's size"):
        urdf2dh.measure(urdf2dh.load("ur5"), 3, noise_pos=5.0)
    assert len(urdf2dh.measure(urdf2dh.load("ur5"), 3)) == 3  # exact measurements: allowed


def test_plan_refuses_too_few_configurations_naming_the_least(capsys):
    code, _, err = run(capsys, "plan", "ur5", "--configs", "5")
    assert code == 2 and "the full level has 36 parameters" in err and "at least 6" in err
    with pytest.raises(SystemExit):
        main(["plan", "ur5", "--configs", "12000"])
    assert "must be from 1 to 10000" in capsys.readouterr().err
    ur5 = urdf2dh.load("ur5")
    p = plan(ur5, 6, level="full")
    assert np.all(np.isfinite(p.std))  # six poses determine all 36
    with pytest.raises(InputError, match="plan at least 2"):
        plan(ur5, 1, level="base-tool")


def test_plan_chooses_among_a_sample_as_well_as_among_all():
    """The stochastic greedy choice (a sample of the candidates per step) against the whole
    greedy choice on the same candidates: the determinant of the information it reaches is
    within a few per cent (log det within 1%)."""
    import urdf2dh.calibration.plan as planning

    ur5 = urdf2dh.load("ur5")
    est = planning._estimate(ur5, "full", True, None, 0)
    rows = planning._rows(est, ur5.sample(400, 2), 1e-4, 1e-4)
    scaled = rows / np.linalg.norm(rows.reshape(-1, rows.shape[2]), axis=0)

    def logdet(chosen):
        flat = scaled[chosen].reshape(-1, scaled.shape[2])
        return np.linalg.slogdet(flat.T @ flat)[1]

    sampled = planning._greedy(rows, 30, seed=0)
    old = planning.SAMPLED
    try:
        planning.SAMPLED = 10**9  # weigh every candidate at every step
        whole = planning._greedy(rows, 30, seed=0)
    finally:
        planning.SAMPLED = old
    assert len(set(sampled)) == 30 and abs(logdet(sampled) - logdet(whole)) < 0.01 * abs(
        logdet(whole)
    )


def test_the_report_says_what_its_warnings_mean_and_what_to_do():
    """Poorly identified parameters: what it means for the result, which joints they belong
    to, and the options (measure more moving them, --fix them, a lower level); the count of
    parameters in words."""
    ur5 = urdf2dh.load("ur5")
    m = synthesize(perturb(ur5, 7, 0.002, 0.001), 7, 1e-4, 1e-4, seed=8)
    cal = calibrate(ur5, m, level="full")
    poor = next(w for w in cal.warnings if "poorly identified" in w)
    assert "their values are uncertain, though the model as a whole fits" in poor
    assert "measure more configurations moving these joints" in poor and "--fix " in poor
    assert "which gives up what they explain" in poor
    assert "lower level" not in poor  # 4 of 36: the level stands
    data = Path(__file__).resolve().parents[1] / "examples" / "calibration-data" / "tiago"
    tiago = urdf2dh.load(str(data / "tiago_48_schunk.urdf"), tip="wrist_ft_tool_link")
    m1 = read_measurements(data / "tiago_m1.csv", tuple(j.name for j in tiago.joints))
    most = calibrate(tiago, m1, level="full", prior="none", accept=True)
    poor = next(w for w in most.warnings if "poorly identified" in w)
    assert (
        " of the 41 parameters are" in poor and "choose a lower level (--identify geometry)" in poor
    )
    assert cal.in_words == (
        "4 for each of 6 revolute joints' lines, 6 joint scales, 6 for the tool"
    )
    from urdf2dh.calibration.report import summary

    assert "identified 36 parameters (4 for each of 6 revolute joints' lines" in summary(cal)


def test_user_units_convert_in_one_place():
    mm = Reading(length_unit="mm")
    assert mm.length_unit == "mm"
    units = UserUnits.of("m", None)
    assert units.length == "m" and units.per_model == 1.0
    ur5 = urdf2dh.load("ur5")
    m = synthesize(ur5, 2, seed=1)
    assert UserUnits.of("m", m).length == "m"


def test_the_diagnosis_finds_a_quaternion_order_a_far_nominal_hides():
    """The PUMA's nominal is 0.28 rad from the robot at the base-tool level: a quaternion read
    in another order shows there by a factor below ten, and against the model identified from
    the positions by thousands."""
    actual, nominal = urdf2dh.load("puma560-actual"), urdf2dh.load("puma560-nominal")
    m = synthesize(actual, 40, 0.01, 1e-5, seed=9)
    assert m.quaternions is not None
    swapped = Measurements(m.joints, m.q, m.points, m.quaternions[:, [3, 0, 1, 2]])
    right = rotation_misfit(actual.fk_batch(m.q)[:, :3, :3], rotation_of(m.quaternions))
    assert right < 1e-4
    opts = FitOptions(pose=True, level="base-tool")
    reads, _, _ = misread(nominal, swapped, opts, [0], reference=actual)
    assert [r.kind for r in reads] == ["quaternion-order"]


def test_the_tutorial_shows_what_calibrate_prints(tmp_path, capsys, monkeypatch):
    """docs/calibrate-your-robot.md's report is what its command prints, line for line."""
    from test_doc_blocks import blocks

    root = Path(__file__).resolve().parents[1]
    page = blocks(root / "docs" / "calibrate-your-robot.md")
    command = next(b.code for b in page if b.lang == "bash" and "--report report.json" in b.code)
    shown = next(b.code for b in page if b.lang == "text" and b.code.startswith("calibrate ur5"))
    argv = command.replace("\\\n", " ").split()[1:]
    monkeypatch.chdir(tmp_path)
    (tmp_path / "examples").symlink_to(root / "examples")
    assert main(argv) == 0
    assert capsys.readouterr().out == shown
    wrong = next(b.code for b in page if b.lang == "bash" and "|| test $? -eq 3" in b.code)
    argv = wrong.split("||")[0].replace("\\\n", " ").split()[1:]
    said = next(b.code for b in page if b.lang == "text" and b.code.startswith("urdf2dh: error"))
    assert main(argv) == 3
    assert capsys.readouterr().err == said
