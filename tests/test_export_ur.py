"""`export --to ur`: the UR client library's calibration hash, and the yaml read back the way
ur_macro.xacro reads it, evaluated by Pinocchio against the source."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import yaml
from consumers import report, ur_description_urdf
from oracle import assert_fk_matches, pin_reference

import urdf2dh
from urdf2dh import to_table
from urdf2dh.emit.export import export, export_table
from urdf2dh.emit.export.ur import calibration_hash, hash_bytes, hash_text, hashed_rows
from urdf2dh.errors import ExportError, UsageError
from urdf2dh.io.sources import open_source

# Published: the hash in Universal_Robots_ROS2_Description's config/<type>/default_kinematics.yaml
# for the nominal UR5 and UR10 (the hash the client library computes from those robots' D-H).
SHIPPED = {"ur5": "calib_209549117540498681", "ur10": "calib_17227329492635474227"}


def test_hash_bytes_is_libstdcxx_std_hash():
    # std::hash<std::string>{}("") with GCC's libstdc++ on x86-64
    assert hash_bytes(b"") == 6142509188972423790
    # every tail length 0..7 takes its own branch; the values must differ and stay 64-bit
    values = {hash_bytes(b"abcdefgh"[:n] + b"12345678") for n in range(8)}
    assert len(values) == 8 and all(0 <= v < 2**64 for v in values)


@pytest.mark.parametrize("robot", sorted(SHIPPED))
def test_hash_of_our_ur_style_table_matches_the_shipped_file(robot):
    table = to_table(urdf2dh.load(robot), "dh", style="ur")
    assert calibration_hash(table) == SHIPPED[robot]
    text = export_table(table, "ur")
    assert text.rstrip().endswith(f"hash: {SHIPPED[robot]}")


def test_hash_text_is_theta_d_a_alpha_per_joint_in_g_format():
    table = to_table(urdf2dh.load("ur10"), "dh", style="ur")
    raw = [r.params.values() for r in table.rows]
    assert raw[1]["theta"] != 0.0 and abs(raw[1]["theta"]) < 1e-10  # round-off of URDF's pi/2
    rows = hashed_rows(table)
    assert rows[1][0] == 0.0 and rows[4][1] == 0.1157 and rows[2][2] == -0.5723
    assert all(str(v) != "-0.0" for row in rows for v in row)
    assert hash_text(rows) == (
        "00.127301.570800-0.612000-0.5723000.16394101.570800.11570-1.570800.092200"
    )


def _pin_fk_of_urdf(text: str, base: str, tip: str, names: list[str], q: np.ndarray):
    model = pin.buildModelFromXML(text)
    data = model.createData()
    base_id = model.getFrameId(base)
    tip_id = model.getFrameId(tip)
    out = np.empty((len(q), 4, 4))
    for k, row in enumerate(q):
        config = pin.neutral(model)
        for name, value in zip(names, row, strict=True):
            config[model.joints[model.getJointId(name)].idx_q] = value
        pin.framesForwardKinematics(model, data, config)
        out[k] = np.linalg.solve(data.oMf[base_id].homogeneous, data.oMf[tip_id].homogeneous)
    return out


@pytest.mark.parametrize("robot", ["ur3", "ur5", "ur10"])
def test_yaml_through_the_macro_moves_like_the_source(robot):
    source = open_source(robot)
    model = source.model()
    text = export(model, "ur")
    tree = yaml.safe_load(text)
    kin = tree["kinematics"]
    for link in ("shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3"):
        assert all(
            isinstance(kin[link][k], float) for k in ("x", "y", "z", "roll", "pitch", "yaw")
        ), kin[link]
    names = [
        "shoulder_pan_joint",
        "shoulder_lift_joint",
        "elbow_joint",
        "wrist_1_joint",
        "wrist_2_joint",
        "wrist_3_joint",
    ]
    q, reference = pin_reference(source, model, samples=100, seed=3)
    poses = _pin_fk_of_urdf(ur_description_urdf(kin), "base_link", "tool0", names, q)
    pos, rot = assert_fk_matches(
        f"{robot} via ur_macro", poses, reference, model.size(), q, rel=1e-9, rot=1e-9
    )
    assert pos < 1e-9 and rot < 1e-9
    consumer = f"ur_macro.xacro's placement (our reader), Pinocchio {pin_version()}"
    report("ur", consumer, (pos, rot), model.size())


def test_yaml_values_are_clean():
    kin = yaml.safe_load(export(urdf2dh.load("ur5"), "ur"))["kinematics"]
    assert kin["forearm"]["x"] == -0.425 and kin["wrist_1"]["x"] == -0.39225
    assert kin["wrist_2"]["y"] == -0.09465 and kin["wrist_3"]["y"] == 0.0823
    assert kin["shoulder"]["yaw"] == 0.0  # round-off written as 0


@pytest.mark.parametrize(
    ("robot", "message"),
    [
        ("panda", "a UR arm has 6 joints; this chain has 7"),
        ("kinova", "UR's base frame at Rz(pi) from base_link"),
        ("stanford", "ur has revolute joints only"),
        ("puma560-actual", "ur has revolute joints only"),
    ],
)
def test_non_ur_chains_are_refused_with_the_reason(robot, message):
    with pytest.raises(ExportError, match=message.replace("(", r"\(").replace(")", r"\)")):
        export(urdf2dh.load(robot), "ur")


def test_a_tool_off_the_flange_is_refused():
    with pytest.raises(ExportError, match="tool0 on D-H frame 6"):
        export(urdf2dh.load("ur5", tip="ee_link"), "ur")


def test_ur_takes_only_the_ur_style_dh_table():
    with pytest.raises(UsageError, match="export target ur takes style ur, not wu"):
        export(urdf2dh.load("ur5"), "ur", style="wu")
    with pytest.raises(UsageError, match="dh tables"):
        export(urdf2dh.load("ur5"), "ur", convention="mdh")


def test_rpy_reads_back_through_the_urdf_convention():
    from urdf2dh.geometry.se3 import from_rpy, rot_x, rot_y, rot_z, rpy

    rng = np.random.default_rng(9)
    cases = [rng.uniform(-np.pi, np.pi, 3) for _ in range(50)]
    cases += [np.array([0.3, np.pi / 2, -1.1]), np.array([0.0, -np.pi / 2, 2.0])]  # gimbal lock
    for r, p, y in cases:
        m = rot_z(y) @ rot_y(p) @ rot_x(r)  # URDF: fixed axes x, then y, then z
        back = from_rpy((0.0, 0.0, 0.0), rpy(m))
        np.testing.assert_allclose(back, m, atol=1e-12)


def pin_version() -> str:
    import pinocchio

    return str(pinocchio.__version__)
