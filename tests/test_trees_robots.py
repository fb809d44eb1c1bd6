"""Every chain of example-robot-data's humanoids and dual-arm robots against Pinocchio:
``verify --all-tips`` takes exactly the leaves that a plain reading of the URDF says
have a moving joint on their chain, and every convention of every chain agrees with Pinocchio.

Chains through a gripper's mimic joints (marked below) keep them coupled: a joint following one
on the chain follows it, one following a finger on another branch stands in for it; the same
with ``--ignore-mimic``, where every such joint is independent. A chain through a floating or
planar joint is refused with the joint named, and a base below it works.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from urdf2dh.cli import main
from urdf2dh.conventions import NAMES
from urdf2dh.io.catalog import example_robot_data_dir

#: (file under example-robot-data's robots/, whether some chain holds a mimic joint)
ROBOTS = [
    ("talos_data/robots/talos_reduced.urdf", True),
    ("pr2_description/urdf/pr2.urdf", True),
    ("romeo_description/urdf/romeo.urdf", True),
    ("baxter_description/urdf/baxter.urdf", True),
    ("tiago_description/robots/tiago_dual.urdf", False),
    ("icub_description/robots/icub.urdf", False),
]

SAMPLES = "50"  # configurations per chain: keeps the 142 chains at a few seconds

REPORT = re.compile(r"^\S+: (\S+) -> (.+), (\d+) joints; against Pinocchio", re.MULTILINE)
RESULT = re.compile(r"^  (\S+(?: model)?) +\S+ \S+ +(\S+) +\S+ rad  (ok|FAILED)$", re.MULTILINE)


def expected_tips(path: Path) -> tuple[str, list[str]]:
    """The root and, in file order, the leaves whose chain from the root holds a joint that is
    not fixed, read from the XML directly (not through urdf2dh's tree)."""
    robot = ET.parse(path).getroot()
    links = [link.get("name") for link in robot.findall("link")]
    parent = {}  # child link -> (parent link, joint type)
    for joint in robot.findall("joint"):
        parent[joint.find("child").get("link")] = (
            joint.find("parent").get("link"),
            joint.get("type"),
        )
    parents = {p for p, _ in parent.values()}
    (root,) = [link for link in links if link not in parent]
    tips = []
    for leaf in (link for link in links if link not in parents):
        link, moving = leaf, False
        while link in parent:
            link, kind = parent[link]
            moving |= kind != "fixed"
        if moving:
            tips.append(leaf)
    return root, tips


CASES = [(f, ignore) for f, mimic in ROBOTS for ignore in ((False, True) if mimic else (False,))]


@pytest.mark.parametrize(
    ("file", "ignore_mimic"),
    CASES,
    ids=[f"{Path(f).stem}{'-ignore-mimic' if i else ''}" for f, i in CASES],
)
def test_verify_all_tips_agrees_with_pinocchio_on_every_chain(capsys, file, ignore_mimic):
    path = example_robot_data_dir() / file
    root, tips = expected_tips(path)
    argv = ["verify", str(path), "--all-tips", "--samples", SAMPLES]
    code = main(argv + (["--ignore-mimic"] if ignore_mimic else []))
    out, err = capsys.readouterr()
    assert code == 0, err
    reports = REPORT.findall(out)
    assert [base for base, _, _ in reports] == [root] * len(tips)
    assert [tip for _, tip, _ in reports] == tips
    results = RESULT.findall(out)
    assert len(results) == len(tips) * (1 + len(NAMES))
    assert all(ok == "ok" for _, _, ok in results)
    assert max(float(rel) for _, rel, _ in results) < 1e-8  # relative to each chain's size
    assert out.endswith(f"on all {len(tips)} chains\n")


def with_root_joint(path: Path, kind: str) -> str:
    """The URDF with a ``world`` link above its root, joined by a ``kind`` joint (as Pinocchio's
    free flyer would be written)."""
    text = path.read_text()
    root, _ = expected_tips(path)
    head = re.search(r"<robot[^>]*>", text)
    assert head is not None
    joint = (
        f'<link name="world"/><joint name="root_joint" type="{kind}">'
        f'<parent link="world"/><child link="{root}"/></joint>'
    )
    return text[: head.end()] + joint + text[head.end() :]


@pytest.mark.parametrize("kind", ["floating", "planar"])
def test_a_humanoid_above_its_free_flyer_is_refused_and_converts_below_it(capsys, tmp_path, kind):
    path = example_robot_data_dir() / "talos_data/robots/talos_reduced.urdf"
    source = tmp_path / "talos_free.urdf"
    source.write_text(with_root_joint(path, kind))
    code = main(
        ["convert", str(source), "--all-tips", "--ignore-mimic", "-o", f"{tmp_path / 'o'}/"]
    )
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "joint 'root_joint' on the chain 'world' -> " in err and f"is {kind};" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["talos_free.urdf"]
    _, tips = expected_tips(path)
    argv = ["convert", str(source), "--all-tips", "--ignore-mimic", "--base", "base_link"]
    assert main([*argv, "-o", f"{tmp_path / 'o'}/"]) == 0
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == sorted(f"{t}.txt" for t in tips)
    if kind == "floating":  # Pinocchio reads the free flyer too; the chains below it agree
        argv[0] = "verify"
        assert main([*argv, "--samples", "5"]) == 0
        assert capsys.readouterr().out.endswith(f"on all {len(tips)} chains\n")
