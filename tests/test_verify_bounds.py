"""verify's memory stays linear in the joints (Pinocchio's forward kinematics joint by joint, not
its ``Data`` with nv^3 derivative tensors), its URDF parser runs on a large stack whatever
``ulimit -s`` says, and a model beyond the bound is refused in one line naming it."""

from __future__ import annotations

import resource
import subprocess
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from chains import random_chain_urdf

import urdf2dh
from urdf2dh.check import verify as verify_module
from urdf2dh.check.verify import _frame_poser, pinocchio_fk
from urdf2dh.cli import main
from urdf2dh.io.poefile import read_poe
from urdf2dh.io.sources import Source, open_source
from urdf2dh.tolerances import EPS, VERIFY_JOINTS

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("robot", ["panda", "tiago-arm", "z1", "so101", "baxter-left", "ur5"])
def test_forward_kinematics_joint_by_joint_is_pinocchio_s_own(robot, monkeypatch):
    """The same poses as pinocchio.forwardKinematics + updateFramePlacement (which the models
    of at most DATA_JOINTS joints use)."""
    monkeypatch.setattr(verify_module, "DATA_JOINTS", 0)  # joint by joint, whatever the size
    source = open_source(robot)
    model = pin.buildModelFromXML(source.document.decode())
    data = model.createData()
    pin.seed(3)  # pinocchio.randomConfiguration's generator
    configs = np.array([pin.randomConfiguration(model) for _ in range(20)])
    frames = [f for f in range(model.nframes) if model.frames[f].type == pin.FrameType.BODY]
    for frame in frames[:: max(1, len(frames) // 6)]:
        ours = _frame_poser(pin, model)(frame, configs)
        for k, config in enumerate(configs):
            pin.forwardKinematics(model, data, config)
            theirs = pin.updateFramePlacement(model, data, frame).homogeneous
            # a few units in the last place (Eigen's products compiled in another function)
            assert np.abs(ours[k] - theirs).max() <= 8 * EPS * max(1.0, np.abs(theirs).max())


def test_mimic_joints_follow_their_leader_as_in_pinocchio():
    """tests/data/parallelogram.urdf: a mimic chain, built by Pinocchio with mimic=True."""
    source = open_source(str(ROOT / "tests" / "data" / "parallelogram.urdf"))
    poe = source.model()
    q = poe.sample(30, 2)
    assert np.abs(pinocchio_fk(source, poe, q) - poe.fk_batch(q)).max() < 1e-12


def _chain_file(tmp_path: Path, joints: int) -> Path:
    path = tmp_path / f"chain{joints}.urdf"
    path.write_text(random_chain_urdf(joints, joints)[0])
    return path


# Runs the command from a small Python process and prints its peak resident memory: a child's
# ru_maxrss counts its parent's at the fork, and pytest's process holds hundreds of MiB.
LAUNCHER = (
    "import resource, subprocess, sys; code = subprocess.call(sys.argv[1:]); "
    "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss); sys.exit(code)"
)


def _verify_in_child(path: Path, stack: int | None = None) -> tuple[int, str, float]:
    """``urdf2dh verify`` in a new process (its stack limited to ``stack`` bytes): exit code,
    stderr and its peak memory in MiB."""

    def limit() -> None:
        if stack is not None:
            resource.setrlimit(resource.RLIMIT_STACK, (stack, stack))

    command = [sys.executable, "-m", "urdf2dh.cli", "verify", str(path), "--samples", "10"]
    proc = subprocess.run(
        [sys.executable, "-c", LAUNCHER, *command],
        capture_output=True, text=True, cwd=ROOT, timeout=300, preexec_fn=limit, check=False,
    )  # fmt: skip
    return proc.returncode, proc.stderr, int(proc.stdout.splitlines()[-1]) / 1024


def test_memory_stays_linear_in_the_joints(tmp_path):
    """400 joints: Pinocchio's Data alone would take ~3.5 GB (nv^3); joint by joint the whole
    verify stays near its start-up size (~200 MB at 1,000 joints, ~330 MB at 2,000)."""
    code, err, peak = _verify_in_child(_chain_file(tmp_path, 400))
    assert code == 0, err
    assert peak < 400, peak


def test_pinocchio_s_parser_gets_a_stack_of_its_own(tmp_path):
    """With a 1 MiB process stack Pinocchio's recursive URDF parser overflows at ~450 links
    (a segmentation fault); on its own thread's stack a 600-link chain is verified."""
    code, err, _ = _verify_in_child(_chain_file(tmp_path, 600), stack=2**20)
    assert code == 0, err


def test_a_urdf_beyond_the_bound_is_refused_in_one_line(tmp_path, capsys, monkeypatch):
    """... as soon as its joint elements are counted: nothing is built of them (no element is
    checked, yourdfpy reads none), by the command and by the Python API."""
    from urdf2dh.io.urdf import parse

    def built(*args):
        raise AssertionError("the tree was built before the bound was checked")

    monkeypatch.setattr(parse, "check_robot", built)
    path = _chain_file(tmp_path, VERIFY_JOINTS)  # plus its fixed tool joint: one too many
    assert main(["verify", str(path)]) == 2
    err = capsys.readouterr().err
    message = (
        f"{path}: the URDF has {VERIFY_JOINTS + 1:,} joints; verify checks at most "
        f"{VERIFY_JOINTS:,} (Pinocchio's model of more takes minutes and gigabytes to build)"
    )
    assert err == f"urdf2dh: error: {message}\n"
    with pytest.raises(urdf2dh.errors.InputError) as e:
        urdf2dh.verify(path)
    assert str(e.value) == message


def test_a_poe_chain_beyond_the_bound_is_refused_naming_it():
    twist = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
    data = {
        "format": "poe",
        "joints": [{"name": f"j{i}", "twist": twist} for i in range(VERIFY_JOINTS + 1)],
        "tool": {"twist": [0, 0, 0, 1, 0, 0]},
    }
    poe = read_poe(data, "long.yaml")
    source = Source("poe", "long.yaml", "long", poe=poe)
    from urdf2dh.errors import InputError

    with pytest.raises(InputError, match=r"^long\.yaml: the chain has 2,001 joints; verify "):
        urdf2dh.verify(source, samples=10)


@pytest.mark.parametrize("robot", ["puma560-actual", "tiago-arm", "kinova"])
def test_both_ways_to_pinocchio_s_poses_agree_on_poe_and_urdf_models(robot, monkeypatch):
    """pinocchio_fk by Pinocchio's Data and joint by joint: helical joints of a POE model (its
    own Pinocchio model), a prismatic one, continuous joints of a URDF."""
    source = open_source(robot)
    poe = source.model()
    q = poe.sample(25, 6)
    by_data = pinocchio_fk(source, poe, q)
    monkeypatch.setattr(verify_module, "DATA_JOINTS", 0)
    by_joint = pinocchio_fk(source, poe, q)
    assert np.abs(by_joint - by_data).max() <= 8 * EPS * max(1.0, np.abs(by_data).max())
