"""Universal Robots' kinematics files as a SOURCE: nominal files with UR's published hashes, real
factory calibrations (their D-H tables as UR's own tests publish them) written as ur_calibration
writes them, the same chain as the description a xacro builds from the file, and export --to ur
read back."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

import urdf2dh
from urdf2dh import XacroOptions
from urdf2dh.emit.export import ExportOptions, export
from urdf2dh.errors import InputError
from urdf2dh.geometry import se3
from urdf2dh.io.urkinematics import LINKS, hash_bytes, hash_text, read_ur_kinematics

ROOT = Path(__file__).resolve().parents[1]
SKELETON = ROOT / "tests" / "data" / "xacro" / "ur_kinematics" / "ur_kinematics.urdf.xacro"
PI_2 = 1.570796327  # pi/2 as UR's controllers report it, in every published UR file

# Universal Robots' published D-H tables (d1, a2, a3, d4, d5, d6; "DH Parameters for
# calculations of kinematics and dynamics") and the hash of each arm's nominal kinematics file in
# Universal_Robots_ROS2_Description (config/<type>/default_kinematics.yaml).
NOMINAL = {
    "ur3": ((0.1519, -0.24365, -0.21325, 0.11235, 0.08535, 0.0819), 9122066269688285636),
    "ur5": ((0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823), 209549117540498681),
    "ur10": ((0.1273, -0.612, -0.5723, 0.163941, 0.1157, 0.0922), 17227329492635474227),
    "ur3e": ((0.15185, -0.24355, -0.2132, 0.13105, 0.08535, 0.0921), 16756443741236045476),
    "ur5e": ((0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996), 12788084448423163542),
    "ur10e": ((0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655), 5119701370761913513),
    "ur16e": ((0.1807, -0.4784, -0.36, 0.17415, 0.11985, 0.11655), 1935737212149401527),
    "ur20": ((0.2363, -0.862, -0.7287, 0.201, 0.1593, 0.1543), 4890363623803256388),
    "ur30": ((0.2363, -0.637, -0.5037, 0.201, 0.1593, 0.1543), 12001109639981648826),
}

# Real factory calibrations: the differences (d, a, theta, alpha per joint) from the nominal
# D-H table that three robots' controllers hold, as Universal Robots publishes them in
# Universal_Robots_ROS2_Driver's ur_calibration/test/calibration_test.cpp (a UR10 and two
# UR10e; the last is the example of ur_calibration's documentation, d2 = 439 m).
CALIBRATIONS = {
    "ur10": (
        (0.00065609212979853, 1.4442162376284788, 0.854147723854608, -2.2989425877563705,
         -1.573498686836816e-05, 1.9072435590711256e-05),
        (4.6311376834935676e-05, -0.00012568315331862312, 0.00186216581161458,
         9.918593870679266e-05, 4.215462720453189e-06, 0.0),
        (-7.290070070824746e-05, -0.01713897289704999, -0.03707159413492756,
         0.054279462160583214, 1.488984257025741e-07, 1.551499479707493e-05),
        (0.000211987863869334, -0.0072553625957652995, -0.013483226769541364,
         0.0013495820227329425, -0.001263136163679901, 0.0),
    ),
    "ur10e-a": (
        (-0.000144894975118076141, 303.469135666158195, -309.88394307789747,
         6.41459904397394975, -4.48232900190081995e-05, -0.00087071402790364627),
        (0.000108651068627930392, 0.240324175250532346, 0.00180628180213493472,
         2.63076149165684402e-05, 3.96638632500012715e-06, 0.0),
        (1.59613525316931737e-07, -0.917209621528830232, 7.12936131346499469,
         0.0710299029424392298, -1.64258976526054923e-06, 9.17286101034808787e-08),
        (-0.000444781952841921679, -0.00160215112531214153, 0.00631917793331091861,
         -0.00165055247340828437, 0.000763682515545038854, 0.0),
    ),
    "ur10e-b": (
        (-0.000160188285741325043, 439.140974079900957, -446.027059806332147,
         6.88618689642360149, -3.86588496858186748e-05, -0.00087908274257374186),
        (2.12234865571205891e-05, 0.632017132627700651, 0.00229833638891230319,
         -4.61409023720933908e-05, -6.39280053471801522e-05, 0.0),
        (-2.41478068943590252e-07, 1.60233952386694556, -1.68607190752171299,
         0.0837331147700118711, -1.01260355871157781e-07, 3.91986209186123702e-08),
        (-0.000650246557584166496, 0.00139416666825590402, 0.00693818880325995126,
         -0.000811641562390219562, 0.000411120504570705592, 0.0),
    ),
}  # fmt: skip


def dh_rows(model, calibration=None):
    """(theta, d, a, alpha) per joint: the nominal table, plus a calibration's differences."""
    (d1, a2, a3, d4, d5, d6), _ = NOMINAL[model]
    d, a = [d1, 0, 0, d4, d5, d6], [0, a2, a3, 0, 0, 0]
    theta, alpha = [0.0] * 6, [PI_2, 0, 0, PI_2, -PI_2, 0]
    if calibration is not None:
        dd, da, dt, dal = calibration
        d = [x + y for x, y in zip(d, dd, strict=True)]
        a = [x + y for x, y in zip(a, da, strict=True)]
        theta = [x + y for x, y in zip(theta, dt, strict=True)]
        alpha = [x + y for x, y in zip(alpha, dal, strict=True)]
    return list(zip(theta, d, a, alpha, strict=True))


def joint_origins(rows):
    """The six joint origins of a kinematics file for a D-H table, as ur_calibration makes them:
    each row split into Rz(theta) Tz(d) and Rx(alpha) Tx(a), joint k's origin the previous row's
    Rx Tx and its own Rz Tz. For joints 2 and 3 (far common normals on calibrated arms) the
    Rz Tz is moved to d = 0: the Rx Tx then runs to where the next axis crosses that joint's
    xy-plane, and the next joint's d takes the rest, the chain's frames beyond unchanged."""
    active = [se3.rot_z(t) @ se3.trans(0, 0, d) for t, d, _, _ in rows]
    passive = [se3.rot_x(al) @ se3.trans(a, 0, 0) for _, _, a, al in rows]
    for i in (1, 2):
        if active[i][2, 3] == 0.0:
            continue
        end = active[i] @ passive[i]  # on the next axis, which runs along its z
        point, direction = end[:3, 3], end[:3, 2]
        crossing = point - (point[2] / direction[2]) * direction
        turn = se3.rot_z(math.atan2(-crossing[1], -crossing[0]))
        beyond = active[i] @ passive[i] @ active[i + 1]
        moved = np.linalg.solve(turn, end)
        moved[:3, 3] = (-math.hypot(crossing[0], crossing[1]), 0.0, 0.0)
        active[i], passive[i] = turn, moved
        active[i + 1] = np.linalg.solve(turn @ moved, beyond)
    return [active[0]] + [passive[k - 1] @ active[k] for k in range(1, 6)]


def kinematics_file(origins, file_hash, angles="rpy"):
    """A kinematics file's text; ``angles`` rpy (URDF's, as ur_macro.xacro reads them) or
    eigen (Eigen's x-y-z angles, R = Rx Ry Rz, as ur_calibration computes them)."""
    lines = ["kinematics:"]
    for link, origin in zip(LINKS, origins, strict=True):
        lines.append(f"  {link}:")
        lines += [f"    {k}: {float(v)!r}" for k, v in zip("xyz", origin[:3, 3], strict=True)]
        if angles == "rpy":
            values = se3.rpy(origin)
        else:  # R = Rx(a) Ry(b) Rz(c)
            r = origin[:3, :3]
            b = math.asin(max(-1.0, min(1.0, r[0, 2])))
            values = (math.atan2(-r[1, 2], r[2, 2]), b, math.atan2(-r[0, 1], r[0, 0]))
        lines += [f"    {k}: {float(v)!r}"
                  for k, v in zip(("roll", "pitch", "yaw"), values, strict=True)]  # fmt: skip
        lines.append("")
    lines.append(f"  hash: {file_hash}")
    return "\n".join(line for line in lines if line) + "\n"


def calib(rows):
    return f"calib_{hash_bytes(hash_text(rows).encode('ascii'))}"


def dh_fk(rows, q):
    """The controller's forward kinematics from base_link (a half turn from UR's base) to the
    flange, D-H frame 6."""
    out = []
    for config in q:
        t = se3.rot_z(math.pi)
        for (theta, d, a, alpha), qi in zip(rows, config, strict=True):
            t = t @ se3.dh_matrix(theta + qi, d, alpha, a)
        out.append(t)
    return np.array(out)


@pytest.mark.parametrize("model", sorted(NOMINAL))
def test_nominal_files_hash_as_universal_robots_publishes(model, tmp_path):
    rows = dh_rows(model)
    published = f"calib_{NOMINAL[model][1]}"
    assert calib(rows) == published  # the published table and the published hash agree
    path = tmp_path / f"{model}.yaml"
    path.write_text(kinematics_file(joint_origins(rows), published))
    kinematics = read_ur_kinematics(yaml.safe_load(path.read_text()), str(path))
    assert kinematics.hash_checked is True
    result = urdf2dh.match(f"{model}-dh", str(path))
    assert result.matched and result.residual[0] <= 1e-9 * result.size


@pytest.mark.parametrize("robot", sorted(CALIBRATIONS))
def test_real_calibrations_read_as_the_controller_moves(robot, tmp_path):
    rows = dh_rows(robot.partition("-")[0], CALIBRATIONS[robot])
    path = tmp_path / f"{robot}.yaml"
    path.write_text(kinematics_file(joint_origins(rows), calib(rows)))
    model = urdf2dh.load(str(path))
    assert model.warnings == ()  # the hash is the one of the controller's table
    assert (model.base_link, model.tip_link) == ("base_link", "tool0")
    q = model.sample(200, 2)
    pos, rot = se3.pose_errors(model.fk_batch(q), dh_fk(rows, q))
    assert pos <= 1e-12 * model.size() and rot <= 1e-12


def test_the_shipped_calibration_file_is_the_tests_own():
    """tests/data/vendor/universal-robots' file (docs/commands/match.md runs it) is this
    module's kinematics file of the documented UR10e calibration, as ur_calibration writes it."""
    rows = dh_rows("ur10e", CALIBRATIONS["ur10e-b"])
    path = (
        ROOT / "tests" / "data" / "vendor" / "universal-robots" / "ur10e-factory-calibration.yaml"
    )
    body = "".join(line for line in path.read_text().splitlines(True) if not line.startswith("#"))
    assert body == kinematics_file(joint_origins(rows), calib(rows))
    assert urdf2dh.load(str(path)).warnings == ()  # its hash is the controller table's


@pytest.mark.parametrize("robot", sorted(CALIBRATIONS))
def test_the_nominal_table_against_a_calibration_is_the_nearest_no_match(robot, tmp_path):
    """UR's published table against one arm's factory calibration: no match (the arm differs
    by up to ~0.2 deg and ~1 mm), and the best match is the obvious one, no joint turned round
    and every zero within a degree, the cells named with the source's values near the table's
    (d of hundreds of metres, D-H's far normals of nearly parallel axes, not shown; said)."""
    model = robot.partition("-")[0]
    rows = dh_rows(model, CALIBRATIONS[robot])
    path = tmp_path / f"{robot}.yaml"
    path.write_text(kinematics_file(joint_origins(rows), calib(rows)))
    result = urdf2dh.match(f"{model}-dh", str(path))
    assert not result.matched and result.convention == "dh"
    assert [j.sign for j in result.joints] == [1] * 6
    assert max(abs(j.offset) for j in result.joints) < math.radians(1.0)
    assert result.residual[0] < 0.01 * result.size
    assert result.disagreements
    for d in result.disagreements:
        limit = math.radians(1.0) if d.column == "alpha" else 0.01
        assert abs(d.source - d.table) < limit, d
    assert any("nearly parallel" in note for note in result.notes)


@pytest.mark.parametrize("robot", ["ur10e-b", "ur10"])
def test_the_same_chain_as_the_description_xacro_builds_from_the_file(robot, tmp_path):
    rows = dh_rows(robot.partition("-")[0], CALIBRATIONS[robot])
    path = tmp_path / "calibration.yaml"
    path.write_text(kinematics_file(joint_origins(rows), calib(rows)))
    options = XacroOptions(packages={"calibration": str(tmp_path)},
                           args={"kinematics": str(path)})  # fmt: skip
    described = urdf2dh.load(str(SKELETON), base="base_link", tip="tool0", xacro=options)
    ours = urdf2dh.load(str(path))
    assert [j.name for j in ours.joints] == [j.name for j in described.joints]
    q = ours.sample(200, 5)
    pos, rot = se3.pose_errors(ours.fk_batch(q), described.fk_batch(q))
    assert pos <= 1e-14 * ours.size() and rot <= 1e-14
    a, b = (urdf2dh.to_table(m, "dh", style="ur") for m in (described, ours))
    for ra, rb in zip(a.rows, b.rows, strict=True):
        assert ra.params.values() == pytest.approx(rb.params.values(), abs=1e-9)


def test_a_hash_the_origins_do_not_give_is_reported(tmp_path):
    rows = dh_rows("ur10e", CALIBRATIONS["ur10e-b"])
    path = tmp_path / "edited.yaml"
    path.write_text(kinematics_file(joint_origins(rows), "calib_12345"))
    (warning,) = urdf2dh.load(str(path)).warnings
    assert "hash calib_12345 is not that of the D-H table of its joint origins" in warning
    assert calib(rows) in warning or "calib_" in warning


def test_angles_written_as_ur_calibration_computes_them(tmp_path):
    """Eigen's x-y-z angles where URDF's rpy are read: the hash holds for them, the reader says
    so and how far apart the two readings put the origins."""
    rows = dh_rows("ur10e", CALIBRATIONS["ur10e-b"])
    origins = joint_origins(rows)
    origins[3] = se3.rot_x(0.3) @ origins[3] @ se3.rot_z(0.05)  # turned about two axes
    true_hash = read_ur_kinematics(yaml.safe_load(kinematics_file(origins, "calib_0")),
                                   "x").computed_hash  # fmt: skip
    path = tmp_path / "eigen.yaml"
    path.write_text(kinematics_file(origins, true_hash, angles="eigen"))
    (note,) = urdf2dh.load(str(path)).warnings
    assert "Eigen's x-y-z angles" in note and "rad apart" in note


def test_export_to_ur_reads_back_as_the_same_table(tmp_path):
    for robot in ("ur3", "ur5", "ur10"):
        source = urdf2dh.load(robot)
        path = tmp_path / f"{robot}.yaml"
        path.write_text(export(source, "ur"))
        back = urdf2dh.load(str(path))
        assert back.warnings == ()
        a, b = (urdf2dh.to_table(m, "dh", style="ur") for m in (source, back))
        for ra, rb in zip(a.rows, b.rows, strict=True):
            assert ra.params.values() == pytest.approx(rb.params.values(), abs=1e-11)
    # the real calibrations, exported from the model read and read back
    for robot, calibration in CALIBRATIONS.items():
        rows = dh_rows(robot.partition("-")[0], calibration)
        first = tmp_path / f"{robot}.yaml"
        first.write_text(kinematics_file(joint_origins(rows), calib(rows)))
        model = urdf2dh.load(str(first))
        again = tmp_path / f"{robot}-again.yaml"
        again.write_text(export(model, "ur", opts=ExportOptions(tol=urdf2dh.EXACT)))
        back = urdf2dh.load(str(again))
        assert back.warnings == ()  # its hash is its table's
        q = model.sample(200, 8)
        pos, rot = se3.pose_errors(back.fk_batch(q), model.fk_batch(q))
        # the exact D-H table of a calibrated UR reaches 439 m (its far common normals): its
        # FK rounds by about eps x the sum of its lengths, a few 1e-13 m
        assert pos <= 1e-11 * model.size() and rot <= 1e-12


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("kinematics:\n  shoulder: {x: 0, y: 0, z: 0, roll: 0, pitch: 0, yaw: 0}\n",
         "kinematics.upper_arm: missing"),
        ("kinematics:\n  shoulder: {x: 0, y: 0, z: a, roll: 0, pitch: 0, yaw: 0}\n",
         "kinematics.shoulder.z must be a number"),
        ("kinematics:\n  shoulder: {x: 0, y: 0, z: 0, roll: 0, pitch: 0, yaw: 0, w: 1}\n",
         "unknown key 'w'"),
        ("kinematics:\n  shoulder: {}\n  elbow: {}\n", "unknown entry 'elbow'"),
    ],
)  # fmt: skip
def test_bad_kinematics_files(text, message, tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        urdf2dh.load(str(path))


def test_a_factory_calibration_into_the_vendors_urdf(tmp_path):
    """The story of the issue: a robot's calibration file put into its vendor's URDF with
    --like (the UR10e description of examples/calibration-data): every link keeps its meshes,
    moves by the calibration's millimetres, and the URDF moves as the controller does."""
    from urdf2dh.emit.urdf_like import urdf_like

    rows = dh_rows("ur10e", CALIBRATIONS["ur10e-b"])
    path = tmp_path / "calibration.yaml"
    path.write_text(kinematics_file(joint_origins(rows), calib(rows)))
    nominal = ROOT / "examples" / "calibration-data" / "ur10" / "ur10_robot.urdf"
    result = urdf_like(urdf2dh.load(str(path)), str(nominal))
    written = tmp_path / "calibrated.urdf"
    written.write_text(result.text)
    assert result.text.count("<mesh ") == nominal.read_text().count("<mesh ")
    arm = [m for m in result.moved if not m.tool]
    assert arm and max(m.distance for m in arm) < 0.005 and max(m.angle for m in arm) < 0.02
    model = urdf2dh.load(str(written), base="base_link", tip="tool0")
    q = model.sample(200, 9)
    pos, rot = se3.pose_errors(model.fk_batch(q), dh_fk(rows, q))
    assert pos <= 1e-12 * model.size() and rot <= 1e-12
