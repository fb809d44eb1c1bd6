"""``export --to ikdh``, proven in the real consumer: ikdh (PyPI) reads the written file with its
own reader (``ikdh.load_robot``, a line scanner) and solves.

For every bundled 6R arm, the real 6R URDFs of tests/data/vendor and a seeded sample of the real
D-H tables ikdh ships (made URDFs): ikdh's forward kinematics of the file, with the file's base and
tool, is Pinocchio's of the source; at seeded configurations within the limits every solution of
``Solver.solve(base^-1 T tool^-1)`` reaches the pose to 1e-9 x size and 1e-9 rad, and the
configuration is among them, or, where ikdh's search lost that branch, ikdh's own Newton step from
it (``solve_from_seed``) stays there: the file's robot reaches the pose at the source's
configuration, and the loss is the solver's (reported)."""

from __future__ import annotations

import math
import re
from importlib.metadata import version as metadata_version
from pathlib import Path

import numpy as np
import pytest
import yaml
from consumers import report
from ik_corpus import VENDOR, dh_urdf, ikdh_robots, sample, six_axis_robots
from ik_handoff import BOUND, IkdhFile, judge, record, refusal
from oracle import assert_fk_matches

from urdf2dh import ExportOptions, PoeModel, export, load
from urdf2dh.check.verify import pinocchio_fk
from urdf2dh.errors import ExportError
from urdf2dh.io.sources import open_source

ikdh = pytest.importorskip("ikdh")
CONSUMER = f"ikdh {metadata_version('ikdh')}"
POSES = 40
MISSED = 0.05  # the most poses whose configuration ikdh's search may lose (measured: under 2%)
REFUSED = {
    "stanford": "ikdh: joints 'joint3' (prismatic) cannot be written; ikdh has revolute joints",
    "puma560-actual": "ikdh: joints 'j3' (helical)",
}


def handoff(label: str, path: str, directory: Path, opts: ExportOptions | None = None) -> None:
    source = open_source(path)
    model: PoeModel = source.model()
    metres = {"mm": 1e-3, "m": 1.0}[model.length_unit]
    consumer = IkdhFile(export(model, "ikdh", opts=opts), directory)
    q = model.sample(POSES, 17)
    reference = pinocchio_fk(source, model, q)
    errors = assert_fk_matches(f"ikdh forward_kin {label}", consumer.fk(q, metres), reference,
                               model.size(), q, rel=1e-12, rot=1e-12)  # fmt: skip
    report("ikdh", CONSUMER, errors, model.size())
    result = judge("ikdh", CONSUMER, label, source, model, q, lambda T: consumer.solve(T, metres))
    record(result)
    assert result.within(BOUND), result.text()
    for row, _ in result.missed:
        pose = pinocchio_fk(source, model, row[None])[0]
        assert consumer.reaches(pose, row, metres), f"{label}: {row} is no solution of the file"
    assert len(result.missed) <= MISSED * POSES, result.text()


@pytest.mark.parametrize("robot", [r for r in six_axis_robots() if r not in REFUSED])
def test_every_bundled_6r_arm_solves_in_ikdh(robot, tmp_path):
    handoff(robot, robot, tmp_path)


@pytest.mark.parametrize("path", VENDOR, ids=lambda p: p.rsplit("/", 1)[-1])
def test_real_6r_urdfs_solve_in_ikdh(path, tmp_path):
    handoff(path.rsplit("/", 1)[-1], path, tmp_path)


def test_a_sample_of_ikdhs_real_dh_tables_round_trips(tmp_path):
    """ikdh's own robots, made URDFs, exported and solved again by ikdh."""
    for path in sample(ikdh_robots(), 8, seed=5):
        urdf = tmp_path / f"{path.stem}.urdf"
        urdf.write_text(dh_urdf(path))
        handoff(f"ikdh:{path.stem}", str(urdf), tmp_path)


@pytest.mark.parametrize("robot, reason", sorted(REFUSED.items()))
def test_chains_ikdh_cannot_take_are_refused_with_the_reason(robot, reason):
    with pytest.raises(ExportError, match=re.escape(reason)):
        export(load(robot), "ikdh")
    refusal("ikdh", robot, reason.removeprefix("ikdh: "))


def test_seven_joints_are_refused_naming_the_count():
    with pytest.raises(ExportError, match=r"ikdh: not 6R: .* the chain has 7 joints"):
        export(load("panda"), "ikdh")


def test_metres_on_request_and_read_back(tmp_path):
    """``--units m`` writes ikdh's own unit: the same robot, read back by ikdh."""
    model = load("kuka-kr6-r700-sixx")
    mm = IkdhFile(export(model, "ikdh"), tmp_path)
    m = IkdhFile(export(model, "ikdh", opts=ExportOptions(units="m")), tmp_path)
    assert (mm.unit, m.unit) == ("mm", "m")
    np.testing.assert_allclose(np.array(m.robot.dh.d) * 1e3, mm.robot.dh.d, rtol=1e-15)
    q = model.sample(5, 1)
    np.testing.assert_allclose(m.fk(q, 1.0), mm.fk(q, 1.0), rtol=0, atol=1e-15)
    with pytest.raises(ExportError, match="ikdh: the length unit must be mm or m, not 'inch'"):
        export(model, "ikdh", opts=ExportOptions(units="inch"))


def test_the_scanner_reads_hostile_names_as_written(tmp_path):
    """ikdh's reader takes a line holding ``dh:`` or ``limits:`` as a section and cuts at
    ``#``: a robot named with them still reads as the table written."""
    from dataclasses import replace

    model = load("ur5")
    hostile = replace(model, name="x # dh: limits: name: [1, 2]\nalpha: [0]")
    text = export(hostile, "ikdh")
    read = IkdhFile(text, tmp_path)
    plain = IkdhFile(export(model, "ikdh"), tmp_path)
    for key in ("a", "d", "alpha", "theta"):
        assert getattr(read.robot.dh, key) == getattr(plain.robot.dh, key)
    assert list(read.robot.limits.lo) == list(plain.robot.limits.lo)
    assert read.robot.name == "x___dh__limits__name___1__2__alpha___0_"
    assert yaml.safe_load(text)["name"] == read.robot.name


def test_exact_multiples_of_pi_are_written_as_ikdh_reads_them(tmp_path):
    text = export(load("puma560-nominal"), "ikdh")
    exact = {"0.0": 0.0, "pi/2": math.pi / 2, "-pi/2": -math.pi / 2, "pi": math.pi}
    written = re.search(r"^  alpha: \[(.*)\]$", text, re.M)[1].split(", ")  # type: ignore[index]
    assert set(written) <= set(exact) and "pi/2" in written, written
    assert list(IkdhFile(text, tmp_path).robot.dh.alpha) == [exact[w] for w in written]


def test_reversed_limits_are_refused_as_ikdh_would_return_nothing(tmp_path):
    """ikdh's own file of the Comau Smart5 NJ 210-3.1 SH gives joint 3 [-21.3, -288] degrees,
    and ikdh solves nothing with it: the export refuses such a joint, naming it. (Written as a
    URDF, the limit is read as the range between, with a warning: the reversed limits reach the
    export from a model made in Python.)"""
    from dataclasses import replace

    path = next(p for p in ikdh_robots() if p.stem == "comau_smart5_nj_210_3_1_sh")
    urdf = tmp_path / "comau.urdf"
    urdf.write_text(dh_urdf(path))
    model = load(str(urdf))
    assert any(w.startswith("joint 'j3': its <limit> has lower -0.371755") for w in model.warnings)
    joints = list(model.joints)
    joints[2] = replace(joints[2], lower=joints[2].upper, upper=joints[2].lower)
    with pytest.raises(ExportError, match=r"ikdh: joint 'j3' has its lower limit -0\.371755 above"):
        export(replace(model, joints=tuple(joints)), "ikdh")
