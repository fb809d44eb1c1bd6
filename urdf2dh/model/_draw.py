"""``numpy.random.default_rng(seed).uniform(low, high, size)``, the same numbers, for the few
draws a conversion makes, without importing ``numpy.random``.

Importing ``numpy.random`` loads all of its bit generators and the legacy ``RandomState``: about a
tenth of ``urdf2dh convert``'s CPU time, for the 100 configurations of a table's self-check. This
module draws them as numpy does, in Python: the seed's words mixed into a 4-word pool and expanded
to 256 bits (numpy's ``SeedSequence``, O'Neill's ``seed_seq_fe``), a PCG64 generator (128-bit LCG,
XSL-RR output) seeded with them, each double the top 53 bits of one output, scaled as
``low + (high - low) * u`` in C order (``Generator.uniform``). Larger draws, and any draw once
``numpy.random`` is imported anyway, are numpy's own; so are draws where numpy's C code may fuse
``low + range * u`` into one multiply-add (machines other than x86-64, where numpy's baseline has
no FMA), so that every machine draws what numpy draws there. tests/test_draw.py holds the numbers
equal, bit for bit, to numpy's.
"""

from __future__ import annotations

import math
import operator
import platform
import sys
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

__all__ = ["PYTHON_DRAWS", "python_uniform", "uniform"]

#: The most numbers drawn here rather than by ``numpy.random`` (about 0.4 us each: 10,000 cost less
#: than its import; more are numpy's).
PYTHON_DRAWS = 10_000

_M32 = 0xFFFFFFFF
_M64 = (1 << 64) - 1
_M128 = (1 << 128) - 1
_POOL = 4  # SeedSequence's pool, 32-bit words
_INIT_A, _MULT_A = 0x43B0D7E5, 0x931E8875  # hashing the entropy into the pool
_INIT_B, _MULT_B = 0x8B51F9DD, 0x58F38DED  # expanding the pool into the generator's state
_MIX_L, _MIX_R = 0xCA01F9DD, 0x4973F715
_PCG_MULT = (2549297995355413924 << 64) + 4865540595714422341
_EXACT = platform.machine().lower() in ("x86_64", "amd64")


def _words(seed: int | Sequence[int]) -> list[int]:
    """The seed as numpy's SeedSequence reads it: 32-bit words, least significant first; a
    tuple's parts one after the other."""
    if not isinstance(seed, int | np.integer):
        return [w for part in seed for w in _words(part)]
    n = operator.index(seed)
    out = [n & _M32]
    n >>= 32
    while n:
        out.append(n & _M32)
        n >>= 32
    return out


def _state(entropy: list[int]) -> list[int]:
    """The pool mixed from ``entropy``, expanded to four 64-bit words."""
    hash_const = _INIT_A

    def hashmix(value: int) -> int:
        nonlocal hash_const
        value ^= hash_const
        hash_const = (hash_const * _MULT_A) & _M32
        value = (value * hash_const) & _M32
        return value ^ (value >> 16)

    def mix(x: int, y: int) -> int:
        r = (_MIX_L * x - _MIX_R * y) & _M32
        return r ^ (r >> 16)

    pool = [hashmix(entropy[i] if i < len(entropy) else 0) for i in range(_POOL)]
    for src in range(_POOL):
        for dst in range(_POOL):
            if src != dst:
                pool[dst] = mix(pool[dst], hashmix(pool[src]))
    for word in entropy[_POOL:]:
        for dst in range(_POOL):
            pool[dst] = mix(pool[dst], hashmix(word))
    out = []
    hash_const = _INIT_B
    for k in range(8):
        value = pool[k % _POOL] ^ hash_const
        hash_const = (hash_const * _MULT_B) & _M32
        value = (value * hash_const) & _M32
        out.append(value ^ (value >> 16))
    return [out[2 * k] | out[2 * k + 1] << 32 for k in range(4)]


def _doubles(seed: int | Sequence[int], count: int) -> list[float]:
    """``count`` doubles in [0, 1) from PCG64 seeded as ``default_rng(seed)`` seeds it."""
    s = _state(_words(seed))
    inc = (((s[2] << 64) | s[3]) << 1 | 1) & _M128
    state = (inc + ((s[0] << 64) | s[1])) & _M128  # the step from 0, then the seed added
    state = (state * _PCG_MULT + inc) & _M128
    out = []
    for _ in range(count):
        state = (state * _PCG_MULT + inc) & _M128
        x = ((state >> 64) ^ state) & _M64
        r = state >> 122
        out.append(((((x >> r) | (x << (64 - r))) & _M64) >> 11) * (1.0 / 9007199254740992.0))
    return out


def uniform(
    low: NDArray[np.float64], high: NDArray[np.float64], count: int, seed: int | tuple[int, ...]
) -> NDArray[np.float64]:
    """``(count, len(low))`` numbers, ``numpy.random.default_rng(seed).uniform(low, high,
    size=(count, len(low)))`` exactly.

    Raises
    ------
    OverflowError
        A range ``high - low`` that is not finite (as numpy raises).
    """
    dof = len(low)
    if not _EXACT or count * dof > PYTHON_DRAWS or "numpy.random" in sys.modules:
        rng = np.random.default_rng(seed)
        return rng.uniform(low, high, size=(count, dof))
    return python_uniform(low, high, count, seed)


def python_uniform(
    low: NDArray[np.float64], high: NDArray[np.float64], count: int, seed: int | tuple[int, ...]
) -> NDArray[np.float64]:
    """:func:`uniform`'s numbers drawn in Python, whatever the machine or the count."""
    dof = len(low)
    lows = [float(a) for a in low]
    spans = [float(b) - a for a, b in zip(lows, high, strict=True)]
    if not all(math.isfinite(s) for s in spans):
        raise OverflowError("Range exceeds valid bounds")
    u = _doubles(seed, count * dof)
    out = np.empty((count, dof))
    out.flat[:] = [lows[k % dof] + spans[k % dof] * u[k] for k in range(count * dof)]
    return out
