"""The hayati convention: every table exact (1e-12 x size) and sane (every
|a| and |d| within 2 x size) on real robots and on chains whose axes are 1e-12 ... 1e-1 rad from
parallel, where D-H tables are either inexact or kilometres long; each row's form stated; its
table files, URDF and roboticstoolbox exports."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from oracle import EXACT, assert_fk_matches, pin_reference
from test_fk import product_of_exponentials

from urdf2dh import Joint, PoeModel, load, to_table
from urdf2dh.cli import main
from urdf2dh.conventions.dh import DhLink
from urdf2dh.conventions.hayati import HayatiLink
from urdf2dh.emit.export import export_table
from urdf2dh.emit.urdf import table_to_urdf
from urdf2dh.errors import UsageError
from urdf2dh.geometry import se3
from urdf2dh.io.catalog import ROBOTS
from urdf2dh.io.sources import open_source

SANE = 2.0  # every |a|, |d| within this x robot size


def _lengths(table):
    records = [table.base, *(r.params for r in table.rows)]
    return [abs(v) for p in records for k, v in p.scalars().items() if k in ("a", "d")]


def assert_exact_and_sane(model, table, q, reference):
    size = model.size()
    assert table.check.max_position_error <= EXACT * size, table.check
    assert table.check.max_rotation_error <= EXACT, table.check
    assert table.warnings == model.warnings
    assert max(_lengths(table), default=0.0) <= SANE * size, (_lengths(table), size)
    assert_fk_matches("hayati", table.fk_batch(q), reference, size, q)


@pytest.mark.parametrize("robot", sorted(ROBOTS))
def test_every_bundled_robot_is_exact_and_sane(robot):
    source = open_source(robot)
    model = source.model()
    q, reference = pin_reference(source, model, samples=100)
    assert_exact_and_sane(model, to_table(model, "hayati"), q, reference)


def test_wu_2019s_three_ill_conditioned_pairs_get_hayati_rows():
    """The actual PUMA's (base z, j1), (j2, j3) and (j6, tool z) are 2.6, 10.3 and 4.9 deg from
    parallel (Wu 2019 §V-B): the base and rows j2 and j6 take Hayati's form, the rest D-H's."""
    table = to_table(load("puma560-actual"), "hayati")
    forms = [type(table.base).__name__] + [type(r.params).__name__ for r in table.rows]
    assert forms == [
        "HayatiLink",
        "DhLink",
        "HayatiLink",
        "DhLink",
        "DhLink",
        "DhLink",
        "HayatiLink",
    ]


def test_exactly_parallel_axes_keep_wus_d_h_row_and_the_text_names_each_form(capsys):
    table = to_table(load("scara"), "hayati")
    assert isinstance(table.rows[0].params, DhLink) and table.rows[0].params.d == 0.0
    assert main(["convert", "puma560-actual", "--convention", "hayati"]) == 0
    lines = capsys.readouterr().out.splitlines()
    head = next(line for line in lines if line.lstrip().startswith("joint"))
    assert "form" in head.split() and "beta [deg]" in head
    rows = {line.split()[0]: line.split() for line in lines if line and line[0] in "123456b"}
    assert rows["base"][1] == "Hayati" and rows["2"][3] == "Hayati" and rows["1"][3] == "D-H"


# ------------------------------------------------------------------------ nearly parallel axes

SETTINGS = settings(
    derandomize=True, max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)


def _tilted(axis, angle, rng):
    """``axis`` turned by ``angle`` about a random direction across it."""
    across = np.cross(axis, rng.normal(size=3))
    return se3.rot_axis(across / np.linalg.norm(across), angle) @ axis


@st.composite
def nearly_parallel_chains(draw):
    """Chains of 2-7 joints where consecutive axes are, by turns, 1e-12 ... 1e-1 rad from
    parallel or anti-parallel (offset sideways by up to the robot's size), exactly parallel, or
    skew; helical and prismatic joints among them; a tool nearly along the last axis too."""
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    n = draw(st.integers(2, 7))
    axis, point, joints = np.array([0.0, 0.0, 1.0]), np.zeros(3), []
    for i in range(n):
        how = draw(st.sampled_from(["near", "near", "anti", "parallel", "skew"]))
        angle = 10.0 ** draw(st.floats(-12.0, -1.0))
        if how in ("near", "anti"):
            axis = _tilted(-axis if how == "anti" else axis, angle, rng)
        elif how == "skew":
            axis = rng.normal(size=3)
            axis /= np.linalg.norm(axis)
        point = point + rng.uniform(-0.5, 0.5, 3)
        kind = str(rng.choice(["revolute", "revolute", "revolute", "prismatic", "helical"]))
        joints.append(
            Joint(f"j{i}", kind, axis, point, 0.05 if kind == "helical" else 0.0, 1.0, -2.0, 2.0)
        )
    home = np.eye(4)
    tool_z = _tilted(axis, 10.0 ** draw(st.floats(-12.0, -1.0)), rng)
    x = np.cross(tool_z, rng.normal(size=3))
    x /= np.linalg.norm(x)
    home[:3, :3] = np.column_stack([x, np.cross(tool_z, x), tool_z])
    home[:3, 3] = point + rng.uniform(-0.3, 0.3, 3)
    return PoeModel(tuple(joints), home, "near", "", "base", "tool")


@SETTINGS
@given(nearly_parallel_chains())
def test_nearly_parallel_axes_are_exact_and_sane(model):
    q = model.sample(50, 2)
    assert_exact_and_sane(model, to_table(model, "hayati"), q, product_of_exponentials(model, q))


@SETTINGS
@given(nearly_parallel_chains())
def test_dh_and_mdh_never_refuse_and_keep_their_declared_bound(model):
    q = model.sample(50, 3)
    reference = product_of_exponentials(model, q)
    for conv in ("dh", "mdh"):
        table = to_table(model, conv)  # never a ConversionError
        bound = table.check.declared_position, table.check.declared_rotation
        assert_fk_matches(
            conv,
            table.fk_batch(q),
            reference,
            model.size(),
            q,
            rel=EXACT + bound[0] / model.size(),
            rot=EXACT + bound[1],
        )


# ------------------------------------------------------------------------ files and exports


def test_table_files_hold_each_rows_form(tmp_path):
    model = load("puma560-actual")
    table = to_table(model, "hayati")
    path = tmp_path / "hayati.yaml"
    assert (
        main(
            [
                "convert",
                "puma560-actual",
                "--convention",
                "hayati",
                "--format",
                "yaml",
                "-o",
                str(path),
            ]
        )
        == 0
    )
    text = path.read_text()
    assert text.count("beta:") == 3  # the base and rows j2, j6: Hayati rows hold beta, no d
    again = load(str(path))
    q = model.sample(100, 4)
    np.testing.assert_allclose(again.fk_batch(q), model.fk_batch(q), atol=1e-12 * model.size())
    back = to_table(again, "hayati")
    assert [type(r.params) for r in back.rows] == [type(r.params) for r in table.rows]


def test_urdf_writer_and_roboticstoolbox_carry_hayati_tables(tmp_path):
    for robot in (load("scara"), load("stanford")):
        table = to_table(robot, "hayati")
        path = tmp_path / "h.urdf"
        path.write_text(table_to_urdf(table)[0])
        written = open_source(str(path))
        q, reference = pin_reference(written, written.model(), samples=60)
        assert_fk_matches("hayati URDF", table.fk_batch(q), reference, robot.size(), q)
        namespace: dict = {"__name__": "generated"}
        exec(compile(export_table(table, "rtb"), "rtb.py", "exec"), namespace)
        rtb = np.array([namespace["robot"].fkine(row).A for row in q])
        assert_fk_matches("hayati rtb", rtb, table.fk_batch(q), robot.size(), q, rel=1e-9, rot=1e-9)


@pytest.mark.parametrize("target", ["kdl", "matlab", "corke-matlab", "ur"])
def test_other_targets_refuse_naming_a_hayati_row(target):
    table = to_table(load("ur5"), "hayati")  # its wrist_3 row is a Hayati row
    odd = next(r for r in table.rows if isinstance(r.params, HayatiLink))
    with pytest.raises(UsageError) as e:
        export_table(table, target)
    message = str(e.value)
    assert f"row {odd.name!r} is a Hayati row: theta, a, alpha, beta" in message
    assert e.value.remedy is not None and e.value.remedy.argument == "convention"
    assert "--" not in message and "\n" not in message


def test_the_hayati_row_is_rz_tx_rx_ry():
    link = HayatiLink(0.3, 0.2, -0.4, 0.05)
    expected = se3.rot_z(0.3) @ se3.trans(x=0.2) @ se3.rot_x(-0.4) @ se3.rot_y(0.05)
    np.testing.assert_allclose(se3.matrix_of(link.frame()), expected, atol=1e-16)
    assert math.isclose(link.frame()[2][3], 0.0)
