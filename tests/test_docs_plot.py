"""docs/commands/plot.md's plots write real pictures and views, and its sample hover text and
error line are what urdf2dh prints. (Every block of the page runs in tests/test_doc_blocks.py;
its picture is checked against a fresh one in tests/test_docs_site.py.)"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

from chains import random_chain_urdf

from urdf2dh import load, to_table
from urdf2dh.cli import main
from urdf2dh.emit.scene import scene

DOC = Path(__file__).resolve().parents[1] / "docs" / "commands" / "plot.md"
TEXT = DOC.read_text(encoding="utf-8")


def _blocks(language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)\n```", TEXT, re.S)


def test_the_commands_run(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    commands = [line.split("#")[0] for b in _blocks("bash") for line in b.splitlines()]
    plots = [shlex.split(c)[1:] for c in commands if c.startswith("urdf2dh plot")]
    assert len(plots) == 4
    for argv in plots:
        assert main(argv) == 0, argv
        assert Path(argv[argv.index("-o") + 1]).stat().st_size > 10_000


def test_the_samples_are_what_urdf2dh_prints(tmp_path, monkeypatch, capsys):
    hover, error = _blocks("text")
    shown = scene(to_table(load("panda"), "mdh"))
    assert hover.splitlines() == list(shown.frames[4].hover)
    monkeypatch.chdir(tmp_path)
    Path("long.urdf").write_text(random_chain_urdf(5, 5_000)[0])
    assert main(["plot", "long.urdf", "-o", "long.png"]) == 2
    assert capsys.readouterr().err == error + "\n"
