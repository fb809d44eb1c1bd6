"""The calibration benchmark's reading of a file whose rows were recorded under a controller's
joint offsets (benchmarks/calibration.py, ``Shifted``): the offsets come off those rows' named
joints and nothing else."""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

import calibration as bench  # noqa: E402


def _tiago() -> bench.RealSet:
    shared = next(r for r in bench.shared_sets() if r.name == "tiago")
    whole = shared.files[0].with_name("tiago_m1.csv")
    return replace(shared, files=(whole,))


def test_offsets_come_off_the_named_rows_and_joints_only():
    real = _tiago()
    _, fit, test = bench.load_set(real)
    shifted = replace(real, shifted=bench.PAL_OFFSETS)
    _, fit2, test2 = bench.load_set(shifted)
    # the split is the same (taken by configuration after the offsets are off)
    assert len(fit2) == len(fit) and len(test2) == len(test)
    np.testing.assert_array_equal(fit2.points, fit.points)
    nominal, (whole,) = bench.read_set(real)
    taken = bench.PAL_OFFSETS.take_off(whole)
    change = whole.q - taken.q
    columns = [whole.joints.index(n) for n in bench.PAL_OFFSETS.offsets]
    expected = np.zeros_like(change)
    expected[8:16, columns] = list(bench.PAL_OFFSETS.offsets.values())
    np.testing.assert_allclose(change, expected, rtol=0, atol=1e-15)
    assert "torso_lift_joint" not in bench.PAL_OFFSETS.offsets
    assert np.array_equal(whole.q[:8], taken.q[:8]) and np.array_equal(whole.q[16:], taken.q[16:])
    assert [j.name for j in nominal.joints] == list(whole.joints)


def test_the_unseen_tiago_session_is_benchmarked_as_it_is_and_with_the_offsets_off(tmp_path):
    sets = [r for r in bench.unseen_sets(tmp_path) if "cross_valid" in r.source]
    assert [r.shifted for r in sets] == [None, bench.PAL_OFFSETS]
    assert sets[0].files == sets[1].files


def test_a_scaling_row_reads_and_calibrates_its_poses(capsys):
    """benchmarks/calibration.py --scaling's row, at 300 poses: the CSV written and read back,
    the default calibration's level, times and the process's peak memory."""
    assert bench.scaling_child(300) == 0
    poses, size, reading, fitting, peak, level = capsys.readouterr().out.split()
    assert int(poses) == 300 and int(size) > 300 * 100
    assert float(reading) > 0 and float(fitting) > 0 and int(peak) > 2**20
    assert level in ("base-tool", "offsets", "geometry", "full")
