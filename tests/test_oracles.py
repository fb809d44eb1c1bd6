"""verify's oracles beyond MJCF: MuJoCo judges URDF sources (through its URDF import, every link
kept) and POE and table files (assembled from the screws, helical joints included); an oracle
that cannot judge says why, alone (exit 2) or beside the other (which decides); a bad oracle
name is refused."""

from __future__ import annotations

import pytest

import urdf2dh
from urdf2dh.check.verify import ORACLE_CHOICES, ORACLES
from urdf2dh.cli import main
from urdf2dh.errors import OracleError, UsageError


@pytest.mark.parametrize("robot", ["ur5", "tiago-arm", "scara", "puma560-actual"])
def test_mujoco_judges_urdf_and_poe_sources(robot):
    report = urdf2dh.verify(robot, samples=50, oracle="both")
    assert report.ok and report.oracles == ("pinocchio", "mujoco") and not report.abstentions
    assert all(c.position <= 1e-14 * report.size for c in report.checks), report.lines()
    assert all(c.rotation <= 1e-14 for c in report.checks), report.lines()


def test_a_table_file_is_judged_by_mujoco(tmp_path):
    table = tmp_path / "kuka.json"
    assert main(["convert", "kuka-kr6-r700-sixx", "--format", "json", "-o", str(table)]) == 0
    report = urdf2dh.verify(str(table), samples=30, oracle="mujoco")
    assert report.ok and report.oracles == ("mujoco",)


def test_an_oracle_that_cannot_judge_says_why(tmp_path, capsys):
    # Pinocchio has no frame for a site of a body fixed to the world
    model = tmp_path / "arm.xml"
    model.write_text('<mujoco><worldbody><body name="b"><site name="s" pos="0 0 0.1"/>'
                     '<body name="l" pos="0 0 0.2"><joint name="j"/><site name="t" pos="0.1 0 0"/>'
                     "</body></body></worldbody></mujoco>")  # fmt: skip
    report = urdf2dh.verify(str(model), "s", "t", samples=10, oracle="both")
    assert report.ok and report.oracles == ("mujoco",)
    assert [a.oracle for a in report.abstentions] == ["pinocchio"]
    assert "Pinocchio has no frame for site 's'" in report.abstentions[0].reason
    assert "Pinocchio did not judge: " in "\n".join(report.lines())
    with pytest.raises(OracleError, match="has no frame for site 's'") as e:
        urdf2dh.verify(str(model), "s", "t", samples=10)
    assert e.value.oracle == "pinocchio"
    assert main(["verify", str(model), "--base", "s", "--tip", "t"]) == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_oracle_names():
    assert ORACLE_CHOICES == (*ORACLES, "both") == ("pinocchio", "mujoco", "both")
    with pytest.raises(UsageError, match="unknown oracle 'mujoko'"):
        urdf2dh.verify("ur5", samples=5, oracle="mujoko")
    with pytest.raises(TypeError):
        urdf2dh.verify("ur5", samples=5, oracle=1)
