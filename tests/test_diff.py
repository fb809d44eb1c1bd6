"""urdf2dh diff: calibration comparison, reproducing Wu 2019 Table II's marks and named pairs."""

from __future__ import annotations

import json

from urdf2dh.cli import main

# Wu 2019 Table II underlines the cells that changed by > 60 deg or > 30 mm between the nominal
# and actual PUMA 560 (rows B->0, 0->1 = j1, ..., 5->6 = j6, 6->T = tool).
WU_MARKED = {("base", "theta"), ("j1", "theta"), ("j2", "theta"), ("j2", "d"), ("j2", "a"),
             ("j3", "theta"), ("j3", "d"), ("j6", "theta"), ("j6", "d"), ("tool", "theta"),
             ("tool", "d")}
# ... and names the parallel pairs (Base Z, joint 1), (joint 2, joint 3), (joint 6, Tool Z).
WU_PAIRS = [("base z", "j1"), ("j2", "j3"), ("j6", "tool z")]


def run_json(capsys, *argv):
    assert main(["diff", *argv, "--format", "json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_puma_diff_marks_what_wu_2019_marks(capsys):
    tree = run_json(capsys, "puma560-nominal", "puma560-actual")
    assert tree["schema"] == "urdf2dh-diff/1"
    marked = {(p["row"], p["param"]) for p in tree["parameters"] if p["marked"]}
    assert marked == WU_MARKED
    assert [(p["first"], p["second"]) for p in tree["ill_conditioned"]] == WU_PAIRS
    assert "CPC or the POE model" in tree["recommendation"]
    assert tree["thresholds"]["length"] == 30.0  # mm, the tables' unit
    j1_alpha = next(p for p in tree["parameters"] if (p["row"], p["param"]) == ("j1", "alpha"))
    assert abs(j1_alpha["change"]) > 3.0 and not j1_alpha["marked"]  # 90 -> -88.854: a sign flip


def test_diff_text_and_thresholds(capsys):
    assert main(["diff", "puma560-nominal", "puma560-actual"]) == 0
    out = capsys.readouterr().out
    assert "11 parameters changed beyond the thresholds" in out
    assert "(j2, j3) 0.000 / 10.254 deg" in out and "-0.0000" not in out
    assert main(["diff", "puma560-nominal", "puma560-actual", "--angle-threshold", "1",
                 "--length-threshold", "1"]) == 0
    assert "11 parameters" not in capsys.readouterr().out


def test_diff_across_units_and_conventions(tmp_path, capsys):
    urdf = tmp_path / "puma.urdf"  # written in metres
    assert main(["convert", "puma560-nominal", "--format", "urdf", "-o", str(urdf)]) == 0
    for conv in ("dh", "mdh", "cpc"):
        tree = run_json(capsys, "puma560-nominal", str(urdf), "--convention", conv)
        assert tree["units"]["length"] == "mm"
        assert not any(p["marked"] for p in tree["parameters"])
        assert max(abs(p["change"]) for p in tree["parameters"]) < 1e-9
    tree = run_json(capsys, "ur5", "ur10")
    assert {(p["row"], p["param"]) for p in tree["parameters"] if p["marked"]} == {
        ("shoulder_lift_joint", "a"), ("elbow_joint", "a"), ("shoulder_pan_joint", "d"),
        ("wrist_1_joint", "d")}


def test_diff_of_different_chains_is_an_input_error(capsys):
    assert main(["diff", "ur5", "panda"]) == 2
    assert "NOMINAL has 6 joints and ACTUAL 7" in capsys.readouterr().err
