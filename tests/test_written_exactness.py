"""Every written table, every convention, reproduces its source to 1e-14 x robot size and
1e-14 rad (or within the deviation it declares): on every bundled robot and on the real vendor
chains in tests/data (scripts/written_exactness.py runs the same on any collection of URDFs),
against an extended-precision FK of the URDF text. Then the rules behind it, one by one."""

from __future__ import annotations

import json
import math
import re
import sys
from pathlib import Path

import numpy as np
import pytest

from urdf2dh import Joint, PoeModel, load, to_table
from urdf2dh.conventions.cpc import r_rows
from urdf2dh.emit.formats import render
from urdf2dh.geometry import frames, se3
from urdf2dh.geometry.se3 import pose_errors
from urdf2dh.tolerances import DEFAULT, EPS

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

import written_exactness  # noqa: E402

VENDOR = ROOT / "tests" / "data" / "vendor"
PROMISE = DEFAULT.report


def test_every_bundled_robot_and_vendor_chain_is_exact_as_written():
    results = []
    files = written_exactness.default_files()
    for path in files:
        got, refused = written_exactness.measure(path)
        assert refused == 0, path
        results += got
    assert written_exactness.PROMISE == PROMISE
    beyond = [m for m in results if not m.within]
    assert not beyond, written_exactness.report(results, len(files), 0, 0)
    chains = {m.chain for m in results}
    assert len(chains) >= 45
    vendor = {"tm5-900-nominal.urdf", "tm14-nominal.urdf", "fanuc-cr7ia.urdf",
              "fanuc-lrmate200id.urdf", "kuka-kr210l150.urdf", "kuka-kr6r900sixx.urdf"}  # fmt: skip
    assert vendor <= {c.split()[0] for c in chains}
    # tables that declare nothing are exact to the promise in every convention
    for conv in ("dh", "mdh", "cpc", "hayati"):
        plain = [m for m in results if m.convention == conv and not m.declared_position]
        assert len(plain) >= 40, conv
        assert max(m.position for m in plain) <= PROMISE
        assert max(m.rotation for m in plain) <= PROMISE


@pytest.mark.parametrize("name", ["tm5-900-nominal", "tm14-nominal"])
def test_techman_cpc_directions_are_unit_vectors_as_written(name):
    """pi/2 rounded to 1.570796 leaves b_z = 1 - 5.3e-14: written as it is, never snapped to 1
    on its own (which made |b| = 1 + 5e-14 and the FK 1.1e-13 x size off)."""
    model = load(str(VENDOR / "techman" / f"{name}.urdf"))
    table = to_table(model, "cpc")
    tree = json.loads(render(table, "json"))
    directions = [tree["base"]["params"]["b"], *(j["params"]["b"] for j in tree["joints"])]
    for b in directions:
        assert abs(math.hypot(*b) - 1.0) <= 2 * EPS, b
        assert all(c == 0.0 or abs(c) > DEFAULT.written for c in b), b
    assert any(0.0 < abs(1.0 - abs(c)) < 1e-12 for b in directions for c in b)  # kept, not 1
    q = model.sample(200, 3)
    pos, rot = pose_errors(table.fk_batch(q), model.fk_batch(q))
    assert pos <= PROMISE * model.size() and rot <= PROMISE


def test_a_joint_on_the_previous_axis_turned_by_round_off_meets_it_at_its_origin():
    """Kinova's joint 1: its origin on the base z, 0.157 m up, its axis turned 2e-13 rad by a
    rounded rpy. The lines meet at that origin (d = 0.15675), not at d = 0, where they are
    3.2e-14 m apart: no judgement, and the table exact."""
    turned = np.array([-2.068e-13, 0.0, -1.0])
    joint = Joint("j1", "revolute", turned / np.linalg.norm(turned), np.array([0, 0, 0.15675]),
                  0.0, 1.0, -3.0, 3.0)  # fmt: skip
    home = se3.stack([frames.axis_frame(tuple(joint.axis), (0.1, 0.0, 0.3))])[0]
    model = PoeModel((joint,), home, "kinova-like")  # the tool's z on the axis
    table = to_table(model, "dh")
    assert table.warnings == ()
    assert table.base.d == pytest.approx(0.15675, abs=1e-15)
    q = model.sample(100, 1)
    pos, rot = pose_errors(table.fk_batch(q), model.fk_batch(q))
    assert pos <= PROMISE * model.size() and rot <= PROMISE
    again = to_table(table.to_poe(), "dh")  # the same rule again: the same table
    assert again.base.d == pytest.approx(table.base.d, abs=1e-15)


def _near_parallel_pair(angle: float) -> PoeModel:
    """Two joints 0.3 m apart whose axes are ``angle`` from parallel, tilted towards each
    other (their exact common normal ~0.3 / angle away), and a tool beyond."""
    u = np.array([0.0, np.sin(angle), np.cos(angle)])
    joints = (
        Joint("j1", "revolute", np.array([0.0, 0.0, 1.0]), np.zeros(3), 0.0, 1.0, -2.0, 2.0),
        Joint("j2", "revolute", u, np.array([0.01, 0.3, 0.1]), 0.0, 1.0, -2.0, 2.0),
    )
    home = np.eye(4)
    home[:3, 3] = [0.0, 0.5, 0.1]
    return PoeModel(joints, home, "pair")


@pytest.mark.parametrize("angle", [3e-15, 2e-14, 3e-13])
def test_round_off_parallel_axes_are_declared_by_dh_and_exact_in_hayati(angle):
    """D-H must make such axes parallel (the exact normal is kilometres away); beyond the
    exactness promised that is a reported judgement with its deviation declared. Hayati is
    exact there and declares nothing."""
    model = _near_parallel_pair(angle)
    q = model.sample(200, 2)
    dh = to_table(model, "dh")
    pos, rot = pose_errors(dh.fk_batch(q), model.fk_batch(q))
    assert pos <= PROMISE * model.size() + dh.check.declared_position
    assert rot <= PROMISE + dh.check.declared_rotation
    if dh.check.declared_rotation:
        assert any("treated as parallel" in w for w in dh.warnings)
    hayati = to_table(model, "hayati")
    assert hayati.warnings == () and hayati.check.declared_position == 0.0
    pos, rot = pose_errors(hayati.fk_batch(q), model.fk_batch(q))
    assert pos <= PROMISE * model.size() and rot <= PROMISE


def test_far_reaching_rows_declare_their_rounding():
    """Axes 1e-3 rad apart, exact (--exact): the D-H common normal lies ~300 m away, and float64
    evaluation of such rows rounds by ~eps x 300 m, beyond 1e-14 x size: declared, warned, and
    the table within it."""
    model = _near_parallel_pair(1e-3)
    table = to_table(model, "dh", DEFAULT.with_exact())
    assert max(abs(r.params.d) for r in table.rows) > 100.0
    assert any("float64 evaluation of its FK may round by up to" in w for w in table.warnings)
    declared = table.check.declared_position
    assert declared > PROMISE * model.size()
    q = model.sample(500, 4)
    pos, _ = pose_errors(table.fk_batch(q), model.fk_batch(q))
    assert pos <= PROMISE * model.size() + declared


def test_r_of_b_at_minus_z_is_the_documented_fixed_rotation():
    """b = -z exactly: Ry(pi) = diag(-1, 1, -1), the limit of eq. (4) from the +x side."""
    assert np.array_equal(np.array(r_rows((0.0, 0.0, -1.0))), np.diag([-1.0, 1.0, -1.0]))
    for e in (1e-3, 1e-8, 1e-15):
        near = np.array(r_rows((math.sin(e), 0.0, -math.cos(e))))
        assert np.abs(near - np.diag([-1.0, 1.0, -1.0])).max() <= 2 * e


def test_the_cpc_documentation_reader_runs_and_agrees():
    """docs/conventions/cpc.md's reader, written from its rules alone, evaluates the SCARA's
    table (a b = -z row) as urdf2dh does."""
    text = (ROOT / "docs" / "conventions" / "cpc.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert blocks
    for block in blocks:
        exec(compile(block, "docs/conventions/cpc.md", "exec"), {})
