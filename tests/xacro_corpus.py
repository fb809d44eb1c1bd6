"""The hostile xacro corpus: xacro files that try to run code, outlive urdf2dh or flood it, each
expanded by the ``urdf2dh`` program in a working directory full of planted modules.

Case ``n`` is one attack (:data:`ATTACKS`) put in one place of a xacro document (:data:`PLACES`):
the corpus is every attack in every place (:func:`cases`). Every attack that runs would leave a
marker file in the case's directory, or a process whose command line holds the case's token;
the planted modules (``json.py``, ``yaml.py``, ``xacro.py``, ``sitecustomize.py``, ... in the
working directory and in ``PYTHONPATH``) would leave one too. A case ends in

* ``refused``: exit 2, one line on stderr naming the file;
* ``expanded``: exit 0 (the benign cases only);

or in a failure: ``code ran`` (a marker appeared, or a process outlived the run), ``internal
error`` (a traceback, "internal error", another exit code, more than one line), ``attack
expanded``, ``memory`` (urdf2dh itself grew past :data:`MEMORY_BOUND`).

The program runs as ``python -E -P -c ...``: like the installed ``urdf2dh`` script, neither its
working directory nor ``PYTHONPATH`` is on its own path (that is the user's interpreter's
business); the environment still holds the hostile ``PYTHONPATH`` for the child to ignore.
"""

from __future__ import annotations

import os
import random
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import quoteattr

import yaml

ROOT = Path(__file__).resolve().parents[1]
FAILURES = ("code ran", "internal error", "attack expanded", "memory")
MEMORY_BOUND = 400 * 2**20  # bytes of resident memory urdf2dh itself may reach (numpy loaded)
LATE = 1.5  # seconds after which a background process of an attack writes its marker
PLANTED = ("json", "yaml", "xacro", "ast", "re", "enum", "string", "math", "resource", "ctypes",
           "sitecustomize", "usercustomize", "glob", "copy", "xml")  # fmt: skip


def _shell(marker: str, token: str) -> str:
    """A shell command that writes ``marker`` at once and again later, from the background."""
    return f"touch {marker}; (sleep {LATE}; touch {marker}.late; sleep 60; echo {token}) &"


def _subclass_escape(command: str) -> str:
    return (
        "(lambda: [c for c in ().__class__.__base__.__subclasses__() if c.__name__ == "
        f"'_wrap_close'][0].__init__.__globals__['system']({command!r}))()"
    )


ATTACKS = {  # name -> (expression builder(marker, token), whether it is benign)
    "lambda escape": (lambda m, t: _subclass_escape(_shell(m, t)), False),
    "lambda fork bomb": (
        lambda m, t: "(lambda: [xacro.load_yaml.__globals__['os'].fork() for i in range(10**6)])()",
        False,
    ),
    "lambda os via globals": (
        lambda m, t: f"(lambda: xacro.load_yaml.__globals__['os'].system({_shell(m, t)!r}))()",
        False,
    ),
    "generator frame": (
        lambda m, t: "[g for g in [(x for x in [1])]][0].gi_frame.f_globals",
        False,
    ),
    "dunder import": (lambda m, t: f"__import__('os').system({_shell(m, t)!r})", False),
    "dunder builtins": (lambda m, t: "__builtins__", False),
    "private attribute": (lambda m, t: "xacro.load_yaml.__globals__", False),
    "format on a variable": (lambda m, t: "('a' + 'b').format(xacro)", False),
    "python.vars": (lambda m, t: "python.vars(python.dict)", False),
    "python.type": (lambda m, t: "python.type(xacro.load_yaml)", False),
    "walrus": (lambda m, t: "(python := 1)", False),
    "message flood": (lambda m, t: "[xacro.message('x' * 4000) for i in range(10**9)]", False),
    "warning flood": (lambda m, t: "[xacro.warning('y' * 4000) for i in range(10**9)]", False),
    "endless": (lambda m, t: "9**9**9", False),
    "huge string": (lambda m, t: "len('x' * 10**10)", False),
    "math": (lambda m, t: "radians(90) + pi / 2 + math.sqrt(2)", True),
    "comprehension": (lambda m, t: "python.sum([i * 2 for i in range(10)])", True),
    "formatting": (lambda m, t: "int('%d%d' % (1, 2))", True),
}
PLACES = ("link name", "property", "macro argument", "condition", "include", "yaml tag")


@dataclass(frozen=True, slots=True)
class Case:
    seed: int
    attack: str
    place: str
    benign: bool


def cases() -> list[Case]:
    """Every attack in every place (a benign value is no condition: not there)."""
    pairs = [(a, p) for a in ATTACKS for p in PLACES if not (ATTACKS[a][1] and p == "condition")]
    return [Case(n, a, p, ATTACKS[a][1]) for n, (a, p) in enumerate(pairs)]


def sample(count: int, seed: int) -> list[Case]:
    """``count`` cases drawn with ``seed``."""
    return random.Random(seed).sample(cases(), count)


def write_case(c: Case, directory: Path, token: str) -> Path:
    """The case's xacro file (and the files it includes) in ``directory``."""
    expression = ATTACKS[c.attack][0](str(directory / "marker"), token)
    inner = "${" + expression + "}"
    head = '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
    if c.place == "link name":
        body = f"<link name={quoteattr('l' + inner)}/>"
    elif c.place == "property":
        body = f'<xacro:property name="p" value={quoteattr(inner)}/><link name="l${{p}}"/>'
    elif c.place == "macro argument":
        body = (
            '<xacro:macro name="m" params="a"><link name="l${a}"/></xacro:macro>'
            f"<xacro:m a={quoteattr(inner)}/>"
        )
    elif c.place == "condition":
        body = f'<xacro:if value={quoteattr(inner)}><link name="x"/></xacro:if><link name="l"/>'
    elif c.place == "include":
        (directory / "inner.xacro").write_text(
            f"{head}<link name={quoteattr('l' + inner)}/></robot>"
        )
        body = '<xacro:include filename="inner.xacro"/>'
    else:  # yaml tag: evaluated by xacro.load_yaml's unit constructors
        text = yaml.safe_dump({"a": expression}, width=2**20)
        (directory / "values.yaml").write_text(text.replace("a: ", "a: !radians ", 1))
        body = ("<xacro:property name=\"v\" value=\"${xacro.load_yaml('values.yaml')}\"/>"
                "<link name=\"l${v['a']}\"/>")  # fmt: skip
    path = directory / "robot.urdf.xacro"
    path.write_text(f"{head}{body}</robot>")
    return path


def plant(directory: Path, marker: Path) -> None:
    """Modules that would write ``marker`` if anything imported them."""
    for name in PLANTED:
        (directory / f"{name}.py").write_text(f"open({str(marker)!r}, 'a').write({name!r})\n")


@dataclass(frozen=True, slots=True)
class Verdict:
    case: Case
    result: str  # refused, expanded, or one of FAILURES
    detail: str
    seconds: float
    max_rss: int  # bytes


# urdf2dh, then its own peak resident memory (VmHWM: this program's, after exec; the rusage of a
# child counts the memory of the process it was forked from, pytest's included) into ../peak
PROGRAM = (
    f"import sys; sys.path.insert(0, {str(ROOT)!r}); from urdf2dh.cli import console\n"
    "try:\n    console()\nfinally:\n"
    "    hwm = [l for l in open('/proc/self/status') if l.startswith('VmHWM:')]\n"
    "    open('../peak', 'w').write(hwm[0].split()[1] if hwm else '')\n"
)


def run_case(c: Case, directory: Path) -> tuple[subprocess.Popen[bytes], str, float]:
    """Start the case (``urdf2dh info``) in ``directory``; the process, its token, its start."""
    token = f"urdf2dh-xacro-corpus-{os.getpid()}-{c.seed}"
    (directory / "cwd").mkdir()
    (directory / "pythonpath").mkdir()
    plant(directory / "cwd", directory / "marker.planted")
    plant(directory / "pythonpath", directory / "marker.planted")
    source = write_case(c, directory, token)
    env = {**os.environ, "PYTHONPATH": str(directory / "pythonpath")}
    argv = [sys.executable, "-E", "-P", "-c", PROGRAM, "info", str(source), "--xacro-timeout", "3"]
    proc = subprocess.Popen(
        argv, cwd=directory / "cwd", env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    return proc, token, time.perf_counter()


def judge(c: Case, directory: Path, proc: subprocess.Popen[bytes], started: float) -> Verdict:
    """Wait for the case's run and judge what it left (markers are looked for again later)."""
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    seconds = time.perf_counter() - started
    assert proc.stdout is not None and proc.stderr is not None
    proc.stdout.read()
    err = proc.stderr.read().decode("utf-8", "replace")
    rss = usage.ru_maxrss * 1024
    peak = directory / "peak"
    if peak.is_file() and peak.read_text().strip().isdigit():
        rss = int(peak.read_text()) * 1024  # urdf2dh's own (kB)
    code = proc.returncode

    def verdict(result: str, detail: str = "") -> Verdict:
        return Verdict(c, result, detail or err.strip()[:300], seconds, rss)

    if markers(directory):
        return verdict("code ran", ", ".join(markers(directory)))
    if "Traceback" in err or "internal error" in err or code not in (0, 2):
        return verdict("internal error", f"exit {code}: {err[-300:]}")
    if rss > MEMORY_BOUND:
        return verdict("memory", f"{rss / 2**20:.0f} MiB")
    if code == 0:
        return verdict("expanded" if c.benign else "attack expanded")
    if err.count("\n") != 1 or "robot.urdf.xacro" not in err:
        return verdict("internal error", f"not one line naming the file: {err[:300]}")
    return verdict("refused")


def markers(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir() if p.name.startswith("marker"))


def survivors(token: str) -> list[int]:
    """Processes whose command line holds ``token``."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                if token.encode() in (entry / "cmdline").read_bytes():
                    found.append(int(entry.name))
            except OSError:
                pass
    return found


def failed(v: Verdict) -> bool:
    return v.result in FAILURES or (v.result == "refused" and v.case.benign)
