"""URDF input at the edges: urdfdom's number grammar, axes normalised as urdfdom and
Pinocchio do or refused, magnitudes that would overflow refused, and the encodings and XML
declarations that Pinocchio and yourdfpy read, read. Pinocchio is the oracle throughout: what we
refuse for the grammar, it refuses; what we read, it reads the same way (``verify`` exits 0)."""

from __future__ import annotations

import math
import warnings

import pinocchio as pin
import pytest

from urdf2dh.cli import main
from urdf2dh.errors import InputError
from urdf2dh.io.urdf import parse_tree, tree_to_poe
from urdf2dh.io.urdf.validate import numbers
from urdf2dh.tolerances import LARGEST_URDF_NUMBER as LARGEST

LIMIT = 'lower="-1" upper="1" effort="1" velocity="1"'


def arm(
    origin: str = 'xyz="0.1 0 0.2" rpy="0 0.3 0"',
    axis: str = 'xyz="0 0 1"',
    limit: str = LIMIT,
    jtype: str = "revolute",
    mimic: str | None = None,
    name: str = "r",
) -> str:
    """A 3-joint arm base -> l1 -> l2 -> l3 -> tool whose second joint 'j' carries the given
    attributes; with ``mimic``, a fourth joint 'm' (prismatic, after 'j') mimics 'j'."""
    axis_el = "" if axis is None else f"<axis {axis}/>"
    links = "".join(f'<link name="{n}"/>' for n in ("base", "l1", "l2", "l3", "tool"))
    mimic_joint = (
        ""
        if mimic is None
        else (
            '<link name="l4"/><joint name="m" type="prismatic"><parent link="l3"/>'
            f'<child link="l4"/><axis xyz="0 1 0"/><limit {LIMIT}/>'
            f'<mimic joint="j" {mimic}/></joint>'
        )
    )
    return (
        f'<robot name="{name}">{links}'
        '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>'
        f'<origin xyz="0 0 0.3"/><axis xyz="0 0 1"/><limit {LIMIT}/></joint>'
        f'<joint name="j" type="{jtype}"><parent link="l1"/><child link="l2"/>'
        f"<origin {origin}/>{axis_el}<limit {limit}/></joint>"
        '<joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>'
        f'<origin xyz="0.4 0.1 0" rpy="0.2 0 0"/><axis xyz="0 1 0"/><limit {LIMIT}/></joint>'
        '<joint name="flange" type="fixed"><parent link="l3"/><child link="tool"/>'
        f'<origin xyz="0 0 0.1"/></joint>{mimic_joint}</robot>'
    )


def run(capsys, tmp_path, data: str | bytes, command: str = "convert") -> tuple[int, str]:
    """``urdf2dh COMMAND file --tip tool`` in-process: exit code and stderr (numpy warnings
    turned into errors, so that none can pass unseen)."""
    path = tmp_path / "in.urdf"
    path.write_bytes(data.encode() if isinstance(data, str) else data)
    argv = [command, str(path), "--tip", "tool"]
    argv += ["-o", str(tmp_path / "out.json")] if command == "convert" else ["--samples", "200"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code = main(argv)
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err + captured.out and "Warning" not in captured.err
    return code, captured.err


def assert_refused(code: int, err: str, tmp_path, *fragments: str) -> None:
    assert code == 2, err
    assert err.startswith("urdf2dh: error: ") and err.count("\n") == 1, err
    assert str(tmp_path / "in.urdf") in err, err
    for fragment in fragments:
        assert fragment in err, (fragment, err)
    assert not (tmp_path / "out.json").exists()


def pinocchio_refuses(text: str) -> bool:
    try:
        pin.buildModelFromXML(text)
    except (RuntimeError, ValueError):
        return True
    return False


# (attribute as the message names it, arm(...) keyword, template with {} for the bad value)
SLOTS = [
    ("origin xyz", "origin", 'xyz="0.1 {} 0.2"'),
    ("origin rpy", "origin", 'rpy="0 {} 0"'),
    ("axis xyz", "axis", 'xyz="0 {} 1"'),
    ("limit lower", "limit", 'lower="{}" upper="1" effort="1" velocity="1"'),
    ("limit upper", "limit", 'lower="-1" upper="{}" effort="1" velocity="1"'),
    ("limit effort", "limit", 'lower="-1" upper="1" effort="{}" velocity="1"'),
    ("limit velocity", "limit", 'lower="-1" upper="1" effort="1" velocity="{}"'),
    ("mimic multiplier", "mimic", 'multiplier="{}"'),
    ("mimic offset", "mimic", 'offset="{}"'),
]
# values urdfdom's strToDouble refuses, and what our message says of them
BAD = [
    ("1_0", "is not"),
    ("0x10", "is not"),
    ("0x1p3", "is not"),
    ("nan", "not finite"),
    ("inf", "not finite"),
    ("-Infinity", "not finite"),
    ("1e999", "not finite"),
    ("1e", "is not"),
    ("1d0", "is not"),
    ("1,5", "is not"),
    ("one", "is not"),
    ("\u0661", "is not"),
    ("1 2", "is not"),
    ("", "is not"),
]


@pytest.mark.parametrize("what, slot, template", SLOTS, ids=[s[0] for s in SLOTS])
@pytest.mark.parametrize("value, says", BAD, ids=[repr(b[0]) for b in BAD])
def test_number_grammar_refuses_what_urdfdom_refuses(
    what, slot, template, value, says, capsys, tmp_path
):
    assert not pinocchio_refuses(arm(**{slot: template.format("0.5")}))  # the same, sound
    text = arm(**{slot: template.format(value)})
    assert pinocchio_refuses(text), text
    code, err = run(capsys, tmp_path, text)
    joint = "joint 'm'" if slot == "mimic" else "joint 'j'"
    assert_refused(code, err, tmp_path, joint, what, says)


@pytest.mark.parametrize("value", [".5", "5.", "+0.5", "-.5e-1", "1E+0", "00.25", "-0"])
def test_number_grammar_reads_what_urdfdom_reads(value, capsys, tmp_path):
    text = arm(origin=f'xyz="  {value}  0 0.2 " rpy="0 {value} 0"')
    assert not pinocchio_refuses(text)
    assert run(capsys, tmp_path, text, "verify")[0] == 0


@pytest.mark.parametrize(
    "slot, value",
    [
        ("limit", 'lower=" -1" upper="1" effort="1" velocity="1"'),
        ("limit", 'lower="-1 " upper="1" effort="1" velocity="1"'),
        ("limit", 'lower="&#9;-1" upper="1" effort="1" velocity="1"'),
        ("origin", 'xyz="&#9;0.1 0 0.2"'),
        ("origin", 'xyz="0.1 0 0.2&#9;"'),
        ("origin", 'xyz="0.1 &#10;0 0.2"'),
        ("origin", 'xyz="  0.1   0 0.2  "'),
        ("mimic", 'multiplier="2 "'),
        ("mimic", 'offset="  0"'),
    ],
)
def test_white_space_is_read_as_urdfdom_reads_it(slot, value, capsys, tmp_path):
    """strToDouble skips white space before a number and refuses any after it; a vector is
    split at spaces first."""
    text = arm(**{slot: value})
    refused = pinocchio_refuses(text)
    code, err = run(capsys, tmp_path, text)
    assert code == (2 if refused else 0), (refused, err)


def test_numbers_directly():
    assert numbers("1 -2.5e-3  .5", 3, "xyz", "f") == [1.0, -2.5e-3, 0.5]
    assert numbers("1e300", 1, "v", "f", None) == [1e300]
    with pytest.raises(InputError, match=r"f: v '1e300' is out of range \('1e300' is beyond"):
        numbers("1e300", 1, "v", "f")
    with pytest.raises(InputError, match="it holds 4"):
        numbers("0 0 1 4", 3, "xyz", "f")


# axes whose squared length is not a normal float64: urdfdom and Pinocchio do not normalise
# them (they stay tiny, or become zero); the table would disagree with Pinocchio
DEGENERATE_AXES = [
    ("1e-300 0 0", "too short"),
    ("5e-324 0 0", "too short"),
    ("1e-160 1e-160 0", "too short"),
    ("1e308 1e308 0", "too long"),
    ("1e200 0 0", "too long"),
    ("0 0 0", "zero axis"),
    ("-0 0 0", "zero axis"),
]


@pytest.mark.parametrize("xyz, says", DEGENERATE_AXES)
def test_axes_urdfdom_cannot_normalise_are_refused(xyz, says, capsys, tmp_path):
    text = arm(axis=f'xyz="{xyz}"')
    model = pin.buildModelFromXML(text)  # Pinocchio loads it, but not as a unit axis
    axis = model.joints[model.getJointId("j")].extract().axis
    assert abs(math.hypot(*axis) - 1.0) > 1e-6, axis
    code, err = run(capsys, tmp_path, text)
    assert_refused(code, err, tmp_path, "joint 'j'", f"axis xyz '{xyz}'", says)


def test_axis_without_xyz_is_refused(capsys, tmp_path):
    text = arm(axis="")  # <axis/>: urdfdom reads a zero axis, yourdfpy 1 0 0
    model = pin.buildModelFromXML(text)
    assert list(model.joints[model.getJointId("j")].extract().axis) == [0.0, 0.0, 0.0]
    code, err = run(capsys, tmp_path, text)
    assert_refused(code, err, tmp_path, "joint 'j'", "<axis> has no xyz")


@pytest.mark.parametrize(
    "xyz",
    [
        "0 2 0",
        "3 4 0",
        "1e-150 0 0",
        "1e150 1e150 0",
        "1e-300 1 0",
        "5e-324 0 -7",
        "-1e-100 -1e-100 -1e-100",
    ],
)
def test_unusual_axes_that_normalise_agree_with_pinocchio(xyz, capsys, tmp_path):
    for jtype in ("revolute", "prismatic"):
        text = arm(axis=f'xyz="{xyz}"', jtype=jtype)
        model = tree_to_poe(parse_tree(text.encode(), "a.urdf"), tip="tool")
        assert abs(math.hypot(*model.joints[1].axis) - 1.0) < 1e-15
        assert run(capsys, tmp_path, text, "verify")[0] == 0


def test_missing_axis_is_x_for_both(capsys, tmp_path):
    assert run(capsys, tmp_path, arm(axis=None), "verify")[0] == 0


@pytest.mark.parametrize(
    "slot, value, what",
    [
        ("origin", 'xyz="1e308 0 0"', "origin xyz"),
        ("origin", 'xyz="0 0 -1e60"', "origin xyz"),
        ("limit", 'lower="-1e308" upper="1e308" effort="1" velocity="1"', "limit lower"),
        ("limit", 'lower="-1" upper="1e51" effort="1" velocity="1"', "limit upper"),
        ("mimic", 'multiplier="1e308"', "mimic multiplier"),
        ("mimic", 'offset="-1e300"', "mimic offset"),
    ],
)
def test_magnitudes_that_would_overflow_are_input_errors(slot, value, what, capsys, tmp_path):
    """Pinocchio reads these; we refuse them with one line, not an overflow or numpy warning."""
    text = arm(**{slot: value})
    assert not pinocchio_refuses(text)
    for command in ("convert", "verify"):
        code, err = run(capsys, tmp_path, text, command)
        joint = "joint 'm'" if slot == "mimic" else "joint 'j'"
        assert_refused(code, err, tmp_path, joint, what, "out of range", f"{LARGEST:g}")


@pytest.mark.parametrize(
    "lower, upper, what", [("-1e16", "1e16", "limit lower"), ("-1", "1e5", "limit upper")]
)
def test_revolute_limits_beyond_float64s_angle_precision_are_input_errors(
    lower, upper, what, capsys, tmp_path
):
    """Beyond 1e4 rad, q + theta loses theta to rounding: dh tables would disagree with
    Pinocchio (at 1e16 rad by radians)."""
    text = arm(limit=f'lower="{lower}" upper="{upper}" effort="1" velocity="1"')
    assert not pinocchio_refuses(text)
    code, err = run(capsys, tmp_path, text)
    assert_refused(
        code,
        err,
        tmp_path,
        "joint 'j'",
        what,
        "out of range for a revolute joint",
        'type="continuous"',
    )
    continuous = text.replace('name="j" type="revolute"', 'name="j" type="continuous"')
    assert run(capsys, tmp_path, continuous, "verify")[0] == 0  # limits ignored, as urdfdom


@pytest.mark.parametrize(
    "slot, value",
    [
        ("limit", 'lower="-1e4" upper="1e4" effort="1" velocity="1"'),  # revolute: the bound
        ("limit", 'lower="-1e16" upper="1e16" effort="1e308" velocity="1e308"'),  # Gazebo's "none"
        ("origin", 'xyz="0 1e40 0" rpy="1e300 -1e300 0"'),
        ("origin", 'xyz="5e-324 0 1e-300" rpy="1e-300 1e-300 1e-160"'),  # underflow is no fault
    ],
)
def test_large_values_within_the_bound_agree_with_pinocchio(slot, value, capsys, tmp_path):
    jtype = "prismatic" if "1e16" in value else "revolute"
    text = arm(**{slot: value}, jtype=jtype)
    code, err = run(capsys, tmp_path, text, "verify")
    assert code == 0, err


def helical(multiplier: str) -> str:
    """A revolute joint 'j' with its lead 'm' (coaxial prismatic mimicking it): one helical
    joint of pitch ``multiplier`` (as urdf2dh.emit.urdf writes it), then a revolute joint."""
    links = "".join(f'<link name="{n}"/>' for n in ("base", "l1", "l2", "l3", "tool"))
    return (
        f'<robot name="h">{links}'
        '<joint name="j" type="revolute"><parent link="base"/><child link="l1"/>'
        f'<origin xyz="0 0.1 0.3" rpy="0.3 0 0"/><axis xyz="0 0 1"/><limit {LIMIT}/></joint>'
        '<joint name="m" type="prismatic"><parent link="l1"/><child link="l2"/>'
        f'<axis xyz="0 0 1"/><limit {LIMIT}/><mimic joint="j" multiplier="{multiplier}"/>'
        '</joint><joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>'
        f'<origin xyz="0.4 0 0"/><axis xyz="0 1 0"/><limit {LIMIT}/></joint>'
        '<joint name="flange" type="fixed"><parent link="l3"/><child link="tool"/>'
        '<origin xyz="0 0 0.1"/></joint></robot>'
    )


@pytest.mark.parametrize("multiplier", ["0.01", "-2.5", "1e40"])
def test_helical_lead_pitch_agrees_with_pinocchio(multiplier, capsys, tmp_path):
    model = tree_to_poe(parse_tree(helical(multiplier).encode(), "h.urdf"), tip="tool")
    assert [j.kind for j in model.joints] == ["helical", "revolute"]
    assert model.joints[0].pitch == float(multiplier)
    code, err = run(capsys, tmp_path, helical(multiplier), "verify")
    assert code == 0, err


@pytest.mark.parametrize(
    "multiplier, says", [("1e308", "out of range"), ("nan", "not finite"), ("1e999", "not finite")]
)
def test_helical_lead_pitch_out_of_range(multiplier, says, capsys, tmp_path):
    code, err = run(capsys, tmp_path, helical(multiplier))
    assert_refused(code, err, tmp_path, "joint 'm'", "mimic multiplier", says)


@pytest.mark.parametrize("offset", ["1e16", "1e50"])
def test_a_base_far_from_the_root_is_verified_to_pinocchios_resolution(offset, capsys, tmp_path):
    """Pinocchio works in the root's frame: a world joint 1e16 m away rounds its base-to-tip
    poses by metres, which verify allows for (our table is exact; found by the corpus)."""
    text = arm().replace('<link name="base"/>', '<link name="world"/><link name="base"/>')
    text = text.replace(
        "</robot>",
        '<joint name="world_joint" type="fixed"><parent link="world"/><child link="base"/>'
        f'<origin xyz="0 {offset} 0"/></joint></robot>',
    )
    path = tmp_path / "w.urdf"
    path.write_text(text)
    assert main(["verify", str(path), "--base", "base", "--tip", "tool", "--samples", "200"]) == 0
    assert "all conventions agree" in capsys.readouterr().out
    near = text.replace(f'xyz="0 {offset} 0"', 'xyz="0 2 0"')
    tree = parse_tree(near.encode(), "w.urdf")
    model = tree_to_poe(tree, "base", "tool")
    from urdf2dh.check.verify import _oracle_rounding
    from urdf2dh.io.sources import Source

    rounding = _oracle_rounding(Source("urdf", "w.urdf", "r", tree, tree.xml), model)
    assert 0 < rounding < 1e-13  # an ordinary world offset: nothing allowed beyond the check
