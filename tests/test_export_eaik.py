"""``export --to eaik``, proven in the real consumer: EAIK (PyPI) runs the generated script.

For every bundled 6-axis arm it solves, the real 6R URDFs of tests/data/vendor and a seeded
sample of the real D-H tables ikdh ships (made URDFs): at seeded configurations within the
limits, every exact solution EAIK returns (``is_LS`` false) reaches the pose Pinocchio gives the
source there to 1e-9 x size and 1e-9 rad, and the configuration is among them (EAIK returns every
branch). Our family verdict is EAIK's; the arms it has no decomposition for are refused."""

from __future__ import annotations

import re
from importlib.metadata import version as metadata_version

import numpy as np
import pytest
from ik_corpus import VENDOR, dh_urdf, ikdh_robots, sample, six_axis_robots
from ik_handoff import BOUND, eaik_solutions, judge, record, refusal, scripted

from urdf2dh import export, load, to_table
from urdf2dh.conventions.analytic import analytic_form
from urdf2dh.conventions.families import Relations, eaik_family
from urdf2dh.errors import ExportError

eaik = pytest.importorskip("eaik")
CONSUMER = f"EAIK {metadata_version('eaik')}"
POSES = 60
REFUSED = {  # bundled 6-joint chains EAIK cannot take, and why
    "stanford": "joints 'joint3' (prismatic) cannot be written; eaik has revolute joints only",
    "puma560-actual": "joints 'j3' (helical), 'j4' (helical), 'j5' (helical), 'j6' (helical)",
}


def handoff(label: str, path: str):
    run, q = scripted("eaik", CONSUMER, label, path, lambda robot, row: robot.fwdKin(row), POSES)
    result = judge("eaik", CONSUMER, label, run.source, run.model, q,
                   lambda T: eaik_solutions(run.robot, T))  # fmt: skip
    record(result)
    assert result.within(BOUND), result.text()
    assert not result.missed, f"{result.text()}: {result.missed[:3]}"
    return run.model, run.robot


@pytest.mark.parametrize("robot", [r for r in six_axis_robots() if r not in REFUSED])
def test_every_bundled_six_axis_arm_solves_in_eaik(robot):
    model, solver = handoff(robot, robot)
    chain = analytic_form(to_table(model, "dh"))
    family = eaik_family(Relations.of(chain))
    assert isinstance(family, tuple)
    assert solver.getKinematicFamily().startswith(family[2].rstrip("_*"))


@pytest.mark.parametrize("path", VENDOR, ids=lambda p: p.rsplit("/", 1)[-1])
def test_real_6r_urdfs_solve_in_eaik(path):
    handoff(path.rsplit("/", 1)[-1], path)


def test_a_sample_of_ikdhs_real_dh_tables_agrees_with_eaik(tmp_path):
    """Every sampled arm EAIK has a decomposition for is exported and solved; every other one
    is refused, and EAIK itself finds none for the frames we would write."""
    solved = refused = 0
    for path in sample(ikdh_robots(), 24, seed=3):
        urdf = tmp_path / f"{path.stem}.urdf"
        urdf.write_text(dh_urdf(path))
        model = load(str(urdf))
        verdict = eaik_family(Relations.of(analytic_form(to_table(model, "dh"))))
        if isinstance(verdict, tuple):
            handoff(f"ikdh:{path.stem}", str(urdf))
            solved += 1
        else:
            with pytest.raises(ExportError, match="no decomposition EAIK knows"):
                export(model, "eaik")
            from eaik.IK_Homogeneous import HomogeneousRobot

            frames = analytic_form(to_table(model, "dh")).joint_frames()
            assert not HomogeneousRobot(frames).hasKnownDecomposition(), path.stem
            refusal("eaik", f"ikdh:{path.stem}", verdict)
            refused += 1
    assert solved >= 12, (solved, refused)


@pytest.mark.parametrize("robot, reason", sorted(REFUSED.items()))
def test_chains_eaik_cannot_take_are_refused_with_the_reason(robot, reason):
    with pytest.raises(ExportError, match=f"^eaik: .*{re.escape(reason)}"):
        export(load(robot), "eaik")
    refusal("eaik", robot, reason)


def test_a_7r_arm_solves_with_a_joint_held():
    """The Panda: its joint 7 held at 0 (EAIK's fixed_axes), EAIK solves for the other six and
    returns all seven; every configuration with joint 7 at 0 is among the solutions."""
    run, q = scripted(
        "eaik", CONSUMER, "panda", "panda", lambda robot, row: robot.fwdKin(row), POSES
    )
    assert "robot = HomogeneousRobot(frames, fixed_axes=[(6, 0.0)])" in run.script
    q[:, 6] = 0.0
    result = judge("eaik", CONSUMER, "panda (joint 7 held)", run.source, run.model, q,
                   lambda T: eaik_solutions(run.robot, T, 7))  # fmt: skip
    record(result)
    assert result.within(BOUND) and not result.missed, result.text()
    assert np.all(np.array([len(eaik_solutions(run.robot, T, 7)) for T in
                            [run.robot.fwdKin(r) for r in q[:5]]]) > 0)  # fmt: skip


def test_seven_joints_none_of_which_can_be_held_are_refused():
    with pytest.raises(ExportError, match=r"eaik: not 6R: .* the chain has 7 joints; and "
                       "holding none of its joints at 0 leaves a chain EAIK solves"):  # fmt: skip
        export(load("xarm7"), "eaik")
