"""The edges of output: a closed stdout, stderr or stdin, a non-blocking stdout that fills up,
the owner and group of a file written over, and a read-only directory. Each failure is one line
and exit 2, naming stdout, the file or the directory; nothing is lost or silently changed."""

from __future__ import annotations

import os
import pwd
import shutil
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

from urdf2dh.cli import main

ROOT = Path(__file__).resolve().parents[1]
ROOTLESS = os.geteuid() != 0
SETPRIV = shutil.which("setpriv")


def _shell(script: str, cwd: Path, *prefix: str) -> subprocess.CompletedProcess:
    """``script`` in bash, ``$PY`` this Python with this checkout first on its path."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "PY": sys.executable}
    return subprocess.run(
        [*prefix, "bash", "-c", script], cwd=cwd, env=env, capture_output=True, text=True
    )


@pytest.mark.parametrize("args", ["convert ur5", "convert ur5 -h", "--version", "robots"])
def test_a_closed_stdout_is_a_failed_write(tmp_path, args):
    proc = _shell(f'"$PY" -m urdf2dh.cli {args} >&-', tmp_path)
    assert (proc.returncode, proc.stderr) == (
        2,
        "urdf2dh: error: stdout: cannot write (it is closed)\n",
    )


def test_a_closed_stdout_takes_no_file_and_costs_no_output(tmp_path):
    """With descriptor 1 closed, the temporary file of -o would be given number 1; the output is
    still exactly the file a normal run writes, and nothing reaches it twice."""
    assert main(["convert", "ur5", "--format", "json", "-o", str(tmp_path / "want.json")]) == 0
    proc = _shell('"$PY" -m urdf2dh.cli convert ur5 --format json -o got.json >&-', tmp_path)
    assert (proc.returncode, proc.stderr) == (0, "")
    assert (tmp_path / "got.json").read_bytes() == (tmp_path / "want.json").read_bytes()


def test_a_closed_stderr_or_stdin_changes_nothing_but_the_messages(tmp_path):
    proc = _shell('"$PY" -m urdf2dh.cli convert nowhere.urdf 2>&-', tmp_path)
    assert (proc.returncode, proc.stdout) == (2, "")  # the message goes nowhere, not to stdout
    proc = _shell('"$PY" -m urdf2dh.cli convert ur5 <&-', tmp_path)
    assert proc.returncode == 0 and "shoulder_pan_joint" in proc.stdout and proc.stderr == ""


def test_a_full_non_blocking_stdout_is_waited_on_not_cut_short(tmp_path):
    sys.path.insert(0, str(ROOT / "tests"))
    from chains import random_chain_urdf

    source = tmp_path / "long.urdf"
    source.write_text(random_chain_urdf(3, 400)[0])
    argv = [sys.executable, "-m", "urdf2dh.cli", "convert", str(source), "--format", "json"]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    want = subprocess.run(argv, capture_output=True, env=env, check=True).stdout
    assert len(want) > 65536  # more than a pipe holds
    read, write = os.pipe()
    os.set_blocking(write, False)
    proc = subprocess.Popen(argv, stdout=write, stderr=subprocess.PIPE, env=env)
    os.close(write)
    time.sleep(1.0)  # the pipe fills while nobody reads
    got = b"".join(iter(lambda: os.read(read, 65536), b""))
    os.close(read)
    assert proc.wait() == 0 and proc.stderr.read() == b""
    assert got == want


@pytest.mark.skipif(ROOTLESS, reason="changing a file's owner needs root")
def test_a_file_written_over_keeps_its_owner_group_and_mode(tmp_path):
    nobody = pwd.getpwnam("nobody")
    target = tmp_path / "table.txt"
    assert main(["convert", "ur5", "-o", str(target)]) == 0
    os.chown(target, nobody.pw_uid, nobody.pw_gid)
    target.chmod(0o2640)  # set-group-ID, which a change of owner would clear
    assert main(["convert", "ur5", "--convention", "mdh", "-o", str(target)]) == 0
    status = target.stat()
    assert "modified D-H" in target.read_text()
    assert (status.st_uid, status.st_gid) == (nobody.pw_uid, nobody.pw_gid)
    assert stat.S_IMODE(status.st_mode) == 0o2640
    directory = tmp_path / "tips"  # a file of -o DIR written over: the same
    argv = ["convert", "tests/data/parallelogram.urdf", "--all-tips", "-o", f"{directory}/"]
    assert main([*argv[:1], str(ROOT / argv[1]), *argv[2:]]) == 0
    kept = sorted(directory.iterdir())[0]
    os.chown(kept, nobody.pw_uid, nobody.pw_gid)
    assert main([*argv[:1], str(ROOT / argv[1]), *argv[2:], "--convention", "mdh"]) == 0
    assert "modified D-H" in kept.read_text()
    assert (kept.stat().st_uid, kept.stat().st_gid) == (nobody.pw_uid, nobody.pw_gid)
    fresh = tmp_path / "fresh.txt"  # a new file is the writer's
    assert main(["convert", "ur5", "-o", str(fresh)]) == 0
    assert fresh.stat().st_uid == os.geteuid()


@pytest.mark.skipif(not ROOTLESS and SETPRIV is None, reason="root without setpriv writes anywhere")
def test_a_read_only_directory_is_named(tmp_path):
    directory = tmp_path / "ro"
    directory.mkdir()
    writable = directory / "table.txt"
    writable.write_text("old")
    writable.chmod(0o666)
    directory.chmod(0o555)
    # root writes into any directory; without CAP_DAC_OVERRIDE it is held to the mode bits
    prefix = () if ROOTLESS else (SETPRIV, "--bounding-set", "-dac_override,-dac_read_search")
    try:
        for output, tail in (
            ("ro/table.txt", "; an existing file is replaced by a new file written beside it"),
            ("ro/new.txt", "\n"),
            ("ro/dir", "\n"),
        ):
            to = "export ur5 --to rtb" if output.endswith("dir") else "convert ur5"
            proc = _shell(f'"$PY" -m urdf2dh.cli {to} -o {output}', tmp_path, *prefix)
            assert proc.returncode == 2, proc.stderr
            assert proc.stderr.startswith(
                f"urdf2dh: error: {output}: cannot write in directory '{directory}' "
                "(Permission denied)"
            ), proc.stderr
            assert proc.stderr.count("\n") == 1 and tail in proc.stderr
        assert writable.read_text() == "old"
        assert sorted(p.name for p in directory.iterdir()) == ["table.txt"]
    finally:
        directory.chmod(0o755)
