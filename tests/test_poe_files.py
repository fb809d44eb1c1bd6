"""POE model files (docs/formats/poe-file.md): un-normalised twists, scale factors, pitch,
prismatic joints, type checks, and the --format poe round trip."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import yaml

from urdf2dh import load, to_table
from urdf2dh.cli import main
from urdf2dh.errors import InputError
from urdf2dh.io.poefile import read_poe


def poe(joints, tool=None, **extra):
    return {
        "format": "poe",
        "name": "t",
        "length_unit": "mm",
        "joints": joints,
        "tool": tool or {"twist": [0, 0, 0, 100, 0, 0]},
        **extra,
    }


def test_unnormalised_twists_give_scale_and_pitch():
    model = read_poe(
        poe(
            [
                {"name": "r", "twist": [0, 0, 2, 0, 0, 0]},
                {"name": "h", "twist": [0, 0, 1.5, 0, -3, 0.75]},  # pitch 0.75 * 1.5 / 1.5^2
                {"name": "p", "twist": [0, 0, 0, 0, 3, 4]},
            ]
        ),
        "t.yaml",
    )
    r, h, p = model.joints
    assert (r.kind, r.scale, r.pitch) == ("revolute", 2.0, 0.0)
    assert (h.kind, h.scale) == ("helical", 1.5)
    assert h.pitch == pytest.approx(0.5)
    assert np.allclose(h.point, [2.0, 0.0, 0.0])  # w x v / |w|^2 for v = p x w
    assert (p.kind, p.scale, p.point) == ("prismatic", 5.0, None)
    assert np.allclose(p.axis, [0, 0.6, 0.8])
    # the model moves as exp(xi q): a quarter turn of r is s = 2 * q
    q = np.array([math.pi / 4, 0.0, 0.0])
    assert np.allclose(model.fk(q)[:3, 3], [0, 100, 0], atol=1e-12)


def test_puma_actual_is_helical_where_wu_says():
    model = load("puma560-actual")
    assert [j.kind for j in model.joints] == ["revolute", "revolute"] + ["helical"] * 4
    assert model.length_unit == "mm"


@pytest.mark.parametrize(
    "entry, message",
    [
        ({"name": "a", "twist": [0, 0, 1, 0, 1, 1], "type": "revolute"}, "declared revolute but"),
        ({"name": "a", "twist": [0, 0, 1, 0, 1, 0], "type": "helical"}, "declared helical but"),
        ({"name": "a", "twist": [0, 0, 1, 0, 1, 0], "type": "prismatic"}, "declared prismatic"),
        ({"name": "a", "twist": [0, 0, 0, 0, 0, 1], "type": "revolute"}, r"w = 0 \(a prismatic"),
        ({"name": "a", "twist": [0, 0, 1, 0, 1, 0], "type": "ball"}, "unknown type 'ball'"),
        ({"name": "a", "twist": [0, 0, 0, 0, 0, 0]}, "zero twist"),
        ({"name": "a", "twist": [0, 0, 1, 0, 1]}, "list of 6 numbers"),
        ({"name": "a", "twist": [0, 0, "x", 0, 1, 0]}, "twist must be a number, not 'x'"),
        ({"name": "a", "twist": [0, 0, 1e300, 0, 1, 0]}, r"twist is 1e\+300: beyond 1e\+12"),
        ({"name": "a", "twist": [0, 0, 1e-300, 0, 0, 0]}, r"scale 0 .* within \[1e-09, 1e\+09\]"),
        ({"name": "a", "twist": [0, 0, 1e-300, 0, 1e-300, 0]}, "scale 1e-300"),
        ({"name": "a", "twist": [0, 0, 1e-11, 0, 0, 0]}, "scale 1e-11"),
        ({"name": "a", "twist": [0, 0, 1, 0, 0, 0], "limits": [-1e308, 1e308]}, "limits is -1e"),
        (
            {"name": "a", "twist": [0, 0, 1, 0, 0, 0], "limits": [0, 10**5000]},
            "too large for a float",
        ),
        ({"name": "a", "twist": [0, 0, float("nan"), 0, 1, 0]}, "finite"),
        ({"name": "a", "twist": [0, 0, 1, 0, 0, 0], "limits": [1, -1]}, "lower < upper"),
    ],
)
def test_bad_joints_are_named(entry, message):
    with pytest.raises(InputError, match=message) as e:
        read_poe(poe([entry]), "robot.yaml")
    assert "robot.yaml: joint 'a'" in str(e.value)


@pytest.mark.parametrize(
    ("name", "message"),
    [
        (7, "joint 1 name must be a non-empty string, not 7"),
        (["x"], "joint 1 name must be a non-empty string, not ['x']"),
        ("", "joint 1 name must be a non-empty string"),
    ],
)
def test_names_must_be_strings(name, message):
    with pytest.raises(InputError, match=re.escape(message)):
        read_poe(poe([{"name": name, "twist": [0, 0, 1, 0, 0, 0]}]), "robot.yaml")


def test_tool_matrix_and_bad_tools():
    m = read_poe(
        poe(
            [{"name": "a", "twist": [0, 0, 1, 0, 0, 0]}],
            tool={"matrix": [[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]},
        ),
        "t.yaml",
    )
    assert np.allclose(m.home[:3, 3], [1, 2, 3])
    rounded = [[0.70711, -0.70711, 0, 0], [0.70711, 0.70711, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    m = read_poe(poe([], tool={"matrix": rounded}), "t.yaml")
    assert np.allclose(m.home[:3, :3].T @ m.home[:3, :3], np.eye(3), atol=1e-15)
    assert any("orthonormalised" in w for w in m.warnings)
    with pytest.raises(InputError, match="not a rotation"):
        read_poe(
            poe([], tool={"matrix": [[1, 0.1, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}),
            "t.yaml",
        )
    mirrored = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, -1, 0], [0, 0, 0, 1]]
    with pytest.raises(InputError, match=r"tool matrix: the 3x3 block is a reflection "
                       r"\(determinant -1\), not a rotation"):  # fmt: skip
        read_poe(poe([], tool={"matrix": mirrored}), "t.yaml")
    with pytest.raises(InputError, match="either 'twist' or 'matrix'"):
        read_poe(poe([], tool={"twist": [0] * 6, "matrix": rounded}), "t.yaml")


def test_format_poe_round_trip(tmp_path, capsys):
    target = tmp_path / "panda.yaml"
    assert main(["convert", "panda", "--format", "poe", "-o", str(target)]) == 0
    tree = yaml.safe_load(target.read_text())
    assert tree["format"] == "poe" and len(tree["joints"]) == 7
    assert tree["joints"][0]["limits"] == pytest.approx([-2.8973, 2.8973])
    original = load("panda")
    again = load(str(target))
    q = np.random.default_rng(3).uniform(-1, 1, size=(50, 7))
    assert np.abs(original.fk_batch(q) - again.fk_batch(q)).max() < 1e-14
    # and converting the POE file gives the same D-H table as the URDF did
    a, b = to_table(original, "dh"), to_table(again, "dh")
    for ra, rb in zip(a.rows, b.rows, strict=True):
        va, vb = ra.params.scalars(), rb.params.scalars()
        assert all(abs(va[k] - vb[k]) < 1e-12 for k in va)


def test_a_revolute_axis_through_the_origin_reads_back_revolute():
    """Found by a random search of tests/test_diff_properties.py: an axis through the base origin
    given by a point 0.517 m along it has the moment v = p x w ~ 1e-65 of pure round-off along
    w, which read back as a pitch (a helical joint) before the writer took it off."""
    from urdf2dh import Joint, PoeModel
    from urdf2dh.io.poefile import poe_to_dict

    axis = np.array([7.498798913309288e-33, -1.0, -6.123233995736766e-17])
    point = np.array([-3.8781770425441945e-33, 0.5171730949687141, 3.166771876792829e-17])
    model = PoeModel((Joint("j2", "revolute", axis, point),), np.eye(4), "through origin")
    tree = poe_to_dict(model)
    w, v = np.array(tree["joints"][0]["twist"][:3]), np.array(tree["joints"][0]["twist"][3:])
    assert abs(float(w @ v)) <= 1e-16 * np.linalg.norm(v)
    again = read_poe(tree, "a.yaml")
    assert again.joints[0].kind == "revolute"
    assert np.abs(again.fk(np.array([0.7]))[:3, 3] - model.fk(np.array([0.7]))[:3, 3]).max() < 1e-15
