"""``urdf2dh COMMAND -h`` ends with one example of the command, and that example runs as shown
(in a temporary directory, in the order ``--help`` lists the commands: ``measure`` writes the
measurements that ``calibrate``'s example reads)."""

from __future__ import annotations

import shlex
from pathlib import Path

import pytest

from urdf2dh.cli import main
from urdf2dh.cli.parser import commands


def _help(name: str, capsys) -> str:
    with pytest.raises(SystemExit) as done:
        main([name, "-h"])
    assert done.value.code == 0
    return capsys.readouterr().out


def test_every_help_ends_with_an_example_that_runs(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    for command in commands():
        lines = _help(command.NAME, capsys).rstrip("\n").splitlines()
        assert lines[-2:] == ["example:", f"  {command.EXAMPLE}"], command.NAME
        argv = shlex.split(command.EXAMPLE)
        assert argv[:2] == ["urdf2dh", command.NAME]
        assert main(argv[1:]) == 0, command.EXAMPLE
        written = argv[argv.index("-o") + 1] if "-o" in argv else None
        if written is not None:
            assert Path(written).stat().st_size > 0, command.EXAMPLE
        capsys.readouterr()


def test_each_commands_page_shows_its_example():
    """Each command's page (docs/commands/NAME.md) shows its ``-h`` example."""
    docs = Path(__file__).resolve().parents[1] / "docs" / "commands"
    for command in commands():
        assert command.EXAMPLE in (docs / f"{command.NAME}.md").read_text(encoding="utf-8")
