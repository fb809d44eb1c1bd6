"""The code as the project keeps it (issue 11): ruff's format and lint rules hold everywhere, and
no module of the package is longer than 300 lines. ruff is pinned in the test extra, so that
its formatting is the same on every machine."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LONGEST = 300


@pytest.mark.parametrize("args", [["format", "--check"], ["check"]])
def test_ruff(args):
    proc = subprocess.run([sys.executable, "-m", "ruff", *args, "."], cwd=ROOT,
                          capture_output=True, text=True)  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_every_module_reads_in_one_sitting():
    long = {str(p.relative_to(ROOT)): n for p in (ROOT / "urdf2dh").rglob("*.py")
            if (n := len(p.read_text().splitlines())) > LONGEST}  # fmt: skip
    assert long == {}
