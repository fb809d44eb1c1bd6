"""The gallery (docs/gallery/): each example page has its code, its output and its picture; the
code runs as shown (from the root of a checkout, as tests/test_doc_blocks.py runs the other
pages), prints what the page shows, and draws the pictures the page shows.

Each ``text`` block shows lines of what the code blocks before it printed (``...`` stands for
lines left out; round-off figures such as ``4.4e-16`` and a table's self-check, which vary from
machine to machine in their last digits, are compared as such). Each picture
``../img/gallery/NAME.png`` is a file NAME.png that the page's code writes: the committed one
must be the picture the code draws (same size, same look), and
``python -m pytest tests/test_gallery.py --update-gallery`` draws them again.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from test_doc_blocks import LINKED, Block, _workspace, blocks, ignored
from test_docs_site import _nav_pages

ROOT = Path(__file__).resolve().parents[1]
GALLERY = ROOT / "docs" / "gallery"
PICTURES = ROOT / "docs" / "img" / "gallery"
PAGES = sorted(p for p in GALLERY.glob("*.md") if p.name != "index.md")
PICTURE = re.compile(r"!\[[^\]]*\]\(\.\./img/gallery/([^)]+)\)")
ROUND_OFF = re.compile(r"\b\d(?:\.\d+)?e-(?:1\d|[2-9]\d)\b")  # 4.4e-16, 2.5e-16, 1e-13
CHECK = re.compile(r"^(check: FK against the source at \d+ configurations:).*")


def comparable(line: str) -> str:
    """A printed line as the pages are held to it: round-off and the self-check's figures
    stand for themselves, trailing spaces dropped."""
    return CHECK.sub(r"\1 ...", ROUND_OFF.sub("<round-off>", line.rstrip()))


def run(page: Path, workspace: Path) -> list[tuple[Block, str]]:
    """Each block of the page with what the code blocks before it printed (since the last
    ``text`` block); the code runs in ``workspace``."""
    env = _workspace(workspace)
    out, printed = [], ""
    for block in blocks(page):
        if block.lang == "bash":
            argv = ["bash", "-euo", "pipefail", "-c", block.code]
        elif block.lang == "python":
            script = workspace / f".block{block.line}.py"
            script.write_text(block.code)
            argv = [sys.executable, str(script)]
        else:
            out.append((block, printed))
            if block.lang == "text":
                printed = ""
            continue
        proc = subprocess.run(
            argv, cwd=workspace, env=env, capture_output=True, text=True, timeout=600
        )
        where = f"{page.relative_to(ROOT)}:{block.line}"
        assert proc.returncode == 0, f"{where} exited {proc.returncode}:\n{proc.stderr[-3000:]}"
        printed += proc.stdout + proc.stderr
        out.append((block, printed))
    return out


def looks_alike(drawn: Path, kept: Path) -> tuple[bool, str]:
    """Same size and, at 64 x 64 in grey, within 0.4% on average: the same picture, whatever a
    font or a library version changes in its last pixels (two different frame pictures of
    the gallery differ by 1.7% and more)."""
    from PIL import Image

    a, b = Image.open(drawn), Image.open(kept)
    if a.size != b.size:
        return False, f"size {a.size}, kept {b.size}"
    small = [np.asarray(im.convert("L").resize((64, 64)), dtype=float) / 255.0 for im in (a, b)]
    difference = float(np.abs(small[0] - small[1]).mean())
    return difference <= 0.004, f"mean grey difference {difference:.4f}"


def test_the_gallery_is_in_the_site():
    nav = _nav_pages(yaml.safe_load((ROOT / "mkdocs.yml").read_text())["nav"])
    assert "gallery/index.md" in nav
    assert {f"gallery/{p.name}" for p in PAGES} <= set(nav)
    assert 6 <= len(PAGES) <= 10  # curated: a handful of worked examples
    index = (GALLERY / "index.md").read_text()
    assert all(f"]({p.name})" in index for p in PAGES)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.stem)
def test_each_example_runs_prints_what_it_shows_and_draws_its_picture(page, tmp_path, request):
    results = run(page, tmp_path)
    langs = [b.lang for b, _ in results]
    assert {"text"} <= set(langs) and {"bash", "python"} & set(langs), langs
    for block, printed in results:
        if block.lang != "text":
            continue
        shown = [comparable(line) for line in block.code.splitlines() if line.strip() != "..."]
        said = {comparable(line) for line in printed.splitlines()}
        missing = [line for line in shown if line and line not in said]
        assert not missing, (
            f"{page.name}:{block.line} shows lines its code does not print: {missing}"
        )
    names = PICTURE.findall(page.read_text())
    assert names, f"{page.name} shows no picture"
    update = request.config.getoption("--update-gallery")
    for name in names:
        drawn = tmp_path / name
        assert drawn.is_file(), f"{page.name}'s code does not draw {name}"
        kept = PICTURES / name
        if update:
            PICTURES.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(drawn, kept)
        assert kept.is_file(), f"{kept.relative_to(ROOT)} is missing (--update-gallery)"
        same, how = looks_alike(drawn, kept)
        assert same, f"{name}: the picture kept is not the one the code draws ({how})"
    written = [
        str(p.relative_to(tmp_path))
        for p in tmp_path.rglob("*")
        if p.is_file() and not str(p.relative_to(tmp_path)).startswith((".", *LINKED))
    ]
    kept_files = sorted(set(written) - ignored(written))
    assert kept_files == [], f"{page.name} writes files .gitignore keeps: {kept_files}"
