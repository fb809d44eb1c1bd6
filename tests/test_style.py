"""The code as the project keeps it: ruff's format and lint rules hold for every file the
project tracks (in a git checkout: what `git ls-files` lists; elsewhere, every file .gitignore
does not ignore), not for what a user's runs leave in the tree. ruff is pinned in the test
extra, so that its formatting is the same on every machine."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def tracked() -> list[str]:
    """The Python files the project tracks, or ``["."]`` outside a git checkout."""
    proc = subprocess.run(["git", "ls-files", "-z", "--", "*.py", "*.pyi"], cwd=ROOT,
                          capture_output=True)  # fmt: skip
    if proc.returncode != 0 or not (ROOT / ".git").exists():
        return ["."]
    return [name for name in proc.stdout.decode().split("\0") if name and (ROOT / name).exists()]


@pytest.mark.parametrize("args", [["format", "--check"], ["check"]])
def test_ruff(args):
    files = ["--force-exclude", *tracked()]  # the configured exclusions hold for named files too
    proc = subprocess.run([sys.executable, "-m", "ruff", *args, *files], cwd=ROOT,
                          capture_output=True, text=True)  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_ruff_judges_the_tracked_files():
    files = tracked()
    assert "urdf2dh/__init__.py" in files and "tests/test_style.py" in files


def test_mypy_strict():
    # the package is fully typed: every function annotated, no Any returned where a type is
    # declared (pyproject.toml's [tool.mypy] holds the settings)
    proc = subprocess.run([sys.executable, "-m", "mypy", "--strict", "urdf2dh"], cwd=ROOT,
                          capture_output=True, text=True)  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr
