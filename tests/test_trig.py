"""urdf2dh.trig: e^{ix} by table and polynomial against the C library's cos and sin."""

from __future__ import annotations

import numpy as np
import pytest

from urdf2dh import trig

RNG = np.random.default_rng(20261121)
ULP_OF_ONE = float(np.spacing(1.0))  # 2.2e-16


def table_expi(x):
    out = np.empty(np.shape(x), dtype=complex)
    assert trig.expi_table(np.asarray(x, dtype=float), out)
    return out


def worst_error(x, e):
    return max(np.abs(e.real - np.cos(x)).max(), np.abs(e.imag - np.sin(x)).max())


@pytest.mark.parametrize("span", [1e-9, 1.0, 4.0, 100.0, trig.REACH])
def test_within_two_units_in_the_last_place(span):
    x = RNG.uniform(-span, span, size=(3, 200_000))
    assert worst_error(x, table_expi(x)) <= 2 * ULP_OF_ONE


def test_at_the_reduction_boundaries():
    """Multiples of the table step h and of pi/2, the half steps where rint rounds to even,
    and their neighbours; signed zeros."""
    k = np.concatenate([np.arange(-5000.0, 5000.0),  # steps near 0, and across the reach
                        RNG.integers(-2**20, 2**20, 5000).astype(float)])
    h = 2 * np.pi / trig.STEPS
    quarter = np.arange(-1000.0, 1000.0)  # |x| <= 1571 rad, within the reach
    points = np.concatenate([k * h, (k + 0.5) * h, quarter * np.pi / 2, quarter * np.pi / 4,
                             [0.0, -0.0]])
    assert np.abs(points).max() <= trig.REACH
    x = np.concatenate([points, np.nextafter(points, np.inf), np.nextafter(points, -np.inf)])
    assert worst_error(x, table_expi(x)) <= 2 * ULP_OF_ONE
    assert table_expi(np.array([0.0]))[0] == 1.0


def test_table_is_the_unit_circle():
    assert np.abs(np.abs(trig.TABLE) - 1.0).max() <= ULP_OF_ONE
    assert trig.TABLE[trig.STEPS // 4] == pytest.approx(1j, abs=1e-16)


def test_out_of_range_goes_to_the_c_library():
    """Too large for the exact reduction, infinite or NaN: expi answers as numpy does."""
    for bad in (trig.REACH + 1.0, -1e9, np.inf, np.nan):
        x = np.full(trig.POLY_MIN, 0.25)
        x[-1] = bad
        out = np.empty(x.size, dtype=complex)
        assert not trig.expi_table(x, out)
        with np.errstate(invalid="ignore"):
            trig.expi(x, out)
            expected = np.cos(x) + 1j * np.sin(x)
        np.testing.assert_array_equal(out, expected)


def test_small_arrays_are_the_c_library_exactly():
    x = RNG.uniform(-3.0, 3.0, size=(7, 100))
    out = np.empty(x.shape, dtype=complex)
    trig.expi(x, out)
    np.testing.assert_array_equal(out.real, np.cos(x))
    np.testing.assert_array_equal(out.imag, np.sin(x))


def test_large_arrays_take_the_table_in_chunks():
    x = RNG.uniform(-3.0, 3.0, size=(5, trig.CHUNK + 7))
    out = np.empty(x.shape, dtype=complex)
    trig.expi(x, out)
    np.testing.assert_array_equal(out, table_expi(x))
    assert worst_error(x, out) <= 2 * ULP_OF_ONE


def test_writes_only_into_contiguous_arrays():
    out = np.empty((4, 2), dtype=complex)[:, 0]
    with pytest.raises(ValueError, match="contiguous"):
        trig.expi_table(np.zeros(4), out)
