"""Mimic joints kept coupled: a joint on the chain that mimics another carries
``mimic: {joint, multiplier, offset}``, tables are driven by the actuated joints only, and
Pinocchio, coupling the URDF's mimic joints itself, agrees."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from oracle import assert_fk_matches, pin_reference

from urdf2dh import load, to_table
from urdf2dh.cli import main
from urdf2dh.conventions import NAMES
from urdf2dh.emit.export import TARGETS
from urdf2dh.errors import ChainError
from urdf2dh.io.sources import open_source
from urdf2dh.io.urdf import parse_tree, tree_to_poe

DATA = Path(__file__).parent / "data"
ARM = str(DATA / "parallelogram.urdf")


def test_the_rows_follow_their_leaders_and_pinocchio_agrees():
    source = open_source(ARM)
    model = source.model()
    assert (model.n, model.dof) == (5, 3)
    assert [
        (j.name, j.mimic and (j.mimic.joint, j.mimic.multiplier, j.mimic.offset))
        for j in model.joints
    ] == [
        ("turn", None),
        ("shoulder", None),
        ("elbow", ("shoulder", -1.0, 0.1)),
        ("wrist_turn", None),
        ("gripper_slide", ("wrist_turn", 0.01, 0.002)),
    ]
    q, reference = pin_reference(source, model)  # Pinocchio with its own mimic joints
    assert q.shape == (200, 3)
    assert_fk_matches("POE", model.fk_batch(q), reference, model.size(), q)
    for conv in NAMES:
        table = to_table(model, conv)
        assert [r.mimic for r in table.rows] == [j.mimic for j in model.joints]
        assert table.dof == 3
        assert_fk_matches(conv, table.fk_batch(q), reference, model.size(), q)
    rows = model.positions(q)
    np.testing.assert_array_equal(rows[:, 2], -q[:, 1] + 0.1)
    np.testing.assert_array_equal(rows[:, 4], 0.01 * q[:, 2] + 0.002)


def test_table_and_poe_files_keep_the_coupling(tmp_path, capsys):
    model = load(ARM)
    q = model.sample(100, 3)
    for fmt, name in (("json", "t.json"), ("yaml", "t.yaml"), ("poe", "t.poe.yaml")):
        path = tmp_path / name
        assert main(["convert", ARM, "--convention", "cpc", "--format", fmt, "-o", str(path)]) == 0
        again = load(str(path))
        assert [j.mimic for j in again.joints] == [j.mimic for j in model.joints]
        np.testing.assert_allclose(again.fk_batch(q), model.fk_batch(q), atol=1e-14)
    tree = json.loads((tmp_path / "t.json").read_text())
    assert tree["joints"][2]["mimic"] == {"joint": "shoulder", "multiplier": -1.0, "offset": 0.1}
    assert "mimic" not in tree["joints"][0]
    assert main(["convert", ARM]) == 0
    text = capsys.readouterr().out
    assert "shoulder m=-1 o=0.1" in text and "wrist_turn m=0.01 o=0.002" in text


def test_the_urdf_writer_writes_mimic_joints_pinocchio_couples(tmp_path):
    model = load(ARM)
    for conv in ("dh", "hayati"):
        path = tmp_path / f"{conv}.urdf"
        assert (
            main(["convert", ARM, "--convention", conv, "--format", "urdf", "-o", str(path)]) == 0
        )
        assert path.read_text().count("<mimic ") == 2
        written = open_source(str(path))
        q, reference = pin_reference(written, written.model(), samples=100)
        assert_fk_matches(f"{conv} URDF", model.fk_batch(q), reference, model.size(), q)
        assert main(["verify", str(path), "--samples", "100"]) == 0


def test_mimic_joints_of_a_millimetre_table_keep_their_meaning(tmp_path):
    """A prismatic follower in a table in mm: the URDF (metres) scales its multiplier."""
    poe = tmp_path / "mm.yaml"
    poe.write_text(
        "format: poe\nname: slides\nlength_unit: mm\njoints:\n"
        "  - {name: turn, twist: [0, 0, 1, 0, 100, 0]}\n"
        "  - {name: slide, twist: [0, 0, 0, 1, 0, 0], mimic: {joint: turn, multiplier: 20, "
        "offset: 5}}\n"
        "tool:\n  matrix: [[1, 0, 0, 300], [0, 1, 0, 0], [0, 0, 1, 50], [0, 0, 0, 1]]\n"
    )
    urdf = tmp_path / "mm.urdf"
    assert main(["convert", str(poe), "--format", "urdf", "-o", str(urdf)]) == 0
    assert 'multiplier="0.02" offset="0.005"' in urdf.read_text()
    model = load(str(poe))
    written = open_source(str(urdf))
    q, reference = pin_reference(written, written.model(), samples=100)
    assert_fk_matches("mm URDF", _metres(model.fk_batch(q)), reference, 1.0, q)


def _metres(poses):
    out = poses.copy()
    out[:, :3, 3] *= 1e-3
    return out


def test_ignore_mimic_makes_them_independent(capsys):
    model = load(ARM, ignore_mimic=True)
    assert model.dof == 5 and all(j.mimic is None for j in model.joints)
    assert any("treated as an independent joint (--ignore-mimic)" in w for w in model.warnings)
    assert main(["verify", ARM, "--ignore-mimic", "--samples", "100"]) == 0


CHAIN = """<robot name="r"><link name="base"/><link name="a"/><link name="b"/><link name="c"/>
<link name="side"/>{extra_links}
<joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>
  <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
<joint name="j2" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0.3 0 0.1"/>
  <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/>{j2}</joint>
<joint name="j3" type="revolute"><parent link="b"/><child link="c"/><origin xyz="0.2 0 0"/>
  <axis xyz="1 0 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/>{j3}</joint>
<joint name="side_joint" type="revolute"><parent link="base"/><child link="side"/>
  <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"""


def _source(tmp_path, j2: str, j3: str):
    path = tmp_path / "r.urdf"
    path.write_text(CHAIN.format(extra_links="", j2=j2, j3=j3))
    return open_source(str(path))


def test_a_mimic_of_a_mimic_follows_the_actuated_joint(tmp_path):
    source = _source(
        tmp_path,
        '<mimic joint="j1" multiplier="2" offset="0.1"/>',
        '<mimic joint="j2" multiplier="-0.5" offset="0.3"/>',
    )
    model = source.model(tip="c")
    relation = model.joints[2].mimic
    assert (relation.joint, relation.multiplier, relation.offset) == ("j1", -1.0, 0.25)
    q, reference = pin_reference(source, model, samples=100)
    for conv in NAMES:
        assert_fk_matches(conv, to_table(model, conv).fk_batch(q), reference, model.size(), q)


def test_a_leader_off_the_chain_has_a_stand_in(tmp_path):
    """Two joints of the chain following a joint on another branch: the first is driven on its
    own (said in a warning), the second follows it; Pinocchio, setting the leader, agrees."""
    source = _source(
        tmp_path,
        '<mimic joint="side_joint" multiplier="2" offset="0.1"/>',
        '<mimic joint="side_joint" multiplier="-1" offset="0.2"/>',
    )
    model = source.model(tip="c")
    assert model.joints[1].mimic is None and model.dof == 2
    relation = model.joints[2].mimic
    assert (relation.joint, relation.multiplier) == ("j2", -0.5)
    assert relation.offset == pytest.approx(0.25, abs=1e-15)
    assert any("'j2' follows 'side_joint', which is not on the chain" in w for w in model.warnings)
    q, reference = pin_reference(source, model, samples=100)
    for conv in NAMES:
        assert_fk_matches(conv, to_table(model, conv).fk_batch(q), reference, model.size(), q)


def test_refusals(tmp_path):
    tree = parse_tree(
        CHAIN.format(
            extra_links="", j2='<mimic joint="side_joint" multiplier="0"/>', j3=""
        ).encode(),
        "r.urdf",
    )
    with pytest.raises(ChainError, match="mimics 'side_joint' with multiplier 0"):
        tree_to_poe(tree, tip="c")


@pytest.mark.parametrize("target", sorted(set(TARGETS) - {"ur", "linuxcnc"}))
def test_targets_without_coupled_joints_refuse_naming_them(target, capsys):
    assert main(["export", ARM, "--to", target]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "'elbow' (mimics 'shoulder')" in err and "has no coupled joints" in err


def test_calibration_refuses_coupled_joints(tmp_path, capsys):
    assert main(["measure", ARM, "--configs", "10", "-o", str(tmp_path / "m.csv")]) == 2
    assert "follow another joint; calibration identifies" in capsys.readouterr().err
    assert not (tmp_path / "m.csv").exists()
