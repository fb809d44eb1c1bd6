"""Ctrl-C at any moment ends a run with 130 and leaves -o as it was, even where a library swallows
the KeyboardInterrupt (trimesh catches BaseException around its optional imports, which yourdfpy
runs); a run exits 0 only if its file was written before the signal came."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from interrupting import OLD, interrupted_run, judge

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


DELAYS = np.sort(np.random.default_rng(18).uniform(0.0, 2.5, 6))


@pytest.mark.parametrize("delay", DELAYS, ids=lambda d: f"{d:.2f}s")
def test_ctrl_c_at_any_moment(tmp_path, delay):
    """scripts/interrupt_corpus.py runs more commands at more moments."""
    target = tmp_path / "table.txt"
    target.write_text(OLD)
    run = interrupted_run(["convert", "ur5", "-o", str(target)], tmp_path, float(delay))
    judge(run, [target])
