"""docs/security.md's shell examples run and print what the page shows."""

from __future__ import annotations

import os
import re
import stat
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "security.md"
EXAMPLES = re.findall(r"```sh\n(.*?)```\n\n```text\n(.*?)```", PAGE.read_text(), re.S)


def test_the_page_has_its_examples():
    assert len(EXAMPLES) == 6


@pytest.mark.parametrize(("script", "shown"), EXAMPLES, ids=lambda s: s.splitlines()[0][:40])
def test_an_example_prints_what_the_page_shows(tmp_path, script, shown):
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    urdf2dh = bin_dir / "urdf2dh"  # this checkout's program, as the installed script runs it
    urdf2dh.write_text(
        f"#!{sys.executable}\nimport sys\nsys.path.insert(0, {str(ROOT)!r})\n"
        "from urdf2dh.cli import console\nconsole()\n"
    )
    urdf2dh.chmod(urdf2dh.stat().st_mode | stat.S_IXUSR)
    work = tmp_path / "work"
    work.mkdir()
    proc = subprocess.run(
        ["bash", "-c", script],
        cwd=work,
        env={**os.environ, "PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}"},
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        timeout=300,
    )
    assert proc.stdout == shown
