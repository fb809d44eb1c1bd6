"""The fast path of ``Table.fk_batch`` and ``PoeModel.fk_batch``: the reference forward
kinematics (:mod:`urdf2dh.model.fk`) with ``e^{ix}`` taken from a table instead of numpy's ``exp``.

In the reference FK of a large batch, numpy's sines and cosines take about two thirds of the
time. Here ``x = k h + r`` with ``h = 2 pi / STEPS``: ``e^{ikh}`` is looked up in a table of
``STEPS`` values and ``e^{ir}``, ``|r| <= h / 2``, is a short Taylor polynomial. That is five
times as fast as numpy's ``cos`` and ``sin`` and makes batch FK about twice as fast
(``benchmarks/run.py``; docs/performance.md). Results agree with the reference
to a few units in the last place (``tests/test_fk.py`` checks every convention).

Batches below ``FAST_MIN`` configurations, and angles beyond the table's reach (huge, infinite or
NaN), take numpy's ``exp``. The self-check and ``verify`` always use the reference itself.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from . import fk

__all__ = ["FAST_MIN", "chain_fk", "chains_fk", "expi"]

FAST_MIN = 4096  # configurations; below it, numpy's exp costs less than the table's passes

STEPS = 4096  # table entries over one turn
# h split in two: H_HIGH has 33 significant bits, so k * H_HIGH is exact for |k| <= REACH_STEPS
# and x - k * H_HIGH loses nothing; H_LOW carries the rest of h (what is left, ~1e-24, is far
# below rounding for the angles within reach)
H_HIGH = 1.57079632673412561417e00 / 1024
H_LOW = 6.07710050630396597660e-11 / 1024
REACH_STEPS = 2.0**20

Mat = NDArray[np.float64]
Complexes = NDArray[np.complex128]


def _table() -> Complexes:
    """``e^{ijh}`` for ``j = 0 .. STEPS - 1``, each rounded once: with ``jh = a + b``, ``a = j
    H_HIGH`` exact and ``b = j H_LOW`` tiny, ``sin(a + b) = sin a + b cos a`` to far below
    rounding (and the same for ``cos``)."""
    j = np.arange(STEPS, dtype=float)
    a, b = j * H_HIGH, j * H_LOW
    return (np.cos(a) - b * np.sin(a)) + 1j * (np.sin(a) + b * np.cos(a))


TABLE = _table()


def expi(x: Mat) -> Complexes:
    """``e^{ix}`` ``(m,)`` for angles ``x`` ``(m,)``, from the table where every angle is within
    its reach (``|x| <= 2^20 h``, about 1600 rad), else from numpy's ``exp``."""
    k = np.rint(x * (1.0 / (H_HIGH + H_LOW)))
    if not np.abs(k).max(initial=0.0) <= REACH_STEPS:  # also false for NaN
        out: Complexes = np.exp(1j * x)
        return out
    r = (x - k * H_HIGH) - k * H_LOW  # |r| <= h / 2
    r2 = r * r
    small = np.empty(x.shape, dtype=np.complex128)
    small.real = 1.0 + r2 * (r2 * (1.0 / 24.0) - 0.5)  # cos r: next term r^6 / 720 < 1e-21
    small.imag = r + r * r2 * (-1.0 / 6.0)  # sin r: next term r^5 / 120 < 3e-18 r
    small *= TABLE[k.astype(np.intp) & (STEPS - 1)]  # k mod STEPS, negative k included
    return small


def chains_fk(chains: Sequence[fk.Chain], q: Mat) -> list[Mat]:
    """:func:`urdf2dh.model.fk.chains_fk`, with :func:`expi` for batches of ``FAST_MIN`` or more."""
    q = np.asarray(q, dtype=float)
    if q.ndim != 2 or q.shape[0] < FAST_MIN:
        return fk.chains_fk(chains, q)
    return fk.chains_fk(chains, q, expi=expi)


def chain_fk(links: Mat, motions: Mat, q: Mat) -> Mat:
    """:func:`urdf2dh.model.fk.chain_fk`, with :func:`expi` for batches of ``FAST_MIN`` or more."""
    return chains_fk([(links, motions)], q)[0]
