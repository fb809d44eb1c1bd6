"""The example scripts run and reach their conclusions (each exits 0 only when it holds)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


def checkout_env() -> dict[str, str]:
    """The environment that runs an example on this checkout's urdf2dh (not an installed one)."""
    path = os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH", "")) if p)
    return {**os.environ, "PYTHONPATH": path}


def run(script: str, *args: str, tmp: Path | None = None) -> str:
    env = {**checkout_env(), **({} if tmp is None else {"TMPDIR": str(tmp)})}
    proc = subprocess.run(
        [sys.executable, str(EXAMPLES / script), *args],
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return proc.stdout


def test_reproduce_table_ii():
    out = run("reproduce_table_ii.py")
    assert "puma560-nominal: Table II, 42 cells" in out
    assert "puma560-actual: Table II, 42 cells" in out
    assert "all cells agree with the printed table" in out


def test_puma_poe_to_cpc():
    out = run("puma_poe_to_cpc.py")
    assert "CPC (Zhuang-Roth-Hamano)" in out
    assert "Table III against joint 6 = [-0.095, -0.031, -0.995, -51, 249, 0]" in out
    assert "POE -> CPC over 1000 configurations" in out


@pytest.mark.parametrize("keep", [False, True])
def test_dh_urdf_roundtrip(tmp_path, keep):
    scratch = tmp_path / "tmp"  # the script's temporary directory goes here, and must go
    scratch.mkdir()
    args = [str(tmp_path / "ur5.urdf")] if keep else []
    out = run("dh_urdf_roundtrip.py", *args, tmp=scratch)
    assert "round trip exact" in out
    if keep:
        assert (tmp_path / "ur5.urdf").read_text().startswith("<?xml")
    assert list(scratch.iterdir()) == []


@pytest.mark.parametrize("keep", [False, True])
def test_calibrate_ur5(tmp_path, keep):
    """nominal URDF -> measure -> calibrate -> UR yaml and calibrated URDF; without OUT_DIR the
    files live in a temporary directory that is gone afterwards."""
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    out_dir = tmp_path / "out"
    args = [str(out_dir)] if keep else []
    proc = subprocess.run(
        [sys.executable, str(EXAMPLES / "calibrate_ur5.py"), *args],
        capture_output=True,
        text=True,
        timeout=300,
        env={**checkout_env(), "TMPDIR": str(scratch)},
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    out = proc.stdout
    assert "$ urdf2dh calibrate ur5" in out and "--to ur" in out and "--format urdf" in out
    assert "calibration walk complete" in out
    assert list(scratch.iterdir()) == []
    if keep:
        names = sorted(p.name for p in out_dir.iterdir())
        assert names == [
            "as-built.yaml",
            "calibrated.json",
            "calibrated.urdf",
            "default_kinematics.yaml",
            "poses.csv",
            "report.json",
        ]
