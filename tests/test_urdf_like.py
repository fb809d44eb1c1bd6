"""``--format urdf --like NOMINAL``: a model's kinematics written into the nominal URDF, its links,
meshes and inertials kept. The real UR10e calibration shipped in examples/, synthetic errors on
other arms, the refusals, and the command line."""

from __future__ import annotations

import math
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from lxml import etree

import urdf2dh
from urdf2dh.calibration.measurements import read_measurements
from urdf2dh.emit.urdf_like import urdf_like
from urdf2dh.errors import ExportError
from urdf2dh.geometry import se3
from urdf2dh.io.catalog import ROBOTS, robot_path

ROOT = Path(__file__).resolve().parents[1]
UR10 = ROOT / "examples" / "calibration-data" / "ur10"
NOMINAL = str(UR10 / "ur10_robot.urdf")


def elements(text):
    parser = etree.XMLParser(remove_comments=True, resolve_entities=False, no_network=True)
    return etree.fromstring(text.encode() if isinstance(text, str) else text, parser=parser)


def link_geometry(root):
    """Each link's visual, collision and inertial elements, as text."""
    return {
        link.get("name"): [etree.tostring(e) for e in link if e.tag in ("visual", "collision",
                                                                        "inertial")]
        for link in root.findall("link")
    }  # fmt: skip


def joints_without_kinematics(root):
    """Each joint element as text with its origin and axis taken out."""
    out = {}
    for joint in root.findall("joint"):
        copy = etree.fromstring(etree.tostring(joint))
        for tag in ("origin", "axis"):
            for e in copy.findall(tag):
                copy.remove(e)
        out[joint.get("name")] = etree.tostring(copy)
    return out


def link_frames(model_source, base, tip):
    """Each link's frame on the chain at the home pose (in the base link), by link name."""
    tree = urdf2dh.io.sources.open_source(model_source).tree
    out, world = {}, np.eye(4)
    for j in tree.chain(base, tip):
        world = world @ j.origin
        out[j.child] = (world, j)
    return out


@pytest.fixture(scope="module")
def calibrated(tmp_path_factory):
    """The UR10e calibrated on its shipped measurements (geometry level chosen), in the
    nominal's base frame, to tool0; and the URDF written like the nominal."""
    nominal = urdf2dh.load(NOMINAL, base="base_link", tip="tool0")
    m = read_measurements(str(UR10 / "ur10_pose_fit.csv"), tuple(j.name for j in nominal.joints),
                          length_unit="m")  # fmt: skip
    cal = urdf2dh.calibrate(nominal, m, frame="nominal")
    result = urdf_like(cal.model, NOMINAL)
    path = tmp_path_factory.mktemp("like") / "ur10e-calibrated.urdf"
    path.write_text(result.text)
    return cal, result, path


def test_real_calibration_keeps_every_mesh_and_inertial(calibrated):
    cal, result, _ = calibrated
    assert cal.level == "geometry"  # a real change of the joints' lines, not only base and tool
    nominal = elements(Path(NOMINAL).read_bytes())
    written = elements(result.text)
    assert link_geometry(written) == link_geometry(nominal)
    meshes = sorted(m.get("filename") for m in written.iter("mesh"))
    assert meshes == sorted(m.get("filename") for m in nominal.iter("mesh")) and len(meshes) >= 14
    # only joint origins and axes changed, and only on the chain
    before, after = joints_without_kinematics(nominal), joints_without_kinematics(written)
    assert before == after
    tree = urdf2dh.io.sources.open_source(NOMINAL).tree
    chain = {j.name for j in tree.chain("base_link", "tool0")}
    assert set(result.joints) <= chain
    assert result.tool_joint == "wrist_3-flange"


def test_real_calibration_forward_kinematics_and_verify(calibrated):
    cal, _, path = calibrated
    written = urdf2dh.load(str(path), base="base_link", tip="tool0")
    q = cal.model.sample(300, 4)
    pos, rot = se3.pose_errors(written.fk_batch(q), cal.model.fk_batch(q))
    assert pos <= 1e-12 * cal.model.size() and rot <= 1e-12
    report = urdf2dh.verify(str(path), base="base_link", tip="tool0", samples=100)
    assert report.ok


def test_real_calibration_link_frames_are_the_nominals_moved_onto_the_model(calibrated):
    """Each moving link's frame lies on the identified axis where the nominal's frame is
    nearest it, its URDF axis the nominal's (or its opposite), and every link's geometry moves
    with its frame: its pose relative to the link is the nominal's."""
    cal, result, path = calibrated
    before = link_frames(NOMINAL, "base_link", "tool0")
    after = link_frames(str(path), "base_link", "tool0")
    joints = {j.name: j for j in cal.model.joints}
    for link, (frame, joint) in after.items():
        if joint.name not in joints:
            continue
        model_joint = joints[joint.name]
        u, p = model_joint.axis, model_joint.point
        nominal_origin = before[link][0][:3, 3]
        nearest = p + ((nominal_origin - p) @ u) * u
        assert np.allclose(frame[:3, 3], nearest, atol=1e-12)
        nominal_axis = before[link][1].axis
        assert np.allclose(joint.axis, nominal_axis) or np.allclose(joint.axis, -nominal_axis)
        assert np.allclose(frame[:3, :3] @ joint.axis, model_joint.scale * model_joint.axis,
                           atol=1e-12)  # fmt: skip
        # the calibration's corrections: centimetres and degrees, not the camera's offset
        moved = next(m for m in result.moved if m.link == link) if link in {
            m.link for m in result.moved} else None  # fmt: skip
        if moved is not None:
            assert moved.distance < 0.1 and moved.angle < math.radians(6)
    # each link's geometry in the base link at home, before and after: the same pose relative
    # to its link (read from each file), moved by the calibration's corrections only
    nominal_xml, written_xml = elements(Path(NOMINAL).read_bytes()), elements(path.read_bytes())
    checked = 0
    for link, (frame, _) in after.items():
        for kind in ("visual", "collision", "inertial"):
            mine = written_xml.find(f"link[@name='{link}']/{kind}/origin")
            theirs = nominal_xml.find(f"link[@name='{link}']/{kind}/origin")
            if theirs is None:
                continue
            local = [se3.from_rpy(tuple(map(float, e.get("xyz", "0 0 0").split())),
                                  tuple(map(float, e.get("rpy", "0 0 0").split())))
                     for e in (mine, theirs)]  # fmt: skip
            assert np.array_equal(local[0], local[1])
            now, then = frame @ local[0], before[link][0] @ local[1]
            assert np.linalg.norm(now[:3, 3] - then[:3, 3]) < 0.1
            turn = now[:3, :3].T @ then[:3, :3]
            assert math.acos(min(1.0, (np.trace(turn) - 1.0) / 2.0)) < math.radians(6)
            checked += 1
    assert checked >= 18  # six arm links, three elements each


def synthetic(robot, seed):
    """``robot`` with every joint's line moved a little and its zero changed (a calibration's
    kind of change), and a tool."""
    rng = np.random.default_rng(seed)
    model = urdf2dh.load(robot)
    size = model.size()
    joints = []
    for j in model.joints:
        w = rng.normal(size=3)
        turn = se3.rot_axis(w / np.linalg.norm(w), 0.02)
        joints.append(replace(j, axis=turn @ j.axis, point=j.point + 0.005 * size *
                              rng.normal(size=3)))  # fmt: skip
    tool = se3.twist_exp(np.concatenate([0.1 * rng.normal(size=3), 0.05 * rng.normal(size=3)]))
    return replace(model, joints=tuple(joints), home=model.home @ tool)


@pytest.mark.parametrize("robot", ["panda", "kuka-kr6-r700-sixx", "ur5"])
def test_synthetic_errors_are_written_exactly(robot, tmp_path):
    model = synthetic(robot, 3)
    result = urdf_like(model, robot)
    path = tmp_path / "like.urdf"
    path.write_text(result.text)
    bundled = ROBOTS[robot]
    written = urdf2dh.load(str(path), base=bundled.base, tip=bundled.tip)
    q = model.sample(200, 1)
    pos, rot = se3.pose_errors(written.fk_batch(q), model.fk_batch(q))
    assert pos <= 1e-12 * model.size() and rot <= 1e-12
    nominal = elements(robot_path(bundled).read_bytes())
    assert link_geometry(elements(result.text)) == link_geometry(nominal)


def test_a_model_of_the_nominal_itself_changes_nothing(tmp_path):
    """The nominal's own model (via its D-H table) written like it: no joint changes."""
    table = urdf2dh.to_table(urdf2dh.load("ur5"), "dh", style="ur")
    result = urdf_like(table, "ur5")
    assert result.joints == () and result.moved == ()


def test_refusals():
    model = urdf2dh.load("ur5")
    scaled = replace(model, joints=(replace(model.joints[0], scale=1.001), *model.joints[1:]))
    with pytest.raises(ExportError, match="joint has no scale"):
        urdf_like(scaled, "ur5")
    # the tip is the last moving link's child, and the model's tip is off that joint's axis
    off = replace(model, home=model.home @ se3.trans(0.05, 0.0, 0.0))
    with pytest.raises(ExportError, match="off the axis of joint 'wrist_3_joint'"):
        urdf_like(off, "ur5", tip="wrist_3_link")
    with pytest.raises(urdf2dh.Urdf2DhError, match="moving joints"):
        urdf_like(urdf2dh.load("panda"), "ur5")
    with pytest.raises(urdf2dh.Urdf2DhError, match="takes a URDF"):
        urdf_like(model, "puma560-nominal")


def run(*args):
    return subprocess.run([sys.executable, "-m", "urdf2dh.cli", *args], capture_output=True,
                          text=True)  # fmt: skip


def test_cli(tmp_path):
    proc = run("convert", "ur5", "--like", "ur5", "--format", "csv")
    assert proc.returncode == 2 and "--like writes a URDF" in proc.stderr
    proc = run("convert", "ur5", "--like", "", "--format", "urdf")  # not taken for no --like
    assert proc.returncode == 2 and "--like: NOMINAL is empty" in proc.stderr and not proc.stdout
    out = tmp_path / "cal.urdf"
    proc = run("calibrate", NOMINAL, str(UR10 / "ur10_pose_fit.csv"), "--tip", "tool0",
               "--like", NOMINAL, "--frame", "device", "-o", str(out))  # fmt: skip
    assert proc.returncode == 2 and "--frame nominal" in proc.stderr and not out.exists()
