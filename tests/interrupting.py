"""Ctrl-C at a moment of a run of the urdf2dh program, judged: exit 130 with every output as it
was, or a completed run (exit 0) whose outputs were all written before the signal came.

A signal before ``urdf2dh.cli.main`` runs is Python's own Ctrl-C, no output touched: before
Python handles signals (death by SIGINT, nothing printed), while it sets itself up ("Fatal
Python error: init_import_site" or "init_sys_streams", exit 1) or imports ``urdf2dh.cli`` (a
traceback, death by SIGINT). It is judged ``before urdf2dh``.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PROGRAM = "import sys; from urdf2dh.cli import console; console()"
OLD = "old"  # what every output holds before the run
CLOCK_TICK = 0.02  # seconds file times may lag the real time


@dataclass(frozen=True, slots=True)
class Interrupted:
    code: int  # 130 (interrupted) or 0 (completed)
    sent: float | None  # when SIGINT was sent (None: the run had ended)
    before_main: bool = False  # Python's own Ctrl-C, before urdf2dh's code ran


def interrupted_run(argv: list[str], cwd: Path, delay: float | None) -> Interrupted:
    """Run ``urdf2dh argv`` in ``cwd`` and send SIGINT after ``delay`` seconds (``None``: no
    signal)."""
    proc = subprocess.Popen(
        [sys.executable, "-c", PROGRAM, *argv],
        cwd=cwd,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    sent = None
    if delay is not None:
        time.sleep(delay)
    if delay is not None and proc.poll() is None:
        sent = time.time()
        proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=300)
    starting = err.startswith(b"Fatal Python error: init_")  # init_import_site, init_sys_streams
    if proc.returncode == -signal.SIGINT or (proc.returncode == 1 and starting):
        in_main = re.search(rb'urdf2dh[/\\]cli\.py", line \d+, in (?!<module>)', err)
        if in_main or not (err == b"" or b"KeyboardInterrupt" in err):
            raise AssertionError(f"exit {proc.returncode}: " + err.decode(errors="replace"))
        return Interrupted(130, sent, before_main=True)
    if b"Traceback" in err or b"internal error" in err:
        raise AssertionError(err.decode(errors="replace"))
    return Interrupted(proc.returncode, sent)


def judge(run: Interrupted, outputs: list[Path]) -> str:
    """``interrupted``, ``before urdf2dh`` or ``completed``; an ``AssertionError`` saying what is
    wrong otherwise."""
    directory = outputs[0].parent
    left = sorted(p.name for p in directory.iterdir() if p.name.startswith("."))
    assert left == [], f"temporary files left: {left}"
    if run.code == 130:
        assert run.sent is not None
        changed = [p.name for p in outputs if p.read_text() != OLD]
        assert changed == [], f"exit 130 but {changed} changed"
        return "before urdf2dh" if run.before_main else "interrupted"
    assert run.code == 0, f"exit {run.code}"
    for p in outputs:
        assert p.read_text() not in (OLD, ""), f"exit 0, but {p.name} was not written"
        late = run.sent is not None and p.stat().st_mtime > run.sent + CLOCK_TICK
        assert not late, f"exit 0, but {p.name} was written after the signal"
    return "completed"
