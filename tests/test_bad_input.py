"""Bad input never crashes and never lies: each case exits 2 with one line on stderr naming the
file, link or joint, no traceback, and no output file left behind."""

from __future__ import annotations

import pytest

from urdf2dh.cli import main

LINKS = '<link name="base"/><link name="a"/><link name="b"/>'


def robot(body: str, links: str = LINKS) -> str:
    return f'<robot name="r">{links}{body}</robot>'


LIMIT = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'


def joint(name="j", jtype="revolute", parent="base", child="a", extra="") -> str:
    if jtype in ("revolute", "prismatic") and "<limit" not in extra:
        extra += LIMIT  # urdfdom refuses either without one
    return (
        f'<joint name="{name}" type="{jtype}"><parent link="{parent}"/>'
        f'<child link="{child}"/>{extra}</joint>'
    )


CHAIN = joint("j1") + joint("j2", parent="a", child="b")

# name -> (file content (str or bytes), extra CLI args, message fragments)
CASES = {
    "malformed XML": ("<robot name='r'><link name='a'>", [], ["malformed XML"]),
    "not a robot": ("<model name='x'/>", [], ["not a URDF robot", "<model>"]),
    "robot without name": ("<robot><link name='a'/></robot>", [], ["no name attribute"]),
    "empty file": ("", [], ["empty file"]),
    "whitespace file": ("  \n\t ", [], ["empty file"]),
    "binary file": (b"\x89PNG\r\n\x1a\n\x00\x00\x00", [], ["binary file"]),
    "no links": ("<robot name='r'/>", [], ["declares no links"]),
    "undeclared child link": (
        robot(joint(child="c")),
        [],
        ["joint 'j'", "undeclared link 'c'", "child"],
    ),
    "undeclared parent link": (
        robot(joint(parent="nowhere")),
        [],
        ["joint 'j'", "undeclared link 'nowhere'"],
    ),
    "missing child element": (
        robot('<joint name="j" type="fixed"><parent link="base"/></joint>'),
        [],
        ["joint 'j'", "no <child link=...>"],
    ),
    "link with two parents": (
        robot(joint("j1") + joint("j2", parent="b", child="a")),
        [],
        ["link 'a' is the child of both", "kinematic loop"],
    ),
    "cycle without root": (
        robot(
            joint("j1", parent="a", child="b") + joint("j2", parent="b", child="a"),
            links='<link name="a"/><link name="b"/>',
        ),
        [],
        ["kinematic loop"],
    ),
    "detached cycle": (
        robot(
            joint("j0", parent="base", child="c")
            + joint("j1", parent="a", child="b")
            + joint("j2", parent="b", child="a"),
            links=LINKS + '<link name="c"/>',
        ),
        [],
        ["not connected to root 'base'", "kinematic loop"],
    ),
    "several roots": (
        robot(joint("j1", parent="base", child="a"), links=LINKS),
        [],
        ["several root links", "base", "b"],
    ),
    "zero axis": (robot(joint(extra='<axis xyz="0 0 0"/>')), [], ["joint 'j'", "zero axis"]),
    "NaN axis": (robot(joint(extra='<axis xyz="0 nan 1"/>')), [], ["joint 'j'", "not finite"]),
    "non-numeric axis": (
        robot(joint(extra='<axis xyz="0 one 1"/>')),
        [],
        ["joint 'j'", "axis xyz '0 one 1' is not 3 numbers"],
    ),
    "short axis": (robot(joint(extra='<axis xyz="0 1"/>')), [], ["joint 'j'", "not 3 numbers"]),
    "NaN origin": (
        robot(joint(extra='<origin xyz="0 0 nan"/>')),
        [],
        ["joint 'j'", "origin xyz", "not finite"],
    ),
    "infinite origin": (
        robot(joint(extra='<origin xyz="0 0 1e999"/>')),
        [],
        ["joint 'j'", "not finite"],
    ),
    "non-numeric origin": (
        robot(joint(extra='<origin rpy="0 x 0"/>')),
        [],
        ["joint 'j'", "origin rpy '0 x 0' is not 3 numbers"],
    ),
    "non-numeric limit": (
        robot(joint(extra='<limit lower="a" upper="1"/>')),
        [],
        ["joint 'j'", "limit lower"],
    ),
    "unknown joint type": (robot(joint(jtype="ball")), [], ["joint 'j'", "unknown type 'ball'"]),
    "revolute joint without limit": (
        robot(joint(extra="<limit/>").replace("<limit/>", "")),
        [],
        ["joint 'j'", "a revolute joint needs a <limit>", 'type="continuous"'],
    ),
    "limit without effort": (
        robot(joint(extra='<limit lower="-1" upper="1" velocity="1"/>')),
        [],
        ["joint 'j'", "<limit> has no effort attribute"],
    ),
    "tab between numbers": (
        robot(joint(extra='<origin xyz="0&#9;0 1"/>')),
        [],
        ["joint 'j'", "urdfdom separates numbers by spaces only"],
    ),
    "unknown URDF version": (
        robot(joint()).replace('name="r"', 'name="r" version="2.0"'),
        [],
        ["<robot version='2.0'> is not a version urdfdom reads"],
    ),
    "floating joint on the chain": (
        robot(joint("j1", jtype="floating") + joint("j2", parent="a", child="b")),
        [],
        ["joint 'j1'", "is floating"],
    ),
    "planar joint on the chain": (
        robot(joint("j1", jtype="planar") + joint("j2", parent="a", child="b")),
        [],
        ["joint 'j1'", "is planar"],
    ),
    "duplicate joint": (
        robot(joint("j") + joint("j", parent="a", child="b")),
        [],
        ["joint 'j' is declared twice"],
    ),
    "duplicate link": (
        robot(joint(), links=LINKS + '<link name="a"/>'),
        [],
        ["link 'a' is declared twice"],
    ),
    "unknown base": (robot(CHAIN), ["--base", "nope"], ["unknown base link 'nope'", "base"]),
    "unknown tip": (robot(CHAIN), ["--tip", "nope"], ["unknown tip link 'nope'"]),
    "tip not below base": (
        robot(CHAIN),
        ["--base", "b", "--tip", "a"],
        ["tip link 'a' is not below base link 'b'"],
    ),
    "mimic of no joint that moves": (
        robot(
            joint("j1")
            + joint("j2", parent="a", child="b", extra='<mimic joint="j3" multiplier="0"/>')
            + joint("j3", parent="base", child="c"),
            links=LINKS + '<link name="c"/>',
        ),
        [],
        ["joint 'j2'", "mimics 'j3' with multiplier 0", "--ignore-mimic"],
    ),
    "joints mimicking each other": (
        robot(
            joint("j1", extra='<mimic joint="j2"/>')
            + joint("j2", parent="a", child="b", extra='<mimic joint="j1"/>')
        ),
        [],
        ["joints ['j1', 'j2'] mimic each other"],
    ),
}


# `info` reads the file and reports chain problems as text (test below), so it meets only the
# file-level cases
CHAIN_LEVEL = {
    "floating joint on the chain",
    "planar joint on the chain",
    "mimic of no joint that moves",
    "joints mimicking each other",
    "unknown base",
    "unknown tip",
    "tip not below base",
}
COMBINATIONS = [
    (case, command)
    for case in sorted(CASES)
    for command in ("convert", "verify", "info")
    if not (command == "info" and case in CHAIN_LEVEL)
]


@pytest.mark.parametrize("case, command", COMBINATIONS)
def test_bad_urdf(case, command, tmp_path, capsys):
    content, args, fragments = CASES[case]
    path = tmp_path / "bad.urdf"
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    out = tmp_path / "out.json"
    argv = [command, str(path), *args] + (["-o", str(out)] if command == "convert" else [])
    assert main(argv) == 2
    captured = capsys.readouterr()
    err = captured.err
    assert err.startswith("urdf2dh: error: ") and err.count("\n") == 1, err
    assert "Traceback" not in err + captured.out
    for fragment in fragments:
        assert fragment in err, (fragment, err)
    assert str(path) in err or "bad.urdf" in err or fragments[0].startswith(("unknown", "tip"))
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["bad.urdf"]


@pytest.mark.parametrize("case", sorted(CHAIN_LEVEL))
def test_info_reports_chain_problems_without_failing(case, tmp_path, capsys):
    content, args, fragments = CASES[case]
    path = tmp_path / "bad.urdf"
    path.write_text(content)
    assert main(["info", str(path), *args]) == 0
    out = capsys.readouterr().out
    assert "chain: not determined" in out and fragments[0] in out


@pytest.mark.parametrize(
    "content, suffix, fragment",
    [
        ("format: poe\njoints: [\n", ".yaml", "malformed YAML"),
        ('{"format": "poe", "joints": [}', ".json", "malformed JSON"),
        ("just some words", ".yaml", "URDF (<robot>), POE model ('format: poe')"),
        (
            "format: poe\njoints: 3\ntool: {twist: [0,0,0,0,0,0]}\n",
            ".yaml",
            "'joints' must be a list",
        ),
        ("format: poe\njoints: []\n", ".yaml", "'tool' must give either"),
        ("schema: urdf2dh/1\nconvention: xyz\n", ".yaml", "convention must be one of"),
        # none of these may be an internal error, a hang or a memory blow-up
        ('{"format": "poe", "n": ' + "9" * 5000 + "}", ".json", "malformed JSON (Exceeds"),
        ("[" * 100_000 + "]" * 100_000, ".json", "nested too deeply"),
        ("[" * 100_000 + "]" * 100_000, ".yaml", "nested too deeply"),
        ("format: poe\nname: caf\xe9\n".encode("latin-1"), ".yaml", "not UTF-8 text (byte 21)"),
        (
            "format: poe\na: &a [x, x, x, x, x, x, x, x, x, x]\n"
            + "".join(
                f"{chr(98 + k)}: &{chr(98 + k)} [*{chr(97 + k)}, *{chr(97 + k)}, *{chr(97 + k)},"
                f" *{chr(97 + k)}, *{chr(97 + k)}, *{chr(97 + k)}, *{chr(97 + k)}, *{chr(97 + k)},"
                f" *{chr(97 + k)}, *{chr(97 + k)}]\n"
                for k in range(8)
            ),
            ".yaml",
            "more than 1,000,000 values (aliases counted as expanded)",
        ),
        (
            "format: poe\nname: [1]\njoints: []\ntool: {twist: [0, 0, 0, 0, 0, 0]}\n",
            ".yaml",
            "name must be a non-empty string",
        ),
    ],
)
def test_bad_model_and_table_files(content, suffix, fragment, tmp_path, capsys):
    path = tmp_path / f"bad{suffix}"
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    out = tmp_path / "out.txt"
    assert main(["convert", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert fragment in err and err.count("\n") == 1 and "Traceback" not in err
    assert not out.exists()


def test_missing_files_directories_and_outputs(tmp_path, capsys):
    assert main(["convert", str(tmp_path / "none.urdf")]) == 2
    assert "none.urdf: no such file" in capsys.readouterr().err
    assert main(["convert", str(tmp_path)]) == 2
    assert "is a directory" in capsys.readouterr().err
    assert main(["convert", "ur5", "-o", str(tmp_path / "no" / "dir" / "x.txt")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert main(["convert", "puma560-actual", "--base", "x"]) == 2
    assert "base and tip links apply to URDF sources" in capsys.readouterr().err


@pytest.mark.parametrize(
    "argv",
    [
        ["convert", "ur5", "--convention", "xyz"],
        ["convert", "ur5", "--format", "pdf"],
        ["verify", "ur5", "--samples", "0"],
        ["convert", "ur5", "--parallel-angle", "-1"],
        ["convert", "ur5", "--parallel-angle", "nan"],
        ["convert", "ur5", "--parallel-angle", "1e300"],  # beyond 0.1 rad is not "nearly parallel"
        ["verify", "ur5", "--samples", "1000000000"],  # would take 44 GiB
        ["convert", "ur5", "--check-samples", "1000001"],
        ["verify", "ur5", "--seed", "-1"],
        ["convert", "x.xacro", "--xacro-timeout", "0"],
        ["convert"],
        ["frobnicate"],
    ],
)
def test_bad_usage_exits_2(argv, capsys):
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert "usage:" in err and "Traceback" not in err


def test_style_ur_with_cpc_is_a_usage_error(capsys):
    assert main(["convert", "ur5", "--convention", "cpc", "--style", "ur"]) == 2
    assert "style ur applies to dh, mdh tables, not cpc" in capsys.readouterr().err
