"""Progress bars are drawn on a terminal only: never into a pipe, a file or a test's capture."""

from __future__ import annotations

import fcntl
import io
import os
import pty
import struct
import subprocess
import sys
import termios
from pathlib import Path

from urdf2dh.progress import enabled, progress

ROOT = Path(__file__).resolve().parents[1]


def test_no_bar_when_stderr_is_not_a_terminal(monkeypatch):
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    assert not enabled()
    assert list(progress(range(5), 5, "work")) == [0, 1, 2, 3, 4]
    assert err.getvalue() == ""


def test_a_bar_on_a_terminal():
    code = (
        "from urdf2dh.progress import enabled, progress\n"
        "assert enabled()\n"
        "print(sum(progress(range(1000), 1000, 'work')))\n"
    )
    main, sub = pty.openpty()
    fcntl.ioctl(sub, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 80, 0, 0))  # an 80-column one
    proc = subprocess.Popen(
        [sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=sub, cwd=ROOT
    )
    os.close(sub)
    drawn = b""
    try:
        while chunk := os.read(main, 65536):  # read while it runs: a pty keeps little
            drawn += chunk
    except OSError:  # the child is gone and the terminal's other end with it
        pass
    os.close(main)
    out, _ = proc.communicate(timeout=60)
    assert proc.returncode == 0
    assert out.strip() == b"499500"
    assert b"work:" in drawn and b"/1000" in drawn  # the bar, cleared at the end
