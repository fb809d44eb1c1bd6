"""A xacro file is a program (docs/security.md): nothing from the working directory runs, its
expressions are checked before xacro evaluates them, the child it runs in can neither start
processes nor write files, whatever it starts dies with it, and what it prints is bounded."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
import tracemalloc
from pathlib import Path
from xml.sax.saxutils import quoteattr

import pytest
from xacro_corpus import survivors as _processes_with

from urdf2dh.cli import main
from urdf2dh.io import child
from urdf2dh.io.xacro_child import refusal

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "xacro"
DEMO = DATA / "demo_arm.urdf.xacro"
DEMO_PACKAGE = ["--package-path", f"demo_description={DATA / 'demo_description'}"]
CONFINE = ROOT / "urdf2dh" / "io" / "confine.py"


def xacro_file(path: Path, link_name: str, body: str = "") -> Path:
    """A one-link xacro robot whose link name is ``link_name`` (an expression, say)."""
    path.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        f"{body}<link name={quoteattr(link_name)}/></robot>"
    )
    return path


def processes_with(token: str, settle: float = 1.0) -> list[int]:
    """The pids of the processes whose command line holds ``token``, after up to ``settle``
    seconds for killed ones to be gone."""
    deadline = time.monotonic() + settle
    while (found := _processes_with(token)) and time.monotonic() < deadline:
        time.sleep(0.02)
    return found


def one_line_error(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


# --------------------------------------------------------------------------- planted modules

PLANTED = ("json", "yaml", "xacro", "ast", "re", "enum", "string", "resource", "ctypes",
           "sitecustomize", "usercustomize", "math", "xml")  # fmt: skip


def plant(directory: Path, marker: Path) -> None:
    for name in PLANTED:
        (directory / f"{name}.py").write_text(
            f"open({str(marker)!r}, 'a').write({name!r} + ' from {directory.name}\\n')\n"
        )


def test_modules_in_the_working_directory_or_pythonpath_never_run(tmp_path, monkeypatch, capsys):
    marker = tmp_path / "ran"
    cwd, hostile, home = tmp_path / "cwd", tmp_path / "pythonpath", tmp_path / "home"
    user_site = home / ".local" / "lib" / f"python{sys.version_info[0]}.{sys.version_info[1]}"
    for d in (cwd, hostile, user_site / "site-packages"):
        d.mkdir(parents=True)
    plant(cwd, marker)
    plant(hostile, marker)
    plant(user_site / "site-packages", marker)
    monkeypatch.chdir(cwd)
    monkeypatch.setenv("PYTHONPATH", str(hostile))
    monkeypatch.setenv("PYTHONSTARTUP", str(hostile / "json.py"))
    monkeypatch.setenv("HOME", str(home))
    assert main(["convert", str(DEMO), *DEMO_PACKAGE, "--format", "csv"]) == 0
    assert "wrist_joint" in capsys.readouterr().out
    assert not marker.exists(), marker.read_text()


def test_a_parent_that_imports_from_its_working_directory_still_expands(tmp_path):
    """``python -m urdf2dh.cli`` puts the working directory first on the parent's path: the
    child still finds the installed xacro, never the one planted there."""
    marker = tmp_path / "ran"
    (tmp_path / "xacro.py").write_text(f"open({str(marker)!r}, 'w').write('xacro')\n")
    argv = ["convert", str(DEMO), *DEMO_PACKAGE, "--format", "csv"]
    code = (
        f"import sys; sys.path[:0] = ['', {str(ROOT)!r}]; from urdf2dh.cli import main; "
        f"sys.exit(main({argv!r}))"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    assert "wrist_joint" in proc.stdout and not marker.exists()


# --------------------------------------------------------------------------- strict evaluation

ESCAPE = (
    "(lambda: [c for c in ().__class__.__base__.__subclasses__() "
    "if c.__name__ == '_wrap_close'][0].__init__.__globals__['system']"
    "('sh -c \"sleep 2; touch {marker}\" & sleep 30 # {token}'))()"
)


def test_a_sandbox_escape_is_refused_and_runs_nothing(tmp_path, capsys):
    """xacro 2.1.1 runs this lambda (it checks names at the top level only): a shell command
    and a background process that outlives the expansion."""
    marker, token = tmp_path / "escaped", f"urdf2dh-test-{os.getpid()}-escape"
    source = xacro_file(
        tmp_path / "evil.urdf.xacro", "${" + ESCAPE.format(marker=marker, token=token) + "}"
    )
    out = tmp_path / "out.urdf"
    out.write_text("old")
    assert main(["convert", str(source), "-o", str(out)]) == 2
    err = one_line_error(capsys)
    assert f"{source}: refused xacro expression ${{(lambda: [c for c" in err
    assert "a lambda is not allowed (docs/security.md)" in err
    time.sleep(3)
    assert not marker.exists() and processes_with(token) == []
    assert out.read_text() == "old"


@pytest.mark.parametrize(
    ("expression", "why"),
    [
        ("(lambda: 1)()", "a lambda is not allowed"),
        ("[g for g in [(x for x in [1])]][0].gi_frame", "a generator expression is not allowed"),
        ("(n := 3)", "an assignment expression (:=) is not allowed"),
        ("__import__('os')", "the name '__import__' is not allowed"),
        ("[].__class__", "the attribute '.__class__' is not allowed"),
        ("xacro.load_yaml._private", "the attribute '._private' is not allowed"),
        ("str.format('x', 1)", "'.format()' is allowed on a string literal only"),
        ("('a' + 'b').format(1)", "'.format()' is allowed on a string literal only"),
        ("python.type(1)", "python.type: it hands out any value's class"),
        ("python.vars(python)", "python.vars: it hands out any object's attributes"),
    ],
)
def test_expressions_that_reach_beyond_their_values_are_refused(tmp_path, capsys, expression, why):
    source = xacro_file(tmp_path / "r.xacro", "${" + expression + "}")
    assert main(["info", str(source)]) == 2
    err = one_line_error(capsys)
    assert f"{source}: refused xacro expression $" in err and why in err, err


def test_a_format_field_reading_an_attribute_is_refused():
    """Braces cannot appear inside ``${...}`` (xacro's lexer ends it at the first ``}``), but a
    YAML unit tag's text is evaluated whole."""
    assert (
        refusal("'{0.__class__}'.format(1)")
        == "the format field '{0.__class__}' reads an attribute"
    )
    assert refusal("'{:{0.real}}'.format(1)") == "the format field '{0.real}' reads an attribute"
    assert refusal("'{}_{:.3f}'.format('a', 1.5)") is None


def test_a_yaml_unit_tag_is_checked_too(tmp_path, capsys):
    evil = tmp_path / "evil.yaml"
    evil.write_text('a: !degrees "(lambda: 90)()"\n')
    source = xacro_file(
        tmp_path / "y.xacro", "l${d['a']}",
        body="<xacro:property name=\"d\" value=\"${xacro.load_yaml('evil.yaml')}\"/>",
    )  # fmt: skip
    assert main(["info", str(source)]) == 2
    err = one_line_error(capsys)
    assert f"refused xacro expression ${{(lambda: 90)()}} in {evil}: a lambda" in err


def test_eval_substitutions_see_only_safe_builtins(tmp_path, capsys):
    """``$(eval ...)`` (no parenthesis inside: xacro's lexer ends it at the first one)."""
    ok = xacro_file(tmp_path / "ok.xacro", "l$(eval 2*3+pi)")
    assert main(["info", str(ok)]) == 0 and "root: l9.14159" in capsys.readouterr().out
    bad = xacro_file(tmp_path / "bad.xacro", "l$(eval open)")
    assert main(["info", str(bad)]) == 2
    assert "name 'open' is not defined" in one_line_error(capsys)


UR_STYLE = [  # expressions of Universal Robots' ROS 2 description and xacro's documentation
    "pi/2", "-pi/2", "radians(90)", "math.radians(-45)", "sqrt(2)/2", "d['d1']",
    "kinematics_parameters['kinematics']['shoulder']['x']", "sec_dict.shoulder.x",
    "xacro.load_yaml(kinematics_parameters_file)", "prefix + 'base_link'",
    "'true' if use_fake_hardware else 'false'", "joint_limit_parameters['max_velocity']",
    "safety_limits and not transmission_hw_interface", "[1, 2, 3][-1]", "len(joints) > 0",
    "python.sorted(names)", "[x * 2 for x in range(3)]", "{'a': 1}['a']", "'%.3f' % value",
    "'{}_link'.format(prefix)", "str(int(2.7))", "xacro.arg('ur_type')", "abs(-1) + min(1, 2)",
    "f'{prefix}_joint'", "math.pi * 2 if flip else 0", "dict(a=1).get('a')",
]  # fmt: skip


@pytest.mark.parametrize("expression", UR_STYLE)
def test_expressions_of_real_descriptions_are_allowed(expression):
    assert refusal(expression) is None


def test_a_ur_style_description_expands(tmp_path, capsys):
    """Macros, properties, a YAML file, dotted and indexed access, radians(), conditionals."""
    (tmp_path / "kin.yaml").write_text(
        "kinematics:\n  shoulder: {x: 0, y: 0, z: 0.1625, roll: 0, pitch: 0, yaw: 0}\n"
        "  upper_arm: {x: 0, y: 0, z: 0, roll: 1.570796327, pitch: 0, yaw: 0}\n"
    )
    (tmp_path / "arm.urdf.xacro").write_text(textwrap.dedent("""\
        <robot name="ur" xmlns:xacro="http://www.ros.org/wiki/xacro">
          <xacro:arg name="flip" default="false"/>
          <xacro:property name="kin" value="${xacro.load_yaml('kin.yaml')['kinematics']}"/>
          <xacro:property name="sh" value="${kin['shoulder']}"/>
          <xacro:macro name="j" params="name parent child k limit:=${pi}">
            <link name="${child}"/>
            <joint name="${name}" type="revolute">
              <parent link="${parent}"/><child link="${child}"/>
              <origin xyz="${k.x} ${k['y']} ${k.z}" rpy="${k.roll} ${k.pitch} ${k.yaw}"/>
              <axis xyz="0 0 1"/>
              <limit lower="${-limit}" upper="${limit}" effort="1" velocity="${radians(180)}"/>
            </joint>
          </xacro:macro>
          <link name="base_link"/>
          <xacro:j name="shoulder_pan_joint" parent="base_link" child="shoulder_link" k="${sh}"/>
          <xacro:unless value="$(arg flip)">
            <xacro:j name="shoulder_lift_joint" parent="shoulder_link" child="upper_arm_link"
                     k="${kin.upper_arm}" limit="${2*pi if kin.upper_arm.x == 0 else pi}"/>
          </xacro:unless>
        </robot>
        """))  # fmt: skip
    assert main(["convert", str(tmp_path / "arm.urdf.xacro"), "--format", "json"]) == 0
    table = json.loads(capsys.readouterr().out)
    assert [j["name"] for j in table["joints"]] == ["shoulder_pan_joint", "shoulder_lift_joint"]
    assert table["joints"][0]["params"]["d"] == pytest.approx(0.1625)


# --------------------------------------------------------------------------- confinement

CONFINED = """
import importlib.util, json, os, sys
spec = importlib.util.spec_from_file_location("confine", {confine!r})
confine = importlib.util.module_from_spec(spec); spec.loader.exec_module(confine)
import ctypes, socket, subprocess
assert confine.forbid_syscalls()
libc = ctypes.CDLL(None, use_errno=True)
results = {{"libc fork": libc.fork() == -1 and ctypes.get_errno() == 1}}
def refused(name, call):
    try:
        call()
    except OSError:
        results[name] = True
    else:
        results[name] = False
if {guard}:
    opened = []
    confine.guard(opened)
refused("os.fork", os.fork)
refused("subprocess", lambda: subprocess.run(["true"]))
try:
    results["os.system"] = os.system("true") != 0  # fork() fails: -1
except OSError:
    results["os.system"] = True
refused("write", lambda: open({out!r}, "w"))
refused("append", lambda: os.open({out!r}, os.O_WRONLY | os.O_CREAT))
refused("unlink", lambda: os.unlink({existing!r}))
refused("rename", lambda: os.rename({existing!r}, {out!r}))
refused("socket", socket.socket)
refused("kill init", lambda: os.kill(1, 0))
if not {guard}:
    os.kill(os.getpid(), 0)  # itself: allowed by the filter (the audit hook refuses any)
results["read"] = open({existing!r}).read() == "keep"
print(json.dumps(results))
"""


@pytest.mark.skipif(
    not sys.platform.startswith("linux") or os.uname().machine not in ("x86_64", "aarch64"),
    reason="the seccomp filter is for Linux on x86-64 and AArch64",
)
@pytest.mark.parametrize("guard", [False, True])
def test_the_child_cannot_start_processes_or_change_files(tmp_path, guard):
    """The seccomp filter alone (machine code calling fork() through ctypes included), and with
    the audit hook on top."""
    existing = tmp_path / "existing"
    existing.write_text("keep")
    code = CONFINED.format(confine=str(CONFINE), guard=guard, out=str(tmp_path / "new"),
                           existing=str(existing))  # fmt: skip
    proc = subprocess.run(
        [sys.executable, "-I", "-S", "-c", code], capture_output=True, text=True, timeout=60
    )
    assert proc.returncode == 0, proc.stderr
    results = json.loads(proc.stdout)
    assert all(results.values()) and len(results) == 11, results
    assert sorted(os.listdir(tmp_path)) == ["existing"] and existing.read_text() == "keep"


def test_the_child_dies_with_urdf2dh(tmp_path):
    """urdf2dh killed with SIGKILL (no chance to clean up): the expansion ends with it."""
    source = xacro_file(tmp_path / "slow.xacro", "${9**9**9}")
    script = (
        f"import sys; sys.path.insert(0, {str(ROOT)!r}); from urdf2dh.cli import main; "
        f"main(['info', {str(source)!r}, '--xacro-timeout', '120'])"
    )
    parent = subprocess.Popen([sys.executable, "-c", script])
    try:
        children: list[int] = []
        for _ in range(200):  # wait for its child
            children = [p for p in _processes_with("xacro_child.py") if _parent_of(p) == parent.pid]
            if children:
                break
            time.sleep(0.05)
        assert children, "the expansion did not start"
    finally:
        parent.kill()
        parent.wait()
    for _ in range(100):
        if not any(Path(f"/proc/{p}").exists() and _parent_of(p) != 0 for p in children):
            break
        time.sleep(0.05)
    assert [p for p in children if Path(f"/proc/{p}").exists() and _state(p) != "Z"] == []


def _parent_of(pid: int) -> int:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return 0
    return int(stat.rsplit(")", 1)[1].split()[1])


def _state(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return "gone"


# --------------------------------------------------------------------------- the process group

# the token comes reversed: only the background process's command line holds it
BACKGROUND = """
import subprocess, sys, time
subprocess.Popen(["sh", "-c", "sleep 2; touch {marker}"])
subprocess.Popen(["sh", "-c", "sleep 60; echo " + "{token}"[::-1]])
print("started", flush=True)
{then}
"""


@pytest.mark.parametrize(
    ("then", "outcome"),
    [
        ("", "finished"),
        ("time.sleep(60)", "timed out"),
        ("sys.stderr.write('x' * 10**6)", "overflow"),
    ],
)
def test_what_the_child_starts_dies_with_it(tmp_path, then, outcome):
    """On every way out of :func:`child.run`: the child's end, its time, an output limit."""
    marker, token = tmp_path / "late", f"urdf2dh-test-{os.getpid()}-{len(then)}"
    program = BACKGROUND.format(marker=marker, token=token[::-1], then=then)
    try:  # within 1 s, before the background process would write its marker
        done = child.run([sys.executable, "-c", program], b"", {}, 1.0, 10**6, 10**5)
        got = "finished" if done.stdout == b"started\n" else repr(done)
    except child.TimedOut:
        got = "timed out"
    except child.Overflow:
        got = "overflow"
    assert got == outcome
    assert processes_with(token) == []
    time.sleep(2.0)
    assert not marker.exists()


def test_ctrl_c_in_urdf2dh_kills_the_childs_group(tmp_path):
    token = f"urdf2dh-test-{os.getpid()}-sigint"
    program = BACKGROUND.format(marker=tmp_path / "late", token=token[::-1], then="time.sleep(60)")
    script = (
        f"import sys; sys.path.insert(0, {str(ROOT)!r}); from urdf2dh.io import child\n"
        f"try:\n    child.run([sys.executable, '-c', {program!r}], b'', {{}}, 60, 10**6, 10**6)\n"
        "except KeyboardInterrupt:\n    sys.exit(130)\n"
    )
    parent = subprocess.Popen([sys.executable, "-c", script])
    for _ in range(200):
        if _processes_with(token):
            break
        time.sleep(0.05)
    assert _processes_with(token), "the child did not start"
    parent.send_signal(signal.SIGINT)
    assert parent.wait(30) == 130
    assert processes_with(token) == []


def test_floods_are_read_within_a_small_bound():
    """A child printing without end: only the limit is read, and little of it kept."""
    flood = "import sys\nwhile True:\n    sys.stderr.write('x' * 65536)\n"
    tracemalloc.start()
    try:
        with pytest.raises(child.Overflow) as caught:
            child.run([sys.executable, "-c", flood], b"", {}, 30.0, 2**20, 64 * 2**20)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert caught.value.stream == "stderr" and peak < 2**20, peak
    with pytest.raises(child.Overflow) as caught:
        child.run([sys.executable, "-c", flood.replace("stderr", "stdout")], b"", {}, 30.0, 1000, 1)
    assert caught.value.stream == "stdout"


def test_a_xacro_printing_in_a_loop_is_stopped(tmp_path, capsys):
    """400 bytes that print xacro.message without end."""
    source = xacro_file(
        tmp_path / "flood.xacro", "${[xacro.message('x' * 1000) for i in range(10**9)]}"
    )
    assert len(source.read_bytes()) < 400
    assert main(["info", str(source)]) == 2
    assert "printed more than 1 MiB of messages" in one_line_error(capsys)
