"""What a xacro expansion may read (docs/security.md): beneath the SOURCE's directory and the
``--package-path`` directories only. Every route xacro offers to another file is refused with a
one-line error naming it (exit 2, no output written), and Linux's Landlock makes the kernel hold
to it in the expansion process, for machine code too."""

from __future__ import annotations

import errno
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from urdf2dh.cli import main
from urdf2dh.io import xacro
from urdf2dh.io.confine import landlock_abi

ROOT = Path(__file__).resolve().parents[1]
CONFINE = ROOT / "urdf2dh" / "io" / "confine.py"
ARM_PACKAGE = ROOT / "tests" / "data" / "xacro" / "arm_description"
KERNEL_ABI = landlock_abi()
needs_landlock = pytest.mark.skipif(
    KERNEL_ABI == 0,
    reason="this kernel has no Landlock (Linux 5.13 on; the development machine and CI have it)",
)
SECRET = "outside-secret-7f3a"
ROBOT = """<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">{body}<link name="base"/>
<link name="{link}"/><joint name="j" type="revolute"><parent link="base"/><child link="{link}"/>
<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"""
INCLUDED = """<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
<xacro:property name="included" value="included"/></robot>"""


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    """``robot/`` (where the SOURCE goes) beside ``common/`` (an include, a YAML file, a secret),
    with the working directory at ``robot/``."""
    (tmp_path / "robot").mkdir()
    common = tmp_path / "common"
    common.mkdir()
    (common / "inc.xacro").write_text(INCLUDED)
    (common / "values.yaml").write_text(f"name: {SECRET}\n")
    return tmp_path


def write_source(tree: Path, body: str = "", link: str = "tip") -> Path:
    source = tree / "robot" / "r.urdf.xacro"
    source.write_text(ROBOT.format(body=body, link=link))
    return source


def refused(capsys: pytest.CaptureFixture[str], argv: list[str], out: Path, file: str) -> str:
    """Run ``argv`` writing to ``out``: exit 2, a one-line error naming ``file``, no output."""
    assert main([*argv, "-o", str(out)]) == 2
    captured = capsys.readouterr()
    err = captured.err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert f"xacro may not read {file}" in err, err
    assert "--package-path NAME=DIR" in err, err
    assert SECRET not in captured.out + err and "root:" not in captured.out
    assert not out.exists()
    return err


INCLUDE = '<xacro:include filename="{}"/>'
LOAD_YAML = '<xacro:property name="v" value="${{xacro.load_yaml(\'{}\')}}"/>'


def test_an_include_outside_the_sources_directory_is_refused(tree, capsys, monkeypatch):
    monkeypatch.chdir(tree / "robot")
    source = write_source(tree, INCLUDE.format("../common/inc.xacro"))
    refused(capsys, ["convert", str(source), "--format", "urdf"], tree / "out.urdf",
            str(tree / "common" / "inc.xacro"))  # fmt: skip


def test_the_same_include_is_read_once_its_directory_is_given(tree, capsys, monkeypatch):
    """Given with --package-path (under any name), relative to the working directory, both
    through the relative include and through $(find)."""
    monkeypatch.chdir(tree / "robot")
    for include in ("../common/inc.xacro", "$(find common)/inc.xacro"):
        source = write_source(tree, INCLUDE.format(include), link="${included}")
        out = tree / "out.urdf"
        argv = ["convert", "r.urdf.xacro", "--package-path", "common=../common"]
        assert main([*argv, "--format", "urdf", "-o", str(out)]) == 0, capsys.readouterr().err
        assert '<link name="included"' in out.read_text()
        out.unlink()
    assert source.exists()


def test_load_yaml_outside_is_refused_and_allowed_once_given(tree, capsys):
    source = write_source(tree, LOAD_YAML.format("../common/values.yaml"), link="${v['name']}")
    out = tree / "out.urdf"
    refused(capsys, ["convert", str(source), "--format", "urdf"], out,
            str(tree / "common" / "values.yaml"))  # fmt: skip
    package = ["--package-path", f"values={tree / 'common'}"]
    assert main(["convert", str(source), *package, "--format", "urdf", "-o", str(out)]) == 0
    assert f'<link name="{SECRET}"' in out.read_text()


# every route xacro offers from a file to /etc/passwd: (xacro body, link name, extra options)
PASSWD_ROUTES = {
    "absolute include": (INCLUDE.format("/etc/passwd"), "tip", []),
    "relative include": (INCLUDE.format("../" * 40 + "etc/passwd"), "tip", []),
    "optional include": ('<xacro:include filename="/etc/passwd" optional="true"/>', "tip", []),
    "glob include": (INCLUDE.format("/etc/pass*"), "tip", []),
    "load_yaml": (LOAD_YAML.format("/etc/passwd"), "${v}", []),
    "argument": (LOAD_YAML.format("$(arg f)"), "${v}", ["--xacro-arg", "f:=/etc/passwd"]),
    "package:// climbing out": (INCLUDE.format("package://pkg/" + "../" * 40 + "etc/passwd"),
                                "tip", ["--package-path", "pkg={tree}/common"]),
    "$(find) climbing out": (INCLUDE.format("$(find pkg)/" + "../" * 40 + "etc/passwd"), "tip",
                             ["--package-path", "pkg={tree}/common"]),
    "symbolic link in the tree": (INCLUDE.format("link.xacro"), "tip", []),
}  # fmt: skip


@pytest.mark.parametrize("route", PASSWD_ROUTES)
def test_etc_passwd_is_refused_by_every_route(tree, capsys, route):
    body, link, options = PASSWD_ROUTES[route]
    (tree / "robot" / "link.xacro").symlink_to("/etc/passwd")
    source = write_source(tree, body, link)
    extra = [o.format(tree=tree) for o in options]
    err = refused(capsys, ["convert", str(source), *extra, "--format", "urdf"],
                  tree / "out.urdf", "")  # fmt: skip
    assert "/etc" in err  # the file, or the directory a glob would list


def test_a_symbolic_link_inside_the_tree_is_named_with_its_target(tree, capsys):
    (tree / "robot" / "link.xacro").symlink_to(tree / "common" / "inc.xacro")
    source = write_source(tree, INCLUDE.format("link.xacro"))
    refused(
        capsys,
        ["convert", str(source), "--format", "urdf"],
        tree / "out.urdf",
        f"{tree / 'robot' / 'link.xacro'} (a link to {tree / 'common' / 'inc.xacro'})",
    )


def test_a_source_that_is_a_link_reads_beside_itself_and_its_target(tree, capsys):
    """The SOURCE given as a symbolic link: its includes resolve beside the link (as xacro
    resolves them); the file the link names is read wherever it lies."""
    real = write_source(tree, INCLUDE.format("inc.xacro"), link="${included}")
    (tree / "common" / "r.urdf.xacro").symlink_to(real)
    out = tree / "out.urdf"
    argv = ["convert", str(tree / "common" / "r.urdf.xacro"), "--format", "urdf", "-o", str(out)]
    assert main(argv) == 0, capsys.readouterr().err
    assert '<link name="included"' in out.read_text()


# --------------------------------------------------------------------------- the kernel's layer

LANDLOCKED = """
import errno, importlib.util, json, os
spec = importlib.util.spec_from_file_location("confine", {confine!r})
confine = importlib.util.module_from_spec(spec)
spec.loader.exec_module(confine)
inside = {inside!r}
abi = confine.restrict_reading([inside])

def outcome(action):
    try:
        action()
    except OSError as e:
        return errno.errorcode[e.errno]
    return "done"

print(json.dumps({{
    "abi": abi,
    "read inside": outcome(lambda: open(os.path.join(inside, "mine")).read()),
    "list inside": outcome(lambda: os.listdir(inside)),
    "read outside": outcome(lambda: os.close(os.open({outside!r}, os.O_RDONLY))),
    "list outside": outcome(lambda: os.listdir({outside_dir!r})),
    "read /etc/passwd": outcome(lambda: open("/etc/passwd").read()),
    "write inside": outcome(lambda: open(os.path.join(inside, "mine"), "a").write("x")),
    "create inside": outcome(lambda: open(os.path.join(inside, "new"), "x")),
    "mkdir inside": outcome(lambda: os.mkdir(os.path.join(inside, "dir"))),
    "remove inside": outcome(lambda: os.unlink(os.path.join(inside, "mine"))),
}}))
"""


@needs_landlock
def test_landlock_makes_the_kernel_refuse_reads_outside_and_every_change(tree):
    """:func:`restrict_reading` alone, without the seccomp filter or the audit hook: plain
    ``open``/``os.open`` calls get ``EACCES`` from the kernel."""
    inside = tree / "robot"
    (inside / "mine").write_text("mine")
    code = LANDLOCKED.format(confine=str(CONFINE), inside=str(inside),
                             outside=str(tree / "common" / "values.yaml"),
                             outside_dir=str(tree / "common"))  # fmt: skip
    proc = subprocess.run(
        [sys.executable, "-I", "-S", "-c", code], capture_output=True, text=True, timeout=60
    )
    assert proc.returncode == 0, proc.stderr
    results = json.loads(proc.stdout)
    assert results.pop("abi") == KERNEL_ABI
    assert results.pop("read inside") == "done" and results.pop("list inside") == "done"
    assert set(results.values()) == {errno.errorcode[errno.EACCES]}, results
    assert sorted(os.listdir(inside)) == ["mine"] and (inside / "mine").read_text() == "mine"


@needs_landlock
def test_the_expansion_runs_under_the_kernels_landlock_abi():
    """The expansion process reports the Landlock ABI it applied: the kernel's."""
    source = ARM_PACKAGE / "urdf" / "arm.urdf.xacro"
    options = xacro.XacroOptions(
        packages={"arm_description": str(ARM_PACKAGE)}, args={"name": "a", "arm_type": "small"}
    )
    job = xacro.job(source, options, xacro.module_dirs(str(source)))
    proc = subprocess.run(xacro.child_argv(), input=job, capture_output=True, timeout=60, env={})
    assert proc.returncode == 0, proc.stderr
    header, _, text = proc.stdout.partition(b"\n")
    result = json.loads(header)
    assert result["landlock"] == KERNEL_ABI >= 1
    assert b'<robot name="a"' in text
    assert str(ARM_PACKAGE / "config" / "small" / "dims.yaml") in result["read"]


def test_a_source_directly_in_the_home_directory_does_not_open_it(tmp_path, capsys, monkeypatch):
    """A SOURCE right in the home directory reads nothing beside it (``~/.ssh`` lies there); the
    message says why and what to do. In a directory of its own it reads its includes again."""
    home = tmp_path / "home"
    (home / ".ssh").mkdir(parents=True)
    (home / ".ssh" / "id_rsa").write_text(SECRET)
    (home / "inc.xacro").write_text(INCLUDED)
    monkeypatch.setenv("HOME", str(home))
    for include in (".ssh/id_rsa", "inc.xacro"):
        source = home / "r.urdf.xacro"
        source.write_text(ROBOT.format(body=INCLUDE.format(include), link="tip"))
        err = refused(capsys, ["convert", str(source), "--format", "urdf"], tmp_path / "o.urdf",
                      str(home / include))  # fmt: skip
        assert f"the SOURCE lies directly in {home}" in err, err
        assert "put the description in a directory of its own" in err, err
    own = home / "robot"
    own.mkdir()
    (own / "inc.xacro").write_text(INCLUDED)
    source = own / "r.urdf.xacro"
    source.write_text(ROBOT.format(body=INCLUDE.format("inc.xacro"), link="${included}"))
    assert main(["convert", str(source), "--format", "urdf", "-o", str(tmp_path / "o.urdf")]) == 0
    assert 'name="included"' in (tmp_path / "o.urdf").read_text()
