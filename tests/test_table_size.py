"""A written table keeps its robot's size: the table file (``--format json``, ``yaml``) and the POE
model file (``--format poe``) state ``size`` in their length unit, every command reading them
takes it, a bad one is refused in one line, and a file without it (older, or written by hand)
takes the size of its own points (docs/formats/table-file.md, docs/formats/poe-file.md)."""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import pytest
import yaml
from hypothesis import given
from jsonschema import Draft202012Validator
from test_properties import SETTINGS, _same_params, chains

import urdf2dh
from urdf2dh import CONVENTIONS, schemas
from urdf2dh.cli import main
from urdf2dh.emit.formats import render
from urdf2dh.io.tablefile import read_table

ROOT = Path(__file__).resolve().parents[1]
# Real robots whose tables' frame origins give another size than their source's (xarm7: 2.2%
# larger, scara: 3.6% smaller, the PUMA's D-H tables: 2.18 times its size)
ROBOTS = ("xarm7", "scara", "puma560-actual")
FORMATS = {"json": ".json", "yaml": ".yaml", "poe": ".poe.yaml"}
MEASUREMENTS = ROOT / "examples" / "calibration-data" / "ur10" / "ur10_pose.csv"


def _tree(path: Path) -> dict:
    return yaml.safe_load(path.read_text())  # JSON is YAML


def _write(path: Path, tree: dict) -> None:
    text = json.dumps(tree) if path.suffix == ".json" else yaml.safe_dump(tree, sort_keys=False)
    path.write_text(text)


@pytest.mark.parametrize("robot", ROBOTS)
def test_a_written_table_reads_back_with_its_robots_size(tmp_path, robot):
    """Every convention in every format: the file states the size, what reads the file has it
    (the model, the table, a conversion of it), equal to the in-memory table's and the robot's,
    where the table's own points would give another."""
    model = urdf2dh.load(robot)
    flips = 0
    for conv in CONVENTIONS:
        table = urdf2dh.to_table(model, conv)
        assert table.size == model.size()
        flips += table.to_poe().own_size() != model.size()
        for fmt, suffix in FORMATS.items():
            out = tmp_path / f"{conv}{suffix}"
            args = ["convert", robot, "--convention", conv, "--format", fmt, "-o", str(out)]
            assert main(args) == 0
            tree = _tree(out)
            assert tree["size"] == model.size(), (conv, fmt)
            again = urdf2dh.load(str(out))
            assert again.size() == table.size == model.size(), (conv, fmt)
            assert urdf2dh.to_table(again, conv).size == table.size, (conv, fmt)
            if fmt != "poe":
                assert read_table(tree, out.name).size == table.size, (conv, fmt)
    assert flips, f"{robot}: no table whose own points give another size"


def test_commands_reading_the_file_measure_against_the_robots_size(tmp_path, capsys):
    """``info``, ``verify`` and ``diff`` of a PUMA's D-H table file measure against the PUMA's
    size (264 mm, where the table's own frame origins reach 577 mm), as they do of the robot;
    a model renamed or scaled keeps it (``diff`` names its sides and brings them to one unit)."""
    out = tmp_path / "puma.yaml"
    assert main(["convert", "puma560-actual", "-o", str(out)]) == 0
    capsys.readouterr()
    said = []
    for source in ("puma560-actual", str(out)):
        assert main(["info", source]) == 0
        text = capsys.readouterr().out
        assert main(["verify", source, "--samples", "50"]) == 0
        text += capsys.readouterr().out
        said.append([line.split("size")[1] for line in text.splitlines() if "size" in line])
        assert main(["diff", source, "puma560-nominal", "--format", "json"]) == 0
        said[-1].append(json.loads(capsys.readouterr().out)["size"])
    assert said[0] == said[1] and said[0][-1] == urdf2dh.load("puma560-actual").size(), said
    assert len(said[0]) == 3 and "264.3 mm" in said[0][1], said
    model = urdf2dh.load(str(out))
    assert model.named("puma").size() == model.size() != model.own_size()
    assert model.scaled(1e-3, "m").size() == 1e-3 * model.size()
    own = urdf2dh.load("puma560-actual")  # a size of its own points: computed again
    assert own.scaled(1e-3, "m").size() == own.scaled(1e-3, "m").own_size()


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_file_without_its_size_still_reads_at_its_own_points_size(tmp_path, fmt):
    """An older or hand-written file: read as before, its size that of its own points (the
    SCARA's D-H frame origins, and the axes' points nearest the base a POE file's twists give:
    3.6% under the SCARA's size)."""
    out = tmp_path / f"scara{FORMATS[fmt]}"
    assert main(["convert", "scara", "--convention", "dh", "--format", fmt, "-o", str(out)]) == 0
    tree = _tree(out)
    del tree["size"]
    _write(out, tree)
    again = urdf2dh.load(str(out))
    model = urdf2dh.load("scara")
    own = urdf2dh.to_table(model, "dh").to_poe().own_size()
    assert again.size() == pytest.approx(own, rel=1e-12)
    assert abs(again.size() / model.size() - 0.964) < 1e-3


BAD = {
    "negative": (-0.5, "size must be positive (the robot's size in mm, at least 1e-292), not -0.5"),
    "zero": (0, "size must be positive (the robot's size in mm, at least 1e-292), not 0"),
    "subnormal": (1e-300, "size must be positive (the robot's size in mm, at least 1e-292)"),
    "text": ("big", "size must be a number, not 'big'"),
    "null": (None, "size must be a number, not None"),
    "boolean": (True, "size must be a number, not True"),
    "huge": (1e300, "size is 1e+300: beyond 1e+12"),
}
COMMANDS = {
    "convert": ["convert", "{file}", "--convention", "mdh", "-o", "{out}.json"],
    "verify": ["verify", "{file}"],
    "diff": ["diff", "puma560-actual", "{file}", "-o", "{out}.txt"],
    "export": ["export", "{file}", "--to", "rtb", "-o", "{out}.py"],
    "info": ["info", "{file}"],
    "calibrate": ["calibrate", "{file}", str(MEASUREMENTS), "-o", "{out}.json"],
}


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("case", BAD)
def test_a_bad_size_is_refused_in_one_line(tmp_path, capsys, fmt, case):
    """Every command refuses it: exit 2, one line naming the file and the field, nothing
    written."""
    value, message = BAD[case]
    src = tmp_path / f"puma{FORMATS[fmt]}"
    assert main(["convert", "puma560-actual", "--format", fmt, "-o", str(src)]) == 0
    tree = _tree(src)
    tree["size"] = value
    _write(src, tree)
    before = src.read_bytes()
    capsys.readouterr()
    for command, args in COMMANDS.items():
        out = tmp_path / f"out-{command}"
        argv = [a.format(file=src, out=out) for a in args]
        assert main(argv) == 2, command
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and f"{src}: {message}" in err, (command, err)
        assert not list(tmp_path.glob("out-*")), command
    assert src.read_bytes() == before


def test_a_bad_size_through_the_command_line_has_no_traceback(tmp_path):
    src = tmp_path / "ur5.json"
    assert main(["convert", "ur5", "-o", str(src)]) == 0
    tree = json.loads(src.read_text())
    tree["size"] = -1.0
    src.write_text(json.dumps(tree))
    out = tmp_path / "ur5-mdh.json"
    proc = subprocess.run(
        [sys.executable, "-m", "urdf2dh.cli", "convert", str(src), "--convention", "mdh",
         "-o", str(out)],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert proc.returncode == 2 and proc.stdout == "" and not out.exists()
    assert proc.stderr == (
        f"urdf2dh: error: {src}: size must be positive (the robot's size in m, at least 1e-292), "
        "not -1\n"
    )


@pytest.mark.parametrize("fmt", ["json", "poe"])
def test_the_schemas_take_a_positive_size_or_none(fmt):
    """The schema a written file names takes its ``size``, or none, and refuses what the reader
    refuses."""
    tree = yaml.safe_load(render(urdf2dh.to_table(urdf2dh.load("scara"), "dh"), fmt))
    validator = Draft202012Validator(schemas.load(tree["schema"]))
    assert validator.is_valid(tree) and tree["size"] == urdf2dh.load("scara").size()
    for bad in (0, -0.5, "big", None, True):
        assert not validator.is_valid(tree | {"size": bad}), bad
    del tree["size"]
    assert validator.is_valid(tree)


@SETTINGS
@given(chains())
def test_a_table_read_back_from_its_file_converts_again_to_itself(model):
    """The idempotence of tests/test_properties.py through the table file: convention -> table
    file -> POE -> the same convention gives the same table, the size kept (a km chain's file is
    labelled m: the table file knows no km)."""
    for conv in CONVENTIONS:
        table = urdf2dh.to_table(model, conv)
        labelled = replace(table, length_unit="m") if table.length_unit == "km" else table
        written = read_table(json.loads(render(labelled, "json")), "table.json")
        assert written.size == table.size, f"{conv}: the table file's size"
        again = urdf2dh.to_table(written.to_poe(), conv)
        _same_params(table, again, model.size(), f"{conv} (file)")
