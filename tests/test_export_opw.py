"""``export --to opw``, read by the real consumer: py-opw-kinematics (PyPI), the Python wrapper of
rs-opw-kinematics, which evaluates the OPW model as opw_kinematics (MoveIt, Tesseract) does.

For every robot that qualifies, the consumer's forward kinematics from the exported file (with the
file's base and tool blocks applied) puts the flange where Pinocchio puts the tip, and its inverse
kinematics returns the sampled configuration among its solutions; robots that are not OPW arms
are refused with the condition that failed."""

from __future__ import annotations

import math
import re
import sys
from dataclasses import replace
from importlib.metadata import version as metadata_version

import numpy as np
import pytest
import yaml
from consumers import report
from oracle import EXACT, assert_fk_matches, pin_reference

from urdf2dh import ExportOptions, Joint, PoeModel, export, load
from urdf2dh.conventions.opw import OpwParameters, opw_fk, opw_from_poe
from urdf2dh.errors import ExportError, UsageError
from urdf2dh.escape import yaml_comment
from urdf2dh.geometry.se3 import from_rpy, inv, rot_x, rot_y, rot_z, trans
from urdf2dh.io.catalog import ROBOTS, our_robots_dir
from urdf2dh.io.sources import open_source
from urdf2dh.tolerances import EXACT as EXACT_TOL
from urdf2dh.units import factor as length_factor

if sys.version_info < (3, 11):  # py-opw-kinematics needs Python 3.11 (pyproject's test extra)
    pytest.importorskip("py_opw_kinematics")
from py_opw_kinematics import KinematicModel, Robot
from scipy.spatial.transform import RigidTransform

IK_ANGLE = 1e-7  # rad: the sampled configuration among the IK solutions (mod 2 pi)
# the bundled robots that are OPW arms; kinova's URDF rounds pi (its axes are 4.9e-12 rad off
# the right angles), a deviation the file declares
OPW_ROBOTS = ["kuka-kr6-r700-sixx", "fanuc-m20ia", "puma560-nominal", "kinova"]
REFUSED = {
    "ur3": "wrist axes do not intersect: offset wrist",
    "ur5": "wrist axes do not intersect: offset wrist",
    "ur10": "wrist axes do not intersect: offset wrist",
    "ur5e-mjcf": "wrist axes do not intersect: offset wrist",
    "z1": "wrist axes do not intersect: offset wrist",
    "talos-left-arm": "axes 2 ('arm_left_3_joint'), 3 ('arm_left_4_joint') are not parallel",
    "stanford": "joints 'joint3' (prismatic) cannot be written",
    "puma560-actual": "'j3' (helical)",
    **{r: "an OPW arm has 6 joints" for r in (
        "panda", "xarm7", "so100", "so101", "baxter-left", "baxter-right", "tiago-arm",
        "finger-edu", "hextilt-arm", "borinot-arm", "twodof", "double-pendulum", "scara",
        "fr3-mjcf", "xarm7-mjcf",
    )},
}  # fmt: skip


def consumer(text: str) -> tuple[Robot, np.ndarray, np.ndarray]:
    """The file as a consumer reads it: py-opw-kinematics' robot (radians) and our B and T."""
    f = yaml.safe_load(text)
    model = KinematicModel(
        **f["opw_kinematics_geometric_parameters"],
        offsets=tuple(f["opw_kinematics_joint_offsets"]),
        flip_axes=tuple(s == -1 for s in f["opw_kinematics_joint_sign_corrections"]),
    )
    blocks = [f[k] for k in ("urdf2dh_base_transform", "urdf2dh_tool_transform")]
    base, tool = (from_rpy(tuple(b["xyz"]), tuple(b["rpy"])) for b in blocks)
    return Robot(model, degrees=False), base, tool


def consumer_fk(robot: Robot, base, tool, q) -> np.ndarray:
    """Poses ``B . F(q) . T`` (N, 4, 4) in metres. (py-opw-kinematics 1.3's ``ee_transform``
    reads a 4x4 ``[R, t]`` as ``F . Rot(R) . Trans(t)``, not as the product ``F . [R, t]``; so T
    is applied here as the file says.)"""
    return base @ robot.batch_forward(q).as_matrix() @ tool


def ik_misses(robot: Robot, base, tool, poses, q) -> float:
    """The worst over configurations of the nearest IK solution's distance (max over joints,
    mod 2 pi) from the configuration the pose came from."""
    worst = 0.0
    for pose, row in zip(poses, q, strict=True):
        target = RigidTransform.from_matrix(inv(base) @ pose @ inv(tool))
        sols = np.array(robot.inverse(target)).reshape(-1, 6)
        diff = np.abs(np.remainder(sols - row + np.pi, 2 * np.pi) - np.pi).max(axis=1)
        worst = max(worst, float(diff.min()) if len(diff) else math.inf)
    return worst


def declared(text: str) -> tuple[float, float]:
    """The FK deviation the file declares (metres, radians), 0 for an exact file."""
    m = re.search(r"caused by these judgements: (\S+) (\S+), (\S+) rad", text)
    if m is None:
        return 0.0, 0.0
    return float(m[1]) * length_factor(m[2].rstrip(","), "m"), float(m[3])


@pytest.mark.parametrize("robot", OPW_ROBOTS)
def test_consumer_fk_and_ik_match_pinocchio(robot):
    source = open_source(robot)
    model = source.model()
    q, reference = pin_reference(source, model, samples=200, seed=31)
    metres = length_factor(model.length_unit, "m")
    reference[:, :3, 3] *= metres
    size = model.size() * metres
    text = export(model, "opw")
    opw, base, tool = consumer(text)
    pos, rot = declared(text)
    assert (pos > 0) == (robot == "kinova")
    err = assert_fk_matches(
        f"py-opw-kinematics {robot}",
        consumer_fk(opw, base, tool, q),
        reference,
        size,
        q,
        rel=EXACT + 1.5 * pos / size,
        rot=EXACT + 1.5 * rot,
    )
    miss = ik_misses(opw, base, tool, reference, q)
    report("opw", f"py-opw-kinematics {metadata_version('py-opw-kinematics')}", err, size)
    assert miss <= IK_ANGLE, f"{robot}: IK misses a sampled configuration by {miss:.3g} rad"


def test_every_bundled_robot_qualifies_or_is_refused_with_its_reason():
    assert sorted(OPW_ROBOTS + list(REFUSED)) == sorted(ROBOTS)
    for robot, reason in REFUSED.items():
        with pytest.raises(ExportError, match=re.escape(reason)):
            export(load(robot), "opw")


PUBLISHED = {
    # opw_kinematics' makeKukaKR6_R700_sixx and the MoveIt OPW plugin's documentation
    "kuka-kr6-r700-sixx": ((0.025, -0.035, 0.0, 0.400, 0.315, 0.365, 0.080),
                           (0, -math.pi / 2, 0, 0, 0, 0), (-1, 1, 1, -1, 1, -1)),
    # ROS-Industrial fanuc_m20ia_support/config/opw_parameters_m20ia.yaml
    "fanuc-m20ia": ((0.15, -0.25, 0.0, 0.525, 0.79, 0.835, 0.10),
                    (0, 0, -math.pi / 2, 0, 0, math.pi), (1, 1, -1, -1, -1, -1)),
}  # fmt: skip


@pytest.mark.parametrize("robot", sorted(PUBLISHED))
def test_our_kuka_and_fanuc_give_the_published_parameters(robot):
    f = yaml.safe_load(export(load(robot), "opw"))
    geometry, offsets, signs = PUBLISHED[robot]
    got = f["opw_kinematics_geometric_parameters"]
    assert list(got) == ["a1", "a2", "b", "c1", "c2", "c3", "c4"]
    np.testing.assert_allclose(list(got.values()), geometry, rtol=0, atol=1e-15)
    turns = np.remainder(np.array(f["opw_kinematics_joint_offsets"]) - offsets + 1, 2 * math.pi)
    np.testing.assert_allclose(turns, 1.0, rtol=0, atol=1e-14)
    assert f["opw_kinematics_joint_sign_corrections"] == list(signs)
    for block in ("urdf2dh_base_transform", "urdf2dh_tool_transform"):
        assert f[block] == {"xyz": [0.0] * 3, "rpy": [0.0] * 3}


def test_the_consumers_ee_transform_is_rotation_then_translation():
    """What docs/exports/opw.md warns of: py-opw-kinematics' ``ee_transform`` [R, t] is
    F . [R, R t]."""
    robot = Robot(KinematicModel(0.1, -0.135, 0.05, 0.615, 0.705, 0.755, 0.085), degrees=False)
    q = np.array([[0.1, 0.2, 0.3, 0.4, 0.5, 0.6]])
    tool = trans(0.1, 0.2, 0.3) @ rot_x(0.3) @ rot_z(0.2)
    flange = robot.batch_forward(q).as_matrix()[0]
    got = robot.batch_forward(q, ee_transform=RigidTransform.from_matrix(tool)).as_matrix()[0]
    rotated = tool.copy()
    rotated[:3, 3] = tool[:3, :3] @ tool[:3, 3]
    np.testing.assert_allclose(got, flange @ rotated, atol=1e-14)
    assert np.abs(got - flange @ tool).max() > 0.01


def test_our_opw_fk_is_the_consumers():
    rng = np.random.default_rng(8)
    for _ in range(5):
        g = rng.uniform(-1, 1, 7)
        p = OpwParameters(*g, offsets=(0.0,) * 6, signs=(1,) * 6, base=np.eye(4), tool=np.eye(4))
        theta = rng.uniform(-4, 4, (50, 6))
        robot = Robot(KinematicModel(*g), degrees=False)
        np.testing.assert_allclose(
            opw_fk(p, theta), robot.batch_forward(theta).as_matrix(), rtol=0, atol=1e-14
        )


# --------------------------------------------------------------------------- the same arm, redrawn


def _moved(model: PoeModel, q0, signs, g, h) -> PoeModel:
    """The same arm with its base frame moved (``g``), its tip frame moved (``h``), its zero at
    ``q0`` of the original and joint ``i`` counted the other way where ``signs[i] = -1``:
    pose'(q) = g . pose(q0 + signs q) . h."""
    from urdf2dh.geometry.se3 import twist_exp

    joints, e = [], np.eye(4)
    for j, q_start, s in zip(model.joints, q0, signs, strict=True):
        moved = g @ e
        lo, hi = j.lower - q_start, j.upper - q_start
        joints.append(
            Joint(
                j.name,
                "revolute",
                s * (moved[:3, :3] @ j.axis),
                moved[:3, :3] @ j.point + moved[:3, 3],
                lower=lo if s > 0 else -hi,
                upper=hi if s > 0 else -lo,
            )
        )
        e = e @ twist_exp(j.twist(), q_start)
    return PoeModel(
        tuple(joints),
        g @ model.fk(np.asarray(q0)) @ h,
        model.name + "-moved",
        "moved",
        "base_link",
        "tool0",
    )


def _rigid(rng) -> np.ndarray:
    a, b, c = rng.uniform(-np.pi, np.pi, 3)
    return trans(*rng.uniform(-0.5, 0.5, 3)) @ rot_z(a) @ rot_y(b) @ rot_x(c)


@pytest.mark.parametrize("robot", ["kuka-kr6-r700-sixx", "fanuc-m20ia"])
@pytest.mark.parametrize("seed", range(4))
def test_any_base_tool_zero_and_signs_give_a_file_the_consumer_follows(robot, seed):
    """The parameters come from the geometry, whatever frames and conventions describe it: the
    moved arm's file moves as the original arm does, its intrinsic lengths unchanged."""
    original = load(robot)
    rng = np.random.default_rng(seed)
    lim = original.limits()
    q0 = rng.uniform(lim[:, 0], lim[:, 1])
    signs = rng.choice([-1, 1], 6)
    g, h = (_rigid(rng), _rigid(rng)) if seed else (np.eye(4), _rigid(rng))
    model = _moved(original, q0, signs, g, h)
    q = model.sample(100, seed)
    reference = g @ original.fk(q0 + signs * q) @ h
    np.testing.assert_allclose(model.fk(q), reference, rtol=0, atol=1e-13)  # the redrawing
    text = export(model, "opw")
    opw, base, tool = consumer(text)
    size = model.size()
    assert_fk_matches(
        f"{robot} moved ({seed})", consumer_fk(opw, base, tool, q), reference, size, q
    )
    assert ik_misses(opw, base, tool, reference, q) <= IK_ANGLE
    first = opw_from_poe(original).geometry()
    again = opw_from_poe(model).geometry()
    # intrinsic to the arm: a1, c2, c3, and a2, b up to the mirror image that OPW's z (towards
    # the base z) picks; c1 and c4 say where B and T sit
    for k in ("a1", "c2", "c3", "a2", "b"):
        same = again[k] if k in ("a1", "c2", "c3") or seed == 0 else abs(again[k])
        want = first[k] if k in ("a1", "c2", "c3") or seed == 0 else abs(first[k])
        assert abs(same - want) <= EXACT * size, (k, again[k], first[k])
    if seed == 0:  # the base frame unmoved: B is the identity (its zero turn in offset 1)
        np.testing.assert_allclose(opw_from_poe(model).base, np.eye(4), atol=1e-15)


# --------------------------------------------------------------------------- refusals, judgements


def _with(model: PoeModel, i: int, axis=None, point=None, scale=1.0) -> PoeModel:
    j = model.joints[i]
    new = Joint(
        j.name,
        j.kind,
        j.axis if axis is None else axis,
        j.point if point is None else point,
        scale=scale,
        lower=j.lower,
        upper=j.upper,
    )
    return replace(model, joints=(*model.joints[:i], new, *model.joints[i + 1 :]))


def _turned(model: PoeModel, i: int, about, angle: float, through=None) -> PoeModel:
    """Axis ``i`` turned by ``angle`` about direction ``about`` through ``through`` (its own
    point by default)."""
    from urdf2dh.geometry.se3 import rot_axis

    r = rot_axis(np.asarray(about, float), angle)[:3, :3]
    j = model.joints[i]
    centre = j.point if through is None else np.asarray(through, float)
    return _with(model, i, axis=r @ j.axis, point=centre + r @ (j.point - centre))


def _kuka() -> PoeModel:
    return load("kuka-kr6-r700-sixx")


def _broken_3_4() -> PoeModel:
    """KUKA redrawn with joint 4 at 1 rad at zero, then axis 4 turned about axis 5 through the
    wrist centre: still perpendicular to axis 5, no longer to axis 3."""
    model = _moved(_kuka(), [0, 0, 0, 1.0, 0, 0], [1] * 6, np.eye(4), np.eye(4))
    wrist = model.joints[3].point + 0.365 * model.joints[3].axis * -1
    return _turned(model, 3, model.joints[4].axis, 0.01, through=wrist)


CONSTRUCTED = {
    "not an ortho wrist: axes 4 ('joint_a4'), 5 ('joint_a5') are not perpendicular":
        lambda: _turned(_kuka(), 4, [0, 0, 1], 0.01),
    "wrist axes do not intersect: offset wrist": lambda: _with(
        _kuka(), 5, point=_kuka().joints[5].point + np.array([0, 0.001, 0])),
    "not an ortho-parallel base: axes 1 ('joint_a1'), 2 ('joint_a2') are not perpendicular":
        lambda: _turned(_kuka(), 1, [1, 0, 0], 0.01),
    "axes 2 ('joint_a2'), 3 ('joint_a3') are not parallel":
        lambda: _turned(_kuka(), 2, [0, 0, 1], 0.01),
    "axes 3 ('joint_a3'), 4 ('joint_a4') are not perpendicular": _broken_3_4,
    "axes 2 ('joint_a2'), 3 ('joint_a3') coincide":
        lambda: _with(_kuka(), 2, point=_kuka().joints[1].point),
    "joints 'joint_a5' (scale 2) move by a multiple": lambda: _with(_kuka(), 4, scale=2.0),
}  # fmt: skip


@pytest.mark.parametrize("message", sorted(CONSTRUCTED))
def test_each_failed_condition_is_named(message):
    with pytest.raises(ExportError, match=re.escape(message)):
        export(CONSTRUCTED[message](), "opw")


def test_a_nearly_parallel_pair_is_judged_reported_and_refused_with_exact():
    model = _turned(_kuka(), 2, [0, 0, 1], 1e-6)
    text = export(model, "opw")
    assert "axes 2 ('joint_a2'), 3 ('joint_a3') are 1e-06 rad off parallel; treated as such" in text
    pos, rot = declared(text)
    assert 1e-9 < pos < 1e-5 and 1e-9 < rot < 1e-5
    q = model.sample(100, 4)
    opw, base, tool = consumer(text)
    assert_fk_matches(
        "judged",
        consumer_fk(opw, base, tool, q),
        model.fk(q),
        model.size(),
        q,
        rel=1.5 * pos / model.size(),
        rot=1.5 * rot,
    )
    with pytest.raises(ExportError, match="are not parallel"):
        export(model, "opw", opts=ExportOptions(tol=EXACT_TOL))


def test_parameters_are_validated():
    good = dict(offsets=(0.0,) * 6, signs=(1,) * 6, base=np.eye(4), tool=np.eye(4))
    with pytest.raises(ValueError, match="sign corrections must be 1 or -1"):
        OpwParameters(*[0.1] * 7, **{**good, "signs": (1, 1, 0, 1, 1, 1)})
    with pytest.raises(ValueError, match="six joint offsets"):
        OpwParameters(*[0.1] * 7, **{**good, "offsets": (0.0,) * 5})
    with pytest.raises(ValueError, match="non-finite"):
        OpwParameters(*[0.1] * 6, math.nan, **good)
    with pytest.raises(ValueError, match="4x4"):
        OpwParameters(*[0.1] * 7, **{**good, "tool": np.eye(3)})


# --------------------------------------------------------------------------- the file, the CLI


def test_names_cannot_inject_yaml(tmp_path):
    evil = 'x"\n# y\nopw_kinematics_joint_offsets: [9, 9, 9, 9, 9, 9] #\u2028c4: 7\x85z'
    urdf = (our_robots_dir() / "kuka-kr6-r700-sixx.urdf").read_text()
    xml = evil.replace("&", "&amp;").replace('"', "&quot;").replace("\n", "&#10;")
    xml = xml.replace("\u2028", "&#x2028;").replace("\x85", "&#x85;")
    urdf = urdf.replace('"joint_a3"', f'"a3{xml}"').replace('"tool0"', f'"tool0{xml}"')
    urdf = urdf.replace('name="kuka-kr6-r700-sixx"', f'name="kr6{xml}"')
    path = tmp_path / "evil.urdf"
    path.write_text(urdf)
    model = load(str(path))
    assert model.joints[2].name == "a3" + evil and model.tip_link == "tool0" + evil
    text = export(model, "opw")
    f = yaml.safe_load(text)
    assert list(f) == [
        "opw_kinematics_geometric_parameters",
        "opw_kinematics_joint_offsets",
        "opw_kinematics_joint_sign_corrections",
        "urdf2dh_base_transform",
        "urdf2dh_tool_transform",
    ]
    assert f["opw_kinematics_geometric_parameters"]["c4"] == 0.08
    assert f["opw_kinematics_joint_offsets"][0] == 0.0
    for line in text.splitlines():  # every name only in comment lines
        assert line.startswith("#") or ("kr6" not in line and "a3" not in line)
    assert (
        "'a3x\"\\n# y\\nopw_kinematics_joint_offsets: [9, 9, 9, 9, 9, 9] #\\u2028c4: 7\\x85z'"
        in text
    )


def test_the_comment_writer_escapes_what_is_not_printable():
    assert yaml_comment('a # "b": c') == '# a # "b": c'
    assert yaml_comment("a\nb\r\tc\u2028d\x85e\ufeff") == "# a\\nb\\r\\tc\\u2028d\\x85e\\ufeff"
    assert "\n" not in yaml_comment("x\n" * 3)


def test_cli_writes_the_file_and_refuses_non_opw_arms(tmp_path, capsys):
    from urdf2dh.cli import main

    out = tmp_path / "m20ia.yaml"
    assert main(["export", "fanuc-m20ia", "--to", "opw", "-o", str(out)]) == 0
    assert yaml.safe_load(out.read_text())["opw_kinematics_joint_sign_corrections"] == [
        1,
        1,
        -1,
        -1,
        -1,
        -1,
    ]
    bad = tmp_path / "ur5.yaml"
    assert main(["export", "ur5", "--to", "opw", "-o", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "wrist axes do not intersect: offset wrist" in err
    assert "Traceback" not in err and not bad.exists()
    assert main(["export", "fanuc-m20ia", "--to", "opw", "--convention", "mdh"]) == 2
    assert "export target opw is written from the POE model" in capsys.readouterr().err
    with pytest.raises(UsageError, match="takes no convention or style"):
        export(_kuka(), "opw", style="ur")


def test_a_table_exports_the_same_parameters_as_its_source():
    """``export_table(table, "opw")`` reads the table's POE model: the same arm."""
    from urdf2dh.conventions.convert import to_table
    from urdf2dh.emit.export import export_table

    model = load("fanuc-m20ia")
    want = yaml.safe_load(export(model, "opw"))
    for convention in ("dh", "cpc"):
        got = yaml.safe_load(export_table(to_table(model, convention), "opw"))
        assert got["opw_kinematics_joint_sign_corrections"] == [1, 1, -1, -1, -1, -1]
        for key in ("opw_kinematics_geometric_parameters", "opw_kinematics_joint_offsets"):
            a, b = got[key], want[key]
            values = (list(a.values()), list(b.values())) if isinstance(a, dict) else (a, b)
            np.testing.assert_allclose(*values, rtol=0, atol=1e-14)


@pytest.mark.parametrize("robot", ["kuka-kr6-r700-sixx", "fanuc-m20ia"])
@pytest.mark.parametrize("convention", ["dh", "mdh", "cpc", "hayati"])
def test_opw_files_carry_no_round_off(tmp_path, robot, convention):
    """From a table file (whose exact parameters carry round-off: 0.03500000000000003), the
    OPW file's parameters are written as the tables snap round-off, so they read as the
    published ones: the same text as from the URDF."""
    from urdf2dh.cli import main

    table = tmp_path / f"{robot}.json"
    assert (
        main(["convert", robot, "--convention", convention, "--format", "json", "-o", str(table)])
        == 0
    )
    direct = yaml.safe_load(export(load(robot), "opw"))
    via = yaml.safe_load(export(load(str(table)), "opw"))
    key = "opw_kinematics_geometric_parameters"
    assert via[key] == direct[key]
    assert all(len(repr(v)) <= 6 for v in via[key].values()), via[key]  # 0.835, -0.035
    assert via["opw_kinematics_joint_offsets"] == direct["opw_kinematics_joint_offsets"]
