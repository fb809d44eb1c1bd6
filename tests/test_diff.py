"""urdf2dh diff: calibration comparison, reproducing Wu 2019 Table II's marks and named pairs."""

from __future__ import annotations

import json

from urdf2dh import diff
from urdf2dh.cli import main

# Wu 2019 Table II underlines the cells that changed by > 60 deg or > 30 mm between the nominal
# and actual PUMA 560 (rows B->0, 0->1 = j1, ..., 5->6 = j6, 6->T = tool).
WU_MARKED = {
    ("base", "theta"),
    ("j1", "theta"),
    ("j2", "theta"),
    ("j2", "d"),
    ("j2", "a"),
    ("j3", "theta"),
    ("j3", "d"),
    ("j6", "theta"),
    ("j6", "d"),
    ("tool", "theta"),
    ("tool", "d"),
}
# ... and names the parallel pairs (Base Z, joint 1), (joint 2, joint 3), (joint 6, Tool Z).
WU_PAIRS = [("base z", "j1"), ("j2", "j3"), ("j6", "tool z")]


def run_json(capsys, *argv):
    assert main(["diff", *argv, "--format", "json"]) == 0
    return json.loads(capsys.readouterr().out)


WU_THRESHOLDS = ["--angle-threshold", "60", "--length-threshold", "30"]


def test_puma_diff_marks_what_wu_2019_marks(capsys):
    tree = run_json(capsys, "puma560-nominal", "puma560-actual", *WU_THRESHOLDS)
    assert tree["schema"] == "urdf2dh-diff/1"
    marked = {(p["row"], p["param"]) for p in tree["parameters"] if p["marked"]}
    assert marked == WU_MARKED
    assert [(p["first"], p["second"]) for p in tree["ill_conditioned"]] == WU_PAIRS
    assert "CPC or the POE model" in tree["recommendation"]
    assert tree["thresholds"]["length"] == 30.0  # mm, the tables' unit
    j1_alpha = next(p for p in tree["parameters"] if (p["row"], p["param"]) == ("j1", "alpha"))
    assert abs(j1_alpha["change"]) > 3.0 and not j1_alpha["marked"]  # 90 -> -88.854: a sign flip


def test_diff_text_and_thresholds(capsys):
    assert main(["diff", "puma560-nominal", "puma560-actual", *WU_THRESHOLDS]) == 0
    out = capsys.readouterr().out
    assert "11 parameters changed beyond the thresholds" in out
    assert "(j2, j3) 0.000 / 10.254 deg" in out and "-0.0000" not in out
    assert (
        main(
            [
                "diff",
                "puma560-nominal",
                "puma560-actual",
                "--angle-threshold",
                "1",
                "--length-threshold",
                "1",
            ]
        )
        == 0
    )
    assert "11 parameters" not in capsys.readouterr().out


def _ur5_with(tmp_path, capsys, **changes):
    """ur5's table file with some of the second row's parameters moved (metres, rad)."""
    assert main(["convert", "ur5", "--format", "json"]) == 0
    tree = json.loads(capsys.readouterr().out)
    for key, step in changes.items():
        tree["joints"][1]["params"][key] += step
    path = tmp_path / "ur5-calibrated.json"
    path.write_text(json.dumps(tree))
    return str(path)


def test_calibration_sized_changes_are_shown_and_marked(tmp_path, capsys):
    """Defaults suited to calibration: 0.1 mm and 0.01 deg; lengths shown to the micrometre."""
    actual = _ur5_with(tmp_path, capsys, d=40e-6, a=0.2e-3, alpha=1e-4)
    assert main(["diff", "ur5", actual]) == 0
    out = capsys.readouterr().out
    assert "0.01 deg (modulo 180) or 0.0001 m" in out
    rows = {tuple(line.split()[:2]): line for line in out.splitlines()[2:]}
    assert "+0.000040 m" in rows[("shoulder_lift_joint", "d")]  # 40 um: shown, not marked
    assert not rows[("shoulder_lift_joint", "d")].endswith("*")
    assert rows[("shoulder_lift_joint", "a")].endswith("+0.000200 m  *")  # 0.2 mm: marked
    assert rows[("shoulder_lift_joint", "alpha")].endswith("+0.0057 deg")  # 1e-4 rad: not
    assert "1 parameter changed beyond the thresholds" in out
    assert "e-14" not in out and "e-17" not in out  # round-off of the conversions: not shown


def test_changes_below_the_printed_precision_are_not_zeros(tmp_path, capsys):
    actual = _ur5_with(tmp_path, capsys, d=2e-9, theta=3e-9)
    assert main(["diff", "ur5", actual]) == 0
    out = capsys.readouterr().out
    assert "+2e-09 m" in out and "+1.72e-07 deg" in out


def test_diff_across_units_and_conventions(tmp_path, capsys):
    urdf = tmp_path / "puma.urdf"  # written in metres
    assert main(["convert", "puma560-nominal", "--format", "urdf", "-o", str(urdf)]) == 0
    for conv in ("dh", "mdh", "cpc"):
        tree = run_json(capsys, "puma560-nominal", str(urdf), "--convention", conv)
        assert tree["units"]["length"] == "mm"
        assert not any(p["marked"] for p in tree["parameters"])
        assert max(abs(p["change"]) for p in tree["parameters"]) < 1e-9
    tree = run_json(capsys, "ur5", "ur10", "--angle-threshold", "60", "--length-threshold", "0.03")
    assert {(p["row"], p["param"]) for p in tree["parameters"] if p["marked"]} == {
        ("shoulder_lift_joint", "a"),
        ("elbow_joint", "a"),
        ("shoulder_pan_joint", "d"),
        ("wrist_1_joint", "d"),
    }


def test_diff_of_different_chains_is_an_input_error(capsys):
    assert main(["diff", "ur5", "panda"]) == 2
    assert "NOMINAL has 6 joints and ACTUAL 7" in capsys.readouterr().err


def _poe_file(path, model):
    import yaml

    from urdf2dh.io.poefile import poe_to_dict

    path.write_text(yaml.safe_dump(poe_to_dict(model), sort_keys=False))
    return str(path)


def test_a_row_that_changes_form_is_reported_not_a_crash(tmp_path, capsys):
    """Two parallel axes made 2 mrad apart: their hayati row is a D-H link in one table and a
    Hayati link in the other. diff reports the row as changed form, with both records, the
    link transform each gives and how far those are apart (text and JSON)."""
    import numpy as np

    import urdf2dh
    from urdf2dh.geometry.se3 import rot_axis
    from urdf2dh.model.poe import PoeModel

    ur5 = urdf2dh.load("ur5")
    tilt = rot_axis(np.array([0.0, 0.0, 1.0]), 0.002)  # out of the common normals' plane
    elbow = ur5.joints[2]
    tilted = type(elbow)(
        elbow.name, elbow.kind, tilt @ elbow.axis, elbow.point, elbow.pitch, elbow.scale
    )
    actual = PoeModel((*ur5.joints[:2], tilted, *ur5.joints[3:]), ur5.home, "tilted")
    a, b = _poe_file(tmp_path / "a.yaml", ur5), _poe_file(tmp_path / "b.yaml", actual)
    tree = run_json(capsys, a, b, "--convention", "hayati")
    forms = tree["changed_form"]
    assert forms and {f["nominal_form"] for f in forms} | {f["actual_form"] for f in forms} == {
        "D-H",
        "Hayati",
    }
    f = forms[0]
    assert set(f) == {
        "row",
        "nominal_form",
        "actual_form",
        "nominal",
        "actual",
        "nominal_link",
        "actual_link",
        "length",
        "angle",
        "marked",
    }
    assert len(f["nominal_link"]) == 4 and f["marked"] and f["angle"] > 0
    assert all(p["row"] != f["row"] for p in tree["parameters"])  # no mixed-up parameters
    assert main(["diff", a, b, "--convention", "hayati"]) == 0
    out = capsys.readouterr().out
    assert f"{f['row']}" in out and "link moved" in out and "changed form" in out


def test_the_columns_are_named_for_what_is_compared(tmp_path, capsys):
    d = diff("puma560-nominal", "puma560-actual", "dh")
    header = str(d).splitlines()[1].split()
    assert header == ["row", "param", "puma560-nominal", "puma560-actual", "change"]
    assert "| row | param | puma560-nominal | puma560-actual | change |" in d._repr_markdown_()
    assert str(diff("ur5", "ur5", "dh")).splitlines()[1].split()[2:4] == ["NOMINAL", "ACTUAL"]
    path = tmp_path / "id" / "ur5-id.json"
    path.parent.mkdir()
    assert main(["convert", "ur5", "-o", str(path)]) == 0
    capsys.readouterr()
    assert str(diff("ur5", str(path), "dh")).splitlines()[1].split()[2:4] == ["ur5", "ur5-id.json"]


def test_base_and_tip_choose_the_chain_of_each_side_with_links(tmp_path, capsys):
    """A table (or POE file) of a sub-chain against the robot it came from: ``--base``/``--tip``
    choose that sub-chain in the robot's URDF and leave the single chain as it is, whichever
    side each is on; with both sides trees, both take them."""
    table = tmp_path / "arm.json"
    chain = ["--base", "panda_link1", "--tip", "panda_link7"]
    assert main(["convert", "panda", *chain, "--format", "json", "-o", str(table)]) == 0
    capsys.readouterr()
    for pair in (("panda", str(table)), (str(table), "panda")):
        tree = run_json(capsys, *pair, *chain)
        joints = {p["row"] for p in tree["parameters"]} - {"base", "tool"}
        assert joints == {f"panda_joint{i}" for i in range(2, 8)}
        assert not any(p["marked"] for p in tree["parameters"])
        assert max(abs(p["change"]) for p in tree["parameters"]) < 1e-12
    assert main(["diff", "panda", str(table)]) == 2  # without them: panda's whole chain
    assert "has 7 joints and" in capsys.readouterr().err
    tree = run_json(capsys, "fr3-mjcf", "fr3-mjcf", "--tip", "fr3_link5")  # both MJCF trees
    assert len({p["row"] for p in tree["parameters"]} - {"base", "tool"}) == 5


def test_base_and_tip_without_a_tree_of_links_are_refused(tmp_path, capsys):
    """Neither side has links to choose from: one line naming both, exit 2, nothing written."""
    table, out = tmp_path / "arm.json", tmp_path / "diff.txt"
    assert main(["convert", "ur5", "--format", "json", "-o", str(table)]) == 0
    capsys.readouterr()
    for argv in (
        [str(table), str(table), "--tip", "tool0"],
        ["puma560-nominal", "puma560-actual", "--base", "j1"],
    ):
        assert main(["diff", *argv, "-o", str(out)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "single chains" in err and "Traceback" not in err
        assert ("arm.json" in err) or ("puma560-actual" in err)
        assert not out.exists()
