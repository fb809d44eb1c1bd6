"""The urdf2dh command line (docs/commands/index.md): output, formats, files, exit codes."""

from __future__ import annotations

import csv
import io
import json
import subprocess
import sys

import pytest
import yaml

import urdf2dh
from urdf2dh import CONVENTIONS
from urdf2dh.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_convert_ur5_prints_the_table(capsys):
    code, out, err = run(capsys, "convert", "ur5")
    assert code == 0, err
    assert "shoulder_pan_joint" in out and "wrist_3_joint" in out
    assert "0.089159" in out and "0.425000" in out and "0.392250" in out
    assert "theta [deg]" in out and "d [m]" in out
    assert "check: FK against the source at 100 configurations" in out


@pytest.mark.parametrize("conv", ["dh", "mdh", "cpc"])
def test_json_and_yaml_hold_the_spec_tree(capsys, conv):
    code, out, _ = run(capsys, "convert", "ur5", "--convention", conv, "--format", "json")
    assert code == 0
    tree = json.loads(out)
    assert tree["schema"] == "urdf2dh/schemas/table-file-1.schema.json"
    assert tree["convention"] == conv
    assert (tree["robot"], tree["source"]) == ("ur5", "ur5_robot.urdf")
    assert (tree["base_link"], tree["tip_link"]) == ("base_link", "tool0")
    assert tree["units"] == {"length": "m", "angle": "rad"}
    assert len(tree["joints"]) == 6
    assert set(tree["joints"][0]) >= {"name", "type", "pitch", "scale", "params"}
    assert len(tree["base"]["matrix"]) == 4 and len(tree["tool"]["matrix"]) == 4
    assert tree["check"]["samples"] == 100
    assert tree["check"]["max_position_error"] < 1e-12
    code, out_yaml, _ = run(capsys, "convert", "ur5", "--convention", conv, "--format", "yaml")
    assert yaml.safe_load(out_yaml) == tree


def test_csv_and_markdown(capsys):
    code, out, _ = run(capsys, "convert", "puma560-actual", "--format", "csv")
    assert code == 0
    rows = list(csv.DictReader(io.StringIO(out)))
    assert [r["row"] for r in rows] == ["base", "1", "2", "3", "4", "5", "6", "tool"]
    assert float(rows[3]["a"]) == pytest.approx(153.3035, abs=1e-4)
    assert rows[3]["type"] == "helical"
    code, out, _ = run(capsys, "convert", "puma560-actual", "--format", "markdown")
    assert out.count("\n|") >= 9 and "| 3 | j3 | helical |" in out


def test_output_file_is_written_atomically(tmp_path, capsys):
    target = tmp_path / "ur5.json"
    code, out, _ = run(capsys, "convert", "ur5", "--format", "json", "-o", str(target))
    assert code == 0 and out == ""
    assert json.loads(target.read_text())["convention"] == "dh"
    assert [p.name for p in tmp_path.iterdir()] == ["ur5.json"]


def test_bad_input_exit_2_and_no_file(tmp_path, capsys):
    target = tmp_path / "out.json"
    code, _out, err = run(capsys, "convert", str(tmp_path / "missing.urdf"), "-o", str(target))
    assert code == 2 and "missing.urdf: no such file" in err
    assert "Traceback" not in err and not target.exists()
    code, _, err = run(capsys, "convert", "ur5", "--tip", "nowhere")
    assert code == 2 and "unknown tip link 'nowhere'" in err and "tool0" in err
    code, _, err = run(capsys, "convert", "no-such-robot")
    assert code == 2 and "bundled robots are" in err and "ur5" in err


def test_default_tip_ties_are_listed(capsys, tmp_path):
    from urdf2dh.io.catalog import ROBOTS, robot_path

    code, _, err = run(capsys, "convert", str(robot_path(ROBOTS["ur5"])))
    assert code == 2
    assert "several leaves tie" in err and "ee_link" in err and "tool0" in err


def test_verify_info_robots_version(capsys):
    code, out, _ = run(capsys, "verify", "ur5", "--samples", "200")
    assert code == 0
    for label in ("POE model", "dh", "mdh", "cpc"):
        assert label in out
    assert "all conventions agree with Pinocchio" in out
    code, out, _ = run(capsys, "info", "ur5")
    assert code == 0 and "chain: base_link -> tool0: 6 movable joints RRRRRR" in out
    assert "candidate tips" in out and "identifiable parameters" in out
    code, out, _ = run(capsys, "robots")
    assert code == 0
    for name in (
        "ur3",
        "ur5",
        "ur10",
        "panda",
        "kinova",
        "xarm7",
        "z1",
        "so100",
        "so101",
        "puma560-nominal",
        "puma560-actual",
    ):
        assert f"\n{name} " in "\n" + out
    with pytest.raises(SystemExit) as e:
        main(["--version"])
    assert e.value.code == 0


def test_version_names_what_it_runs_on(capsys):
    from importlib.metadata import version

    import numpy

    from urdf2dh import __version__

    with pytest.raises(SystemExit) as e:
        main(["--version"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith(f"urdf2dh {__version__} (yourdfpy {version('yourdfpy')}, ")
    assert f"Pinocchio {version('pin')}, numpy {numpy.__version__}, " in out
    assert f"xacro {version('xacro')}; Python {sys.version.split()[0]})" in out


def test_console_script_runs_without_traceback(tmp_path):
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'/><joint name='j' type='revolute'>")
    proc = subprocess.run(
        [sys.executable, "-m", "urdf2dh.cli", "convert", str(bad)], capture_output=True, text=True
    )
    assert proc.returncode == 2
    assert "malformed XML" in proc.stderr and "Traceback" not in proc.stderr
    assert proc.stderr.count("\n") == 1


def test_output_file_gets_the_usual_permissions(tmp_path, capsys):
    import os
    import stat

    target = tmp_path / "ur5.csv"
    assert main(["convert", "ur5", "--format", "csv", "-o", str(target)]) == 0
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(target.stat().st_mode) == 0o666 & ~umask


def test_verify_checks_the_written_table_at_configurations_of_its_own():
    import numpy as np

    from urdf2dh.check.verify import VERIFY_STREAM

    model = urdf2dh.load("so100")
    report = urdf2dh.verify("so100", samples=300, seed=0, check_samples=150)
    assert [c.table.check.samples for c in report.checks[1:]] == [150] * len(CONVENTIONS)
    assert report.ok
    ours = model.sample(300, (0, VERIFY_STREAM))
    checks = model.sample(300, 0)
    assert not np.allclose(ours, checks)
