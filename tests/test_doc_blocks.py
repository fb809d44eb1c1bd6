"""Every code block a user can copy from README.md and docs/*.md runs as shown.

Blocks are read as a CommonMark renderer reads them (markdown-it-py): each fenced ``bash`` block
runs in ``bash -euo pipefail``, each ``python`` block in this Python, in order, one document at
a time in a temporary directory where the repository's folders (``tests``, ``examples``, ...)
are linked, as in a checkout, and where ``urdf2dh`` and ``python`` are this checkout's. Blocks
of other languages, and ``text`` blocks (output, excerpts of generated files), are shown, not
run; so are README's "Quick start" commands, which are what CI runs (tests/test_readme.py).

What a document's blocks write is what they would write into the root of a checkout: every such
file is one the repository's ``.gitignore`` ignores (a user who follows the documentation from
the root and then runs the tests leaves the project's files as they were), as is what
``mkdocs build`` writes (``site/``).

A ``python`` block that imports a consumer not installed here (PyKDL: Debian's python3-pykdl,
which scripts/check-consumers installs and then runs these tests again) is left out, and the
test says so once the others have passed.
"""

from __future__ import annotations

import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import pytest
import yaml
from markdown_it import MarkdownIt
from test_docs_site import _nav_pages

ROOT = Path(__file__).resolve().parents[1]
GALLERY = ROOT / "docs" / "gallery"  # its examples run in tests/test_gallery.py, output checked
DOCS = [
    ROOT / "README.md",
    *sorted(p for p in (ROOT / "docs").rglob("*.md") if GALLERY not in p.parents),
]
RUN = ("bash", "python")
LINKED = ("tests", "examples", "robots", "scripts", "benchmarks", "docs")
OPTIONAL = {"PyKDL": "Debian's python3-pykdl"}  # consumers the test extra does not install


@dataclass(frozen=True)
class Block:
    lang: str
    code: str
    line: int  # 1-based line of the opening fence
    section: str


def blocks(path: Path) -> list[Block]:
    """The fenced blocks of a Markdown file, with the heading each stands under."""
    tokens = MarkdownIt("commonmark").parse(path.read_text(encoding="utf-8"))
    out, section = [], ""
    for i, token in enumerate(tokens):
        if token.type == "heading_open":
            section = tokens[i + 1].content
        elif token.type == "fence" and token.map is not None:
            lang = token.info.split()[0] if token.info.strip() else ""
            out.append(Block(lang, token.content, token.map[0] + 1, section))
    return out


def to_run(path: Path) -> list[Block]:
    return [
        b
        for b in blocks(path)
        if b.lang in RUN and not (path.name == "README.md" and b.section == "Quick start")
    ]


def _workspace(tmp_path: Path) -> dict[str, str]:
    """Link the repository's folders, put shims for ``urdf2dh`` and ``python`` first on PATH,
    and make Debian's PyKDL importable where it is installed for this Python."""
    for name in LINKED:
        if (ROOT / name).exists():
            (tmp_path / name).symlink_to(ROOT / name)
    bin_dir = tmp_path / ".bin"
    bin_dir.mkdir()
    shims = {"urdf2dh": f'exec "{sys.executable}" -m urdf2dh.cli "$@"'}
    shims.update(dict.fromkeys(("python", "python3"), f'exec "{sys.executable}" "$@"'))
    for name, body in shims.items():
        (bin_dir / name).write_text(f"#!/bin/sh\n{body}\n")
        (bin_dir / name).chmod(0o755)
    paths = [str(ROOT)]
    tag = f"cpython-{sys.version_info.major}{sys.version_info.minor}"
    debian = glob.glob(f"/usr/lib/python3/dist-packages/PyKDL.{tag}-*.so")
    if debian:  # the one module, not Debian's whole dist-packages
        kdl = tmp_path / ".pykdl"
        kdl.mkdir()
        (kdl / Path(debian[0]).name).symlink_to(debian[0])
        paths.append(str(kdl))
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=os.pathsep.join(paths))
    env["PATH"] = f"{bin_dir}{os.pathsep}{env.get('PATH', '')}"
    return env


def _missing(block: Block, env: dict[str, str]) -> str | None:
    for module, where in OPTIONAL.items():
        if re.search(rf"^\s*(import|from)\s+{module}\b", block.code, re.M):
            probe = subprocess.run(
                [sys.executable, "-c", f"import {module}"], env=env, capture_output=True
            )
            if probe.returncode != 0:
                return f"{module} ({where})"
    return None


@pytest.mark.parametrize("path", DOCS, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_code_block_runs_as_shown(path, tmp_path):
    env = _workspace(tmp_path)
    left_out = []
    for block in to_run(path):
        where = f"{path.relative_to(ROOT)}:{block.line}"
        missing = _missing(block, env)
        if missing:
            left_out.append(f"{where} needs {missing}")
            continue
        if block.lang == "bash":
            argv = ["bash", "-euo", "pipefail", "-c", block.code]
        else:
            script = tmp_path / f".block{block.line}.py"
            script.write_text(block.code)
            argv = [sys.executable, str(script)]
        proc = subprocess.run(
            argv, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600
        )
        assert proc.returncode == 0, (
            f"{where} ({block.lang}) exited {proc.returncode}:\n{block.code}\n"
            f"stdout:\n{proc.stdout[-3000:]}\nstderr:\n{proc.stderr[-3000:]}"
        )
    written = [
        str(p.relative_to(tmp_path))
        for p in sorted(tmp_path.rglob("*"))
        if p.is_file() and not _ours(p.relative_to(tmp_path))
    ]
    kept = sorted(set(written) - ignored(written))
    assert kept == [], f"{path.relative_to(ROOT)}'s blocks write files .gitignore keeps: {kept}"
    if left_out:
        pytest.skip("ran every other block; left out: " + "; ".join(left_out))


def _ours(relative: Path) -> bool:
    """Whether a path of the workspace is its own (linked folders, shims, the blocks' scripts)."""
    top = relative.parts[0]
    return top in LINKED or top in (".bin", ".pykdl") or top.startswith(".block")


def ignored(names: list[str]) -> set[str]:
    """The paths (relative to the root) that the repository's .gitignore ignores, as git reads
    it (in a repository of their own, so that this holds outside a checkout too)."""
    if not names:
        return set()
    with tempfile.TemporaryDirectory() as repo:
        shutil.copy(ROOT / ".gitignore", Path(repo) / ".gitignore")
        subprocess.run(["git", "init", "-q", repo], check=True)
        proc = subprocess.run(
            ["git", "-C", repo, "check-ignore", "--no-index", "--stdin"],
            input="\n".join(names),
            capture_output=True,
            text=True,
        )
    assert proc.returncode in (0, 1), proc.stderr  # 1: none is ignored
    return set(proc.stdout.splitlines())


def test_what_mkdocs_build_writes_is_ignored():
    assert ignored(["site/index.html", "site/commands/convert/index.html"]) == {
        "site/index.html",
        "site/commands/convert/index.html",
    }


def test_the_blocks_are_found():
    """The reader sees README's blocks: the set-up commands, the everyday jobs, the Python."""
    readme = blocks(ROOT / "README.md")
    assert [b.section for b in readme if b.lang == "bash"][:2] == ["Quick start"] * 2
    assert all(b.section != "Quick start" for b in to_run(ROOT / "README.md"))
    jobs = {b.section for b in to_run(ROOT / "README.md")}
    assert jobs >= {
        "Convert a URDF",
        "Verify against Pinocchio",
        "Export a controller file",
        "Diff two robots",
        "Calibrate from measurements",
        "The same from Python",
    }
    python = [b.code for b in readme if b.lang == "python"]
    assert any("urdf2dh.calibrate(" in code and "urdf2dh.verify(" in code for code in python)


def test_every_page_of_the_site_is_run():
    """Every page the site builds (mkdocs.yml's nav) is one whose blocks this module runs, or
    one of the gallery's (tests/test_gallery.py runs them)."""
    nav = _nav_pages(yaml.safe_load((ROOT / "mkdocs.yml").read_text())["nav"])
    gallery = set(GALLERY.glob("*.md"))
    assert {ROOT / "docs" / page for page in nav} <= set(DOCS) | gallery
