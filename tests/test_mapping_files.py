"""POE and table files read numbers as YAML 1.2 and JSON do (never YAML 1.1's octal, base 60,
``_`` groups, binary or yes/no), refuse what YAML 1.1 would read as another number naming the
file and the field, and refuse a key given twice in one mapping, naming it."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from urdf2dh import load
from urdf2dh.cli import main
from urdf2dh.errors import InputError
from urdf2dh.io.mappings import read_mapping

POE = """format: poe
name: arm
length_unit: mm
joints:
  - {{name: j1, twist: [0, 0, 1, 0, 0, 0], limits: [{lower}, {upper}]}}
  - {{name: j2, twist: [0, 1, 0, {vx}, 0, 0]}}
tool:
  twist: [0, 0, 0, 100, 0, 0]
"""


def poe_text(lower: str = "-1", upper: str = "1", vx: str = "-300") -> str:
    return POE.format(lower=lower, upper=upper, vx=vx)


def refused(tmp_path: Path, capsys, text: str, suffix: str = ".yaml") -> str:
    """The one-line error of `convert` on the file, after checking that nothing was written."""
    path = tmp_path / f"arm{suffix}"
    path.write_text(text)
    out = tmp_path / "out.json"
    assert main(["convert", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert not out.exists()
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("urdf2dh: error: "), err
    assert str(path) in lines[0]
    return lines[0]


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        ("0100", "a leading zero: YAML 1.1 reads it as octal 64, YAML 1.2 as decimal 100"),
        ("-0100", "octal -64"),
        ("2:50", "YAML 1.1 reads it as 170"),
        ("1:30.5", "YAML 1.1 reads it as 90.5"),
        ("1_000", "YAML 1.1 reads it as 1000"),
        ("0b11", "YAML 1.1 reads it as 3"),
        ("yes", "YAML 1.1 reads it as true"),
        ("off", "YAML 1.1 reads it as false"),
    ],
)
def test_yaml_1_1_numbers_are_refused_naming_the_field(tmp_path, capsys, value, expected):
    line = refused(tmp_path, capsys, poe_text(upper=value))
    assert "joint 'j1' limits must be a number, not" in line and expected in line


@pytest.mark.parametrize(
    ("value", "reason"), [("0x1F", "hexadecimal"), ("0o17", "octal"), ("-0x10", "hexadecimal")]
)
def test_yaml_1_2_numbers_of_other_bases_are_refused_as_every_file_refuses_them(
    tmp_path, capsys, value, reason
):
    line = refused(tmp_path, capsys, poe_text(upper=value))
    assert f"joint 'j1' limits must be a number, not '{value}' ({reason}" in line


@pytest.mark.parametrize("value", [".inf", "-.inf", ".nan", ".NaN", "1e400"])
def test_non_finite_numbers_are_refused_where_a_number_is_expected(tmp_path, capsys, value):
    line = refused(tmp_path, capsys, poe_text(vx=value))
    # 1e400 is a YAML number beyond float64; .inf and .nan are not of urdf2dh's number grammar
    assert "joint 'j2' twist must be" in line and "finite" in line, line


@pytest.mark.parametrize(
    ("value", "number"),
    [("1e3", 1000.0), ("+2", 2.0), (".5", 0.5), ("3.", 3.0), ("010.5", 10.5),
     ("-2.5E-1", -0.25)],
)  # fmt: skip
def test_yaml_1_2_numbers_are_read_as_yaml_1_2_reads_them(tmp_path, value, number):
    path = tmp_path / "arm.yaml"
    path.write_text(poe_text(upper=value))
    model = load(str(path))
    assert model.joints[0].upper == number


def test_a_name_is_read_as_written(tmp_path):
    """YAML 1.1 would read these names as 64, 170 and true; YAML 1.2 reads the text."""
    path = tmp_path / "arm.yaml"
    text = poe_text().replace("name: j1", "name: 0100").replace("name: j2", "name: 2:50")
    path.write_text(text.replace("name: arm", "name: yes"))
    model = load(str(path))
    assert [j.name for j in model.joints] == ["0100", "2:50"] and model.name == "yes"


def test_the_table_file_reads_its_numbers_the_same_way(tmp_path, capsys):
    assert main(["convert", "ur5", "--format", "yaml"]) == 0
    text = capsys.readouterr().out
    assert "alpha: 1.5707963267948966" in text
    line = refused(tmp_path, capsys, text.replace("alpha: 1.5707963267948966", "alpha: 1:30", 1))
    assert "alpha must be a number, not '1:30' (YAML 1.1 reads it as 90;" in line
    assert "samples: 100" in text
    line = refused(tmp_path, capsys, text.replace("samples: 100", "samples: 0144"))
    assert "check samples must be a number, not '0144' (a leading zero" in line
    line = refused(tmp_path, capsys, text.replace("samples: 100", "samples: 2.5"))
    assert "check samples must be a whole number" in line


@pytest.mark.parametrize(
    ("text", "key", "line"),
    [
        ("format: poe\nformat: poe\n", "'format'", 2),
        (poe_text().replace("twist: [0, 0, 1, 0, 0, 0]", "twist: [0, 0, 1, 0, 0, 0], twist: [1]"),
         "'twist'", 5),
        (poe_text() + "tool: {twist: [0, 0, 0, 1, 0, 0]}\n", "'tool'", 9),
    ],
)  # fmt: skip
def test_a_key_twice_in_yaml_is_refused_naming_it_and_its_line(tmp_path, capsys, text, key, line):
    message = refused(tmp_path, capsys, text)
    assert f"key {key} appears twice in one mapping (line {line})" in message


def test_a_key_twice_in_json_is_refused_naming_it(tmp_path, capsys):
    tree = {"format": "poe", "joints": [{"name": "j1", "twist": [0, 0, 1, 0, 0, 0]}],
            "tool": {"twist": [0, 0, 0, 1, 0, 0]}}  # fmt: skip
    text = json.dumps(tree).replace('"name": "j1"', '"name": "j1", "name": "j9"')
    assert "key 'name' appears twice in one mapping" in refused(tmp_path, capsys, text, ".json")


def test_merge_keys_still_merge_and_the_mapping_own_keys_win(tmp_path):
    path = tmp_path / "arm.yaml"
    path.write_text(
        "format: poe\nlength_unit: mm\nlimits: &lim {limits: [-1, 1], type: revolute}\n"
        "joints:\n  - {<<: *lim, name: j1, twist: [0, 0, 1, 0, 0, 0], limits: [-2, 2]}\n"
        "tool: {twist: [0, 0, 0, 100, 0, 0]}\n"
    )
    (joint,) = load(str(path)).joints
    assert (joint.lower, joint.upper, joint.kind) == (-2.0, 2.0, "revolute")


def test_reading_is_the_same_for_yaml_and_json():
    yaml_tree = read_mapping(Path("a.yaml"), "a.yaml", b"a: [1, 2.5, -3e-2, true, null, 16]")
    json_tree = read_mapping(Path("a.json"), "a.json", b'{"a": [1, 2.5, -3e-2, true, null, 16]}')
    assert yaml_tree == json_tree
    assert [type(v) for v in yaml_tree["a"]] == [type(v) for v in json_tree["a"]]
    # YAML 1.2's numbers outside urdf2dh's grammar are text, refused where a number is expected
    assert read_mapping(Path("a.yaml"), "a.yaml", b"a: [-.Inf, 0x10]")["a"] == ["-.Inf", "0x10"]
    assert math.isinf(read_mapping(Path("a.yaml"), "a.yaml", b"a: -1e999")["a"])


def test_a_huge_integer_is_one_line(tmp_path):
    with pytest.raises(InputError, match=r"a\.yaml: malformed YAML \(Exceeds the limit"):
        read_mapping(Path("a.yaml"), "a.yaml", b"a: " + b"7" * 5000)


def test_values_and_depth_are_bounded_before_anything_is_built():
    """Counted from the parser's events: a list of a million and one values, or lists nested
    1,001 deep (libyaml's composer would recurse on), are refused naming the bound."""
    many = b"a: [" + b", ".join([b"0"] * 1_000_001) + b"]\n"
    with pytest.raises(InputError, match=r"^many\.yaml: more than 1,000,000 values$"):
        read_mapping(Path("many.yaml"), "many.yaml", many)
    deep = b"a: " + b"[" * 1_001 + b"]" * 1_001 + b"\n"
    with pytest.raises(InputError, match=r"^deep\.yaml: nested too deeply \(more than 1,000 "):
        read_mapping(Path("deep.yaml"), "deep.yaml", deep)
    assert read_mapping(Path("ok.yaml"), "ok.yaml", b"a: " + b"[" * 999 + b"]" * 999 + b"\n")
