"""urdf2dh/model/_draw.py draws numpy's numbers without numpy.random: ``default_rng(seed).uniform``
bit for bit, for integer seeds of one and several words and tuple seeds, any number of joints; and
a conversion, drawing its self-check's configurations, does not import numpy.random."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from urdf2dh.io.sources import open_source
from urdf2dh.model import _draw

SEEDS = [0, 1, 7, 2**31, 2**32 - 1, 2**32, 2**64 + 3, 2**128 + 1, (), (0,), (0, 3), (5, 11),
         (2**40, 1), (7, 2**33, 9, 1, 0), (1, 2, 3, 4, 5, 6)]  # fmt: skip


def ranges(dof: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    low = rng.uniform(-4.0, 0.5, dof) * 10.0 ** rng.integers(-3, 3, dof)
    return low, low + rng.uniform(0.0, 7.0, dof)


@pytest.mark.parametrize(
    "seed", SEEDS + [int(s) for s in np.random.default_rng(8).integers(0, 2**63, 20)]
)
def test_python_draws_are_numpys(seed):
    for dof in (0, 1, 6, 7):
        low, high = ranges(dof, dof)
        ours = _draw.python_uniform(low, high, 37, seed)
        theirs = np.random.default_rng(seed).uniform(low, high, size=(37, dof))
        assert ours.dtype == theirs.dtype and ours.shape == theirs.shape
        assert np.array_equal(ours, theirs), (seed, dof)


def test_every_path_draws_numpys_numbers():
    low, high = ranges(7, 1)
    small, large = 50, _draw.PYTHON_DRAWS // 7 + 1  # the Python draw, numpy's
    for count in (small, large):
        got = _draw.uniform(low, high, count, (3, 1))
        assert np.array_equal(got, np.random.default_rng((3, 1)).uniform(low, high, (count, 7)))
    model = open_source("panda").model()
    lim = model.limits()
    expected = np.random.default_rng(5).uniform(lim[:, 0], lim[:, 1], size=(100, model.dof))
    assert np.array_equal(model.sample(100, 5), expected)


def test_a_range_that_is_not_finite_is_refused_as_numpy_refuses_it():
    low, high = np.array([-1.0, -1.7e308]), np.array([1.0, 1.7e308])
    with pytest.raises(OverflowError), np.errstate(over="ignore"):
        np.random.default_rng(0).uniform(low, high, size=(2, 2))
    with pytest.raises(OverflowError):
        _draw.python_uniform(low, high, 2, 0)


def test_a_conversion_imports_no_numpy_random():
    code = (
        "import sys\nfrom urdf2dh.cli import main\nassert main(['convert', 'ur5']) == 0\n"
        "print('numpy.random' in sys.modules, 'numpy' in sys.modules)"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines()[-1] == ("False True" if _draw._EXACT else "True True")
