"""No command writes over a file it read (docs/security.md): SOURCE, what a xacro file included or
loaded, a bundled robot's installed file, measurements, marker layouts, by any name (symbolic and
hard links included); two outputs of a run are never one file; all outputs of a run are written
together or none is."""

from __future__ import annotations

import hashlib
import os
import shutil
import tempfile
from pathlib import Path

import pytest

from urdf2dh.cli import main
from urdf2dh.io import files

ROOT = Path(__file__).resolve().parents[1]
ARM_PACKAGE = ROOT / "tests" / "data" / "xacro" / "arm_description"


@pytest.fixture
def inputs(tmp_path, monkeypatch):
    """A working directory of inputs of every kind; example-robot-data's files are copies."""
    shutil.copy(ROOT / "tests" / "data" / "genser6.urdf", tmp_path / "arm.urdf")
    os.link(tmp_path / "arm.urdf", tmp_path / "hard.urdf")
    os.link(tmp_path / "arm.urdf", tmp_path / "arm.png")  # for plot, which wants an image name
    os.link(tmp_path / "arm.urdf", tmp_path / "arm.txt")  # for diff, which writes text or json
    (tmp_path / "link.urdf").symlink_to(tmp_path / "arm.urdf")
    shutil.copytree(ARM_PACKAGE, tmp_path / "arm_description")
    erd = tmp_path / "erd"
    (erd / "ur_description" / "urdf").mkdir(parents=True)
    from urdf2dh.io.catalog import ROBOTS, robot_path

    shutil.copy(robot_path(ROBOTS["ur5"]), erd / "ur_description" / "urdf" / "ur5_robot.urdf")
    monkeypatch.setenv("EXAMPLE_ROBOT_DATA_DIR", str(erd))
    monkeypatch.chdir(tmp_path)
    assert main(["convert", "arm.urdf", "--format", "json", "-o", "table.json"]) == 0
    assert main(["convert", "arm.urdf", "--format", "poe", "-o", "model.poe.yaml"]) == 0
    shutil.copy(ROOT / "robots" / "puma560-nominal.yaml", "nominal.yaml")
    common = ["--configs", "30", "--seed", "1"]
    assert main(["measure", "puma560-actual", *common, "-o", "poses.csv"]) == 0
    layout = ["--markers", "3", "--marker-layout", "layout.csv"]
    assert main(["measure", "puma560-actual", *common, *layout, "-o", "markers.csv"]) == 0
    assert main(["measure", "puma560-actual", "--configs", "10", "-o", "held.csv"]) == 0
    assert main(["plan", "arm.urdf", "--configs", "8", "--seed", "1", "-o", "cands.csv"]) == 0
    return tmp_path


def snapshot(directory: Path) -> dict[str, str]:
    """Every file below ``directory`` -> a digest of its bytes (links as where they point)."""
    out = {}
    for p in sorted(directory.rglob("*")):
        if p.is_symlink():
            out[str(p)] = "-> " + os.readlink(p)
        elif p.is_file():
            out[str(p)] = hashlib.sha256(p.read_bytes()).hexdigest()
    return out


XACRO = ["arm_description/urdf/arm.urdf.xacro", "--package-path",
         "arm_description=arm_description", "--xacro-arg", "name:=a", "--xacro-arg",
         "arm_type:=small"]  # fmt: skip
ERD_UR5 = "erd/ur_description/urdf/ur5_robot.urdf"
# (the command before -o, the inputs it reads that -o may name)
RUNS = [
    (["convert", "arm.urdf"], ["arm.urdf", "link.urdf", "hard.urdf"]),
    (["convert", *XACRO], [XACRO[0], "arm_description/urdf/arm_macro.xacro",
                           "arm_description/config/small/dims.yaml"]),
    (["convert", "ur5"], [ERD_UR5]),
    (["convert", "table.json"], ["table.json"]),
    (["convert", "model.poe.yaml"], ["model.poe.yaml"]),
    (["export", "arm.urdf", "--to", "rtb"], ["arm.urdf", "hard.urdf"]),
    (["export", *XACRO, "--to", "kdl"], ["arm_description/config/small/dims.yaml"]),
    (["diff", "arm.urdf", "table.json"], ["arm.txt", "table.json"]),
    (["plot", "arm.urdf"], ["arm.png"]),
    (["measure", "arm.urdf", "--configs", "5"], ["arm.urdf", "hard.urdf"]),
    (["calibrate", "nominal.yaml", "poses.csv"], ["nominal.yaml", "poses.csv"]),
    (["calibrate", "nominal.yaml", "markers.csv", "--marker-layout", "layout.csv"],
     ["layout.csv", "markers.csv"]),
    (["calibrate", "nominal.yaml", "poses.csv", "--validate", "held.csv"], ["held.csv"]),
    (["plan", "arm.urdf", "--configs", "4", "--candidates", "cands.csv"], ["cands.csv"]),
    (["measure", "arm.urdf", "--configurations", "cands.csv"], ["cands.csv", "hard.urdf"]),
]  # fmt: skip


@pytest.mark.parametrize(("command", "targets"), RUNS, ids=lambda v: " ".join(v)[:40])
def test_no_output_replaces_an_input(inputs, capsys, command, targets):
    before = snapshot(inputs)
    for target in targets:
        assert main([*command, "-o", target]) == 2, target
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "refusing to write over it" in err, err
        assert snapshot(inputs) == before, target


@pytest.mark.parametrize(
    ("option", "target"),
    [
        ("--report", "poses.csv"),
        ("--report", "nominal.yaml"),
        ("--plot", "poses.png"),
        ("--marker-layout", "arm.urdf"),
    ],
)
def test_second_outputs_are_held_to_it_too(inputs, capsys, option, target):
    os.link(inputs / "poses.csv", inputs / "poses.png")  # --plot wants an image's name
    before = snapshot(inputs)
    if option in ("--report", "--plot"):
        argv = ["calibrate", "nominal.yaml", "poses.csv", "-o", "new.txt", option, target]
    else:
        argv = ["measure", "arm.urdf", "--configs", "5", "--markers", "2", "-o", "m.csv"]
        argv += [option, target]
    assert main(argv) == 2
    assert "refusing to write over it" in capsys.readouterr().err
    assert snapshot(inputs) == before


def test_the_messages_say_what_the_file_is(inputs, capsys):
    for argv, words in [
        (["convert", "arm.urdf", "-o", "hard.urdf"], "hard.urdf: is the SOURCE file"),
        (["convert", "ur5", "-o", ERD_UR5], "is the installed file of bundled robot 'ur5'"),
        (["convert", *XACRO, "-o", XACRO[0]], "is the SOURCE file"),
        (["convert", *XACRO, "-o", "arm_description/config/small/dims.yaml"],
         "is a file the xacro SOURCE read"),
        (["calibrate", "nominal.yaml", "poses.csv", "-o", "poses.csv"], "is an input of this run"),
    ]:  # fmt: skip
        assert main(argv) == 2
        assert words in capsys.readouterr().err


def test_a_directory_holding_a_link_to_an_input_is_refused(inputs, capsys):
    out = inputs / "out"
    out.mkdir()
    os.link(inputs / "arm.urdf", out / "tool.urdf")
    before = snapshot(inputs)
    assert main(["convert", "arm.urdf", "--all-tips", "--format", "urdf", "-o", "out"]) == 2
    assert "out/tool.urdf: is the SOURCE file" in capsys.readouterr().err
    assert snapshot(inputs) == before


def test_an_input_read_in_an_earlier_run_is_not_one_of_this_run(inputs):
    """Inputs are the run's (files.one_run): the next run may write where the last one read."""
    assert main(["convert", "ur5", "-o", "table.json"]) == 0
    assert "shoulder_pan_joint" in (inputs / "table.json").read_text()


# --------------------------------------------------------------------------- outputs of a run


@pytest.mark.parametrize("link", ["same", "symbolic", "hard"])
def test_two_outputs_naming_one_file_are_refused(inputs, capsys, link):
    (inputs / "out.txt").write_text("old")
    other = {"same": "out.txt", "symbolic": "sym.json", "hard": "hard.json"}[link]
    if link == "symbolic":
        (inputs / other).symlink_to(inputs / "out.txt")
    elif link == "hard":
        os.link(inputs / "out.txt", inputs / other)
    before = snapshot(inputs)
    argv = ["calibrate", "nominal.yaml", "poses.csv", "-o", "out.txt", "--report", other]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{other}: is the same file as out.txt" in err
    assert snapshot(inputs) == before


def test_two_new_outputs_naming_one_file_are_refused(inputs, capsys):
    argv = ["measure", "arm.urdf", "--configs", "5", "--markers", "2"]
    assert main([*argv, "-o", "m.csv", "--marker-layout", "./m.csv"]) == 2
    assert "./m.csv: is the same file as m.csv" in capsys.readouterr().err
    assert not (inputs / "m.csv").exists()


def test_a_failing_second_output_leaves_the_first_as_it_was(inputs, capsys, monkeypatch):
    """The report cannot be put in place (a full disk at its rename): the model file that was
    renamed before it is put back."""
    (inputs / "model.txt").write_text("old model")
    (inputs / "report.json").write_text("old report")
    before = snapshot(inputs)
    real, calls = os.replace, []

    def replace(src, dst):
        calls.append(dst)
        if str(dst).endswith("report.json"):
            raise OSError(28, "No space left on device")
        real(src, dst)

    monkeypatch.setattr(files.os, "replace", replace)
    argv = ["calibrate", "nominal.yaml", "poses.csv", "--helical", "all", "-o", "model.txt",
            "--report", "report.json"]  # fmt: skip
    assert main(argv) == 2
    assert "report.json: cannot write (No space left on device)" in capsys.readouterr().err
    assert any(str(c).endswith("model.txt") for c in calls)  # it was put in place, then back
    assert snapshot(inputs) == before


def test_a_report_that_cannot_be_written_is_refused_before_the_fit(inputs, capsys):
    (inputs / "folder.json").mkdir()
    (inputs / "model.txt").write_text("old model")
    before = snapshot(inputs)
    argv = ["calibrate", "nominal.yaml", "poses.csv", "-o", "model.txt", "--report", "folder.json"]
    assert main(argv) == 2
    assert "folder.json: is not a regular file" in capsys.readouterr().err
    assert snapshot(inputs) == before


def test_measure_writes_both_files_or_neither(inputs, capsys, monkeypatch):
    real, made = tempfile.mkstemp, []

    def mkstemp(*args, **kwargs):
        made.append(kwargs.get("prefix"))
        if len(made) == 2:
            raise OSError(13, "Permission denied")
        return real(*args, **kwargs)

    monkeypatch.setattr(tempfile, "mkstemp", mkstemp)
    argv = ["measure", "arm.urdf", "--configs", "5", "--markers", "2"]
    assert main([*argv, "-o", "m.csv", "--marker-layout", "lay.csv"]) == 2
    assert f"lay.csv: cannot write in directory '{inputs}' (Permission denied)" in (
        capsys.readouterr().err
    )
    assert not (inputs / "m.csv").exists() and not (inputs / "lay.csv").exists()
    assert [p.name for p in inputs.iterdir() if p.name.startswith(".")] == []
    monkeypatch.setattr(tempfile, "mkstemp", real)
    assert main([*argv, "-o", "m.csv", "--marker-layout", "lay.csv"]) == 0
    assert (inputs / "m.csv").read_text().startswith("joint1,")
    assert (inputs / "lay.csv").read_text().startswith("marker,x,y,z")


def test_a_sample_of_the_overwrite_corpus(tmp_path):
    """A seeded sample of tests/overwrite_cases.py (scripts/overwrite_corpus.py runs it all)."""
    from overwrite_cases import Workspace, run_case, sample

    ws = Workspace(tmp_path)
    verdicts = [run_case(ws, case) for case in sample(ws, 24, seed=18)]
    assert [v for v in verdicts if v.result != "refused"] == []
    assert {v.case.kind for v in verdicts} >= {"input as output", "same file"}


def test_a_device_may_take_two_outputs(inputs):
    """Two outputs to /dev/null are not one file replaced twice: a device is written into."""
    argv = ["measure", "arm.urdf", "--configs", "5", "--markers", "2"]
    assert main([*argv, "-o", os.devnull, "--marker-layout", os.devnull]) == 0
