"""Ctrl-C at any moment ends a run with 130 and leaves -o as it was, even where a library swallows
the KeyboardInterrupt (trimesh catches BaseException around its optional imports, which yourdfpy
runs) or an import is under way; a run exits 0 only if its file was written before the signal
came."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from interrupting import OLD, interrupted_run, judge

from urdf2dh.io import interrupts

ROOT = Path(__file__).resolve().parents[1]

SWALLOWED = """
import os, signal, sys
sys.path.insert(0, {root!r})

class Interrupt:  # Ctrl-C while yourdfpy's element parsers load (trimesh's transformations)
    def find_spec(self, name, path=None, target=None):
        if name.endswith("trimesh.transformations"):
            sys.meta_path.remove(self)
            os.kill(os.getpid(), signal.{signal})
        return None

sys.meta_path.insert(0, Interrupt())
from urdf2dh.cli import main
sys.exit(main(["convert", "ur5", "-o", sys.argv[1]]))
"""


@pytest.mark.parametrize(("name", "code"), [("SIGINT", 130), ("SIGTERM", 143)])
def test_a_signal_while_the_urdf_reader_loads_ends_the_run(tmp_path, name, code):
    """A signal while yourdfpy's element parsers are loaded (urdf2dh/io/urdf/_yourdfpy.py, in
    the middle of trimesh's modules) ends the run with its code, nothing written, no internal
    error."""
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


def test_an_interrupt_a_library_swallowed_is_raised_again_before_writing():
    with interrupts.handled():
        try:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(1.0)  # KeyboardInterrupt is raised here
            raise AssertionError("no KeyboardInterrupt")
        except KeyboardInterrupt:
            pass  # as a library catching BaseException does
        assert interrupts.pending()
        with pytest.raises(KeyboardInterrupt):
            interrupts.check()
        assert interrupts.exit_code(0) == 130
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_a_signal_during_an_import_is_held_until_it_is_done(tmp_path):
    module = tmp_path / "slow_module_for_interrupts.py"
    module.write_text("import os, signal, time\nos.kill(os.getpid(), signal.SIGINT)\n"
                      "time.sleep(0.3)\nDONE = True\n")  # fmt: skip
    sys.path.insert(0, str(tmp_path))
    try:
        with interrupts.handled(), pytest.raises(KeyboardInterrupt):
            import slow_module_for_interrupts  # noqa: F401

            time.sleep(1.0)  # raised here, once the import is done
        assert sys.modules["slow_module_for_interrupts"].DONE  # imported whole
    finally:
        sys.path.remove(str(tmp_path))
        sys.modules.pop("slow_module_for_interrupts", None)


DELAYS = np.sort(np.random.default_rng(18).uniform(0.0, 2.5, 6))


@pytest.mark.parametrize("delay", DELAYS, ids=lambda d: f"{d:.2f}s")
def test_ctrl_c_at_any_moment(tmp_path, delay):
    """scripts/interrupt_corpus.py runs more commands at more moments."""
    target = tmp_path / "table.txt"
    target.write_text(OLD)
    run = interrupted_run(["convert", "ur5", "-o", str(target)], tmp_path, float(delay))
    judge(run, [target])
