"""The overwrite corpus: every command, every input it reads named as one of its outputs in every
way a file can be named, two outputs naming one file, and outputs failing halfway.

A :class:`Workspace` holds inputs of every kind (URDF, xacro with an included macro file and a
YAML file it loads, a table file, a POE file, measurements, a marker layout, a nominal model,
example-robot-data's files as copies (``EXAMPLE_ROBOT_DATA_DIR``) and this project's bundled
``robots/`` file itself). :func:`cases` lists the runs; :func:`run_case` runs one through
``urdf2dh.cli.main`` and judges it:

* ``refused``: exit 2, one line on stderr, and no file changed;
* ``written`` (an expected output only: the next step of a fault case);

or a failure: ``input overwritten`` (a file the run read changed), ``half-written`` (an output
changed though the run failed), ``not refused`` (exit 0 with an input as output), ``internal
error`` (a traceback, "internal error", another exit code, more than one line), ``bad
refusal`` (refused for another reason than the case's: :data:`REASONS`). An output named with a
suffix whose format the command does not write, or that ``--format`` contradicts, is refused
for that before anything is read (:data:`NAMED`): a refusal too.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import os
import random
import shutil
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from urdf2dh.cli import main
from urdf2dh.io import files
from urdf2dh.io.catalog import ROBOTS, our_robots_dir, robot_path

ROOT = Path(__file__).resolve().parents[1]
FAILURES = ("input overwritten", "half-written", "not refused", "bad refusal", "internal error")
REASONS = {  # what the one line of a refusal says, by kind of case
    "input as output": "refusing to write over it",
    "same file": "two outputs of one run cannot go to one file",
    "fault": "cannot write",
}
# the refusal of an output whose name says another format (urdf2dh.cli.options.output_format)
NAMED = ("which {command} does not write; its formats are", "the suffix chooses")
XACRO = ["arm_description/urdf/arm.urdf.xacro", "--package-path",
         "arm_description=arm_description", "--xacro-arg", "name:=a", "--xacro-arg",
         "arm_type:=small"]  # fmt: skip
OURS = "scara"  # a robot of this project's robots/: its installed file is an input too
ERD_UR5 = "erd/ur_description/urdf/ur5_robot.urdf"


class Workspace:
    """A directory of inputs of every kind; :meth:`snapshot` digests every file a run could
    change (the workspace's and the bundled ``robots/`` file)."""

    def __init__(self, directory: Path) -> None:
        self.dir = directory
        self.ours = robot_path(ROBOTS[OURS])
        self._ours_bytes = self.ours.read_bytes()
        shutil.copy(ROOT / "tests" / "data" / "genser6.urdf", directory / "arm.urdf")
        shutil.copytree(ROOT / "tests" / "data" / "xacro" / "arm_description",
                        directory / "arm_description")  # fmt: skip
        erd = directory / "erd" / "ur_description" / "urdf"
        erd.mkdir(parents=True)
        shutil.copy(robot_path(ROBOTS["ur5"]), erd / "ur5_robot.urdf")
        shutil.copy(our_robots_dir() / "puma560-nominal.yaml", directory / "nominal.yaml")
        (directory / "links").mkdir()
        (directory / "dirlink").symlink_to(directory / "arm_description" / "config")
        with self.inside():
            for argv in (
                ["convert", "arm.urdf", "--format", "json", "-o", "table.json"],
                ["convert", "arm.urdf", "--format", "poe", "-o", "model.poe.yaml"],
                ["measure", "puma560-actual", "--configs", "30", "--seed", "1", "-o", "poses.csv"],
                ["measure", "puma560-actual", "--configs", "30", "--seed", "1", "--markers", "3",
                 "--marker-layout", "layout.csv", "-o", "markers.csv"],
            ):  # fmt: skip
                code, _, err = quiet(argv)
                if code != 0:
                    raise RuntimeError(f"workspace: {argv}: {err}")

    @contextlib.contextmanager
    def inside(self) -> Iterator[None]:
        """In the workspace, with example-robot-data's files taken from its copies."""
        cwd, erd = os.getcwd(), os.environ.get("EXAMPLE_ROBOT_DATA_DIR")
        os.chdir(self.dir)
        os.environ["EXAMPLE_ROBOT_DATA_DIR"] = str(self.dir / "erd")
        try:
            yield
        finally:
            os.chdir(cwd)
            if erd is None:
                del os.environ["EXAMPLE_ROBOT_DATA_DIR"]
            else:
                os.environ["EXAMPLE_ROBOT_DATA_DIR"] = erd

    def snapshot(self) -> dict[str, str]:
        out = {}
        for p in [*sorted(self.dir.rglob("*")), self.ours]:
            if p.is_symlink():
                out[str(p)] = "-> " + os.readlink(p)
            elif p.is_file():
                out[str(p)] = hashlib.sha256(p.read_bytes()).hexdigest()
        return out

    def restore_ours(self) -> None:
        """Put the bundled robot's file back, should a failing case have changed it."""
        if self.ours.read_bytes() != self._ours_bytes:
            self.ours.write_bytes(self._ours_bytes)

    def name(self, path: str, form: str, n: int) -> str:
        """Another name of ``path``: ``given``, ``dotted`` (``./``), ``absolute``, ``symlink``,
        ``hardlink`` (made in ``links/``) or ``dirlink`` (through a linked directory)."""
        target = Path(path) if Path(path).is_absolute() else self.dir / path
        if form == "given":
            return path
        if form == "dotted":
            return f"./{path}" if not Path(path).is_absolute() else path
        if form == "absolute":
            return str(target)
        if form == "symlink":
            link = self.dir / "links" / f"sym{n}{target.suffix}"
            link.unlink(missing_ok=True)
            link.symlink_to(target)
            return str(link)
        if form == "hardlink":
            link = self.dir / "links" / f"hard{n}{target.suffix}"
            link.unlink(missing_ok=True)
            os.link(target, link)
            return str(link)
        if form == "dirlink" and target.parent == self.dir / "arm_description" / "config":
            return str(self.dir / "dirlink" / target.name)
        return str(target)


def quiet(argv: list[str]) -> tuple[int, str, str]:
    """``urdf2dh`` in this process: exit code, stdout, stderr."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as e:
            code = e.code if isinstance(e.code, int) else 2
    return code, out.getvalue(), err.getvalue()


# (command, inputs it reads, its output options)
RUNS = [
    (["convert", "arm.urdf"], ["arm.urdf"], ["-o"]),
    (["convert", *XACRO], [XACRO[0], "arm_description/urdf/arm_macro.xacro",
                           "arm_description/config/small/dims.yaml"], ["-o"]),
    (["convert", "ur5"], [ERD_UR5], ["-o"]),
    (["convert", OURS], ["OURS"], ["-o"]),
    (["convert", "table.json"], ["table.json"], ["-o"]),
    (["convert", "model.poe.yaml"], ["model.poe.yaml"], ["-o"]),
    (["convert", "arm.urdf", "--all-tips", "--format", "urdf"], ["arm.urdf"], ["-o DIR"]),
    (["export", "arm.urdf", "--to", "rtb"], ["arm.urdf"], ["-o"]),
    (["export", *XACRO, "--to", "linuxcnc"], ["arm_description/config/small/dims.yaml"], ["-o"]),
    (["export", "arm.urdf", "--all-tips", "--to", "kdl"], ["arm.urdf"], ["-o DIR"]),
    (["diff", "arm.urdf", "table.json"], ["arm.urdf", "table.json"], ["-o"]),
    (["diff", "ur5", *XACRO], [ERD_UR5, "arm_description/urdf/arm_macro.xacro"], ["-o"]),
    (["plot", "arm.urdf"], ["arm.urdf"], ["-o"]),
    (["measure", "arm.urdf", "--configs", "5", "--markers", "2"], ["arm.urdf"],
     ["-o", "--marker-layout"]),
    (["measure", *XACRO, "--configs", "5"], [XACRO[0], "arm_description/config/small/dims.yaml"],
     ["-o"]),
    (["calibrate", "nominal.yaml", "poses.csv"], ["nominal.yaml", "poses.csv"],
     ["-o", "--report"]),
    (["calibrate", "nominal.yaml", "markers.csv", "--marker-layout", "layout.csv"],
     ["layout.csv", "markers.csv", "nominal.yaml"], ["-o", "--report"]),
]  # fmt: skip
FORMS = ("given", "dotted", "absolute", "symlink", "hardlink", "dirlink")


@dataclass(frozen=True)
class Case:
    n: int
    kind: str  # "input as output", "same file", "fault"
    argv: tuple[str, ...]
    outputs: tuple[str, ...] = ()  # the run's outputs that may change only on success
    fault: str = ""  # "rename" or "stage": the second output fails there
    detail: str = field(default="", compare=False)


def _argv(ws: Workspace, command: list[str], option: str, target: str, n: int) -> list[str]:
    """``command`` with the input ``target`` given to ``option`` (the other outputs new)."""
    argv = list(command)
    if option == "-o DIR":
        out = ws.dir / f"out{n}"
        out.mkdir(exist_ok=True)
        from urdf2dh.cli.chains import FORMAT_SUFFIXES
        from urdf2dh.emit.export import TARGETS

        suffix = FORMAT_SUFFIXES["urdf"] if command[0] == "convert" else TARGETS["kdl"].suffix
        tip = "tool" + suffix  # the tip of arm.urdf
        (out / tip).unlink(missing_ok=True)
        os.link(target if Path(target).is_absolute() else ws.dir / target, out / tip)
        return [*argv, "-o", str(out)]
    if option != "-o":
        argv += ["-o", f"new{n}.out"]
    return [*argv, option, target]


def cases(ws: Workspace) -> list[Case]:
    """Every case of the corpus (making the links they name in ``ws``)."""
    out: list[Case] = []
    for command, inputs, options in RUNS:
        for path in inputs:
            path = str(ws.ours) if path == "OURS" else path
            for option in options:
                for form in FORMS if option != "-o DIR" else ("given",):
                    n = len(out)
                    target = ws.name(path, form, n)
                    if command[0] == "plot" and option == "-o":  # its suffix picks the format
                        link = ws.dir / "links" / f"plot{n}.png"
                        os.link(ws.dir / path, link)
                        target = str(link)
                    argv = _argv(ws, command, option, target, n)
                    out.append(Case(n, "input as output", tuple(argv), detail=f"{form} {path}"))
    for command, first, second in (
        (["calibrate", "nominal.yaml", "poses.csv"], "-o", "--report"),
        (["measure", "arm.urdf", "--configs", "5", "--markers", "2"], "-o", "--marker-layout"),
    ):
        for exists in (False, True):
            for form in ("given", "dotted", "absolute", "symlink", "hardlink"):
                if not exists and form in ("symlink", "hardlink"):
                    continue
                n = len(out)
                base = f"twice{n}.out"
                if exists:
                    (ws.dir / base).write_text("old")
                    other = ws.name(base, form, n)
                else:  # a name for a file that does not exist yet
                    other = {"given": base, "dotted": f"./{base}", "absolute": str(ws.dir / base)}
                    other = other[form]
                argv = (*command, first, base, second, other)
                out.append(Case(n, "same file", argv, (base,), detail=f"{form}, exists {exists}"))
    for command, first, second in (
        # the actual PUMA's joints are helical: without --helical the calibration is refused
        (["calibrate", "nominal.yaml", "poses.csv", "--helical", "all"], "-o", "--report"),
        (["measure", "arm.urdf", "--configs", "5", "--markers", "2"], "-o", "--marker-layout"),
    ):
        for fault in ("rename", "stage"):
            for exists in (False, True):
                n = len(out)
                a, b = f"first{n}.out", f"second{n}.out"
                if exists:
                    (ws.dir / a).write_text("old a")
                    (ws.dir / b).write_text("old b")
                argv = (*command, first, a, second, b)
                out.append(Case(n, "fault", argv, (a, b), fault, f"{fault}, exist {exists}"))
    return out


@contextlib.contextmanager
def _fault(kind: str) -> Iterator[None]:
    """The second output fails: at its rename (a full disk) or when its temporary file is made."""
    with pytest.MonkeyPatch.context() as mp:
        if kind == "rename":
            real_replace, calls = os.replace, []

            def replace(src: str, dst: str) -> None:
                calls.append(dst)
                if len(calls) == 2:
                    raise OSError(28, "No space left on device")
                real_replace(src, dst)

            mp.setattr(files.os, "replace", replace)
        elif kind == "stage":
            real_mkstemp, made = tempfile.mkstemp, []

            def mkstemp(*args: object, **kwargs: object) -> tuple[int, str]:
                made.append(1)
                if len(made) == 2:
                    raise OSError(13, "Permission denied")
                return real_mkstemp(*args, **kwargs)  # type: ignore[arg-type]

            mp.setattr(tempfile, "mkstemp", mkstemp)
        yield


@dataclass(frozen=True)
class Verdict:
    case: Case
    result: str
    detail: str


def run_case(ws: Workspace, case: Case) -> Verdict:
    before = ws.snapshot()
    with ws.inside(), _fault(case.fault) if case.fault else contextlib.nullcontext():
        code, _, err = quiet(list(case.argv))
    after = ws.snapshot()
    changed = sorted(k for k in before.keys() | after.keys() if before.get(k) != after.get(k))
    ws.restore_ours()

    def verdict(result: str, detail: str = "") -> Verdict:
        return Verdict(case, result, detail or err.strip()[:300])

    if "Traceback" in err or "internal error" in err or code not in (0, 2):
        return verdict("internal error", f"exit {code}: {err[-300:]}")
    outputs = {str(ws.dir / o) for o in case.outputs}
    inputs_changed = [c for c in changed if c not in outputs]
    if inputs_changed:
        return verdict("input overwritten", ", ".join(inputs_changed))
    if code == 0:
        return verdict("not refused", " ".join(case.argv))
    if changed:
        return verdict("half-written", ", ".join(changed))
    if err.count("\n") != 1:
        return verdict("internal error", f"not one line: {err[:300]}")
    named = any(n.format(command=case.argv[0]) in err for n in NAMED)
    if REASONS[case.kind] not in err and not named:
        return verdict("bad refusal")
    return verdict("refused")


def sample(ws: Workspace, count: int, seed: int) -> list[Case]:
    """``count`` cases drawn with ``seed``."""
    return random.Random(seed).sample(cases(ws), count)
