"""``urdf2dh match``: which table is this? The shipped references against their robots, tables
perturbed by every kind of difference (each alone and all together, seeded), tables rounded to a
datasheet's digits, a table of another robot, and TABLE corrected."""

from __future__ import annotations

import math
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import urdf2dh
from urdf2dh import units
from urdf2dh.check.match import match
from urdf2dh.errors import InputError
from urdf2dh.geometry import se3
from urdf2dh.io.catalog import lookup, robot_path
from urdf2dh.io.handtable import read_hand_table
from urdf2dh.io.tablefile import read_table

ROOT = Path(__file__).resolve().parents[1]
UR10E = str(ROOT / "examples" / "calibration-data" / "ur10" / "ur10_robot.urdf")
LENGTH = {"m": 1.0, "mm": 1e3, "cm": 1e2, "in": 1.0 / 0.0254}


# ----------------------------------------------------------------------------- building tables


def at_zero(model, delta):
    """The model whose zero is ``model``'s configuration ``delta``: ``P(q) = S(q + delta)``."""
    joints, f = [], np.eye(4)
    for j, d in zip(model.joints, delta, strict=True):
        point = f[:3, :3] @ j.point + f[:3, 3] if j.point is not None else None
        joints.append(replace(j, axis=f[:3, :3] @ j.axis, point=point))
        f = f @ se3.twist_exp(j.twist(), d)
    return replace(model, joints=tuple(joints), home=model.fk(np.asarray(delta, dtype=float)))


def turned(model, flips):
    """The model with the joints ``flips`` turning the other way."""
    joints = tuple(
        replace(j, axis=-j.axis) if i in flips else j for i, j in enumerate(model.joints)
    )
    return replace(model, joints=joints)


def placed(model, base, tool):
    """``base . T(q) . tool``."""
    r, t = base[:3, :3], base[:3, 3]
    joints = tuple(
        replace(j, axis=r @ j.axis, point=None if j.point is None else r @ j.point + t)
        for j in model.joints
    )
    return replace(model, joints=joints, home=base @ model.home @ tool)


def write_table(table, path, length_unit="m", angle_unit="rad", decimals=12, shuffle=False):
    """A table as a person writes it: a CSV of theta, d, a, alpha (no base and tool rows)."""
    k = LENGTH[length_unit]

    def angle(v):
        return f"{math.degrees(v) if angle_unit == 'deg' else v:.{decimals}f}"

    columns = ["joint", "theta", "d", "a", "alpha"]
    if shuffle:
        columns = ["alpha", "a", "joint", "d", "theta"]
    lines = [",".join(columns)]
    for r in table.rows:
        p = r.params.values()
        cells = {"joint": r.name, "theta": angle(p["theta"]), "d": f"{k * p['d']:.{decimals}f}",
                 "a": f"{k * p['a']:.{decimals}f}", "alpha": angle(p["alpha"])}  # fmt: skip
        lines.append(",".join(cells[c] for c in columns))
    path.write_text("\n".join(lines) + "\n")
    return path


def random_transform(rng, size):
    w = rng.normal(size=3)
    w *= rng.uniform(0.2, 2.5) / np.linalg.norm(w)
    return se3.twist_exp(np.concatenate([w, 0.3 * size * rng.normal(size=3)]), 1.0)


def agrees(result, source, size):
    """The fit's forward kinematics against the source's, at fresh configurations."""
    q = source.sample(300, 7)
    ours = result.poses(q, source)
    pos, rot = se3.pose_errors(ours, source.fk_batch(q))
    return pos / size, rot


# ----------------------------------------------------------------------------- the references

SHIPPED = [
    ("ur3-dh", "ur3", {}),
    ("ur5-dh", "ur5", {}),
    ("ur10-dh", "ur10", {}),
    ("ur10e-dh", UR10E, {"base": "base_link", "tip": "tool0"}),
    ("panda-mdh", "panda", {}),
    ("panda-mdh", "fr3-mjcf", {}),  # Menagerie's FR3 (MJCF): the Panda's kinematics
    ("puma560-wu2019-dh", "puma560-nominal", {}),
    ("kuka-kr6-r700-sixx-opw", "kuka-kr6-r700-sixx", {}),
    ("fanuc-m20ia-opw", "fanuc-m20ia", {}),
]


@pytest.mark.parametrize(("reference", "robot", "chain"), SHIPPED)
def test_shipped_references_match_their_robots(reference, robot, chain):
    result = match(reference, robot, **chain)
    source = urdf2dh.load(robot, **chain)
    assert result.matched, result.text()
    assert result.residual[0] <= 1e-9 * source.size() and result.residual[1] <= 1e-9
    expected = urdf2dh.load(reference)  # read as a model too, in its own units
    if reference.endswith("-opw"):  # OPW's frames are the support packages' own
        assert result.reading == "the file's own chain"
        assert np.allclose(result.base, np.eye(4), atol=1e-9)
        assert np.allclose(result.tool, np.eye(4), atol=1e-9 * source.size())
        return
    assert result.convention == ("mdh" if reference == "panda-mdh" else "dh")
    assert result.length_unit == expected.length_unit
    assert [j.sign for j in result.joints] == [1] * source.n
    assert [j.shown for j in result.joints] == ["0"] * source.n
    if reference.startswith("ur"):  # base_link is UR's base frame turned by pi about z
        assert np.allclose(result.base, se3.rot_z(math.pi), atol=1e-9)
    else:
        assert np.allclose(result.base, np.eye(4), atol=1e-9)
    assert np.allclose(result.tool, np.eye(4), atol=1e-9 * source.size())
    # TABLE corrected: the source's exact table, laid out as the reference (UR's negative a2, a3)
    corrected = result.corrected
    assert corrected is not None and corrected.convention == result.convention
    assert corrected.check.max_position_error <= 1e-14 * source.size() * 10
    table = read_hand_table(robot_path(lookup(reference)))
    joints = [r for r in table.rows if r.kind != "fixed"]
    factor = units.factor(expected.length_unit, source.length_unit)
    for row, written in zip(corrected.rows[1:-1], joints[1:-1], strict=True):
        p = row.params.values()
        assert p["a"] == pytest.approx(factor * written.a.value, abs=1e-9)
        assert p["d"] == pytest.approx(factor * written.d.value, abs=1e-9)


# ----------------------------------------------------------------------------- perturbed tables

KINDS = ["units", "convention", "offsets", "directions", "base", "tool", "all"]


def perturbed(robot, kind, seed, tmp_path, rounding=12):
    """A table of ``robot`` with one kind of difference (or all), written as a CSV; the
    differences made."""
    rng = np.random.default_rng((seed, KINDS.index(kind)))
    source = urdf2dh.load(robot)
    n, size = source.n, source.size()
    every = kind == "all"
    convention = "mdh" if kind == "convention" or (every and rng.uniform() < 0.5) else "dh"
    delta = np.zeros(n)
    if kind == "offsets" or every:
        delta[1:-1] = rng.uniform(-math.pi, math.pi, n - 2)
    flips = set()
    if kind == "directions" or every:
        flips = {int(i) for i in rng.choice(np.arange(1, n - 1), 2, replace=False)}
    base = random_transform(rng, size) if kind == "base" or every else np.eye(4)
    tool = random_transform(rng, size) if kind == "tool" or every else np.eye(4)
    model = placed(turned(at_zero(source, delta), flips), base, tool)
    length, angle = ("mm", "deg") if kind == "units" or every else ("m", "rad")
    table = urdf2dh.to_table(model.scaled(units.metres_per(model.length_unit), "m"), convention)
    name = Path(robot).stem
    path = write_table(table, tmp_path / f"{name}-{kind}-{seed}.csv", length, angle, rounding,
                       shuffle=every)  # fmt: skip
    return path, source, {"convention": convention, "length": length, "angle": angle,
                          "delta": delta, "flips": flips}  # fmt: skip


@pytest.mark.parametrize("robot", ["ur5", "panda", "kuka-kr6-r700-sixx"])
@pytest.mark.parametrize("kind", KINDS)
def test_perturbed_tables_match(robot, kind, tmp_path):
    path, source, made = perturbed(robot, kind, 0, tmp_path)
    result = match(str(path), robot)
    size = source.size()
    assert result.matched, result.text()
    assert result.convention == made["convention"]
    assert result.length_unit == made["length"]
    assert result.angle_units == (made["angle"], made["angle"])
    assert result.residual[0] <= 1e-9 * size and result.residual[1] <= 1e-9
    pos, rot = agrees(result, source, size)
    assert pos <= 1e-9 and rot <= 1e-9
    if kind == "offsets":  # the table's zero is the source's at delta: offsets -delta
        found = np.array([j.offset for j in result.joints])
        assert np.allclose(np.remainder(found[1:-1] + made["delta"][1:-1] + math.pi, 2 * math.pi),
                           math.pi, atol=1e-9)  # fmt: skip
        assert any("its zero is" in d for d in result.differences)
    if kind == "directions":  # never more turned joints than were made (a symmetry may save one)
        assert 0 < sum(j.sign < 0 for j in result.joints) <= len(made["flips"])
        assert any("turns the other way" in d for d in result.differences)
    if kind == "base":
        assert not np.allclose(result.base, np.eye(4))
    if kind == "tool":
        assert not np.allclose(result.tool, np.eye(4))


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_every_difference_at_once_seeded(seed, tmp_path):
    for robot in ("ur5", "fanuc-m20ia", "stanford"):
        path, source, made = perturbed(robot, "all", seed, tmp_path)
        result = match(str(path), robot)
        assert result.matched, result.text()
        assert (result.convention, result.length_unit) == (made["convention"], made["length"])
        pos, rot = agrees(result, source, source.size())
        assert pos <= 1e-9 and rot <= 1e-9


def test_datasheet_rounding_is_judged_at_its_precision(tmp_path):
    """A table written to 0.1 mm and 0.01 degree matches at that precision; one cell changed
    by far more than its last digit does not, and the row and column are named."""
    source = urdf2dh.load("ur10")
    table = urdf2dh.to_table(at_zero(source, [0, 0.3, -0.2, 0.1, 0.4, 0]), "dh", style="ur")
    path = write_table(table, tmp_path / "datasheet.csv", "mm", "deg", 2)
    result = match(str(path), "ur10")
    assert result.matched, result.text()
    assert 1e-9 < result.residual[0] <= result.allowed[0]  # the rounding is seen, and allowed
    assert result.allowed[0] < 1e-3  # 0.01 mm digits allow micrometres, not millimetres
    lines = path.read_text().splitlines()
    cells = lines[3].split(",")  # row 3: a is -572.30 mm
    cells[3] = f"{float(cells[3]) + 0.5:.2f}"  # half a millimetre off
    lines[3] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    result = match(str(path), "ur10")
    assert not result.matched
    assert [(d.row, d.column) for d in result.disagreements] == [("elbow_joint", "a")]
    assert result.disagreements[0].table == pytest.approx(-0.5718)
    assert result.disagreements[0].source == pytest.approx(-0.5723)


def test_a_table_of_another_robot_is_no_match_naming_the_joints(tmp_path):
    result = match("ur5-dh", "ur10")
    assert not result.matched
    named = {(d.row, d.column) for d in result.disagreements}
    assert named == {("2", "a"), ("3", "a"), ("4", "d"), ("5", "d")}
    assert "no match" in result.text() and "they disagree at" in result.text()
    assert result.corrected is None
    # a table of another kind of arm: the rows where the geometry differs are named
    other = match("ur5-dh", "kuka-kr6-r700-sixx")
    assert not other.matched and len(other.disagreements) >= 3


def test_menageries_ur5e_is_not_urs_table():
    """MuJoCo Menagerie's UR5e (MJCF) has its own dimensions (a3 0.392 m, d4 0.134 m, d5 0.1 m
    against UR's 0.3922, 0.1333, 0.0997): no match, those cells named; the words of a
    near-identity turn are a number, never NaN."""
    result = match("ur5e-dh", "ur5e-mjcf")
    assert not result.matched
    named = {(d.row, d.column) for d in result.disagreements}
    assert named == {("3", "a"), ("4", "d"), ("5", "d")}
    assert "nan" not in result.text()


def test_another_number_of_joints_is_no_match():
    result = match("panda-mdh", "ur5")
    assert not result.matched and result.joints == ()
    assert "the table has 7 joints, the source's chain 6" in result.text()


def test_a_table_file_is_compared_as_it_is(tmp_path):
    """A table file (its convention and units said) as TABLE, in millimetres against a source
    in metres."""
    source = urdf2dh.load("kinova")
    table = urdf2dh.to_table(placed(source.scaled(1e3, "mm"), se3.rot_x(0.3), np.eye(4)), "mdh")
    path = tmp_path / "kinova-mm.json"
    path.write_text(urdf2dh.render(table, "json"))
    result = match(str(path), "kinova")
    assert result.matched and result.convention == "mdh"
    assert np.allclose(result.base[:3, :3], se3.rot_x(-0.3)[:3, :3], atol=1e-12)


# ----------------------------------------------------------------------------- the command


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "urdf2dh.cli", *args], capture_output=True,
                          text=True, cwd=cwd)  # fmt: skip


def test_cli_match_writes_table_corrected(tmp_path):
    out = tmp_path / "ur5-corrected.json"
    proc = run("match", "ur5-dh", "ur5", "-o", str(out))
    assert proc.returncode == 0, proc.stderr
    assert "matches" in proc.stdout and "turned 180 deg about z" in proc.stdout
    import json

    table = read_table(json.loads(out.read_text()), str(out))
    source = urdf2dh.load("ur5")
    q = source.sample(200, 3)
    pos, rot = se3.pose_errors(table.fk_batch(q), source.fk_batch(q))
    assert pos <= 1e-14 * source.size() * 10 and rot <= 1e-14 * 10
    assert [r.params.a for r in table.rows][1:3] == pytest.approx([-0.425, -0.39225], abs=1e-12)
    assert table.base.theta == pytest.approx(math.pi)


def test_cli_no_match_exits_1_and_writes_nothing(tmp_path):
    out = tmp_path / "corrected.yaml"
    proc = run("match", "ur5-dh", "ur10", "-o", str(out))
    assert proc.returncode == 1
    assert "no match" in proc.stdout and "not written" in proc.stderr
    assert not out.exists()


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("joint,theta,d,a\n1,0,0,0\n", "no column alpha"),
        ("joint,theta,d,a,alpha,colour\n1,0,0,0,0,red\n", "unknown column 'colour'"),
        ("theta,d,a,alpha\n0,0,x,0\n", "row 'joint1': a must be a number"),
        ("theta [furlong],d,a,alpha\n0,0,0,0\n", "an angle's unit is deg or rad"),
        # the one number grammar (urdf2dh.numerals): Python's float takes these, urdf2dh not
        ("theta,d,a,alpha\n0,0,\u0661,0\n", "not '\u0661' (digits that are not ASCII"),
        ("theta,d,a,alpha\n0,0,0.4_25,0\n", "not '0.4_25' (digits grouped with '_'"),
        ("theta,d,a,alpha\n0,0,0,pi/1e999\n", "beyond the range of float64"),
    ],
)
def test_bad_tables_are_errors_naming_the_file_row_and_column(text, message, tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=r"bad\.csv") as caught:
        match(str(path), "ur5")
    assert message in str(caught.value)


def test_cli_bad_table_is_one_line_exit_2(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("joint,theta,d,a,alpha,colour\n1,0,0,0,0,red\n")
    proc = run("match", str(path), "ur5", "-o", str(tmp_path / "out.yaml"))
    assert proc.returncode == 2 and "unknown column 'colour'" in proc.stderr, proc.stderr
    assert "Traceback" not in proc.stderr and len(proc.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "out.yaml").exists()


# ----------------------------------------------------------------------------- reading tables


def test_cells_as_people_write_them(tmp_path):
    path = tmp_path / "cells.csv"
    path.write_text(
        "# a datasheet\nα (deg), a [mm], d_mm, θ\n"
        "90, 0, 333, q1\n-90, 0, 0, θ2 - 90\n0, 425.0, 0, q3+pi/2\n0,0,107,0\n"
    )
    table = read_hand_table(path)
    assert table.angle_unit("alpha") == "deg" and table.length_unit == "mm"
    assert table.source == "a datasheet"
    first, second, third, flange = table.rows
    assert first.kind == "revolute" and flange.kind == "fixed"  # variables marked: others fixed
    assert second.theta.value == -90.0 and third.theta.value == pytest.approx(math.pi / 2)
    assert third.theta.step == 0.0 and third.a.step == 0.05  # pi/2 exact; 425.0 to 0.1 mm
    yaml_path = tmp_path / "rows.yaml"
    yaml_path.write_text("- {theta: 0, d: 0.1, a: 0, alpha: 1.5708}\n- {theta: 0, d: q2, a: 0, "
                         "alpha: 0}\n")  # fmt: skip
    rows = read_hand_table(yaml_path).rows
    assert rows[1].kind == "prismatic" and rows[0].kind == "fixed"
