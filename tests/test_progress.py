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


def on_a_terminal(argv: list[str]) -> tuple[int, bytes, bytes]:
    """Run ``argv`` with stderr on an 80-column pseudo-terminal: exit code, stdout, and what
    was drawn on the terminal."""
    main, sub = pty.openpty()
    fcntl.ioctl(sub, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 80, 0, 0))
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=sub, cwd=ROOT)
    os.close(sub)
    drawn = b""
    try:
        while chunk := os.read(main, 65536):  # read while it runs: a pty keeps little
            drawn += chunk
    except OSError:  # the child is gone and the terminal's other end with it
        pass
    os.close(main)
    out, _ = proc.communicate(timeout=300)
    return proc.returncode, out, drawn


def test_a_bar_on_a_terminal():
    code = (
        "from urdf2dh.progress import enabled, progress\n"
        "assert enabled()\n"
        "print(sum(progress(range(1000), 1000, 'work')))\n"
    )
    status, out, drawn = on_a_terminal([sys.executable, "-c", code])
    assert status == 0
    assert out.strip() == b"499500"
    assert b"work:" in drawn and b"/1000" in drawn  # the bar, cleared at the end


def test_verify_draws_its_blocks_and_a_trees_chains_on_a_terminal():
    """``verify --samples`` large runs block by block (16,384 configurations each) and the
    chains of a tree one by one: each a bar on a terminal; in a pipe, stderr stays empty."""
    verify = [sys.executable, "-m", "urdf2dh.cli", "verify", "ur5", "--samples", "40000"]
    status, out, drawn = on_a_terminal(verify)
    assert status == 0 and out.endswith(b"agree with Pinocchio\n")
    assert b"verify:" in drawn and b"/3" in drawn  # 3 blocks
    piped = subprocess.run(verify, capture_output=True, cwd=ROOT, timeout=300)
    assert piped.returncode == 0 and piped.stderr == b"" and piped.stdout == out
    tree = [sys.executable, "-m", "urdf2dh.cli", "convert", "ur5", "--all-tips", "--format", "json"]
    status, out, drawn = on_a_terminal(tree)
    assert status == 0 and b"convert:" in drawn and b"/2" in drawn  # tool0, ee_link
