"""Every export target, evaluated by its consumer (real, or exactly as documented: see
consumers.py) at seeded configurations, against Pinocchio: <= 1e-9 (relative to the robot's size,
and in radians)."""

from __future__ import annotations

import math
import re
import subprocess
import sys
from importlib.metadata import version as metadata_version
from pathlib import Path

import numpy as np
import pytest
from chains import RELATIONS, random_chain_urdf
from consumers import (
    FakeKdl,
    RigidBodyTree,
    SerialLink,
    genserkins_fk,
    genserkins_hal,
    genserkins_links,
    kdl_fk,
    real_pykdl,
    report,
)
from oracle import assert_fk_matches, pin_reference

from urdf2dh import load, units
from urdf2dh.emit.export import TARGETS, ExportOptions, export
from urdf2dh.errors import ExportError, UsageError
from urdf2dh.io.sources import Source, open_source
from urdf2dh.io.urdf import parse_tree, tree_to_poe

DATA = Path(__file__).parent / "data"
AGREE = 1e-9  # the bound: every target matches Pinocchio to this
ROBOTS = ["ur5", "panda", "kinova", "stanford", "scara", "tiago-arm", "puma560-nominal"]
PYKDL = real_pykdl()
PYKDL_VERSION = getattr(PYKDL, "__version__", "?") + " (Debian's python3-pykdl)"


def _random_source(seed: int) -> tuple[Source, object]:
    text, _ = random_chain_urdf(seed, 3 + seed % 5, scale=0.5 + seed % 3)
    tree = parse_tree(text.encode(), f"random{seed}.urdf")
    source = Source("urdf", f"random{seed}.urdf", tree.name, tree, text.encode())
    return source, tree_to_poe(tree, "base", "tool")


def _cases():
    for robot in ROBOTS:
        yield pytest.param(robot, id=robot)
    for seed in range(6):
        yield pytest.param(seed, id=f"random{seed}")


def _source(case):
    if isinstance(case, int):
        return _random_source(case)
    source = open_source(case)
    return source, source.model()


def _rtb_fk(script: str, q: np.ndarray) -> np.ndarray:
    namespace: dict = {"__name__": "generated_rtb"}
    exec(compile(script, "generated_rtb.py", "exec"), namespace)
    robot = namespace["robot"]
    return np.array([robot.fkine(row).A for row in q])


def _matlab_fk(script: str, tip: str, q: np.ndarray) -> np.ndarray:
    tree = RigidBodyTree(script)
    return np.array([tree.get_transform(row, tip) for row in q])


def _corke_fk(script: str, q: np.ndarray) -> np.ndarray:
    robot = SerialLink(script)
    return np.array([robot.fkine(row) for row in q])


@pytest.mark.parametrize("convention", ["dh", "mdh"])
@pytest.mark.parametrize("case", list(_cases()))
def test_toolbox_targets_move_like_pinocchio(case, convention):
    source, model = _source(case)
    q, reference = pin_reference(source, model, samples=40, seed=11)
    size = model.size()
    label = f"{case} {convention}"
    scripts = {t: export(model, t, convention) for t in ("rtb", "kdl", "matlab", "corke-matlab")}
    errors = assert_fk_matches(
        f"rtb {label}", _rtb_fk(scripts["rtb"], q), reference, size, q, rel=AGREE, rot=AGREE
    )
    report(
        "rtb", f"roboticstoolbox-python {metadata_version('roboticstoolbox-python')}", errors, size
    )
    assert_fk_matches(
        f"kdl (as documented) {label}",
        kdl_fk(FakeKdl, scripts["kdl"], q),
        reference,
        size,
        q,
        rel=AGREE,
        rot=AGREE,
    )
    if PYKDL is not None:
        errors = assert_fk_matches(
            f"PyKDL {label}",
            kdl_fk(PYKDL, scripts["kdl"], q),
            reference,
            size,
            q,
            rel=AGREE,
            rot=AGREE,
        )
        report("kdl", f"PyKDL {PYKDL_VERSION}", errors, size)
    tip = model.tip_link or "tool"
    assert_fk_matches(
        f"matlab {label}",
        _matlab_fk(scripts["matlab"], tip, q),
        reference,
        size,
        q,
        rel=AGREE,
        rot=AGREE,
    )
    assert_fk_matches(
        f"corke-matlab {label}",
        _corke_fk(scripts["corke-matlab"], q),
        reference,
        size,
        q,
        rel=AGREE,
        rot=AGREE,
    )


def test_the_kdl_stand_in_reads_the_documented_frames():
    """The stand-in's Frame.DH is Rz(theta) Tz(d) Rx(alpha) Tx(a) and Frame.DH_Craig1989 is
    Rx(alpha) Tx(a) Rz(theta) Tz(d) (KDL's documentation), composed here from elementary
    transforms; where PyKDL imports (Debian's python3-pykdl), the real one agrees too."""
    from urdf2dh.geometry import se3

    rng = np.random.default_rng(5)
    for a, alpha, d, theta in rng.uniform(-2, 2, (20, 4)):
        expected = {
            "DH": se3.rot_z(theta) @ se3.trans(z=d) @ se3.rot_x(alpha) @ se3.trans(x=a),
            "DH_Craig1989": se3.rot_x(alpha) @ se3.trans(x=a) @ se3.rot_z(theta) @ se3.trans(z=d),
        }
        for name, frame in expected.items():
            ours = getattr(FakeKdl.Frame, name)(a, alpha, d, theta).m
            np.testing.assert_allclose(ours[:3], frame[:3], atol=1e-14)
            if PYKDL is not None:
                real = getattr(PYKDL.Frame, name)(a, alpha, d, theta)
                got = np.array([[real.M[i, j] for j in range(3)] + [real.p[i]] for i in range(3)])
                np.testing.assert_allclose(got, frame[:3], atol=1e-14)


def test_matlab_offsets_sit_in_fixed_bodies():
    script = export(load("ur5"), "matlab")
    assert script.count('"dh");') == 6
    # setFixedTransform(..., "dh") ignores theta of revolute joints: every row passes 0 there
    assert all(
        line.rstrip().endswith('0], "dh");')
        for line in script.splitlines()
        if line.endswith('"dh");')
    )
    assert 'rigidBody("body1_offset")' in script  # UR5 (Wu style) has theta_1 = pi
    mdh = export(load("stanford"), "matlab", "mdh")
    lines = mdh.splitlines()
    joint3 = lines.index('joint = rigidBodyJoint("joint3", "prismatic");')
    assert lines[joint3 + 2].startswith("setFixedTransform(joint, [") and " 0 " in lines[joint3 + 2]


def test_rtb_script_runs_standalone(tmp_path):
    script = tmp_path / "ur5_rtb.py"
    script.write_text(export(load("ur5"), "rtb", style="ur"))
    proc = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=300
    )
    assert proc.returncode == 0, proc.stderr
    assert "DHRobot: ur5, 6 joints (RRRRRR), standard DH" in proc.stdout
    # what it prints shows no round-off: right angles as 90.0 degrees, and the URDF's pi/2
    # written 1.57079632679 (4.9e-12 rad off) not as 2.8e-10 degrees, nor in the pose
    assert "90.0°" in proc.stdout and "-90.0°" in proc.stdout
    assert re.search(r"\d\.\d{5,}°|e-\d+", proc.stdout) is None, proc.stdout
    assert "alpha=pi/2" in script.read_text()  # exact, as Python reads it


# --------------------------------------------------------------------------- linuxcnc


def _genser_check(text: str, source: Source, model, metres: float) -> tuple[float, float]:
    """The file read back as halcmd reads it and evaluated as genserkins and HAL's scale
    document (consumers.py), against Pinocchio; the command path gives the drives' positions
    back."""
    hal = genserkins_hal(text)
    q, reference = pin_reference(source, model, samples=60, seed=2)
    q_deg = np.degrees(np.pad(q, ((0, 0), (0, 6 - model.n))))
    angles = hal.angles(q_deg)
    np.testing.assert_allclose(hal.commands(angles), q_deg, rtol=0, atol=1e-12)
    reported = np.array([genserkins_fk(hal.links, row) for row in angles])
    poses = hal.tip_poses(reported, metres)
    return assert_fk_matches("genserkins", poses, reference, model.size(), q, rel=AGREE, rot=AGREE)


@pytest.mark.parametrize(("units", "metres"), [(None, 0.001), ("mm", 0.001), ("inch", 0.0254)])
def test_genserkins_parameters_move_like_pinocchio(units, metres):
    source = open_source(str(DATA / "genser6.urdf"))
    model = source.model()
    text = export(model, "linuxcnc", opts=ExportOptions(units=units))
    links = genserkins_links(text)
    assert math.isclose(links[0][2] * metres, 0.6, rel_tol=1e-12)  # pedestal 0.25 + 0.35
    assert math.isclose(links[5][2] * metres, 0.1, rel_tol=1e-12)  # tool length in D-5
    assert "loadrt" not in text  # zero offsets: genserkins' joints are the arm's
    _genser_check(text, source, model, metres)


def test_genserkins_pads_short_chains_with_zero_links():
    source = open_source(str(DATA / "genser6.urdf"))
    model = source.model(tip="link4")
    text = export(model, "linuxcnc")
    assert genserkins_links(text)[4:] == [(0.0, 0.0, 0.0), (0.0, 0.0, 0.0)]
    assert "# joint 5: none" in text
    _genser_check(text, source, model, 0.001)


GENSER_ROBOTS = [
    "ur3", "ur5", "ur10", "kuka-kr6-r700-sixx", "fanuc-m20ia", "puma560-nominal", "kinova", "z1",
    "double-pendulum",
]  # fmt: skip


def genser_cases():
    """Bundled arms genserkins takes, and random 6R chains (skew, parallel, intersecting...
    axes, their tips on the last axis)."""
    for robot in GENSER_ROBOTS:
        source = open_source(robot)
        yield robot, source, source.model()
    revolute = tuple(r for r in RELATIONS if r != "prismatic")
    for seed in range(6):
        text, _ = random_chain_urdf(seed, 6, revolute, tool=False)
        tree = parse_tree(text.encode(), f"random6r{seed}.urdf")
        source = Source("urdf", f"random6r{seed}.urdf", tree.name, tree, text.encode())
        yield f"random6r{seed}", source, tree_to_poe(tree, "base", "link6")


@pytest.mark.parametrize("case", list(genser_cases()), ids=lambda case: case[0])
def test_genserkins_takes_arms_with_joint_zeros(case):
    """Theta offsets, a base turned about joint 1, a tip turned about or against the last axis
    are written for genserkins (scale components, folded links), and what it cannot hold is
    stated in the file; the file moves like the source."""
    _, source, model = case
    text = export(model, "linuxcnc")
    _genser_check(text, source, model, units.factor("mm", model.length_unit))


def test_genserkins_reverses_a_last_joint_whose_tip_faces_against_it():
    """KUKA's and FANUC's flanges face against joint 6's axis: joint 5 turns the other way
    (gain -1 both ways), joint 2's (FANUC: 1's) zero is 90 degrees from the D-H zero."""
    kuka = genserkins_hal(export(load("kuka-kr6-r700-sixx"), "linuxcnc"))
    assert kuka.feedback == {2: (1.0, 90.0), 5: (-1.0, 0.0)}
    assert kuka.command == {2: (1.0, -90.0), 5: (-1.0, 0.0)}
    fanuc = genserkins_hal(export(load("fanuc-m20ia"), "linuxcnc"))
    assert fanuc.feedback == {1: (1.0, 90.0), 5: (-1.0, 180.0)}
    ur5 = export(load("ur5"), "linuxcnc")
    assert genserkins_hal(ur5).feedback[5] == (1.0, 180.0)  # tool0's half turn about joint 6
    assert "# joint 5: wrist_3_joint, genserkins angle q + 180.0 deg, limits -180 .. 540" in ur5


def test_genserkins_states_the_frames_it_cannot_hold():
    text = export(load("so100"), "linuxcnc")
    assert "pose in base = Rz(90.0 deg) Tz(0.0 mm) . pose LinuxCNC reports." in text
    assert "pose of gripper = pose LinuxCNC reports . Rx(90.0 deg) Rz(0.0 deg)." in text
    turned = _turn_tool(load(str(DATA / "genser6.urdf"), tip="link5"))
    assert "pose of link5 = pose LinuxCNC reports . Rx(90.0 deg) Rz(0.0 deg)." in export(
        turned, "linuxcnc"
    )


@pytest.mark.parametrize(
    ("robot", "message"),
    [
        ("finger-edu", "the tip 'finger_tip_link' lies 0.16 m off the last joint's axis"),
        ("twodof", "the tip 'Tip' lies 0.122 m off the last joint's axis"),
        ("panda", "evaluates 6 joints, and this chain has 7"),
        ("stanford", "linuxcnc has revolute joints only"),
        ("puma560-actual", "linuxcnc has revolute joints only"),
    ],
)
def test_genserkins_refuses_what_it_cannot_carry(robot, message):
    with pytest.raises(ExportError, match=message):
        export(load(robot), "linuxcnc")


def _turn_tool(model):
    """The same chain with its tool turned 90 degrees about x (its origin stays on the axis)."""
    from dataclasses import replace

    from urdf2dh.geometry.se3 import rot_x

    return replace(model, home=model.home @ rot_x(math.pi / 2))


# --------------------------------------------------------------------------- refusals, CLI


LIMITS = """<robot name="turns"><link name="a"/><link name="b"/><link name="c"/>
<joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
<limit lower="-12.566370614359172" upper="12.566370614359172" effort="1" velocity="1"/></joint>
<joint name="j2" type="revolute"><parent link="b"/><child link="c"/><origin xyz="0.3 0 0"/>
<axis xyz="0 0 1"/><limit lower="-6.283185307179586" upper="3.141592653589793" effort="1"
velocity="1"/></joint></robot>"""


def test_joint_limits_that_are_whole_turns_are_written_as_they_are(tmp_path):
    """A limit of exactly 4 pi is not an angle to wrap into [-pi, pi] (which made it 0)."""
    path = tmp_path / "turns.urdf"
    path.write_text(LIMITS)
    model = load(str(path))
    script = export(model, "rtb")
    assert "qlim=[-12.5663706143592, 12.5663706143592]" in script
    assert "qlim=[-6.28318530717959, 3.14159265358979]" in script
    assert "'qlim', [-12.5663706143592 12.5663706143592]" in export(model, "corke-matlab")
    assert "PositionLimits = [-6.28318530717959 3.14159265358979]" in export(model, "matlab")


@pytest.mark.parametrize("target", sorted(TARGETS))
def test_helical_joints_are_refused_by_every_target(target):
    with pytest.raises(ExportError, match="helical"):
        export(load("puma560-actual"), target, opts=ExportOptions())


def test_targets_refuse_other_conventions_and_styles():
    model = load("ur5")
    refusal = (
        r"linuxcnc takes mdh tables, not dh \(row 'shoulder_pan_joint' is a D-H row: "
        r"theta, d, alpha, a\)$"
    )
    with pytest.raises(UsageError, match=refusal):
        export(model, "linuxcnc", "dh")
    with pytest.raises(UsageError, match="unknown export target 'vrml'"):
        export(model, "vrml")


def test_cli_names_every_target_and_convention(capsys):
    """The command line's choices come from the registries themselves."""
    from urdf2dh.cli import main
    from urdf2dh.conventions import NAMES

    with pytest.raises(SystemExit):
        main(["export", "ur5", "--to", "vrml"])
    err = capsys.readouterr().err
    assert all(repr(name) in err for name in TARGETS), err
    with pytest.raises(SystemExit):
        main(["convert", "ur5", "--convention", "xyz"])
    err = capsys.readouterr().err
    assert all(repr(name) in err for name in NAMES), err


def test_cli_export_writes_the_file_and_refusals_leave_none(tmp_path, capsys):
    from urdf2dh.cli import main

    target = tmp_path / "ur10.yaml"
    assert main(["export", "ur10", "--to", "ur", "-o", str(target)]) == 0
    assert target.read_text().rstrip().endswith("hash: calib_17227329492635474227")
    hal = tmp_path / "twodof.hal"
    assert main(["export", "twodof", "--to", "linuxcnc", "-o", str(hal)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "lies 0.122 m off the last joint's axis" in err
    assert "Traceback" not in err and not hal.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ur10.yaml"]
    assert main(["export", "ur5", "--to", "rtb", "--units", "inch"]) == 2
    assert "--units applies to --to linuxcnc" in capsys.readouterr().err
    assert main(["export", "panda", "--to", "kdl", "--convention", "mdh"]) == 0
    assert "kdl.Frame.DH_Craig1989(" in capsys.readouterr().out


def test_help_imports_no_heavy_optional_package():
    code = (
        "import sys\n"
        "from urdf2dh.cli import main\n"
        "for argv in (['--help'], ['export', '--help'], ['plot', '--help']):\n"
        "    try:\n"
        "        main(argv)\n"
        "    except SystemExit:\n"
        "        pass\n"
        "heavy = {'yourdfpy', 'pinocchio', 'matplotlib', 'roboticstoolbox', 'xacro', 'PyKDL'}\n"
        "print(sorted(heavy & {m.split('.')[0] for m in sys.modules}))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip().splitlines()[-1] == "[]"


def test_the_linuxcnc_header_names_the_unit_of_its_values():
    """The file's first lines say the unit its A and D values are in (not the source's, m)."""
    model = load("tests/data/genser6.urdf")
    values = {}
    for unit in ("mm", "inch"):
        text = export(model, "linuxcnc", opts=ExportOptions(units=unit))
        assert f"# Lengths in {unit} unless stated, angles in radians." in text.splitlines()[:4]
        lines = [line for line in text.splitlines() if line.startswith("setp genserkins.")]
        values[unit] = np.array([float(line.split()[-1]) for line in lines if "ALPHA" not in line])
    assert model.length_unit == "m" and np.abs(values["mm"]).max() > 100.0  # mm, not m
    assert np.allclose(values["mm"], 25.4 * values["inch"], rtol=1e-12, atol=1e-9)


# --------------------------------------------------------------------------- exact multiples of pi

EXACT = {"0.0": 0.0, "pi/2": math.pi / 2, "-pi/2": -math.pi / 2, "pi": math.pi, "-pi": -math.pi}


def _kdl_angles(script: str) -> list[str]:
    """Each ``Frame.DH``/``DH_Craig1989`` call's alpha and theta text, as the script writes them."""
    calls = re.findall(r"Frame\.DH(?:_Craig1989)?\(([^()]*)\)", script)
    return [text for args in calls for text in args.split(", ")[1::2]]


def _matlab_angles(script: str, target: str) -> list[str]:
    """A MATLAB script's D-H angles (alpha of ``setFixedTransform``'s ``[a alpha d theta]``;
    ``'alpha'``, ``'offset'`` of a revolute ``Link``) as it writes them."""
    if target == "matlab":
        rows = re.findall(r'setFixedTransform\(joint, \[(\S+ \S+ \S+ \S+)\], "m?dh"\)', script)
        return [row.split(" ")[1] for row in rows]
    links = re.findall(r"'alpha', ([^,]+), 'offset', ([^,]+),", script)
    return [text for link in links for text in link]


@pytest.mark.parametrize("convention", ["dh", "mdh"])
@pytest.mark.parametrize("target", ["matlab", "corke-matlab", "kdl"])
def test_matlab_and_kdl_write_exact_multiples_of_pi_as_pi(target, convention):
    """PUMA 560's right angles are written ``pi/2``, ``-pi/2``, ``pi`` (as the rtb target writes
    them), and read back, as MATLAB and Python read them, as exactly the table's angles."""
    from matlab_reader import Call, read_matlab

    from urdf2dh import to_table
    from urdf2dh.conventions.base import written_angle
    from urdf2dh.tolerances import DEFAULT

    model = load("puma560-nominal")
    table = to_table(model, convention)
    script = export(model, target, convention)
    written = _kdl_angles(script) if target == "kdl" else _matlab_angles(script, target)
    assert "pi/2" in written and set(written) <= set(EXACT), written
    assert "1.5707963267949" not in script and "3.14159265358979" not in script
    keys = ("alpha",) if target == "matlab" else ("alpha", "theta")
    records = [r.params for r in table.rows]
    records += [table.base, table.tool] if target == "kdl" else []
    params = [p.scalars().get(k, 0.0) for p in records for k in keys]
    exact = [a for a in (written_angle(p, DEFAULT.written) for p in params) if a != 0.0]
    assert sorted(EXACT[w] for w in written if w != "0.0") == sorted(exact)
    if target == "kdl":  # Python reads it: the chain's frames are the table's exactly
        assert "from math import pi" in script
        compile(script, "kdl.py", "exec")
        return
    statements = read_matlab(script).statements  # MATLAB reads it
    if target == "matlab":  # theta = pi of joints 4 and 5 in fixed bodies: Rz(pi) exactly
        fixed = [
            s.value.args[1]
            for s in statements
            if isinstance(s.value, Call)
            and s.value.name == "setFixedTransform"
            and len(s.value.args) == 2
        ]
        turned = [m for m in fixed if m[0, 0] == -1.0]
        assert len(turned) == 2 and all(m[0, 1] == 0.0 and m[1, 0] == 0.0 for m in turned)


def test_angles_off_a_multiple_of_pi_stay_numbers():
    """Only a multiple of pi/2 (up to the files' round-off) is written as ``pi``: a tilted twist
    is a number with every digit it has, in every target that writes ``pi``."""
    from urdf2dh.emit.export.common import Numbers
    from urdf2dh.tolerances import DEFAULT

    numbers = Numbers(1.0, DEFAULT.written)
    assert numbers.pi_ang(math.pi / 2) == "pi/2" and numbers.pi_ang(-math.pi) == "pi"
    assert numbers.pi_ang(math.pi / 2 + 4e-16) == "pi/2"  # round-off (DEFAULT.written: 8.9e-16)
    for x in (math.pi / 2 + 1e-3, 0.3, math.pi / 4, 4.896650092486704e-12, -2.9):
        assert float(numbers.pi_ang(x)) == x
