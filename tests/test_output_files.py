"""Output files: -o never replaces anything but a regular file, never the SOURCE,
keeps an existing file's mode, writes through symbolic links, leaves no temporary file behind
when a run fails or is interrupted, and a write that fails (a full disk) is an error."""

from __future__ import annotations

import os
import shutil
import signal
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from urdf2dh.cli import main
from urdf2dh.io import files

ROOT = Path(__file__).resolve().parents[1]


def test_writing_onto_the_source_is_refused(tmp_path, capsys):
    source = tmp_path / "arm.urdf"
    shutil.copy(ROOT / "tests" / "data" / "genser6.urdf", source)
    before = source.read_bytes()
    for output in (str(source), str(tmp_path / "." / "arm.urdf")):
        assert main(["convert", str(source), "--format", "urdf", "-o", output]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "is the SOURCE file" in err
    link = tmp_path / "link.urdf"
    link.symlink_to(source)
    assert main(["convert", str(source), "-o", str(link)]) == 2
    assert source.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["arm.urdf", "link.urdf"]


def test_a_symbolic_link_is_written_through_and_stays_a_link(tmp_path, capsys):
    real = tmp_path / "real.json"
    real.write_text("old")
    link = tmp_path / "table.json"
    link.symlink_to(real)
    assert main(["convert", "ur5", "--format", "json", "-o", str(link)]) == 0
    assert (
        link.is_symlink()
        and '"schema": "urdf2dh/schemas/table-file-1.schema.json"' in real.read_text()
    )
    dangling = tmp_path / "dangling.json"
    dangling.symlink_to(tmp_path / "nowhere" / "x.json")
    assert main(["convert", "ur5", "-o", str(dangling)]) == 2
    assert "dangling symbolic link" in capsys.readouterr().err


def test_an_existing_files_mode_is_kept(tmp_path):
    target = tmp_path / "table.yaml"
    target.write_text("old")
    target.chmod(0o640)
    assert main(["convert", "ur5", "--format", "yaml", "-o", str(target)]) == 0
    assert stat.S_IMODE(target.stat().st_mode) == 0o640
    target.chmod(0o444)  # read-only: replaced (the directory allows it), still read-only
    assert main(["convert", "ur5", "--format", "yaml", "-o", str(target)]) == 0
    assert stat.S_IMODE(target.stat().st_mode) == 0o444 and "schema" in target.read_text()


def test_devices_and_fifos_are_written_into_not_replaced(tmp_path):
    assert main(["convert", "ur5", "-o", os.devnull]) == 0
    assert Path(os.devnull).is_char_device()
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    reader = subprocess.Popen(["cat", str(fifo)], stdout=subprocess.PIPE)
    assert main(["convert", "ur5", "--format", "csv", "-o", str(fifo)]) == 0
    out, _ = reader.communicate(timeout=30)
    assert b"shoulder_pan_joint" in out and stat.S_ISFIFO(fifo.lstat().st_mode)


def test_other_files_are_refused(tmp_path, capsys):
    folder = tmp_path / "folder"
    folder.mkdir()
    assert main(["convert", "ur5", "-o", str(folder)]) == 2
    assert "is not a regular file" in capsys.readouterr().err
    assert main(["convert", "ur5", "-o", str(tmp_path / "no" / "such" / "dir.txt")]) == 2
    assert "does not exist" in capsys.readouterr().err


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full on this system")
def test_a_full_disk_is_an_error(tmp_path):
    code = "from urdf2dh.cli import main; raise SystemExit(main(['convert', 'ur5']))"
    with open("/dev/full", "wb") as full:
        proc = subprocess.run(
            [sys.executable, "-c", code], stdout=full, stderr=subprocess.PIPE, text=True, cwd=ROOT
        )
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.startswith("urdf2dh: error: stdout: cannot write (No space left")
    assert proc.stderr.count("\n") == 1
    assert main(["convert", "ur5", "-o", "/dev/full"]) == 2


@pytest.mark.parametrize("interruption", [KeyboardInterrupt, SystemExit])
def test_an_interrupted_write_leaves_no_temporary_file(tmp_path, monkeypatch, interruption):
    target = tmp_path / "table.json"
    target.write_text("old")

    def interrupted(*args: object) -> None:
        raise interruption()

    monkeypatch.setattr(files.os, "replace", interrupted)
    with pytest.raises(interruption):
        files.write_output("new", str(target))
    assert [p.name for p in tmp_path.iterdir()] == ["table.json"]
    assert target.read_text() == "old"


PROBE = """
import os, signal, sys
from urdf2dh.io import files
from urdf2dh.cli import main

real = getattr(os, "{hook}")
def hooked(path, *args):
    print(path, flush=True)          # the temporary file now exists
    os.kill(os.getpid(), signal.{signal})
    return real(path, *args)
setattr(files.os, "{hook}", hooked)
sys.exit(main(["convert", "ur5", "-o", sys.argv[1]]))
"""


def _probe(tmp_path: Path, name: str, hook: str) -> tuple[subprocess.CompletedProcess, Path]:
    target = tmp_path / "table.txt"
    target.write_text("old")
    proc = subprocess.run(
        [sys.executable, "-c", PROBE.format(signal=name, hook=hook), str(target)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
    )
    temporary = Path(proc.stdout.strip())
    assert temporary.parent == tmp_path and temporary.name.startswith(".table.txt."), proc.stdout
    assert "Traceback" not in proc.stderr, proc.stderr
    return proc, target


@pytest.mark.parametrize(("name", "code"), [("SIGTERM", 143), ("SIGINT", 130)])
def test_signals_while_writing_leave_the_file_and_no_temporary_file(tmp_path, name, code):
    proc, target = _probe(tmp_path, name, "chmod")  # the temporary file is written, not renamed
    assert proc.returncode == code, proc.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["table.txt"] and target.read_text() == "old"
    assert getattr(signal, name)  # the signal the probe sent


@pytest.mark.parametrize("name", ["SIGTERM", "SIGINT"])
def test_a_signal_while_renaming_lets_the_rename_finish(tmp_path, name):
    """Once outputs are being put in place, the run has done its work: exit 0, file written."""
    proc, target = _probe(tmp_path, name, "replace")
    assert proc.returncode == 0, proc.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["table.txt"]
    assert "shoulder_pan_joint" in target.read_text()
