"""A failed write to stdout is an error like any other: ``urdf2dh ... > /dev/full`` exits 2 with
one line on stderr, for every command's help and usage (argparse would ignore it) and for every
text a command prints (the tables, ``robots``, ``info``, verify's report, calibrate's summary).
A reader that goes away (``| head``) is not an error."""

from __future__ import annotations

import contextlib
import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

from urdf2dh import cli

FULL = Path("/dev/full")
ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.skipif(not FULL.exists(), reason="no /dev/full on this system")

COMMANDS = [
    "convert",
    "verify",
    "diff",
    "info",
    "export",
    "plot",
    "robots",
    "measure",
    "calibrate",
    "plan",
    "match",
]


def test_every_command_is_listed_here():
    parser = cli.get_argument_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    assert sorted(sub.choices) == sorted(COMMANDS)


def _to_full(argv: list[str]) -> tuple[int, str]:
    """``urdf2dh argv`` in-process with stdout on /dev/full: exit code and stderr."""
    err = io.StringIO()
    with open(FULL, "w", encoding="utf-8") as full, contextlib.redirect_stderr(err):
        with contextlib.redirect_stdout(full):
            try:
                code = cli.main(argv)
            except SystemExit as e:
                code = e.code if isinstance(e.code, int) else 2
    return code, err.getvalue()


@pytest.mark.parametrize("argv", [["-h"], ["--version"], [], *([c, "-h"] for c in COMMANDS)])
def test_help_and_usage_that_cannot_be_written_fail(argv):
    code, err = _to_full(argv)
    assert (code, err) == (2, "urdf2dh: error: stdout: cannot write (No space left on device)\n")


@pytest.fixture(scope="module")
def measurements(tmp_path_factory):
    path = tmp_path_factory.mktemp("m") / "m.csv"
    assert cli.main(["measure", "ur5", "--configs", "30", "-o", str(path)]) == 0
    return str(path)


OUTPUTS = [
    ["robots"],
    ["info", "ur5"],
    ["convert", "ur5"],
    ["convert", "ur5", "--format", "csv"],
    ["convert", "ur5", "--all-tips", "--format", "json"],
    ["verify", "ur5", "--samples", "20"],
    ["diff", "puma560-nominal", "puma560-actual"],
    ["export", "ur5", "--to", "rtb"],
    ["measure", "ur5", "--configs", "5"],
    ["plan", "ur5", "--configs", "3"],
    ["convert", "ur5", "-o", str(FULL)],
    ["plot", "ur5", "-o", str(FULL)],
    ["match", str(ROOT / "robots" / "references" / "ur5-dh.yaml"), "ur5"],
    ["match", str(ROOT / "robots" / "references" / "ur5-dh.yaml"), "ur5", "-o", str(FULL)],
]


@pytest.mark.parametrize("argv", OUTPUTS, ids=[" ".join(a[:2]) for a in OUTPUTS])
def test_output_that_cannot_be_written_fails(argv):
    code, err = _to_full(argv)
    assert code == 2 and err.count("\n") == 1 and err.startswith("urdf2dh: error: "), err
    assert "internal error" not in err


def test_calibrates_summary_that_cannot_be_written_fails(measurements, tmp_path):
    out = tmp_path / "model.yaml"
    code, err = _to_full(["calibrate", "ur5", measurements, "-o", str(out)])
    assert (code, err) == (2, "urdf2dh: error: stdout: cannot write (No space left on device)\n")


def _run(args: list[str], stdout) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run(
        [sys.executable, "-m", "urdf2dh.cli", *args],
        stdout=stdout,
        stderr=subprocess.PIPE,
        text=True,
        cwd=ROOT,
        env=env,
        timeout=120,
    )


@pytest.mark.parametrize("args", [["--help"], ["robots"], ["convert", "ur5"]])
def test_the_process_exits_2_with_one_line(args):
    with open(FULL, "w") as full:
        got = _run(args, full)
    assert (got.returncode, got.stderr) == (
        2,
        "urdf2dh: error: stdout: cannot write (No space left on device)\n",
    )


def test_a_reader_going_away_is_not_an_error():
    for args in (["--help"], ["robots"]):
        p = subprocess.Popen(
            [sys.executable, "-m", "urdf2dh.cli", *args],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            cwd=ROOT,
            env={**os.environ, "PYTHONPATH": str(ROOT)},
        )
        assert p.stdout is not None and p.stdout.read(10)
        p.stdout.close()  # before the command has written everything
        assert p.wait(timeout=120) == 0 and p.stderr is not None and p.stderr.read() == b""
