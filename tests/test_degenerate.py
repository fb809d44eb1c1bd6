"""Degenerate geometry, exact: each case a URDF read by urdf2dh and by Pinocchio.

And nearly parallel axes from rounded URDF angles: sane tables, judgements named in warnings
with the deviation they caused, ``--exact`` keeping the geometry.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from oracle import assert_fk_matches, pin_reference

from urdf2dh import CONVENTIONS, DEFAULT, EXACT, load, to_table
from urdf2dh.cli import main
from urdf2dh.io.sources import Source
from urdf2dh.io.urdf import parse_tree

HALF = repr(math.pi / 2)
PI = repr(math.pi)


def urdf(joints: list[tuple[str, str, str, str]], tip: tuple[str, str] = ("0 0 0", "0 0 0")):
    """URDF text of a chain: joints are (type, xyz, rpy, axis); a fixed 'tip' link at the end."""
    links = ['<link name="base"/>'] + [f'<link name="l{i}"/>' for i in range(1, len(joints) + 1)]
    body = []
    for i, (jtype, xyz, rpy, axis) in enumerate(joints, 1):
        limit = (
            '<limit lower="-0.5" upper="0.5" effort="1" velocity="1"/>'
            if jtype == "prismatic"
            else '<limit lower="-3" upper="3" effort="1" velocity="1"/>'
            if jtype == "revolute"
            else ""
        )
        parent = "base" if i == 1 else f"l{i - 1}"
        body.append(
            f'<joint name="j{i}" type="{jtype}"><parent link="{parent}"/>'
            f'<child link="l{i}"/><origin xyz="{xyz}" rpy="{rpy}"/>'
            f'<axis xyz="{axis}"/>{limit}</joint>'
        )
    last = f"l{len(joints)}" if joints else "base"
    body.append(
        f'<joint name="tip_joint" type="fixed"><parent link="{last}"/>'
        f'<child link="tip"/><origin xyz="{tip[0]}" rpy="{tip[1]}"/></joint>'
    )
    return (
        '<robot name="case">' + "".join(links) + '<link name="tip"/>' + "".join(body) + "</robot>"
    )


def source(text: str) -> Source:
    tree = parse_tree(text.encode(), "case.urdf")
    return Source("urdf", "case.urdf", "case", tree, text.encode())


R = "revolute"
P = "prismatic"
CASES = {
    "anti-parallel axes": urdf(
        [
            (R, "0 0 0.3", "0 0 0", "0 0 1"),
            (R, "0.4 0.1 0", f"{PI} 0 0", "0 0 1"),
            (R, "0.3 0 0", "0 0 0", "0 0 1"),
        ],
        ("0.1 0 0", "0 0 0"),
    ),
    "coincident axes": urdf(
        [
            (R, "0 0 0.3", "0 0 0", "0 0 1"),
            (R, "0 0 0.2", "0 0 0.7", "0 0 1"),
            (R, "0 0 -0.5", f"{PI} 0 0", "0 0 1"),
        ],
        ("0 0 0.1", "0 0 0"),
    ),
    "intersecting axes": urdf(
        [
            (R, "0 0 0.3", "0 0 0", "0 0 1"),
            (R, "0 0 0", f"{HALF} 0 0", "0 0 1"),
            (R, "0 0 0", f"0 {HALF} 0", "0 0 1"),
        ],
        ("0 0 0.2", "0 0 0"),
    ),
    "prismatic first": urdf(
        [(P, "0.1 0.2 0.3", "0.3 0.2 0.1", "0 0 1"), (R, "0.2 0 0", f"{HALF} 0 0", "0 0 1")],
        ("0 0.1 0.1", "0 0 0"),
    ),
    "prismatic last": urdf(
        [(R, "0 0 0.3", "0 0 0", "0 0 1"), (P, "0.2 0.1 0", "0.4 -0.3 0.2", "0 0 1")],
        ("0 0 0.1", "0 0 0"),
    ),
    "consecutive prismatic": urdf(
        [
            (P, "0 0 0.1", "0 0 0", "0 0 1"),
            (P, "0.1 0 0", f"0 {HALF} 0", "0 0 1"),
            (P, "0 0.1 0", f"{HALF} 0 0", "0 0 1"),
            (R, "0 0 0.2", "0 0 0", "0 0 1"),
        ],
        ("0.1 0 0", "0 0 0"),
    ),
    "prismatic parallel to revolute": urdf(
        [
            (R, "0 0 0.3", "0 0 0", "0 0 1"),
            (P, "0.25 0 0", "0 0 0", "0 0 1"),
            (R, "0 0.1 0", "0 0 0", "0 0 1"),
            (P, "0 0 0", "0 0 0", "0 0 -1"),
        ],
        ("0.05 0 0", "0 0 0"),
    ),
    "zero-length chain": urdf(
        [
            (R, "0 0 0", "0 0 0", "0 0 1"),
            (R, "0 0 0", f"{HALF} 0 0", "0 0 1"),
            (R, "0 0 0", f"0 {HALF} 0", "0 0 1"),
        ]
    ),
    "no movable joint": urdf([], ("0.1 0.2 0.3", "0.1 0.2 0.3")),
    "CPC singular direction": urdf(
        [
            (R, "0 0 0.4", "0 0 0", "0 0 1"),
            (R, "0.3 0 0", "0 0 0", "0 0 1"),
            (P, "0.2 0 0", f"{PI} 0 0", "0 0 1"),
        ],
        ("0 0 0.05", "0 0 0"),
    ),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_degenerate_case_is_exact(case):
    src = source(CASES[case])
    model = src.model("base", "tip")
    q, reference = pin_reference(src, model, samples=150)
    assert_fk_matches(f"{case}: POE", model.fk_batch(q), reference, model.size(), q)
    for conv in CONVENTIONS:
        table = to_table(model, conv)
        assert_fk_matches(f"{case}: {conv}", table.fk_batch(q), reference, model.size(), q)
        assert not [w for w in table.warnings if "treated as" in w]
    if case == "CPC singular direction":
        cpc = to_table(model, "cpc")
        assert any("no frame reversal can avoid it" in w for w in cpc.warnings)
        assert cpc.rows[-1].params.b == (0.0, 0.0, -1.0)


def test_base_equal_to_tip(capsys):
    assert main(["convert", "ur5", "--base", "tool0", "--tip", "tool0", "--format", "json"]) == 0
    out = capsys.readouterr().out
    assert '"joints": []' in out
    assert (
        main(["verify", "ur5", "--base", "wrist_3_link", "--tip", "tool0", "--samples", "20"]) == 0
    )


# ----------------------------------------------------------------- nearly parallel axes


def rounded_arm(off: float, along: str = "y") -> str:
    """A 3R arm whose second axis is ``off`` rad from the first: a URDF that turns an axis about
    x and back with a rounded angle, as ``rpy="1.5708 0 0"`` does (off = 3.7e-6). The link
    offsets run along ``along``: along y the tilt swings the common normal far away (the D-H
    problem); along x, the tilt axis, the common normal stays near."""
    offset = {"x": "0.4 0 0", "y": "0 0.4 0"}[along]
    return urdf(
        [
            (R, "0 0 0.3", "0 0 0", "0 0 1"),
            (R, offset, f"{math.pi / 2 + off} 0 0", "0 1 0"),
            (R, "0.3 0 0", f"{-math.pi / 2} 0 0", "0 0 1"),
        ],
        ("0.2 0 0", "0 0 0"),
    )


def test_a_tilt_about_the_common_perpendicular_stays_exact():
    model = source(rounded_arm(3.7e-6, along="x")).model("base", "tip")
    table = to_table(model, "dh")
    assert table.warnings == ()
    assert table.rows[0].params.alpha == pytest.approx(3.7e-6, rel=1e-6)
    assert table.check.max_position_error < 1e-15 * 100


def test_the_issue_example_rpy_1_5708(tmp_path, capsys):
    path = tmp_path / "rounded.urdf"
    path.write_text(
        urdf(
            [
                (R, "0 0 0.3", "0 0 0", "0 0 1"),
                (R, "0 0.4 0", "1.5708 0 0", "0 1 0"),
                (R, "0.3 0 0", "-1.5708 0 0", "0 0 1"),
            ],
            ("0.2 0 0", "0 0 0"),
        )
    )
    assert main(["convert", str(path), "--format", "json"]) == 0
    import json

    table = json.loads(capsys.readouterr().out)
    assert all(abs(j["params"][k]) < 1.0 for j in table["joints"] for k in ("d", "a"))
    named = [w for w in table["warnings"] if "treated as parallel" in w]
    assert any("'j1' and 'j2'" in w for w in named)
    assert any("FK deviation from the source" in w for w in table["warnings"])


@pytest.mark.parametrize("off", [1e-9, 1e-7, 3.7e-6, 9e-5])
def test_rounded_angles_give_sane_tables_and_a_stated_deviation(off):
    src = source(rounded_arm(off))
    model = src.model("base", "tip")
    q, reference = pin_reference(src, model, samples=200)
    for conv in ("dh", "mdh"):
        table = to_table(model, conv)
        extent = model.extent()
        assert all(abs(getattr(r.params, k)) <= extent for r in table.rows for k in ("d", "a"))
        snapped = [w for w in table.warnings if "treated as parallel" in w]
        assert len(snapped) == 1 and "'j1' and 'j2'" in snapped[0]
        assert f"{off:.3g} rad from parallel" in snapped[0]
        summary = next(w for w in table.warnings if "FK deviation from the source" in w)
        declared = table.check.declared_position
        assert f"at most {declared:.3g} m" in summary
        # the declared deviation bounds what the table really has: against Pinocchio, at other
        # configurations; it scales with the angle, and the measured one is within it
        assert 0.2 * off * 0.3 < table.check.max_position_error <= declared
        assert declared <= 5 * off * model.reach()
        assert_fk_matches(
            f"{off} {conv}",
            table.fk_batch(q),
            reference,
            model.size(),
            q,
            rel=declared / model.size(),
            rot=table.check.declared_rotation,
        )
    cpc = to_table(model, "cpc")  # CPC is continuous: exact, no judgement
    assert_fk_matches(f"{off} cpc", cpc.fk_batch(q), reference, model.size(), q)


@pytest.mark.parametrize("off", [3.7e-6, 2e-4])
def test_exact_mode_keeps_the_geometry_and_warns_about_far_offsets(off):
    model = source(rounded_arm(off)).model("base", "tip")
    table = to_table(model, "dh", EXACT)
    far = [w for w in table.warnings if "far beyond the robot's size" in w]
    assert far and "'j1'" in far[0] and "cpc" in far[0]
    assert not [w for w in table.warnings if "treated as" in w]
    assert max(abs(r.params.d) for r in table.rows) > 100 * model.extent()
    # D-H's own conditioning limits the precision to about eps * |d|
    big = max(abs(r.params.d) for r in table.rows)
    assert table.check.max_position_error < 1e-13 * big + 1e-15


def test_cli_tolerance_options(tmp_path, capsys):
    path = tmp_path / "rounded.urdf"
    path.write_text(rounded_arm(3.7e-6))
    assert main(["convert", str(path), "--tip", "tip"]) == 0
    assert "treated as parallel (--parallel-angle 0.0001;" in capsys.readouterr().out
    # beyond a smaller --parallel-angle, the exact normal (100 km away, over 1e3 x size) is
    # still out of reach: dh treats them as parallel all the same, a deviation not asked for,
    # so that without --convention the hayati table is written (urdf2dh.conventions.choice)
    smaller = ["--tip", "tip", "--parallel-angle", "1e-6"]
    assert main(["convert", str(path), *smaller, "--convention", "dh"]) == 0
    out = capsys.readouterr().out
    assert "treated as parallel" in out and "far beyond the robot's size" not in out
    assert main(["convert", str(path), *smaller]) == 0
    out = capsys.readouterr().out
    assert "warning: written in hayati, not dh: dh would treat" in out
    assert "(beyond --parallel-angle 1e-06), as parallel" in out
    assert main(["convert", str(path), "--tip", "tip", "--exact", "--convention", "dh"]) == 0
    assert "far beyond the robot's size" in capsys.readouterr().out
    assert main(["convert", str(path), "--tip", "tip", "--exact"]) == 0
    assert "warning: written in hayati, not dh: dh would put row" in capsys.readouterr().out


# ----------------------------------------------------------------- mimic joints


def test_mimic_joint_following_another_branch_stands_in_for_it(capsys):
    """Panda's right finger follows the left one, which is not on the chain to the right
    finger: it is driven on its own, said in a warning; --ignore-mimic says so as well."""
    assert main(["convert", "panda", "--tip", "panda_rightfinger"]) == 0
    out = capsys.readouterr().out
    assert "'panda_finger_joint2' follows 'panda_finger_joint1', which is not on the chain" in out
    assert main(["verify", "panda", "--tip", "panda_rightfinger", "--samples", "50"]) == 0
    capsys.readouterr()
    assert main(["convert", "panda", "--tip", "panda_rightfinger", "--ignore-mimic"]) == 0
    out = capsys.readouterr().out
    assert "treated as an independent joint (--ignore-mimic)" in out
    assert (
        main(["verify", "panda", "--tip", "panda_rightfinger", "--ignore-mimic", "--samples", "50"])
        == 0
    )
    # off the chain, mimic joints do not matter
    model = load("panda", tip="panda_leftfinger")
    assert model.n == 8 and model.warnings == ()
    assert np.isfinite(to_table(model, "dh").check.max_position_error)


@pytest.mark.parametrize("off", [2e-4, 2e-3])
def test_beyond_the_parallel_angle_dh_never_refuses_and_hayati_is_exact(off):
    """Axes 2e-4 and 2e-3 rad apart, beyond --parallel-angle. At 2e-4 the exact D-H row would
    put d 2 km away (over 1e3 x size): dh and mdh treat the axes as parallel with the deviation
    declared, naming --convention hayati. At 2e-3 it is 200 m (under 1e3 x size): the exact
    table is kept and warned about. hayati is exact and sane in both."""
    src = source(rounded_arm(off))
    model = src.model("base", "tip")
    q, reference = pin_reference(src, model, samples=200)
    for conv in ("dh", "mdh"):
        table = to_table(model, conv)
        big = max(abs(getattr(r.params, k)) for r in table.rows for k in ("d", "a"))
        if off == 2e-4:
            assert big <= model.size()
            assert any(
                "treated as parallel" in w and "--convention hayati" in w for w in table.warnings
            )
            rel, rot = table.check.declared_position / model.size(), table.check.declared_rotation
        else:
            assert 100 * model.size() < big < DEFAULT.sane_factor * model.size()
            assert any(
                "far beyond the robot's size" in w and "--convention hayati" in w
                for w in table.warnings
            )
            rel, rot = 1e-12, 1e-12
        assert_fk_matches(
            f"{off} {conv}", table.fk_batch(q), reference, model.size(), q, rel=rel, rot=rot
        )
    hayati = to_table(model, "hayati")
    assert hayati.warnings == ()
    assert all(
        abs(v) <= 2 * model.size()
        for r in hayati.rows
        for k, v in r.params.scalars().items()
        if k in ("d", "a")
    )
    assert_fk_matches(f"{off} hayati", hayati.fk_batch(q), reference, model.size(), q)
