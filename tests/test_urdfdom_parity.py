"""urdf2dh reads URDF as urdfdom (Pinocchio's reader) does: a seeded sample of the parity corpus
(scripts/urdfdom_parity.py) against the real Pinocchio; tabs and line breaks in attributes kept
as tinyxml2 keeps them; a limit with lower above upper read as the range between, with a
warning naming the joint; and one number grammar for every file urdf2dh reads."""

from __future__ import annotations

import json
import sys
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))

import urdfdom_parity

from urdf2dh.calibration.measurements import read_measurements
from urdf2dh.cli import main
from urdf2dh.errors import InputError
from urdf2dh.io.sources import open_source
from urdf2dh.io.urdf import parse_tree
from urdf2dh.io.urdf.parse import keep_attribute_whitespace


def test_a_seeded_sample_keeps_parity_with_pinocchio():
    outcomes = urdfdom_parity.run_corpus(count=90, seed=31)
    broken = [o for o in outcomes if o.problems]
    assert not broken, urdfdom_parity.report(broken)
    assert {o.case.kinds[0] for o in outcomes} == set(urdfdom_parity.CLASSES)
    verdicts = Counter(o.verdict for o in outcomes)
    assert verdicts["Pinocchio loads, urdf2dh converts"] >= 15, verdicts
    assert verdicts["Pinocchio refuses, urdf2dh exit 2"] >= 30, verdicts


def test_the_parity_invariants_are_checked():
    case = urdfdom_parity.Case(("number",), "x", "<robot/>", "j1")
    path = "/tmp/p.urdf"
    good = "urdf2dh: error: /tmp/p.urdf: joint 'j1': origin xyz '1_0' is not 3 numbers\n"
    assert urdfdom_parity.judge(case, path, False, 2, good) == []
    assert urdfdom_parity.judge(case, path, True, 0, "") == []
    for pinocchio, code, err in [
        (False, 0, ""),  # Pinocchio refuses, we convert
        (True, 2, good),  # Pinocchio loads, we refuse, not for a documented reason
        (False, 2, "urdf2dh: error: /tmp/p.urdf: some fault\n"),  # no joint named
        (False, 2, "urdf2dh: internal error: KeyError\n"),
        (False, 2, good + good),  # two lines
        (False, 3, good),
    ]:
        assert urdfdom_parity.judge(case, path, pinocchio, code, err), (pinocchio, code, err)


def test_white_space_in_attribute_values_is_kept_as_tinyxml2_keeps_it():
    plain = b'<robot name="r"><joint name="j" type="fixed"/></robot>'
    assert keep_attribute_whitespace(plain) is plain  # the common file, as it is
    text = (
        b"<robot name='r'>\n<!-- <joint name=\"x\ty\"> -->\n<joint\n name=\"j\"\n type='fixed'>"
        b'<origin xyz="0\t0 1" rpy="0\r\n0\r0"/></joint><![CDATA[ a="1\t2" ]]></robot>'
    )
    assert keep_attribute_whitespace(text) == (
        b"<robot name='r'>\n<!-- <joint name=\"x\ty\"> -->\n<joint\n name=\"j\"\n type='fixed'>"
        b'<origin xyz="0&#9;0 1" rpy="0&#10;0&#10;0"/></joint><![CDATA[ a="1\t2" ]]></robot>'
    )


LINKS = '<link name="a"/><link name="b"/><link name="c"/>'


def _gripper(lower: str, upper: str) -> str:
    limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
    return (
        f'<robot name="g">{LINKS}<joint name="arm" type="revolute"><parent link="a"/>'
        f'<child link="b"/><axis xyz="0 0 1"/>{limit}</joint>'
        '<joint name="finger" type="prismatic"><parent link="b"/><child link="c"/>'
        f'<origin xyz="0.1 0 0"/><axis xyz="1 0 0"/><limit lower="{lower}" upper="{upper}" '
        'effort="1" velocity="1"/></joint></robot>'
    )


def test_a_limit_with_lower_above_upper_is_read_as_the_range_between_and_warned(tmp_path, capsys):
    path = tmp_path / "gripper.urdf"
    path.write_text(_gripper("0.04", "0"))
    model = open_source(str(path)).model()
    finger = model.joints[-1]
    assert (finger.lower, finger.upper) == (0.0, 0.04)
    warning = (
        "joint 'finger': its <limit> has lower 0.04 above upper 0; read as the range [0, 0.04] "
        "(as Gazebo reads it; urdfdom and Pinocchio keep lower and upper as written)"
    )
    assert warning in model.warnings
    assert main(["convert", str(path)]) == 0
    assert f"warning: {warning}\n" in capsys.readouterr().out
    q = model.sample(300, 4)  # what measure and verify draw: within the range
    assert 0.0 <= q[:, 1].min() and q[:, 1].max() <= 0.04
    assert main(["verify", str(path), "--samples", "50"]) == 0
    # a URDF of version 1.2 may not: urdfdom refuses it there
    path.write_text(_gripper("0.04", "0").replace('name="g"', 'name="g" version="1.2"'))
    assert main(["convert", str(path)]) == 2
    assert "joint 'finger': limit lower '0.04' is above upper '0'" in capsys.readouterr().err


# Forms of numbers: every file urdf2dh reads holds numbers in one grammar (urdf2dh.numerals)
NUMBERS = {"1": 1.0, "-2.5": -2.5, ".5": 0.5, "5.": 5.0, "+5": 5.0, "1E-3": 1e-3, "2.5e+1": 25.0}
NOT_NUMBERS = {
    "-1.2_396": "digits grouped with '_'",
    "\uff11": "digits that are not ASCII",
    "\u0661.5": "digits that are not ASCII",
    "0x1F": "hexadecimal",
    "0o17": "octal",
    "nan": "finite",
    "Infinity": "finite",
    "1,5": "a decimal comma",
    "1e": "",
    "--1": "",
}


def _in_urdf(text: str) -> float:
    urdf = _gripper("0", "0.04").replace('<origin xyz="0.1 0 0"/>', f'<origin xyz="{text} 0 0"/>')
    tree = parse_tree(urdf.encode(), "g.urdf")
    return float(tree.joints["finger"].origin[0, 3])


def _in_poe(text: str, tmp_path: Path) -> float:
    path = tmp_path / "arm.yaml"
    path.write_text(  # block style: "1,5" is one plain scalar there
        "format: poe\njoints:\n  - name: j1\n    twist: [0, 0, 1, 0, 0, 0]\n    limits:\n"
        f"      - -9\n      - {text}\ntool: {{twist: [0, 0, 0, 1, 0, 0]}}\n",
        encoding="utf-8",
    )
    return float(open_source(str(path)).model().joints[0].upper)


def _in_csv(text: str, tmp_path: Path) -> float:
    path = tmp_path / "m.csv"
    path.write_text(f'j1,x,y,z\n" {text}\t",0,0,1\n', encoding="utf-8")  # quoted: "1,5"
    return float(read_measurements(path, ("j1",)).q[0, 0])


@pytest.mark.parametrize(("text", "value"), NUMBERS.items())
def test_a_number_reads_the_same_in_every_file(text, value, tmp_path):
    assert _in_urdf(text) == _in_poe(text, tmp_path) == _in_csv(text, tmp_path) == value


@pytest.mark.parametrize(("text", "reason"), NOT_NUMBERS.items())
def test_a_text_that_is_no_number_is_refused_by_every_file_with_its_reason(text, reason, tmp_path):
    for read in (_in_urdf, lambda t: _in_poe(t, tmp_path), lambda t: _in_csv(t, tmp_path)):
        with pytest.raises(InputError) as e:
            read(text)
        message = str(e.value)
        assert repr(text)[1:-1] in message and "\n" not in message, message
        # the grammar's reason; in YAML, or what a YAML 1.1 reader would make of it
        assert reason in message or "YAML 1.1 reads it as" in message, message


def test_json_numbers_follow_the_grammar_too(tmp_path):
    path = tmp_path / "arm.json"
    tree = {"format": "poe", "joints": [{"name": "j1", "twist": [0, 0, 1, 0, 0, 0]}],
            "tool": {"twist": [0, 0, 0, 1, 0, 0]}}  # fmt: skip
    for bad in ("NaN", "Infinity", "1e999"):
        path.write_text(json.dumps(tree).replace("[0, 0, 0, 1, 0, 0]", f"[0, 0, 0, {bad}, 0, 0]"))
        with pytest.raises(InputError, match="tool twist must be finite"):
            open_source(str(path))
    path.write_text(json.dumps(tree))
    assert np.allclose(open_source(str(path)).model().home[:3, 3], [1, 0, 0])


@pytest.mark.parametrize("text", ["-1.2_396", "\uff11", "0x1F", "nan", "1,5"])
def test_options_and_marker_layouts_hold_numbers_in_the_same_grammar(text, tmp_path, capsys):
    from urdf2dh.calibration.measurements import read_layout

    for argv, said in (
        (["convert", "ur5", f"--parallel-angle={text}"], f"'{text}' is not a number"),
        (["verify", "ur5", "--samples", text.replace("-", "")], "is not an integer"),
    ):
        with pytest.raises(SystemExit) as e:  # argparse's usage error
            main(argv)
        assert e.value.code == 2 and said in capsys.readouterr().err
    layout = tmp_path / "layout.csv"
    layout.write_text(f'marker,x,y,z\n0,1,"{text}",3\n', encoding="utf-8")
    with pytest.raises(InputError, match=r"x, y, z must be (numbers|finite)"):
        read_layout(layout)
    layout.write_text(f'marker,x,y,z\n"{text}",1,2,3\n', encoding="utf-8")
    with pytest.raises(InputError, match="is not an integer"):
        read_layout(layout)


def test_a_fixed_joints_axis_is_not_read_as_urdfdom_reads_none():
    text = (
        _gripper("0", "0.04")
        .replace('type="prismatic"', 'type="fixed"')
        .replace('<axis xyz="1 0 0"/>', '<axis xyz="nan x"/>')
    )
    assert urdfdom_parity.pinocchio_model(text) is not None  # Pinocchio loads it
    assert parse_tree(text.encode(), "g.urdf").joints["finger"].type == "fixed"
    broken = text.replace('type="fixed"', 'type="planar"')  # a planar joint's axis is read
    assert urdfdom_parity.pinocchio_model(broken) is None
    with pytest.raises(InputError, match="joint 'finger': axis xyz 'nan x'"):
        parse_tree(broken.encode(), "g.urdf")
