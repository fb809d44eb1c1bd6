"""Ctrl-C at any moment ends a run with 130 and leaves -o as it was, even where a library swallows
the KeyboardInterrupt (trimesh catches BaseException around its optional imports, which yourdfpy
runs); a run exits 0 only if its file was written before the signal came."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]

SWALLOWED = """
import os, signal, sys
sys.path.insert(0, {root!r})

class Interrupt:  # Ctrl-C while trimesh imports trimesh.path, inside its `except BaseException`
    def find_spec(self, name, path=None, target=None):
        if name == "trimesh.path":
            sys.meta_path.remove(self)
            os.kill(os.getpid(), signal.{signal})
        return None

sys.meta_path.insert(0, Interrupt())
from urdf2dh.cli import main
sys.exit(main(["convert", "ur5", "-o", sys.argv[1]]))
"""


@pytest.mark.parametrize(("name", "code"), [("SIGINT", 130), ("SIGTERM", 143)])
def test_a_signal_a_library_swallowed_still_ends_the_run(tmp_path, name, code):
    target = tmp_path / "table.txt"
    target.write_text("old")
    proc = subprocess.run(
        [sys.executable, "-c", SWALLOWED.format(root=str(ROOT), signal=name), str(target)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == code, proc.stderr
    assert target.read_text() == "old" and os.listdir(tmp_path) == ["table.txt"]
    assert proc.stderr == ""  # no internal error from what the swallowed signal left behind


CONVERT = (
    "import sys; from urdf2dh.cli import console; "
    "sys.argv[1:] = ['convert', 'ur5', '-o', {}]; console()"
)


def interrupted_run(target: Path, delay: float) -> tuple[int, float | None]:
    """Run ``urdf2dh convert ur5 -o target`` (the program: :func:`urdf2dh.cli.console`), send
    SIGINT after ``delay`` seconds: the exit code and when the signal was sent (``None``: the run
    had ended).

    A signal before ``main`` runs (Python starting, ``import urdf2dh.cli``) is Python's own
    Ctrl-C: a traceback of the import and death by SIGINT; from ``main``'s first line on, 130.
    """
    proc = subprocess.Popen(
        [sys.executable, "-c", CONVERT.format(repr(str(target)))],
        cwd=ROOT,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    time.sleep(delay)
    sent = None
    if proc.poll() is None:
        sent = time.time()
        proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    if proc.returncode == -signal.SIGINT:  # before main: no frame of main's in the traceback
        assert b", in main\n" not in err and b", in _run\n" not in err, err
        return 130, sent
    assert b"Traceback" not in err and b"internal error" not in err, err
    return proc.returncode, sent


def check_interrupted(target: Path, code: int, sent: float | None) -> str:
    """Exit 130 with the file as it was, or a completed run whose file was written before the
    signal; anything else fails."""
    names = sorted(os.listdir(target.parent))
    assert names == [target.name], names  # no temporary file left
    if code == 130:
        assert sent is not None and target.read_text() == "old"
        return "interrupted"
    assert code == 0, code
    assert "shoulder_pan_joint" in target.read_text()
    # written before the signal came (file times lag real time by up to a clock tick)
    assert sent is None or target.stat().st_mtime <= sent + 0.02, (target.stat().st_mtime, sent)
    return "completed"


DELAYS = np.sort(np.random.default_rng(18).uniform(0.0, 2.5, 6))


@pytest.mark.parametrize("delay", DELAYS, ids=lambda d: f"{d:.2f}s")
def test_ctrl_c_at_any_moment(tmp_path, delay):
    target = tmp_path / "table.txt"
    target.write_text("old")
    code, sent = interrupted_run(target, float(delay))
    check_interrupted(target, code, sent)
