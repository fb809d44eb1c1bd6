"""The documentation site builds with no warning (``mkdocs build --strict``: every link and
anchor found, every docstring of the API reference parsed), every page under docs/ is in its
navigation, the API reference holds every public name, the changelog page is CHANGELOG.md, and
every picture shown with the command that drew it is one that command draws."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

import urdf2dh
from urdf2dh.cli import main

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def _nav_pages(nav) -> list[str]:
    pages = []
    for item in nav:
        if isinstance(item, str):
            pages.append(item)
        else:
            for value in item.values():
                pages += [value] if isinstance(value, str) else _nav_pages(value)
    return pages


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("site")
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    proc = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(out)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    log = proc.stdout + proc.stderr
    assert proc.returncode == 0, log
    assert "WARNING" not in log and "ERROR" not in log, log
    return out


def test_the_site_builds_strictly_with_every_page(site):
    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text())
    nav = _nav_pages(config["nav"])
    assert len(nav) == len(set(nav))
    on_disk = sorted(str(p.relative_to(DOCS)) for p in DOCS.rglob("*.md"))
    assert sorted(nav) == on_disk
    assert len(nav) >= 12
    for page in nav:
        html = site / (page[: -len(".md")].removesuffix("index") + "/index.html").lstrip("/")
        html = site / "index.html" if page == "index.md" else html
        assert html.is_file(), page


def test_the_api_reference_has_every_public_name(site):
    html = (site / "api" / "index.html").read_text(encoding="utf-8")
    documented = set(re.findall(r'id="urdf2dh\.([A-Za-z_]+)"', html))
    public = {n for n in urdf2dh.__all__ if not n.startswith("_") and not n.isupper()}
    assert public <= documented | {"Urdf2DhError"}, public - documented
    assert 'id="urdf2dh.errors.Urdf2DhError"' in html


def test_the_changelog_page_is_the_changelog(site):
    changelog = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    headings = re.findall(r"^#+ \[?([^\]\n]+)", changelog, re.M)  # "## [0.2.0] - date": 0.2.0
    page = (site / "changelog" / "index.html").read_text(encoding="utf-8")
    assert headings and all(h.strip() in page for h in headings), headings


PICTURE = re.compile(r"!\[[^\]]*\]\(((?:\.\./)*img/[^)]+\.png)\)\n\n\*`(urdf2dh plot [^`]+)`\*")


def _pictures() -> list[tuple[Path, str, str]]:
    return [
        (page, m[1], m[2])
        for page in sorted(DOCS.rglob("*.md"))
        for m in PICTURE.finditer(page.read_text(encoding="utf-8"))
    ]


def test_every_convention_page_shows_its_frames():
    shown = {page.name for page, _, _ in _pictures() if page.parent.name == "conventions"}
    assert shown >= {"dh.md", "mdh.md", "cpc.md", "hayati.md", "poe.md"}


@pytest.mark.parametrize("page,png,command", _pictures(), ids=lambda v: str(v)[-40:])
def test_the_picture_is_what_its_command_draws(page, png, command, tmp_path, monkeypatch):
    from matplotlib.image import imread

    monkeypatch.setenv("MPLBACKEND", "Agg")
    argv = shlex.split(command)[1:]
    argv[argv.index("-o") + 1] = str(tmp_path / "fresh.png")
    assert main(argv) == 0
    kept, fresh = imread(page.parent / png), imread(tmp_path / "fresh.png")
    assert kept.shape == fresh.shape
    assert abs(float(kept.mean()) - float(fresh.mean())) < 0.01


def test_every_export_target_has_its_page_with_an_example():
    """Each target has docs/exports/TARGET.md, listed in the exports index, whose first command
    exports to it (tests/test_doc_blocks.py runs it), and says what it writes, its limits and
    which consumer checks it."""
    from urdf2dh.emit.export import TARGETS

    index = (DOCS / "exports" / "index.md").read_text(encoding="utf-8")
    for target in TARGETS:
        page = (DOCS / "exports" / f"{target}.md").read_text(encoding="utf-8")
        assert f"]({target}.md)" in index, target
        command = re.search(r"```bash\n(urdf2dh export [^\n]*)", page)
        assert command and f"--to {target}" in command[1], target
        for heading in ("## What it writes", "## Limits", "## How it is checked"):
            assert heading in page, (target, heading)


def test_formulas_are_mathml_and_the_site_loads_nothing_from_elsewhere(site):
    """Every formula is drawn by the browser from MathML written at build time: no TeX left for a
    script to typeset, no script or style fetched from another site (the site reads offline)."""
    pages = {p: p.read_text(encoding="utf-8") for p in site.rglob("*.html")}
    formulas = {p: text.count("<math") for p, text in pages.items()}
    for name in ("dh", "mdh", "hayati", "poe"):
        assert formulas[site / "conventions" / name / "index.html"] >= 1, name
    for page, text in pages.items():
        assert 'class="arithmatex"' not in text, page
        fetched = re.findall(r'<(?:script|link)\b[^>]*(?:src|href)="(https?:)?//[^"]*"', text)
        assert fetched == [], (page, fetched)
