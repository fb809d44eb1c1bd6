"""``urdf2dh measure`` and ``urdf2dh calibrate`` (docs/calibration.md): files, formats, the report,
the text output, and every refusal (bad rows, too few measurements, no convergence)."""

from __future__ import annotations

import json

import numpy as np
import pytest
import yaml

import urdf2dh
from urdf2dh.calibration.measurements import read_layout, read_measurements
from urdf2dh.cli import main
from urdf2dh.geometry.se3 import pose_errors

PUMA_JOINTS = ("j1", "j2", "j3", "j4", "j5", "j6")


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def poses(tmp_path_factory):
    """200 noisy poses of the actual PUMA 560, as ``measure`` writes them."""
    path = tmp_path_factory.mktemp("meas") / "puma.csv"
    assert (
        main(
            [
                "measure",
                "puma560-actual",
                "--configs",
                "200",
                "--noise-pos",
                "0.01",
                "--noise-rot",
                "1e-5",
                "--seed",
                "4",
                "-o",
                str(path),
            ]
        )
        == 0
    )
    return path


def test_measure_writes_exact_seeded_poses(tmp_path, capsys):
    out = tmp_path / "m.csv"
    code, _, err = run(
        capsys, "measure", "puma560-actual", "--configs", "7", "--seed", "3", "-o", out
    )
    assert code == 0, err
    header = out.read_text().splitlines()[0]
    assert header == "j1,j2,j3,j4,j5,j6,x,y,z,qx,qy,qz,qw"
    m = read_measurements(out, PUMA_JOINTS)
    actual = urdf2dh.load("puma560-actual")
    assert np.array_equal(m.q, actual.sample(7, 3))
    poses = actual.fk_batch(m.q)
    assert np.abs(m.points - poses[:, :3, 3]).max() == 0.0  # written to the last bit
    again = tmp_path / "again.csv"
    run(capsys, "measure", "puma560-actual", "--configs", "7", "--seed", "3", "-o", again)
    assert again.read_bytes() == out.read_bytes()


def test_measure_markers_writes_positions_and_the_layout(tmp_path, capsys):
    out, lay = tmp_path / "m.csv", tmp_path / "layout.csv"
    code, _, err = run(
        capsys,
        "measure",
        "scara",
        "--configs",
        "5",
        "--markers",
        "3",
        "--marker-layout",
        lay,
        "-o",
        out,
    )
    assert code == 0, err
    lines = out.read_text().splitlines()
    assert lines[0].endswith(",x,y,z,marker") and "qw" not in lines[0]
    assert [line.rsplit(",", 1)[1] for line in lines[1:4]] == ["0", "1", "2"]
    assert len(lines) == 1 + 15 and sorted(read_layout(lay)) == [0, 1, 2]


def test_calibrate_writes_every_convention_and_the_report(poses, tmp_path, capsys):
    report = tmp_path / "r.json"
    out = tmp_path / "id.json"
    code, text, err = run(
        capsys,
        "calibrate",
        "puma560-nominal",
        poses,
        "--helical",
        "all",
        "--holdout",
        "0.25",
        "--seed",
        "1",
        "--format",
        "json",
        "-o",
        out,
        "--report",
        report,
    )
    assert code == 0, err
    table = json.loads(out.read_text())
    assert (
        table["schema"] == "urdf2dh/schemas/table-file-1.schema.json"
        and table["convention"] == "dh"
    )
    assert table["check"]["max_position_error"] < 1e-10 * 300
    tree = json.loads(report.read_text())
    assert tree["schema"] == "urdf2dh/schemas/calibration-report-2.schema.json"
    counts = tree["counts"]
    assert (counts["measurements"], counts["fit"], counts["held_out"]) == (200, 150, 50)
    assert counts["parameters"] == counts["rank"] == 42
    assert counts["formula"] == "5h + 4r + 2t + n + 6 = 5*6 + 4*0 + 2*0 + 6 + 6 = 42"
    assert tree["condition_number"] > 1
    for when in ("before", "after"):
        for which in ("fit", "held_out"):
            r = tree["residuals"][when][which]
            assert set(r) == {
                "count",
                "rms_position",
                "max_position",
                "rms_rotation",
                "max_rotation",
            }
    assert len(tree["parameters"]) == 42 and all(p["std"] > 0 for p in tree["parameters"])
    scale = next(p for p in tree["parameters"] if p["name"] == "j2.scale")
    assert abs(scale["value"] - 1.00002) < 5 * scale["std"] and scale["unit"] == "1"
    assert tree["diff"]["convention"] == "dh" and tree["diff"]["parameters"]
    assert tree["model"]["format"] == "poe"
    # the text output says the same, briefly, on stdout (the model went to the file)
    assert "identified 42 parameters" in text and "determine 42 of them (numerical rank)" in text
    assert "held out" in text and "noise floor" in text and err == ""
    for conv, fmt in [("mdh", "yaml"), ("cpc", "csv"), ("dh", "urdf"), ("dh", "markdown")]:
        code, text, err = run(
            capsys,
            "calibrate",
            "puma560-nominal",
            poses,
            "--helical",
            "all",
            "--convention",
            conv,
            "--format",
            fmt,
        )
        assert code == 0, err
        assert "identified 42 parameters" in err  # the summary goes to stderr here
    code, text, err = run(
        capsys, "calibrate", "puma560-nominal", poses, "--format", "yaml", "--convention", "poe",
        "--helical", "all",
    )  # fmt: skip
    assert code == 0 and yaml.safe_load(text)["format"] == "poe"
    # without --helical the revolute model leaves millimetres the rotations deny: refused
    code, text, err = run(capsys, "calibrate", "puma560-nominal", poses, "--convention", "poe")
    assert code == 3 and not text and err.count("\n") == 1 and "--helical" in err, err


def test_the_identified_file_is_a_source_for_export_and_convert(tmp_path, capsys):
    meas, out = tmp_path / "m.csv", tmp_path / "cal.json"
    run(capsys, "measure", "ur5", "--configs", "40", "-o", meas)
    code, _, err = run(
        capsys,
        "calibrate",
        "ur5",
        meas,
        "--keep-scale",
        "--keep-tool-axis",
        "--frame",
        "nominal",
        "--convention",
        "poe",
        "--format",
        "json",
        "-o",
        out,
    )
    assert code == 0, err
    model = urdf2dh.load(str(out))
    ur5 = urdf2dh.load("ur5")
    q = ur5.sample(200, 1)
    position, rotation = pose_errors(model.fk_batch(q), ur5.fk_batch(q))
    assert position < 1e-10 and rotation < 1e-10
    for target in ("ur", "rtb", "kdl"):
        code, text, err = run(capsys, "export", out, "--to", target)
        assert code == 0 and text, (target, err)
    code, _, err = run(capsys, "convert", out, "--convention", "cpc")
    assert code == 0, err


def _write(tmp_path, text: str):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    return path


GOOD = "0,0,0,0,0,0,1,2,3,0,0,0,1"
HEADER = "j1,j2,j3,j4,j5,j6,x,y,z,qx,qy,qz,qw"


@pytest.mark.parametrize(
    "text, fragment",
    [
        (
            f"{HEADER}\n{GOOD}\n0,0,nan,0,0,0,1,2,3,0,0,0,1\n",
            "row 2 (line 3), column 'j3': 'nan' is not a finite number",
        ),
        (
            f"{HEADER}\n{GOOD}\n0,0,0,0,0,0,1,2,3,0,0,1\n",
            "row 2 (line 3): 12 fields, but the header has 13",
        ),
        (f"j1,j2,j3,j4,j5,j7,x,y,z\n{GOOD[:17]}\n", "column 'j7' is neither a joint of the chain"),
        ("j1,j2,j3,j4,j5,x,y,z\n0,0,0,0,0,1,2,3\n", "the header has no column for joint 'j6'"),
        (
            f"{HEADER}\n{GOOD}\n0,0,0,0,0,0,1,2,3,0,0,0,1.5\n",
            "row 2 (line 3), column 'qw': the quaternion (qx, qy, qz, qw) has norm 1.5",
        ),
        (
            "j1,j2,j3,j4,j5,j6,x,y,z,marker\n0,0,0,0,0,0,1,2,3,1.5\n",
            "row 1 (line 2), column 'marker': '1.5' is not an integer",
        ),
        (f"{HEADER}\n0,0,0,0,0,0,1,two,3,0,0,0,1\n", "column 'y': 'two' is not a number"),
        (f"j1,j2,j3,j4,j5,j6,x,y,z,qx,qy\n{GOOD[:21]}\n", "but no 'qz'"),
        ("j1,j1,j3,j4,j5,j6,x,y,z\n", "column 'j1' appears twice"),
        (f"{HEADER}\n", "no measurements after the header"),
        ("", "empty file"),
    ],
)
def test_bad_rows_exit_2_naming_file_row_and_column(tmp_path, capsys, text, fragment):
    path = _write(tmp_path, text)
    out = tmp_path / "never.json"
    code, _, err = run(capsys, "calibrate", "puma560-nominal", path, "-o", out)
    assert code == 2
    assert err.startswith("urdf2dh: error: ") and str(path) in err and fragment in err, err
    assert "Traceback" not in err and not out.exists()


def test_too_few_measurements_exit_2_with_both_counts(tmp_path, capsys):
    """Without a prior, fewer equations than parameters are refused; with the default one the
    prior's rows complete them, and the report says how few the measurements determine."""
    meas = tmp_path / "few.csv"
    run(capsys, "measure", "puma560-actual", "--configs", "6", "-o", meas)
    full = ("--helical", "all", "--identify", "full")
    code, _, err = run(capsys, "calibrate", "puma560-nominal", meas, *full, "--prior", "none")
    assert code == 2
    assert "6 poses give 36 equations (6 each), fewer than the 42 parameters" in err
    code, _, err = run(capsys, "calibrate", "puma560-nominal", meas, *full)
    assert code == 0, err
    assert "the measurements determine 36 of the 42 parameters" in err
    run(capsys, "measure", "puma560-actual", "--configs", "10", "--measure", "position", "-o", meas)
    code, _, err = run(
        capsys, "calibrate", "puma560-nominal", meas, "--identify", "full", "--prior", "none"
    )
    assert code == 2 and "10 positions give 30 equations (3 each), fewer than the 33" in err


def test_no_convergence_exits_1_with_the_residual_and_writes_nothing(poses, tmp_path, capsys):
    out, report = tmp_path / "never.json", tmp_path / "never-report.json"
    code, _, err = run(
        capsys,
        "calibrate",
        "puma560-nominal",
        poses,
        "--max-iterations",
        "1",
        "-o",
        out,
        "--report",
        report,
    )
    assert code == 1
    assert "did not converge in 1 iterations (RMS position residual" in err
    assert "nothing written" in err and not out.exists() and not report.exists()


def test_markers_need_their_layout_and_position_measurements(tmp_path, capsys):
    meas, lay = tmp_path / "m.csv", tmp_path / "lay.csv"
    run(
        capsys,
        "measure",
        "puma560-actual",
        "--configs",
        "30",
        "--markers",
        "3",
        "--marker-layout",
        lay,
        "-o",
        meas,
    )
    code, _, err = run(capsys, "calibrate", "puma560-nominal", meas)
    assert code == 2 and "3 markers; give their positions on the tool" in err
    code, _, err = run(capsys, "calibrate", "puma560-nominal", meas, "--measure", "pose")
    assert code == 2 and "--measure pose needs an orientation (qx, qy, qz, qw" in err
    code, out, err = run(
        capsys,
        "calibrate",
        "puma560-nominal",
        meas,
        "--marker-layout",
        lay,
        "--helical",
        "all",
        "--convention",
        "poe",
        "--format",
        "json",
    )
    assert code == 0, err
    assert "5 for each of 6 helical joints' lines, 6 joint scales, 3 for each of 3 markers" in err
    actual = urdf2dh.load("puma560-actual")
    home = np.array(json.loads(out)["tool"]["matrix"])
    assert np.allclose(home, actual.home, atol=1e-9 * actual.size())


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["--helical", "j9"], "--helical: 'j9' is not a joint of the chain"),
        (["--convention", "poe", "--format", "csv"], "--convention poe writes a POE model file"),
        (["--noise-pos", "0.01"], "give both noise levels"),
    ],
)
def test_bad_options_exit_2(poses, capsys, argv, fragment):
    code, _, err = run(capsys, "calibrate", "puma560-nominal", poses, *argv)
    assert code == 2 and fragment in err, err


def test_holdout_must_be_a_fraction(poses, capsys):
    with pytest.raises(SystemExit) as e:
        main(["calibrate", "puma560-nominal", str(poses), "--holdout", "1.5"])
    assert e.value.code == 2 and "must be in [0, 1)" in capsys.readouterr().err


def test_conventions_come_from_the_one_list():
    from urdf2dh.cli import get_argument_parser
    from urdf2dh.conventions import NAMES as CONVENTIONS

    parser = get_argument_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    calibrate = sub.choices["calibrate"]
    conv = next(a for a in calibrate._actions if a.dest == "convention")
    assert tuple(conv.choices) == (*CONVENTIONS, "poe")


@pytest.mark.parametrize(
    "text, fragment",
    [
        ("marker,x,y\n0,1,2\n", "a marker layout has the header 'marker,x,y,z'"),
        (
            "marker,x,y,z\n0,1,2,3\n0,1,2,3\n",
            "row 2 (line 3), column 'marker': marker 0 appears twice",
        ),
        ("marker,x,y,z\na,1,2,3\n", "column 'marker': 'a' is not an integer"),
        ("marker,x,y,z\n0,1,nan,3\n", "x, y, z must be finite"),
        ("marker,x,y,z\n", "no markers after the header"),
    ],
)
def test_bad_marker_layouts_exit_2(tmp_path, capsys, text, fragment):
    meas, lay = tmp_path / "m.csv", tmp_path / "lay.csv"
    run(capsys, "measure", "puma560-actual", "--configs", "20", "--markers", "1", "-o", meas)
    lay.write_text(text)
    code, _, err = run(capsys, "calibrate", "puma560-nominal", meas, "--marker-layout", lay)
    assert code == 2 and str(lay) in err and fragment in err, err


def test_measure_option_conflicts_exit_2(tmp_path, capsys):
    code, _, err = run(
        capsys, "measure", "ur5", "--configs", "3", "--markers", "2", "--measure", "pose"
    )
    assert code == 2 and "--markers measures positions" in err
    code, _, err = run(
        capsys, "measure", "ur5", "--configs", "3", "--marker-layout", tmp_path / "l.csv"
    )
    assert code == 2 and "--marker-layout writes the layout of --markers K" in err
    assert not (tmp_path / "l.csv").exists()


def test_a_layout_missing_a_measured_marker_exits_2(tmp_path, capsys):
    meas, lay = tmp_path / "m.csv", tmp_path / "lay.csv"
    run(
        capsys,
        "measure",
        "puma560-actual",
        "--configs",
        "20",
        "--markers",
        "2",
        "--marker-layout",
        lay,
        "-o",
        meas,
    )
    lay.write_text("marker,x,y,z\n0,1,2,3\n")
    code, _, err = run(capsys, "calibrate", "puma560-nominal", meas, "--marker-layout", lay)
    assert code == 2 and "marker 1 is not in the marker layout (markers there: [0])" in err


def test_pose_files_with_a_marker_column_are_refused(tmp_path, capsys):
    path = tmp_path / "m.csv"
    path.write_text(f"{HEADER},marker\n{GOOD},0\n")
    code, _, err = run(capsys, "calibrate", "puma560-nominal", path)
    assert code == 2 and "a 'marker' column goes with position measurements" in err
