"""README's two set-up commands are exactly what CI runs first."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_ci_runs_the_readme_commands():
    """CI's first commands are README's two, as written; it may do more after them (the real
    consumers: scripts/check-consumers)."""
    readme = (ROOT / "README.md").read_text()
    quick = readme.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```bash\n(.*?)\n```", quick, re.S)
    assert len(blocks) == 2
    ci = [
        line
        for line in (ROOT / ".ci" / "run").read_text().splitlines()
        if line and not line.startswith("#") and not line.startswith(("set ", "cd "))
    ]
    assert ci[:2] == blocks
    assert "urdf2dh convert ur5" in blocks[0] and "pytest" in blocks[1]


def test_ci_runs_every_real_consumer_after_the_tests():
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    commands = [line for line in ci if line and not line.startswith("#")]
    assert commands[-1] == ". .venv/bin/activate && scripts/check-consumers"
    assert (ROOT / "scripts" / "check-consumers").stat().st_mode & 0o111


def test_the_readme_is_a_front_door():
    """At most 250 lines, one picture, links to the documentation that resolve, and no project
    history or references to documents outside the repository."""
    readme = (ROOT / "README.md").read_text()
    assert len(readme.splitlines()) <= 250
    pictures = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", readme)
    assert len(pictures) == 1 and (ROOT / pictures[0]).is_file()
    links = re.findall(r"\]\(((?:docs/|CHANGELOG)[^)#]*)", readme)
    assert len(links) >= 10
    for link in links:
        assert (ROOT / link).is_file(), link
    for phrase in ("SPEC", "cannot run here", "before the", "architecture change"):
        assert phrase not in readme, phrase
