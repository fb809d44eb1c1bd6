"""The README's export, xacro and plot examples run as written (outputs into a temporary dir)."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from urdf2dh.cli import main

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
SECTIONS = README.split("## Exporting controller and toolbox files", 1)[1]
COMMANDS = [
    block.replace("\\\n", " ").split("&&")[0].split("#")[0].strip()
    for block in re.findall(r"```bash\n(.*?)\n```", SECTIONS, re.S)
]


def test_every_target_has_an_example():
    targets = {re.search(r"--to (\S+)", c)[1] for c in COMMANDS if "--to" in c}
    assert targets == {"ur", "linuxcnc", "rtb", "matlab", "kdl", "corke-matlab", "opw"}


@pytest.mark.parametrize("command", COMMANDS)
def test_readme_example_runs(command, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    argv = shlex.split(command)
    assert argv[0] == "urdf2dh"
    argv = argv[1:]
    if "-o" in argv:
        i = argv.index("-o") + 1
        argv[i] = str(tmp_path / argv[i])
    assert main(argv) == 0, capsys.readouterr().err
    if "-o" in argv:
        assert Path(argv[argv.index("-o") + 1]).stat().st_size > 0
