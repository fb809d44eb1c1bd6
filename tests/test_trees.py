"""Every chain of a tree (docs/trees-mimic.md): which tips ``--all-tips`` and a
repeated ``--tip`` take, what several tables look like on stdout, ``-o DIR`` written all or
nothing, tip names that cannot be file names, ``verify`` and ``export`` over several chains.

The tree of these tests (:func:`tree_urdf`): base -> trunk (revolute), then a left arm (revolute
+ continuous) and a right one (prismatic + a fixed tool), and a camera on the base through a
fixed joint only.
"""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np
import pytest
import yaml

from urdf2dh.check import verify
from urdf2dh.cli import main
from urdf2dh.cli.chains import FORMAT_SUFFIXES
from urdf2dh.conventions import NAMES
from urdf2dh.errors import shown
from urdf2dh.io import files


def tree_urdf(
    left: str = "left_tip",
    right: str = "right_tip",
    right_joint: str = "prismatic",
) -> str:
    """A small tree; ``right_joint`` is the type of the right arm's joint (``floating`` or
    ``planar`` to put one on that chain)."""
    left_q, right_q = quoteattr(left), quoteattr(right)
    limit = '<limit lower="0" upper="0.4" effort="1" velocity="1"/>'
    return f"""<robot name="ytree">
  <link name="base"/><link name="trunk"/><link name="left_1"/><link name={left_q}/>
  <link name="right_1"/><link name={right_q}/><link name="camera"/>
  <joint name="j0" type="revolute"><parent link="base"/><child link="trunk"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="left_1" type="revolute"><parent link="trunk"/><child link="left_1"/>
    <origin xyz="0 0.2 0.1" rpy="0.3 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="left_2" type="continuous"><parent link="left_1"/><child link={left_q}/>
    <origin xyz="0.25 0 0"/><axis xyz="0 1 0"/></joint>
  <joint name="right_1" type="{right_joint}"><parent link="trunk"/><child link="right_1"/>
    <origin xyz="0 -0.2 0.1"/><axis xyz="0 0 1"/>{limit if right_joint == "prismatic" else ""}
  </joint>
  <joint name="right_tool" type="fixed"><parent link="right_1"/><child link={right_q}/>
    <origin xyz="0.1 0 0" rpy="0 1.5708 0"/></joint>
  <joint name="camera" type="fixed"><parent link="base"/><child link="camera"/>
    <origin xyz="0.1 0 0.5"/></joint>
</robot>
"""


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    path = tmp_path / "ytree.urdf"
    path.write_text(tree_urdf())
    return path


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def listing(directory: Path) -> dict[str, bytes]:
    """Every entry below ``directory`` (hidden ones included) -> its bytes (b"" for others)."""
    return {
        str(p.relative_to(directory)): p.read_bytes() if p.is_file() else b""
        for p in sorted(directory.rglob("*"))
    }


def one_line_error(err: str) -> str:
    assert err.count("\n") == 1 and err.startswith("urdf2dh: error: "), err
    return err


# --------------------------------------------------------------------------- which chains


def test_all_tips_takes_every_leaf_with_a_moving_joint_in_file_order(capsys, tree):
    code, out, err = run(capsys, "convert", tree, "--all-tips")
    assert code == 0, err
    sections = out.split("\n==> ")
    assert [s.split(" <==\n")[0].removeprefix("==> ") for s in sections] == [
        "left_tip",
        "right_tip",
    ]  # camera (fixed joints only) is skipped
    for section, tip in zip(sections, ("left_tip", "right_tip"), strict=True):
        code, single, _ = run(capsys, "convert", tree, "--tip", tip)
        assert code == 0 and section.split(" <==\n", 1)[1] == single


def test_repeated_tips_keep_their_order_and_may_be_fixed_only(capsys, tree):
    code, out, err = run(
        capsys, "convert", tree, "--tip", "camera", "--tip", "left_tip", "--format", "json"
    )
    assert code == 0, err
    tables = json.loads(out)
    assert list(tables) == ["camera", "left_tip"]
    assert tables["camera"]["joints"] == [] and len(tables["left_tip"]["joints"]) == 3


def test_without_tips_the_default_tip_rule_stays(capsys, tree):
    code, _, err = run(capsys, "convert", tree)  # left_tip and right_tip tie as deepest
    assert code == 2 and "several leaves tie" in one_line_error(err)
    code, _, _ = run(capsys, "convert", tree, "--tip", "right_tip", "-o", tree.parent / "t")
    assert code == 0 and (tree.parent / "t").is_file()  # one --tip: -o is a file


def test_base_below_the_root_and_a_bundled_robots_base(capsys, tree):
    code, out, _ = run(capsys, "convert", tree, "--all-tips", "--base", "trunk", "--format", "yaml")
    assert code == 0
    docs = list(yaml.safe_load_all(out))
    assert [(d["base_link"], d["tip_link"], len(d["joints"])) for d in docs] == [
        ("trunk", "left_tip", 2),
        ("trunk", "right_tip", 1),
    ]
    code, out, _ = run(capsys, "convert", "ur5", "--all-tips", "--format", "json")
    assert code == 0  # ur5's own base is base_link; its leaf 'base' hangs on fixed joints only
    assert [(t["base_link"], t["tip_link"]) for t in json.loads(out).values()] == [
        ("base_link", "ee_link"),
        ("base_link", "tool0"),
    ]


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--tip", "left_tip", "--tip", "left_tip"], "--tip 'left_tip' is given twice"),
        (["--tip", "left_tip", "--tip", "nowhere"], "tip 'nowhere': "),
        (["--all-tips", "--base", "camera"], "no leaf below base link 'camera' has a moving joint"),
        (["--all-tips", "--base", "nowhere"], "unknown base link 'nowhere'"),
    ],
)
def test_bad_tip_choices_are_one_line_errors(capsys, tree, argv, message):
    code, out, err = run(capsys, "convert", tree, *argv)
    assert (code, out) == (2, "") and message in one_line_error(err)


def test_all_tips_with_tip_and_on_a_single_chain_file_are_refused(capsys, tree):
    with pytest.raises(SystemExit) as e:  # argparse: mutually exclusive
        main(["convert", str(tree), "--all-tips", "--tip", "left_tip"])
    assert e.value.code == 2
    assert "not allowed with argument" in capsys.readouterr().err
    code, _, err = run(capsys, "convert", "puma560-nominal", "--all-tips")
    assert code == 2 and "a poe file is a single chain" in one_line_error(err)


# --------------------------------------------------------------------------- stdout


def test_stdout_markdown_has_a_heading_per_tip(capsys, tree):
    code, out, _ = run(capsys, "convert", tree, "--all-tips", "--format", "markdown")
    assert code == 0
    assert [line for line in out.splitlines() if line.startswith("## ")] == [
        "## left_tip",
        "## right_tip",
    ]


def test_stdout_json_and_yaml_hold_each_table_file(capsys, tree):
    for fmt, load in (
        ("json", lambda s: list(json.loads(s).values())),
        ("yaml", lambda s: list(yaml.safe_load_all(s))),
    ):
        code, out, _ = run(
            capsys, "convert", tree, "--all-tips", "--format", fmt, "--convention", "mdh"
        )
        assert code == 0
        singles = []
        for tip in ("left_tip", "right_tip"):
            _, single, _ = run(
                capsys, "convert", tree, "--tip", tip, "--format", fmt, "--convention", "mdh"
            )
            singles.append(yaml.safe_load(single))
        assert load(out) == singles


@pytest.mark.parametrize("fmt", ["csv", "urdf", "poe"])
def test_stdout_refuses_formats_of_one_file_per_chain(capsys, tree, fmt):
    code, out, err = run(capsys, "convert", tree, "--all-tips", "--format", fmt)
    assert (code, out) == (2, "") and "give -o DIR" in one_line_error(err)


# --------------------------------------------------------------------------- -o FILE, -o DIR/


@pytest.mark.parametrize("fmt", ["json", "yaml", "text", "markdown"])
def test_a_file_name_gets_the_one_document_stdout_would(capsys, tree, tmp_path, fmt):
    """``-o tables.json`` is a file, not a directory named tables.json."""
    target = tmp_path / f"tables.{fmt}"
    code, out, err = run(capsys, "convert", tree, "--all-tips", "--format", fmt, "-o", target)
    assert (code, out) == (0, ""), err
    assert target.is_file()
    _, printed, _ = run(capsys, "convert", tree, "--all-tips", "--format", fmt)
    assert target.read_text() == printed
    if fmt == "json":
        assert sorted(json.loads(printed)) == ["left_tip", "right_tip"]


def test_one_file_per_chain_needs_a_directory(capsys, tree, tmp_path):
    for argv in (
        ["convert", tree, "--all-tips", "--format", "csv", "-o", tmp_path / "tables.csv"],
        ["export", tree, "--all-tips", "--to", "rtb", "-o", tmp_path / "robots.py"],
    ):
        code, out, err = run(capsys, *argv)
        assert (code, out) == (2, "")
        assert "give -o DIR/ (a trailing slash, or an existing directory)" in one_line_error(err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ytree.urdf"]
    existing = tmp_path / "existing"  # an existing directory needs no slash
    existing.mkdir()
    code, _, err = run(capsys, "export", tree, "--all-tips", "--to", "rtb", "-o", existing)
    assert code == 0, err
    assert sorted(os.listdir(existing)) == ["left_tip.py", "right_tip.py"]


@pytest.mark.parametrize("fmt", sorted(FORMAT_SUFFIXES))
def test_a_new_directory_gets_one_file_per_tip(capsys, tree, tmp_path, fmt):
    out_dir = tmp_path / "tables"
    code, out, err = run(
        capsys, "convert", tree, "--all-tips", "--format", fmt, "-o", f"{out_dir}/"
    )
    assert (code, out) == (0, ""), err
    suffix = FORMAT_SUFFIXES[fmt]
    assert sorted(os.listdir(out_dir)) == [f"left_tip{suffix}", f"right_tip{suffix}"]
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(out_dir.stat().st_mode) == 0o777 & ~umask
    for tip in ("left_tip", "right_tip"):
        single = tmp_path / f"single{suffix}"
        assert run(capsys, "convert", tree, "--tip", tip, "--format", fmt, "-o", single)[0] == 0
        written = out_dir / f"{tip}{suffix}"
        assert written.read_bytes() == single.read_bytes()
        assert stat.S_IMODE(written.stat().st_mode) == 0o666 & ~umask
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["ytree.urdf", "tables", f"single{suffix}"]
    )  # no temporary directory left


def test_an_existing_directory_keeps_other_files_and_modes(capsys, tree, tmp_path):
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    (out_dir / "notes.txt").write_text("mine")
    (out_dir / "left_tip.json").write_text("old")
    (out_dir / "left_tip.json").chmod(0o640)
    code, _, err = run(capsys, "convert", tree, "--all-tips", "--format", "json", "-o", out_dir)
    assert code == 0, err
    assert sorted(os.listdir(out_dir)) == ["left_tip.json", "notes.txt", "right_tip.json"]
    assert (out_dir / "notes.txt").read_text() == "mine"
    assert json.loads((out_dir / "left_tip.json").read_text())["tip_link"] == "left_tip"
    assert stat.S_IMODE((out_dir / "left_tip.json").stat().st_mode) == 0o640
    link = tmp_path / "link"  # a symbolic link to a directory is that directory
    link.symlink_to(out_dir)
    assert run(capsys, "convert", tree, "--all-tips", "--format", "csv", "-o", link)[0] == 0
    assert (out_dir / "right_tip.csv").is_file() and link.is_symlink()


def failing_runs(tmp_path: Path) -> list[tuple[list[str], int, tuple[str, ...]]]:
    """Runs over several chains of which one fails: (argv, exit code, parts of the message)."""
    floating = tmp_path / "floating.urdf"
    floating.write_text(tree_urdf(right_joint="floating"))
    planar = tmp_path / "planar.urdf"
    planar.write_text(tree_urdf(right_joint="planar"))
    good = tmp_path / "good.urdf"
    good.write_text(tree_urdf())
    return [
        (
            ["convert", str(floating), "--all-tips"],
            2,
            (
                "tip 'right_tip': ",
                "floating.urdf: joint 'right_1' on the chain 'base' -> 'right_tip' is floating",
            ),
        ),
        (
            ["convert", str(planar), "--all-tips", "--format", "yaml"],
            2,
            ("tip 'right_tip': ", "planar.urdf: joint 'right_1' on the chain", "is planar"),
        ),
        (
            ["convert", str(good), "--tip", "left_tip", "--tip", "nowhere", "--format", "csv"],
            2,
            ("tip 'nowhere': ", "good.urdf: unknown tip link 'nowhere'"),
        ),
        (
            ["export", str(floating), "--all-tips", "--to", "rtb"],
            2,
            ("tip 'right_tip': ", "joint 'right_1'"),
        ),
        (
            ["export", "ur5", "--all-tips", "--to", "ur"],
            2,
            ("tip 'ee_link': ur: ur_macro.xacro puts tool0 on D-H frame 6",),
        ),
    ]


def test_a_failing_tip_leaves_no_new_directory(capsys, tmp_path):
    for argv, code, message in failing_runs(tmp_path):
        before = sorted(os.listdir(tmp_path))
        got, _, err = run(capsys, *argv, "-o", f"{tmp_path / 'out'}/")
        assert got == code and all(m in one_line_error(err) for m in message)
        assert sorted(os.listdir(tmp_path)) == before  # no DIR, no temporary directory


def test_a_failing_tip_leaves_an_existing_directory_as_it_was(capsys, tmp_path):
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    (out_dir / "left_tip.txt").write_text("old")
    (out_dir / "other").write_text("kept")
    before = listing(out_dir)
    for argv, code, message in failing_runs(tmp_path):
        got, _, err = run(capsys, *argv, "-o", out_dir)
        assert got == code and all(m in one_line_error(err) for m in message)
        assert listing(out_dir) == before


def test_a_table_failing_its_self_check_fails_the_run(capsys, tree, tmp_path, monkeypatch):
    """Exit 1, naming the tip, and nothing written (the failing check is forced: no real chain
    of this tree fails it)."""
    from urdf2dh.conventions import choice, convert
    from urdf2dh.errors import ConversionError

    real = convert.checked  # the conversion and self-check behind to_table and choose

    def failing(model, *args, **kwargs):
        if model.tip_link == "right_tip":
            raise ConversionError("self-check failed (forced)")
        return real(model, *args, **kwargs)

    monkeypatch.setattr(convert, "checked", failing)
    monkeypatch.setattr(choice, "checked", failing)  # convert's table without --convention
    code, out, err = run(capsys, "convert", tree, "--all-tips", "-o", f"{tmp_path / 'out'}/")
    assert (code, out) == (1, "")
    assert "tip 'right_tip': self-check failed" in one_line_error(err)
    assert not (tmp_path / "out").exists()


def test_what_is_not_a_regular_file_is_never_replaced(capsys, tree, tmp_path):
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    (tmp_path / "elsewhere.txt").write_text("not mine")
    for make in (
        lambda p: p.symlink_to(tmp_path / "elsewhere.txt"),
        lambda p: p.mkdir(),
        lambda p: os.mkfifo(p),
    ):
        make(out_dir / "right_tip.txt")
        before = listing(out_dir)
        code, _, err = run(capsys, "convert", tree, "--all-tips", "-o", out_dir)
        assert code == 2 and "is not a regular file" in one_line_error(err)
        assert listing(out_dir) == before
        entry = out_dir / "right_tip.txt"
        entry.rmdir() if entry.is_dir() and not entry.is_symlink() else entry.unlink()
    assert (tmp_path / "elsewhere.txt").read_text() == "not mine"
    regular = tmp_path / "a-file"
    regular.write_text("x")
    code, _, err = run(capsys, "convert", tree, "--all-tips", "-o", f"{regular}/")
    assert code == 2 and "is not a directory" in one_line_error(err)
    code, _, err = run(capsys, "convert", tree, "--all-tips", "-o", f"{tmp_path / 'no' / 'dir'}/")
    assert code == 2 and "does not exist" in one_line_error(err)


def test_the_source_file_is_never_written_over(capsys, tmp_path):
    source = tmp_path / "left_tip.urdf"
    source.write_text(tree_urdf())
    before = source.read_bytes()
    code, _, err = run(capsys, "convert", source, "--all-tips", "--format", "urdf", "-o", tmp_path)
    assert code == 2 and "is the SOURCE file" in one_line_error(err)
    assert source.read_bytes() == before and sorted(os.listdir(tmp_path)) == ["left_tip.urdf"]


def test_a_rename_failing_midway_puts_everything_back(tmp_path, monkeypatch):
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    (out_dir / "a.txt").write_text("old a")
    before = listing(out_dir)
    real, calls = os.replace, []

    def replace(src, dst):
        calls.append(dst)
        if len(calls) == 2:  # after a.txt is replaced, b.txt's rename fails
            raise OSError(28, "No space left on device")
        real(src, dst)

    monkeypatch.setattr(os, "replace", replace)
    with pytest.raises(files.InputError, match="No space left on device"):
        files.write_directory({"a.txt": "new a", "b.txt": "new b"}, str(out_dir))
    assert listing(out_dir) == before


# --------------------------------------------------------------------------- tip names


@pytest.mark.parametrize(
    "name, why",
    [
        ("a/b", "it holds '/'"),
        ("..", "'.' or '..'"),
        (".", "'.' or '..'"),
        ("a\\b", "it holds '\\\\'"),
        ("a\nb", "control character"),
        ("a\tb", "control character"),
        ("-rf", "starts with '-'"),
        ("x" * 252, "at most 255 bytes"),
    ],
)
def test_a_tip_that_cannot_be_a_file_name_is_refused(capsys, tmp_path, name, why):
    source = tmp_path / "t.urdf"
    source.write_text(tree_urdf(left=name))
    code, _, err = run(capsys, "convert", source, "--all-tips", "-o", f"{tmp_path / 'out'}/")
    assert code == 2
    assert f"tip link {shown(name)} cannot name a file" in one_line_error(err) and why in err
    assert sorted(os.listdir(tmp_path)) == ["t.urdf"]
    code, out, err = run(capsys, "convert", source, "--all-tips")  # stdout needs no file name
    assert code == 0, err
    headings = [line for line in out.splitlines() if line.startswith("==> ")]
    heading = name if name.isprintable() else repr(name)
    assert headings == [f"==> {heading} <==", "==> right_tip <=="]


def test_tips_differing_only_in_case_are_refused(capsys, tmp_path):
    source = tmp_path / "t.urdf"
    source.write_text(tree_urdf(left="Tip", right="tip"))
    code, _, err = run(
        capsys, "export", source, "--all-tips", "--to", "kdl", "-o", f"{tmp_path / 'out'}/"
    )
    assert code == 2 and "'Tip' and 'tip' differ only in case" in one_line_error(err)
    assert not (tmp_path / "out").exists()


# --------------------------------------------------------------------------- verify, export


def test_verify_reports_each_chain(capsys, tree):
    code, out, err = run(capsys, "verify", tree, "--all-tips", "--samples", "20")
    assert code == 0, err
    assert "ytree: base -> left_tip, 3 joints;" in out
    assert "ytree: base -> right_tip, 2 joints;" in out
    assert out.count("  ok\n") == 2 * (1 + len(NAMES)) and "FAILED" not in out
    assert out.endswith("verify: all conventions agree with Pinocchio on all 2 chains\n")


def test_verify_exits_1_when_one_chain_disagrees(capsys, tree, monkeypatch):
    """Pinocchio's answer is shifted by 1 mm for the left chain only: that chain fails, the
    other is still reported."""
    real = verify.pinocchio_evaluator

    def shifted(source, model):
        evaluate = real(source, model)

        def moved(q):
            poses = evaluate(q)
            if model.tip_link == "left_tip":
                poses[:, 0, 3] += 1e-3
            return poses

        return moved

    monkeypatch.setattr(verify, "pinocchio_evaluator", shifted)
    code, out, err = run(capsys, "verify", tree, "--all-tips", "--samples", "5")
    assert code == 1
    assert "-> left_tip" in out and "-> right_tip" in out
    assert "FAILED on base -> left_tip for POE model" in err
    assert err.splitlines()[-1] == "verify: FAILED on 1 of 2 chains: 'left_tip'"


def test_verify_goes_on_past_a_table_failing_its_self_check(capsys, tree, monkeypatch):
    from urdf2dh.errors import ConversionError

    real = verify.to_table

    def failing(model, conv, *args, **kwargs):
        if model.tip_link == "left_tip" and conv == "mdh":
            raise ConversionError("self-check failed (forced)")
        return real(model, conv, *args, **kwargs)

    monkeypatch.setattr(verify, "to_table", failing)
    code, out, err = run(capsys, "verify", tree, "--all-tips", "--samples", "5")
    assert code == 1 and "-> right_tip" in out
    assert err.splitlines() == [
        "verify: tip 'left_tip': self-check failed (forced)",
        "verify: FAILED on 1 of 2 chains: 'left_tip'",
    ]


def test_verify_refuses_a_chain_through_a_floating_joint(capsys, tmp_path):
    source = tmp_path / "floating.urdf"
    source.write_text(tree_urdf(right_joint="planar"))
    code, out, err = run(capsys, "verify", source, "--all-tips", "--samples", "5")
    assert (code, out) == (2, "")
    assert "joint 'right_1' on the chain 'base' -> 'right_tip' is planar" in one_line_error(err)
    code, out, _ = run(capsys, "verify", source, "--tip", "left_tip", "--tip", "camera")
    assert code == 0 and "on all 2 chains" in out


def test_export_writes_one_file_per_tip_with_the_targets_suffix(capsys, tmp_path):
    out_dir = tmp_path / "rtb"
    code, _, err = run(
        capsys,
        "export",
        "ur5",
        "--tip",
        "tool0",
        "--tip",
        "ee_link",
        "--to",
        "rtb",
        "-o",
        f"{out_dir}/",
    )
    assert code == 0, err
    assert sorted(os.listdir(out_dir)) == ["ee_link.py", "tool0.py"]
    for tip in ("tool0", "ee_link"):
        code, single, _ = run(capsys, "export", "ur5", "--tip", tip, "--to", "rtb")
        assert (out_dir / f"{tip}.py").read_text() == single
    code, out, err = run(capsys, "export", "ur5", "--all-tips", "--to", "rtb")
    assert (code, out) == (2, "") and "give -o DIR" in one_line_error(err)


def test_the_written_tables_match_their_chains(capsys, tree, tmp_path):
    """Each file of -o DIR, read back as a SOURCE, has the FK of its own chain."""
    from urdf2dh import load

    out_dir = tmp_path / "out"
    assert (
        run(capsys, "convert", tree, "--all-tips", "--format", "json", "-o", f"{out_dir}/")[0] == 0
    )
    rng = np.random.default_rng(13)
    for tip in ("left_tip", "right_tip"):
        model = load(str(tree), tip=tip)
        table = load(str(out_dir / f"{tip}.json"))
        q = rng.uniform(-1.0, 1.0, (20, model.n)) * np.array(
            [1.0 if j.kind == "revolute" else 0.2 for j in model.joints]
        )
        np.testing.assert_allclose(table.fk_batch(q), model.fk_batch(q), atol=1e-12)


PROBE = """
import os, signal, sys
from urdf2dh.cli import main

real, calls = os.{call}, []
def interrupted(path, *args):
    calls.append(path)
    if len(calls) == {when}:
        print(path, flush=True)
        os.kill(os.getpid(), signal.{signal})
    return real(path, *args)
os.{call} = interrupted
sys.exit(main(["convert", sys.argv[1], "--all-tips", "-o", sys.argv[2]]))
"""


def _interrupted(tree: Path, target: Path, call: str, when: int, name: str):
    proc = subprocess.run(
        [sys.executable, "-c", PROBE.format(call=call, when=when, signal=name), tree, target],
        capture_output=True,
        text=True,
        cwd=Path(__file__).resolve().parents[1],
        timeout=120,
    )
    assert proc.stdout.strip() and "Traceback" not in proc.stderr  # the signal was sent
    return proc


@pytest.mark.parametrize(("name", "code"), [("SIGTERM", 143), ("SIGINT", 130)])
def test_signals_leave_a_directory_as_it_was(tree, tmp_path, name, code):
    """Interrupted while the files of an existing DIR are written, or before a new DIR's
    rename."""
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    (out_dir / "left_tip.txt").write_text("old")
    before = listing(tmp_path)
    for when, target in ((2, out_dir), (1, f"{tmp_path / 'new'}/")):  # 2nd file's mode; new DIR's
        proc = _interrupted(tree, target, "chmod", when, name)
        assert proc.returncode == code, proc.stderr
        assert listing(tmp_path) == before


@pytest.mark.parametrize("name", ["SIGTERM", "SIGINT"])
def test_a_signal_between_two_renames_lets_them_finish(tree, tmp_path, name):
    """Once the files are being put in place, the run has done its work: all are written."""
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    (out_dir / "left_tip.txt").write_text("old")
    proc = _interrupted(tree, out_dir, "replace", 1, name)
    assert proc.returncode == 0, proc.stderr
    assert sorted(os.listdir(out_dir)) == ["left_tip.txt", "right_tip.txt"]
    assert all("D-H" in (out_dir / f).read_text() for f in os.listdir(out_dir))
