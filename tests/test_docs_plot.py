"""docs/commands/plot.md runs as written: its commands and Python blocks (in a temporary
directory), its sample hover text and error line are what urdf2dh prints, and its picture is
one the tool makes."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
from chains import random_chain_urdf

from urdf2dh.cli import main
from urdf2dh.conventions.convert import to_table
from urdf2dh.emit.scene import scene
from urdf2dh.io.sources import open_source

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


@pytest.mark.parametrize("block", _blocks("python"))
def test_the_python_runs(tmp_path, monkeypatch, block):
    monkeypatch.chdir(tmp_path)
    exec(compile(block, str(DOC), "exec"), {})


def test_the_samples_are_what_urdf2dh_prints(tmp_path, monkeypatch, capsys):
    hover, error = _blocks("text")
    shown = scene(to_table(open_source("panda").model(), "mdh"))
    assert hover.splitlines() == list(shown.frames[4].hover)
    monkeypatch.chdir(tmp_path)
    Path("long.urdf").write_text(random_chain_urdf(5, 5_000)[0])
    assert main(["plot", "long.urdf", "-o", "long.png"]) == 2
    assert capsys.readouterr().err == error + "\n"


def test_the_picture_is_the_tools(tmp_path):
    from matplotlib.image import imread

    shown = re.search(r"!\[[^\]]*\]\((\.\./img/[^)]+\.png)\)\n\n\*`(urdf2dh plot [^`]+)`\*", TEXT)
    assert shown, "the picture and the command that made it"
    argv = shlex.split(shown[2])[1:]
    argv[argv.index("-o") + 1] = str(tmp_path / "fresh.png")
    assert main(argv) == 0
    kept, fresh = imread(DOC.parent / shown[1]), imread(tmp_path / "fresh.png")
    assert kept.shape == fresh.shape
    assert abs(float(kept.mean()) - float(fresh.mean())) < 0.01
