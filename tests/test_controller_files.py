"""The controller files urdf2dh writes that describe a whole chain, read back as SOURCEs: OPW
parameter files (and ROS-Industrial's, as published) and LinuxCNC genserkins HAL files. Each
export read back gives the table it was written from. (UR kinematics files:
tests/test_ur_kinematics.py.)"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import urdf2dh
from urdf2dh import units
from urdf2dh.conventions.opw import opw_from_poe
from urdf2dh.emit.export import export
from urdf2dh.emit.export.common import ExportOptions
from urdf2dh.errors import InputError
from urdf2dh.geometry import se3

ROOT = Path(__file__).resolve().parents[1]
VENDOR = ROOT / "tests" / "data" / "vendor" / "ros-industrial"
GENSER6 = str(ROOT / "tests" / "data" / "genser6.urdf")


def same_table(a, b, convention, style="wu", tol=1e-11):
    """The two chains' tables, cell by cell (angles modulo a turn), in ``a``'s length unit."""
    b = b.scaled(units.factor(b.length_unit, a.length_unit), a.length_unit)
    ta, tb = (urdf2dh.to_table(m, convention, style=style) for m in (a, b))
    assert [r.name for r in ta.rows] == [r.name for r in tb.rows]
    for ra, rb in zip((ta.base, *(r.params for r in ta.rows), ta.tool),
                      (tb.base, *(r.params for r in tb.rows), tb.tool), strict=True):  # fmt: skip
        for (name, x), y in zip(ra.scalars().items(), rb.scalars().values(), strict=True):
            if type(ra).quantities()[name] == "angle":
                x, y = x - y, 0.0
                x = math.remainder(x, 2 * math.pi)
            assert x == pytest.approx(y, abs=tol * max(1.0, ta.size)), (name, ra, rb)


def fk_agrees(a, b, scale=1e-12):
    b = b.scaled(units.factor(b.length_unit, a.length_unit), a.length_unit)
    q = a.sample(200, 6)
    pos, rot = se3.pose_errors(b.fk_batch(q), a.fk_batch(q))
    assert pos <= scale * a.size() and rot <= scale


OPW_ARMS = [
    "kuka-kr6-r700-sixx",
    "fanuc-m20ia",
    *(str(VENDOR / f) for f in ("kuka-kr210l150.urdf", "fanuc-lrmate200id.urdf",
                                "kuka-kr6r900sixx.urdf")),
]  # fmt: skip


@pytest.mark.parametrize("robot", OPW_ARMS)
def test_opw_export_reads_back_as_the_same_chain(robot, tmp_path):
    source = urdf2dh.load(robot)
    path = tmp_path / "opw.yaml"
    path.write_text(export(source, "opw"))
    back = urdf2dh.load(str(path))
    assert (back.base_link, back.tip_link) == (source.base_link, source.tip_link)
    fk_agrees(source, back)
    same_table(source, back, "dh")
    a, b = opw_from_poe(source), opw_from_poe(back)
    assert a.geometry() == pytest.approx(b.geometry(), abs=1e-12)
    assert a.signs == b.signs and a.offsets == pytest.approx(b.offsets, abs=1e-12)


def test_opw_export_with_base_and_tool_reads_back(tmp_path):
    """An arm whose base link is off axis 1 and whose tip is tilted: OPW's two extra blocks."""
    source = urdf2dh.load("kuka-kr6-r700-sixx")
    base = se3.from_rpy((0.1, -0.2, 0.3), (0.1, 0.2, -0.3))
    tool = se3.from_rpy((0.0, 0.02, 0.1), (0.0, 0.4, 0.0))
    from dataclasses import replace

    moved = replace(
        source,
        joints=tuple(replace(j, axis=base[:3, :3] @ j.axis,
                             point=base[:3, :3] @ j.point + base[:3, 3]) for j in source.joints),
        home=base @ source.home @ tool,
    )  # fmt: skip
    path = tmp_path / "opw.yaml"
    path.write_text(export(moved, "opw"))
    back = urdf2dh.load(str(path))
    fk_agrees(moved, back)
    same_table(moved, back, "dh")


def test_published_opw_files_read_as_rosparam_writes_them(tmp_path):
    """ROS-Industrial's file (deg() offsets), and the same entries under a MoveIt group."""
    fanuc = urdf2dh.load("fanuc-m20ia-opw")
    assert [j.name for j in fanuc.joints] == [f"joint_{i}" for i in range(1, 7)]
    fk_agrees(urdf2dh.load("fanuc-m20ia"), fanuc, 1e-12)
    group = tmp_path / "kinematics.yaml"
    text = (ROOT / "robots" / "references" / "fanuc-m20ia-opw.yaml").read_text()
    body = "\n".join("  " + line for line in text.splitlines() if not line.startswith("#"))
    group.write_text("manipulator:\n  kinematics_solver: moveit_opw_kinematics_plugin/MoveItOPW"
                     f"KinematicsPlugin\n{body}\n")  # fmt: skip
    fk_agrees(fanuc, urdf2dh.load(str(group)), 1e-15)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("opw_kinematics_geometric_parameters: {a1: 0.1}\n", "no a2"),
        ("opw_kinematics_geometric_parameters: {a1: 0, a2: 0, b: 0, c1: 1, c2: 1, c3: 1, c4: 0}\n"
         "opw_kinematics_joint_offsets: [0, 0, deg(x), 0, 0, 0]\n", r"must be a number, deg\(x\)"),
        ("opw_kinematics_geometric_parameters: {a1: 0, a2: 0, b: 0, c1: 1, c2: 1, c3: 1, c4: 0}\n"
         "opw_kinematics_joint_sign_corrections: [1, 1, 2, 1, 1, 1]\n", "six of 1 or -1"),
        ("opw_kinematics_geometric_parameters: {a1: 0, a2: 0, b: 0, c1: 1, c2: 1, c3: 1, c4: 0}\n"
         "opw_kinematics_joint_offsets: [0, 0]\n", "must be a list of six"),
        ("opw_kinematics_geometric_parameters: {a1: 0, a2: 0, b: 0, c1: 1, c2: 1, c3: 1, c4: 0}\n"
         "opw_kinematics_joint_offsets: [0, 0, deg(1.2.3), 0, 0, 0]\n", r"must be a number, deg"),
        ("opw_kinematics_geometric_parameters: {a1: 0, a2: 0, b: 0, c1: 1, c2: 1, c3: 1, c4: 0}\n"
         "opw_kinematics_joint_offsets: [0, 0, deg(1e999), 0, 0, 0]\n", "beyond the range"),
        ("dh: {a: [0, 0], d: [0], alpha: [0], theta: [0]}\n", r"dh\.a must be a list of 6"),
        ("dh: {a: [0,0,0,0,0,0], d: [0,0,0,0,0,0], alpha: [0,0,0,0,0,pi/0], theta: [0,0,0,0,0,0]}"
         "\n", r"dh\.alpha\[5\]: 'pi/0' divides by zero"),
        ("dh: {a: [0,0,0,0,0,0], d: [0,0,0,0,0,0], alpha: [0,0,0,0,0,tau], theta: [0,0,0,0,0,0]}\n",
         r"dh\.alpha\[5\] must be a number, pi, pi/N or pi\*N, not 'tau'"),
        ("dh: {a: [0,0,0,0,0,0], d: [0,0,0,0,0,0], alpha: [0,0,0,0,0,0], theta: [0,0,0,0,0,0]}\n"
         "base: [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n",
         "not a rigid transform"),
        ("dh: {a: [0,0,0,0,0,0], d: [0,0,0,0,0,0], alpha: [0,0,0,0,0,0], theta: [0,0,0,0,0,0]}\n"
         "limits: {J1: [10]}\n", r"limits\.J1 must be \[lower, upper\]"),
        ("dh: {a: [0,0,0,0,0,0], d: [0,0,0,0,0,0], alpha: [0,0,0,0,0,0], theta: [0,0,0,0,0,0]}\n"
         '# urdf2dh chain: {"unit": "furlong"}\n', "unit must be mm or m"),
    ],
)  # fmt: skip
def test_bad_opw_and_ikdh_files(text, message, tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        urdf2dh.load(str(path))


HAL_ARMS = [(GENSER6, None), (GENSER6, "inch"), ("kuka-kr6-r700-sixx", None), ("so100", None),
            ("fanuc-m20ia", None), ("ur5", None)]  # fmt: skip


@pytest.mark.parametrize(("robot", "length"), HAL_ARMS)
def test_linuxcnc_export_reads_back_as_the_same_table(robot, length, tmp_path):
    """genserkins' links, the joints' zeros and directions (scale components), the world frame
    and the tool's turn (so100: both), the names and the unit: the mdh table it was written
    from, to the digits the file writes."""
    source = urdf2dh.load(robot)
    table = urdf2dh.to_table(source, "mdh", style="zero")
    path = tmp_path / "genser.hal"
    path.write_text(export(source, "linuxcnc", opts=ExportOptions(units=length)))
    back = urdf2dh.load(str(path))
    assert back.length_unit == ("in" if length == "inch" else "mm")
    assert back.warnings == ()
    # the file writes angles to 15 significant digits (ur5's rounded pi/2: 4.9e-12 rad)
    fk_agrees(table.to_poe(), back, 1e-11)
    same_table(table.to_poe(), back, "mdh", "zero")


@pytest.mark.parametrize("target", ["linuxcnc", "opw", "ikdh"])
def test_names_of_any_length_and_character_read_back(target, tmp_path):
    """Names with quotes, backslashes, line breaks and letters beyond ASCII, one of 1500
    characters (HAL cuts comment lines at 1000 bytes), come back as they were."""
    from dataclasses import replace

    source = urdf2dh.load("kuka-kr6-r700-sixx")
    names = ['a "quoted" \\ name', "line\nbreak", "joint # 3", "ünïcode ✓", "x" * 1500, ""]
    source = replace(
        source,
        joints=tuple(replace(j, name=n or "j6") for j, n in zip(source.joints, names, strict=True)),
        name='robot \\ "x"\n',
        base_link="base\u202e",
    )
    path = tmp_path / "file"
    path.write_text(export(source, target))
    back = urdf2dh.load(str(path))
    assert [j.name for j in back.joints] == [j.name for j in source.joints]
    assert (back.name, back.base_link) == (source.name, source.base_link)


def test_a_hal_file_without_urdf2dhs_comments(tmp_path):
    """A configuration's own genserkins lines: six joints in millimetres, said in a warning."""
    lines = [line for line in export(urdf2dh.load(GENSER6), "linuxcnc").splitlines()
             if line.startswith("setp genserkins.")]  # fmt: skip
    path = tmp_path / "machine.hal"
    path.write_text("\n".join(lines) + "\n")
    model = urdf2dh.load(str(path))
    assert [j.name for j in model.joints] == [f"joint_{i}" for i in range(6)]
    assert model.length_unit == "mm" and "no urdf2dh chain comment" in model.warnings[0]
    fk_agrees(urdf2dh.to_table(urdf2dh.load(GENSER6), "mdh", style="zero").to_poe(), model)


def test_bad_hal_files(tmp_path):
    path = tmp_path / "bad.hal"
    path.write_text("setp genserkins.A-0 wide\n")
    with pytest.raises(InputError, match=r"genserkins\.A-0: 'wide' is not a number"):
        urdf2dh.load(str(path))
    path.write_text("setp genserkins.D-1 1_0\n")  # the one number grammar: no '_' groups
    with pytest.raises(InputError, match=r"genserkins\.D-1: '1_0' is not a number"):
        urdf2dh.load(str(path))
    path.write_text("setp urdf2dh-fb-2.gain 2.0\n")
    with pytest.raises(InputError, match="must be 1 or -1"):
        urdf2dh.load(str(path))
    path.write_text("# urdf2dh chain: {not json\n")
    with pytest.raises(InputError, match="malformed"):
        urdf2dh.load(str(path))


def test_every_whole_chain_export_is_a_source():
    """The export targets whose files describe a whole chain are read back; the others write
    programs (scripts for toolboxes and solvers)."""
    from urdf2dh.emit.export import TARGETS
    from urdf2dh.io.sources import READERS

    files = {"ur": "ur", "opw": "opw", "linuxcnc": "hal", "ikdh": "ikdh"}
    assert set(files) <= set(TARGETS) and set(files.values()) <= set(READERS)
    assert all(TARGETS[t].suffix in (".yaml", ".hal") for t in files)
    programs = {t for t in TARGETS if t not in files}
    assert all(TARGETS[t].suffix in (".py", ".m") for t in programs), programs


def limits(model):
    return [x for j in model.joints for x in (j.lower, j.upper)]


IKDH_ARMS = [("kuka-kr6-r700-sixx", None), ("ur5", "m"), ("fanuc-m20ia", None), (GENSER6, None),
             (str(VENDOR / "fanuc-lrmate200id.urdf"), "mm")]  # fmt: skip


@pytest.mark.parametrize(("robot", "length"), IKDH_ARMS)
def test_ikdh_export_reads_back_as_the_same_table(robot, length, tmp_path):
    """The D-H table, base and tool, names, unit and limits (the made-up +-180 deg of a joint
    without limits left out) of the table the file was written from."""
    source = urdf2dh.load(robot)
    table = urdf2dh.to_table(source, "dh")
    path = tmp_path / "robot.yaml"
    path.write_text(export(source, "ikdh", opts=ExportOptions(units=length)))
    back = urdf2dh.load(str(path))
    assert back.warnings == () and back.length_unit == (length or "mm")
    assert (back.name, back.base_link, back.tip_link) == (table.robot, table.base_link,
                                                          table.tip_link)  # fmt: skip
    assert limits(back) == pytest.approx(limits(source), abs=1e-12)
    fk_agrees(table.to_poe(), back, 1e-12)
    same_table(table.to_poe(), back, "dh")


def test_ikdhs_own_robot_files_read_as_ikdh_reads_them():
    """ikdh's bundled robots (RoboDK's arms; a sample): the chain ikdh's own reader makes of
    each, in metres, said in a warning."""
    import ikdh
    from ik_corpus import ikdh_robots, sample

    for path in sample(ikdh_robots(), 25, 35):
        model = urdf2dh.load(str(path))
        assert model.length_unit == "m" and "no urdf2dh chain comment" in model.warnings[0]
        robot = ikdh.load_robot(str(path))
        dh = [list(getattr(robot.dh, k)) for k in ("a", "d", "alpha", "theta")]
        lo, hi = np.radians(list(robot.limits.lo)), np.radians(list(robot.limits.hi))
        assert limits(model) == pytest.approx(
            [x for pair in zip(lo, hi, strict=True) for x in pair]
        )
        q = model.sample(50, 3)
        want = []
        for config in q:
            t = np.eye(4)
            for (a, d, alpha, theta), qi in zip(zip(*dh, strict=True), config, strict=True):
                t = t @ se3.dh_matrix(theta + qi, d, alpha, a)
            want.append(t)
        pos, rot = se3.pose_errors(model.fk_batch(q), np.array(want))
        assert pos <= 1e-14 * model.size() and rot <= 1e-14, path.name
