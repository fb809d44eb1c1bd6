"""A seeded corpus of output-path tricks, each run as its own ``urdf2dh`` process: what ``-o``
names (a new file under some umask, an existing file of some mode and owner, a chain of symbolic
links, a dangling link, a hard link, a directory, a read-only file or directory, ``/dev/full``),
a closed stdout, and two writers of one file at once.

    PYTHONPATH=. python scripts/output_corpus.py                 # 120 cases, seed 0
    PYTHONPATH=. python scripts/output_corpus.py --count 40 --seed 3

Every case must hold:

- exit 0 or 2, no traceback and no internal error;
- exit 0: the output holds exactly what a plain run writes; a file written over keeps its mode,
  owner and group, a new file gets ``0666 & ~umask`` and the writer's owner; a symbolic link
  stays a link to the file written;
- exit 2: one line, ``urdf2dh: error: <the output as named>: ...`` (``stdout: ...`` for stdout),
  naming the directory where the directory is what refuses; nothing in the case's directory
  changed;
- always: no other file changed (content, mode, owner, group, link), no temporary file left,
  and no file's owner changed (counted).

Ownership cases need root (they are drawn only then); read-only directories are tried without
``CAP_DAC_OVERRIDE`` (``setpriv``), as a user other than root meets them. The script prints the
cases by class and verdict, then every broken case, and exits 1 if any broke an invariant.
tests/test_output_corpus.py runs a seeded sample.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import shutil
import stat
import subprocess
import sys
import tempfile
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from corpus_main import corpus_main

ROOT = Path(__file__).resolve().parents[1]
Rng = np.random.Generator
ROOTED = os.geteuid() == 0
SETPRIV = shutil.which("setpriv")
COMMANDS = (
    ("convert", "ur5"),
    ("convert", "ur5", "--convention", "hayati"),
    ("convert", str(ROOT / "tests" / "data" / "genser6.urdf"), "--convention", "mdh"),
    ("export", "ur5", "--to", "rtb"),
)
MODES = (0o600, 0o640, 0o644, 0o444, 0o664, 0o2750, 0o666)
UMASKS = (0o022, 0o002, 0o077, 0o027, 0o000)


@dataclass
class Case:
    """What a case sets up and runs: ``setup`` makes the directory's files and returns the
    output as named (``None``: stdout); ``expect`` is ``"written"`` or ``"refused"``."""

    kind: str
    description: str
    command: tuple[str, ...]
    setup: Callable[[Path], str | None]
    expect: str
    umask: int = 0o022
    closed_stdout: bool = False
    unprivileged: bool = False  # run without CAP_DAC_OVERRIDE
    writers: int = 1
    names: tuple[str, ...] = ()  # what a refusal must name besides the output
    target: str = ""  # the file the output lands in, relative to the case's directory
    new: bool = False  # the output is a new file
    extra: dict[str, object] = field(default_factory=dict)


@dataclass(frozen=True, slots=True)
class Outcome:
    case: Case
    codes: tuple[int, ...]
    err: str
    problems: tuple[str, ...]
    owners_changed: int


def _nobody() -> tuple[int, int]:
    import grp
    import pwd

    user = pwd.getpwnam("nobody")
    try:
        group = grp.getgrnam("nogroup").gr_gid
    except KeyError:
        group = user.pw_gid
    return user.pw_uid, group


def _file(path: Path, mode: int, owner: tuple[int, int] | None = None) -> None:
    path.write_text("old content\n")
    if owner is not None:
        os.chown(path, *owner)
    path.chmod(mode)


def make_case(rng: Rng, i: int, commands: tuple[tuple[str, ...], ...] = COMMANDS) -> Case:
    """Case ``i``: its class drawn in turn, its details (and its command, one of ``commands``)
    from ``rng``."""
    classes = [
        k
        for k in CLASSES
        if (ROOTED or k != "owner") and (k != "read-only dir" or SETPRIV or not ROOTED)
    ]
    kind = classes[i % len(classes)]
    command = commands[int(rng.integers(len(commands)))]
    return CLASSES[kind](rng, kind, command)


def new_file(rng: Rng, kind: str, command: tuple[str, ...]) -> Case:
    umask = int(rng.choice(UMASKS))
    name = str(rng.choice(["out.txt", "table.txt", "sub dir/out.txt", "ü.txt", "out"]))

    def setup(d: Path) -> str:
        (d / name).parent.mkdir(exist_ok=True)
        return name

    return Case(kind, f"new {name!r}, umask {umask:03o}", command, setup, "written", umask=umask,
                target=name, new=True)  # fmt: skip


def existing(rng: Rng, kind: str, command: tuple[str, ...]) -> Case:
    mode = int(rng.choice(MODES))
    owner = None
    if kind == "owner":
        uid, gid = _nobody()
        owner = [(uid, gid), (uid, 0), (0, gid)][int(rng.integers(3))]

    def setup(d: Path) -> str:
        _file(d / "out.txt", mode, owner)
        return "out.txt"

    said = f"existing, mode {mode:04o}" + ("" if owner is None else f", owner {owner}")
    return Case(kind, said, command, setup, "written", target="out.txt")


def links(rng: Rng, kind: str, command: tuple[str, ...]) -> Case:
    depth = int(rng.integers(1, 4))
    mode = int(rng.choice(MODES))
    owner = _nobody() if ROOTED and rng.random() < 0.5 else None
    relative = bool(rng.integers(2))

    def setup(d: Path) -> str:
        (d / "real").mkdir()
        _file(d / "real" / "file.txt", mode, owner)
        previous = d / "real" / "file.txt"
        for k in range(depth):
            link = d / f"link{k}"
            link.symlink_to(os.path.relpath(previous, d) if relative else previous)
            previous = link
        return previous.name

    return Case(kind, f"{depth} links ({'relative' if relative else 'absolute'}) to a file "
                f"{mode:04o}", command, setup, "written", target="real/file.txt")  # fmt: skip


def dangling(rng: Rng, kind: str, command: tuple[str, ...]) -> Case:
    def setup(d: Path) -> str:
        (d / "out.txt").symlink_to(d / str(rng.choice(["nowhere", "gone/x.txt"])))
        return "out.txt"

    return Case(kind, "a dangling link", command, setup, "refused")


def hard_link(rng: Rng, kind: str, command: tuple[str, ...]) -> Case:
    mode = int(rng.choice(MODES))

    def setup(d: Path) -> str:
        _file(d / "first.txt", mode)
        os.link(d / "first.txt", d / "second.txt")
        return "second.txt"

    # the file is replaced, not written into: the other name keeps the old content
    return Case(kind, f"a hard link, mode {mode:04o}", command, setup, "written",
                target="second.txt", extra={"unchanged": "first.txt"})  # fmt: skip


def directory(rng: Rng, kind: str, command: tuple[str, ...]) -> Case:
    def setup(d: Path) -> str:
        (d / "out.txt").mkdir()
        (d / "out.txt" / "inside").write_text("x")
        return "out.txt"

    return Case(kind, "a directory", command, setup, "refused")


def read_only_file(rng: Rng, kind: str, command: tuple[str, ...]) -> Case:
    mode = int(rng.choice([0o444, 0o400, 0o000]))

    def setup(d: Path) -> str:
        _file(d / "out.txt", mode)
        return "out.txt"

    # replaced (its directory allows it), keeping its mode, as cp --remove-destination would
    return Case(kind, f"a read-only file {mode:04o}", command, setup, "written", target="out.txt")


def read_only_dir(rng: Rng, kind: str, command: tuple[str, ...]) -> Case:
    there = bool(rng.integers(2))

    def setup(d: Path) -> str:
        (d / "ro").mkdir()
        if there:
            _file(d / "ro" / "out.txt", 0o666)
        (d / "ro").chmod(int(rng.choice([0o555, 0o500, 0o755 if not ROOTED else 0o555])))
        return "ro/out.txt"

    return Case(kind, f"a read-only directory, {'a writable file in it' if there else 'no file'}",
                command, setup, "refused", unprivileged=ROOTED,
                names=("cannot write in directory",))  # fmt: skip


def full(rng: Rng, kind: str, command: tuple[str, ...]) -> Case:
    to_stdout = bool(rng.integers(2))

    def setup(d: Path) -> str | None:
        return None if to_stdout else "/dev/full"

    case = Case(kind, "stdout to /dev/full" if to_stdout else "-o /dev/full", command, setup,
                "refused", names=("No space left on device",))  # fmt: skip
    case.extra["stdout"] = "/dev/full" if to_stdout else None
    return case


def closed_stdout(rng: Rng, kind: str, command: tuple[str, ...]) -> Case:
    to_file = bool(rng.integers(2))

    def setup(d: Path) -> str | None:
        return "out.txt" if to_file else None

    if to_file:  # no file takes stdout's number: the file is as a plain run writes it
        return Case(kind, "stdout closed, -o FILE", command, setup, "written",
                    closed_stdout=True, target="out.txt", new=True)  # fmt: skip
    return Case(kind, "stdout closed", command, setup, "refused", closed_stdout=True,
                names=("stdout: cannot write (it is closed)",))  # fmt: skip


def concurrent(rng: Rng, kind: str, command: tuple[str, ...]) -> Case:
    exists = bool(rng.integers(2))

    def setup(d: Path) -> str:
        if exists:
            _file(d / "out.txt", 0o640)
        return "out.txt"

    return Case(kind, f"{2} writers at once, {'existing' if exists else 'new'} file", command,
                setup, "written", writers=2, target="out.txt", new=not exists)  # fmt: skip


CLASSES: dict[str, Callable[[Rng, str, tuple[str, ...]], Case]] = {
    "new file": new_file,
    "mode": existing,
    "owner": existing,
    "symbolic links": links,
    "dangling link": dangling,
    "hard link": hard_link,
    "directory": directory,
    "read-only file": read_only_file,
    "read-only dir": read_only_dir,
    "/dev/full": full,
    "closed stdout": closed_stdout,
    "concurrent": concurrent,
}


# ----------------------------------------------------------------------------- running


def snapshot(d: Path) -> dict[str, tuple[object, ...]]:
    """Every entry under ``d``: its kind, mode, owner, group, and content or link target."""
    out: dict[str, tuple[object, ...]] = {}
    for root, dirs, files in os.walk(d):
        for name in dirs + files:
            path = Path(root) / name
            st = os.lstat(path)
            if stat.S_ISLNK(st.st_mode):
                what: object = os.readlink(path)
            elif stat.S_ISREG(st.st_mode):
                what = hashlib.sha256(path.read_bytes()).hexdigest()
            else:
                what = "dir"
            out[str(path.relative_to(d))] = (stat.S_IFMT(st.st_mode), stat.S_IMODE(st.st_mode),
                                             st.st_uid, st.st_gid, what)  # fmt: skip
    return out


_REFERENCE: dict[tuple[tuple[str, ...], str], bytes] = {}


def reference(command: tuple[str, ...], name: str) -> bytes:
    """What a plain run of ``command`` writes to a new file named ``name`` (the name's suffix
    may choose the format), once per command and name."""
    key = (command, Path(name).name)
    if key not in _REFERENCE:
        with tempfile.TemporaryDirectory(prefix="urdf2dh-output-reference-") as directory:
            target = Path(directory) / key[1]
            subprocess.run(_argv(command, str(target)), capture_output=True, check=True,
                           env=_env())  # fmt: skip
            _REFERENCE[key] = target.read_bytes()
    return _REFERENCE[key]


def _env() -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": str(ROOT)}


def _argv(command: tuple[str, ...], output: str | None = None) -> list[str]:
    return [sys.executable, "-m", "urdf2dh.cli", *command, *(["-o", output] if output else [])]


def run_case(case: Case, d: Path) -> Outcome:
    output = case.setup(d)
    before = snapshot(d)
    prefix = (
        [SETPRIV, "--bounding-set", "-dac_override,-dac_read_search"] if case.unprivileged else []
    )

    def start() -> subprocess.Popen[bytes]:
        def child() -> None:
            os.umask(case.umask)
            if case.closed_stdout:
                os.close(1)

        sink = case.extra.get("stdout")
        stdout = subprocess.DEVNULL if sink is None else opened.enter_context(open(str(sink), "wb"))
        argv = [*prefix, *_argv(case.command, output)]
        return subprocess.Popen(
            argv, cwd=d, env=_env(), stdout=stdout, stderr=subprocess.PIPE, preexec_fn=child
        )

    with contextlib.ExitStack() as opened:
        procs = [start() for _ in range(case.writers)]
        results = [(p.wait(timeout=120), p.stderr.read().decode() if p.stderr else "")
                   for p in procs]  # fmt: skip
        for p in procs:
            if p.stderr:
                p.stderr.close()
    after = snapshot(d)
    codes = tuple(code for code, _ in results)
    err = "".join(e for _, e in results)
    problems = judge(case, output, codes, results, before, after, d)
    owners = sum(1 for k, v in before.items() if k in after and after[k][2:4] != v[2:4])
    return Outcome(case, codes, err, tuple(problems), owners)


Snapshot = dict[str, tuple[object, ...]]


def judge(
    case: Case,
    output: str | None,
    codes: tuple[int, ...],
    results: list[tuple[int, str]],
    before: Snapshot,
    after: Snapshot,
    d: Path,
) -> list[str]:
    """The invariants of the module docstring that a case's runs break."""
    problems = []
    for code, err in results:
        if "Traceback" in err or "internal error" in err:
            problems.append(f"internal error: {err.strip()[:300]}")
        if code not in (0, 2):
            problems.append(f"exit code {code}")
        want = 0 if case.expect == "written" else 2
        if code != want:
            problems.append(f"exit {code}, not {want} ({case.expect}): {err.strip()[:300]}")
        if code == 2:
            lines = err.splitlines()
            named = output if output is not None else "stdout"
            if len(lines) != 1 or not lines[0].startswith(f"urdf2dh: error: {named}: "):
                problems.append(f"refusal not one line naming {named}: {err[:300]!r}")
            for name in case.names:
                if name not in err:
                    problems.append(f"refusal does not say {name!r}: {err.strip()[:300]}")
        elif code == 0 and err:
            problems.append(f"wrote to stderr: {err[:200]!r}")
    leftovers = [k for k in after if Path(k).name.startswith(".") and k not in before]
    if leftovers:
        problems.append(f"temporary files left: {leftovers}")
    for key, old in before.items():
        if key == case.target and case.expect == "written":
            continue
        if after.get(key) != old:
            problems.append(f"{key} changed: {old} -> {after.get(key)}")
    if case.expect == "written" and codes and codes[0] == 0:
        target = d / case.target
        data = target.read_bytes() if target.exists() else b""
        if data != reference(case.command, output or case.target):
            problems.append(f"{case.target} is not what a plain run writes ({len(data)} bytes)")
        st = os.lstat(target)
        if case.new:
            mode = 0o666 & ~case.umask
            if stat.S_IMODE(st.st_mode) != mode and case.writers == 1:
                problems.append(f"new file mode {stat.S_IMODE(st.st_mode):04o}, not {mode:04o}")
            if st.st_uid != os.geteuid():
                problems.append("new file is not the writer's")
        elif case.target in before:
            old = before[case.target]
            if (stat.S_IMODE(st.st_mode), st.st_uid, st.st_gid) != old[1:4]:
                problems.append(f"{case.target}: mode or owner changed {old[1:4]} -> "
                                f"{(stat.S_IMODE(st.st_mode), st.st_uid, st.st_gid)}")  # fmt: skip
        for key, old in before.items():  # links stay links to the same place
            if old[0] == stat.S_IFLNK and after.get(key) != old:
                problems.append(f"link {key} changed")
        unchanged = case.extra.get("unchanged")
        if unchanged and (d / str(unchanged)).read_text() != "old content\n":
            problems.append(f"{unchanged} (the other hard link) was written into")
    return problems


def run_corpus(
    count: int, seed: int, commands: tuple[tuple[str, ...], ...] = COMMANDS
) -> list[Outcome]:
    """``count`` seeded cases, each run in a fresh directory of its own."""
    rng = np.random.default_rng(seed)
    outcomes = []
    for i in range(count):
        case = make_case(rng, i, commands)
        d = Path(tempfile.mkdtemp(prefix="urdf2dh-output-"))
        try:
            outcomes.append(run_case(case, d))
        finally:
            for path in d.rglob("*"):
                if path.is_dir() and not path.is_symlink():
                    path.chmod(0o755)
            shutil.rmtree(d, ignore_errors=True)
    return outcomes


def report(outcomes: list[Outcome]) -> str:
    lines = [f"{len(outcomes)} output-path cases, {sum(len(o.codes) for o in outcomes)} runs", ""]
    by = Counter((o.case.kind, code) for o in outcomes for code in o.codes)
    for kind in CLASSES:
        codes = ", ".join(f"exit {c}: {n}" for (k, c), n in sorted(by.items()) if k == kind)
        if codes:
            lines.append(f"  {kind:<16} {codes}")
    internal = sum("internal error" in o.err for o in outcomes)
    owners = sum(o.owners_changed for o in outcomes)
    lines += ["", f"internal errors: {internal}; owners changed: {owners}"]
    broken = [o for o in outcomes if o.problems]
    lines += [f"Cases that broke an invariant: {len(broken)}"]
    for o in broken:
        lines.append(f"  {o.case.kind} ({o.case.description}; {' '.join(o.case.command)}): "
                     + "; ".join(o.problems))  # fmt: skip
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    return corpus_main(__doc__, run_corpus, report, 120, argv)


if __name__ == "__main__":
    sys.exit(main())
