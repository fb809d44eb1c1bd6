"""The code as the project keeps it: ruff's format and lint rules hold everywhere. ruff is pinned
in the test extra, so that its formatting is the same on every machine."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("args", [["format", "--check"], ["check"]])
def test_ruff(args):
    proc = subprocess.run([sys.executable, "-m", "ruff", *args, "."], cwd=ROOT,
                          capture_output=True, text=True)  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_mypy_strict():
    # the package is fully typed: every function annotated, no Any returned where a type is
    # declared (pyproject.toml's [tool.mypy] holds the settings)
    proc = subprocess.run([sys.executable, "-m", "mypy", "--strict", "urdf2dh"], cwd=ROOT,
                          capture_output=True, text=True)  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr
