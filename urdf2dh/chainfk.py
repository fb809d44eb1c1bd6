"""Batched forward kinematics of a parameter table: the poses of ``N`` configurations at once.

A table's FK (SPEC §2) is a product of elementary motions: joint turns ``Rz(j s + theta)``
and slides ``Tz(k s + d)``, and constant ``Rx(alpha)``, ``Tx(a)``, ``Rz``, ``Tz`` (``dh``,
``mdh``) or dense shape matrices ``V`` (``cpc``). A :class:`Program` lists them once per
table; :func:`run` applies them to a block of configurations at a time, vectorised over the
block:

* the rotations are composed base to tip, each held as its three rows, row-major over the
  block (``(3, m, 4)``): ``R Rz(phi)`` turns the x and y columns, with ``w = x + i y`` it is
  ``w e^{-i phi}``, one complex product (the same for ``Rx(alpha)`` and the y and z columns);
  a dense ``V`` is one stacked ``3x3`` matrix product;
* the position is carried tip to base, ``p = o_1 (o_2 (... o_K (0)))`` (the base's motions
  first): one vector per configuration, so that a turn costs a complex product of ``m``
  elements instead of ``3 m`` and ``Tz``/``Tx`` one addition to a component instead of an axpy
  on a column (a ``dh`` or ``mdh`` table's FK has no dense product at all, so no BLAS call);
* the rows are copied into the poses as 32-byte items (one loop over the block).

A joint's constant offsets join its motion (``Rz(j s) Rz(theta) = Rz(j s + theta)``), so a
revolute joint costs a complex product on the rotations and one on the position; the sines
and cosines of all joints come from one call (:func:`urdf2dh.trig.expi`). Multiplying by 1 or
adding 0 is skipped, which changes no bit. Large batches are split over threads (numpy
releases the GIL in its loops).

:func:`run_links` and :func:`compare_links` evaluate chains given as dense links
``G_0 Q_1 G_1 ... Q_n G_n`` instead, several side by side in the same numpy calls: the
self-check's table and POE model.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import se3
from .trig import expi

__all__ = ["BLOCK", "Program", "compare_links", "map_blocks", "run", "run_links", "workers"]

BLOCK = 16384  # configurations per block (4096 is slower: per-call costs; 32768 no faster)
THREADS_FROM = 4 * BLOCK  # configurations: below this, one thread

Mat = NDArray[np.float64]
Motions = Mat | Sequence[Sequence[tuple[float, float]]]  # (k, n, 2): an array or plain floats
Complexes = NDArray[np.complex128]

# operations on the current frames F (one per configuration of the block)
TURN, SLIDE, RZ, TZ, RX, TX, MATRIX = range(7)


@dataclass(frozen=True)
class Program:
    """The motions of a chain: ``base`` (4x4), then ``ops`` in order.

    ``TURN i`` is ``Rz(-angle_i)`` with ``angle_i = turn[i, 0] q_i + turn[i, 1]`` (so that
    ``e^{i angle}`` is the factor of ``x + i y``); ``SLIDE i`` is ``Tz(slide[i, 0] q_i +
    slide[i, 1])``; ``RZ e`` and ``RX e`` multiply by the unit complex ``e`` (``e^{-i theta}``);
    ``TZ d`` and ``TX a`` translate; ``MATRIX G`` multiplies by a dense 4x4. The constant
    operations before the first joint, ``lead``, are folded into ``base`` for the rotations
    and applied one by one to the position (no dense product where the base is elementary).
    """

    n: int
    base: Mat
    turn: Mat  # (n, 2): per joint, angle = c q + o (rows of prismatic joints: unused)
    slide: Mat  # (n, 2): per joint, t = c q + o
    ops: tuple[tuple[int, Any], ...]
    lead: tuple[tuple[int, Any], ...]

    @staticmethod
    def build(
        base: Mat | list[tuple[int, Any]],
        joints: Sequence[tuple[float, float, float, float, float]],
        between: Sequence[tuple[list[tuple[int, Any]], list[tuple[int, Any]]]],
        tool: list[tuple[int, Any]],
    ) -> Program:
        """From the base (a 4x4, or its elementary operations), each joint's ``(rotation,
        translation, scale, theta, d)`` (the motion ``Rz(rotation s + theta) Tz(translation s
        + d)``, ``s = scale q``), the constant operations ``(before, after)`` it, and the
        tool's operations."""
        ops: list[tuple[int, Any]] = list(base) if isinstance(base, list) else [(MATRIX, base)]
        turn, slide = np.zeros((len(joints), 2)), np.zeros((len(joints), 2))
        for i, ((rot, lin, scale, theta, d), (before, after)) in enumerate(
            zip(joints, between, strict=True)
        ):
            ops.extend(before)
            if rot:
                turn[i] = (-rot * scale, -theta)
                ops.append((TURN, i))
            else:
                ops.extend(rz(theta))
            if lin:
                slide[i] = (lin * scale, d)
                ops.append((SLIDE, i))
            else:
                ops.extend(translate(TZ, d))
            ops.extend(after)
        ops.extend(tool)
        first = next(k for k, (op, _) in enumerate([*ops, (TURN, -1)]) if op in (TURN, SLIDE))
        lead = ops[:first]
        del ops[:first]
        return Program(len(joints), se3.matrix_of(_product(se3.IDENTITY, lead)), turn, slide,
                       tuple(ops), tuple(lead))


def _frame(op: int, arg: Any) -> se3.Frame:
    """The :data:`~urdf2dh.se3.Frame` of a constant operation."""
    if op == MATRIX:
        return se3.frame_of(arg)
    if op in (TZ, TX):
        z, x = (arg, 0.0) if op == TZ else (0.0, arg)
        return ((1.0, 0.0, 0.0, x), (0.0, 1.0, 0.0, 0.0), (0.0, 0.0, 1.0, z))
    c, s = arg.real, -arg.imag  # arg = e^{-i angle}
    if op == RZ:
        return ((c, -s, 0.0, 0.0), (s, c, 0.0, 0.0), (0.0, 0.0, 1.0, 0.0))
    return ((1.0, 0.0, 0.0, 0.0), (0.0, c, -s, 0.0), (0.0, s, c, 0.0))


def _product(f: se3.Frame, ops: Sequence[tuple[int, Any]]) -> se3.Frame:
    for op in ops:
        f = se3.compose(f, _frame(*op))
    return f


def rz(theta: float) -> list[tuple[int, Any]]:
    """``Rz(theta)`` (nothing for 0)."""
    return [(RZ, complex(math.cos(theta), -math.sin(theta)))] if theta else []


def rx(alpha: float) -> list[tuple[int, Any]]:
    """``Rx(alpha)`` (nothing for 0)."""
    return [(RX, complex(math.cos(alpha), -math.sin(alpha)))] if alpha else []


def translate(op: int, length: float) -> list[tuple[int, Any]]:
    """``Tz`` or ``Tx`` (nothing for 0)."""
    return [(op, float(length))] if length else []


class _Work:
    """One thread's scratch arrays for blocks of up to ``m`` configurations."""

    def __init__(self, n: int, m: int) -> None:
        self.angles = np.empty(n * m)
        self.turns = np.empty(n * m, dtype=np.complex128)
        self.frames = np.empty((2, 12 * m))
        self.vectors = np.empty((2, m, 4))  # the position, carried from the tip (see _position)
        self.tmp = np.empty(m)


def _pairs(a: Mat) -> tuple[Complexes, Complexes]:
    """Of an array whose last axis holds ``(x, y, z, ..)``: the views ``x + i y`` and
    ``y + i z`` (complex)."""
    return a[..., 0:2].view(np.complex128)[..., 0], a[..., 1:3].view(np.complex128)[..., 0]


class _Frames:
    """A block's frames ``(3, m, 4)`` (the top three rows of each pose, row-major over the
    block) and views of them: ``x + i y`` and ``y + i z`` (complex)."""

    def __init__(self, flat: Mat, m: int) -> None:
        self.f = flat[: 12 * m].reshape(3, m, 4)
        self.xy, self.yz = _pairs(self.f)


ROW = np.dtype((np.void, 32))  # a row of a pose as one item: copies of rows are one loop over m
LAST_ROW = np.array([0.0, 0.0, 0.0, 1.0]).view(ROW)[0]


def _block(program: Program, q: Mat, out: Mat, work: _Work) -> None:
    """Poses ``out`` ``(m, 4, 4)`` (contiguous) for configurations ``q`` ``(m, n)``.

    The rotations are composed base to tip; the position is carried tip to base
    (:func:`_position`), one vector per configuration instead of a column per row.
    """
    m, n = q.shape
    angles = work.angles[: n * m].reshape(n, m)
    np.multiply(q.T, program.turn[:, :1], out=angles)
    if program.turn[:, 1].any():  # (adding 0 changes no bit)
        angles += program.turn[:, 1:]
    turns = work.turns[: n * m].reshape(n, m)
    expi(angles, turns)
    cur, other = _Frames(work.frames[0], m), None
    ops = program.ops
    if ops and ops[0][0] == TURN:  # the base's x + i y times the first turn, written at once
        start = np.ascontiguousarray(program.base[:3, :2]).view(np.complex128)
        np.multiply(start, turns[ops[0][1]], out=cur.xy)
        cur.f[:, :, 2] = program.base[:3, 2, None]
        ops = ops[1:]
    else:
        for c in range(3):
            cur.f[:, :, c] = program.base[:3, c, None]
    for op, arg in ops:
        if op == TURN:
            cur.xy *= turns[arg]
        elif op == RZ:
            cur.xy *= arg
        elif op == RX:
            cur.yz *= arg
        elif op == MATRIX:  # (its translation is the position's)
            other = other or _Frames(work.frames[1], m)
            np.matmul(cur.f[:, :, :3], arg[:3, :3], out=other.f[:, :, :3])
            cur, other = other, cur
    _position(program, q, turns, work, cur.f[:, :, 3].T)
    rows = out.reshape(m, 16).view(ROW)  # (m, 4)
    for r, row in enumerate(cur.f.reshape(3 * m, 4).view(ROW).reshape(3, m)):
        rows[:, r] = row
    rows[:, 3] = LAST_ROW


def _position(program: Program, q: Mat, turns: Complexes, work: _Work, out: Mat) -> None:
    """The positions ``(m, 3)`` of the chain's origin: ``p = o_1 (o_2 (... o_K (0)))``, the
    motions (the base's first) applied to a vector from the last to the first (a turn is one
    complex product of ``m`` elements, a translation one addition to a component).

    The vector is held as ``(x, -y, z, 1)``: then ``Rz(phi)`` acting on it is ``(x - i y)
    e^{-i phi}`` and ``Rx(alpha)`` is ``(-y + i z) e^{-i alpha}``, the same factors as the
    rotations' (:class:`Program`).
    """
    m = q.shape[0]
    v, other = work.vectors[0, :m], work.vectors[1, :m]
    v.view(ROW)[:, 0] = LAST_ROW  # (0, 0, 0, 1)
    xy, yz = _pairs(v)
    for op, arg in reversed(program.lead + program.ops):
        if op == TURN:
            xy *= turns[arg]
        elif op == SLIDE:
            c, o = program.slide[arg]
            t = work.tmp[:m]
            np.multiply(q[:, arg], c, out=t)
            t += o
            v[:, 2] += t
        elif op == RZ:
            xy *= arg
        elif op == RX:
            yz *= arg
        elif op == TZ:
            v[:, 2] += arg
        elif op == TX:
            v[:, 0] += arg
        else:  # MATRIX G: v <- G v, in the held coordinates S G S with S = diag(1, -1, 1, 1)
            np.dot(v, (_FLIP * arg * _FLIP[:, None]).T, out=other)
            v, other = other, v
            xy, yz = _pairs(v)
    out[:, 0] = v[:, 0]
    np.negative(v[:, 1], out=out[:, 1])
    out[:, 2] = v[:, 2]


_FLIP = np.array([1.0, -1.0, 1.0, 1.0])


def run(program: Program, q: Mat) -> Mat:
    """Poses ``(N, 4, 4)`` of configurations ``q`` ``(N, n)``."""
    out = np.empty((q.shape[0], 4, 4))

    def job(lo: int, hi: int, work: _Work) -> None:
        _block(program, q[lo:hi], out[lo:hi], work)

    map_blocks(q.shape[0], BLOCK, job, lambda m: _Work(program.n, m))
    return out


def run_links(links: Mat, motions: Mat, q: Mat) -> Mat:
    """Poses ``(k, N, 4, 4)`` of ``k`` chains in link form, ``T = G_0 Q_1 G_1 ... Q_n G_n``
    with ``Q_i = Rz(motions[.., i, 0] q_i) Tz(motions[.., i, 1] q_i)``, at the same
    configurations ``q`` ``(N, n)``: ``links`` ``(k, n + 1, 4, 4)``, ``motions`` ``(k, n, 2)``.

    The chains share every numpy call (a joint is one complex product and one stacked matrix
    product for all ``k``), which is what makes a small batch cheap.
    """
    k, count = len(links), q.shape[0]
    out = np.empty((k, count, 4, 4))

    def job(lo: int, hi: int, work: Mat) -> None:
        f = _links_block(links, motions, q[lo:hi], work)
        out[:, lo:hi, :3] = f.transpose(0, 2, 1, 3)
        out[:, lo:hi, 3] = (0.0, 0.0, 0.0, 1.0)

    map_blocks(count, BLOCK, job, lambda m: np.empty((2, k * 12 * m)))
    return out


def compare_links(links: Mat, motions: Motions, q: Mat) -> tuple[float, float]:
    """The worst position and rotation difference (as :func:`urdf2dh.se3.pose_errors`
    measures them) between two chains in link form (``k = 2`` in :func:`run_links`' terms)
    at configurations ``q``: the self-check, without building the poses."""
    worst: list[list[float]] = []

    def job(lo: int, hi: int, work: Mat) -> None:
        worst.append(_worst_squares(_links_block(links, motions, q[lo:hi], work)))

    map_blocks(q.shape[0], BLOCK, job, lambda m: np.empty((2, 24 * m)))
    if not worst:
        return 0.0, 0.0
    pos2, rot2 = (max(w) if not any(math.isnan(x) for x in w) else math.nan
                  for w in zip(*worst, strict=True))
    return se3.errors_of_squares(pos2, rot2)


def _worst_squares(f: Mat) -> list[float]:
    """Of frames ``(2, 3, m, 4)``: the largest sums of squared differences over the position
    entries and over the rotation entries."""
    d = np.subtract(f[0], f[1])  # (3, m, 4)
    d *= d
    s = d.sum(axis=0)  # per configuration and column, over the rows
    return [float(s[:, 3].max()), float(s[:, :3].sum(axis=1).max())]


def _links_block(links: Mat, motions: Motions, q: Mat, work: Mat) -> Mat:
    """The frames ``(k, 3, m, 4)`` (top three rows, row-major over the block) of ``q``."""
    (m, n), k = q.shape, len(links)
    frames = [w[: k * 12 * m].reshape(k, 3, m, 4) for w in work]
    xys = [_pairs(f)[0] for f in frames]
    rows = [f.reshape(k, 3 * m, 4) for f in frames]
    # which joints turn or slide in some chain, and whether all chains turn alike (plain floats,
    # decided in Python)
    chains = motions.tolist() if isinstance(motions, np.ndarray) else motions
    rotations = [[chain[i][0] for chain in chains] for i in range(n)]  # per joint, per chain
    translations = [[chain[i][1] for chain in chains] for i in range(n)]
    turning = [any(r) for r in rotations]
    sliding = [any(t) for t in translations]
    shared = all(min(r) == max(r) for r in rotations)  # then the turns are computed once
    width = 1 if shared else k
    rate = np.array([[-x for x in r[:width]] for r in rotations]).reshape(n, width, 1, 1)
    turns = np.empty((n, width, 1, m), dtype=np.complex128)  # turns[i] meets (k, 3, m)
    expi(np.multiply(q.T[:, None, None, :], rate), turns)  # e^{-i rot q}
    frames[0][...] = links[:, 0, :3, None, :]  # G_0
    cur, nxt = 0, 1
    for i in range(n):
        if turning[i]:
            xys[cur] *= turns[i]
        if sliding[i]:
            f = frames[cur]
            shift = np.multiply(q[:, i], np.array(translations[i])[:, None])  # (k, m)
            f[:, :, :, 3] += shift[:, None, :] * f[:, :, :, 2]
        np.matmul(rows[cur], links[:, i + 1], out=rows[nxt])
        cur, nxt = nxt, cur
    return frames[cur]


def workers(count: int) -> int:
    """Threads for a batch of ``count`` configurations: one below :data:`THREADS_FROM`, else
    the CPUs this process may use, or ``URDF2DH_THREADS`` if set."""
    if count < THREADS_FROM:
        return 1
    wanted = os.environ.get("URDF2DH_THREADS")
    if wanted:
        return max(1, int(wanted))
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
               else os.cpu_count() or 1)


@cache
def _pool(threads: int) -> ThreadPoolExecutor:
    return ThreadPoolExecutor(threads, thread_name_prefix="urdf2dh-fk")


def map_blocks(
    count: int, block: int, job: Callable[[int, int, Any], None], make_work: Callable[[int], Any]
) -> None:
    """Call ``job(lo, hi, work)`` over ``range(count)`` in blocks of at most ``block``; with
    several threads (this one and ``threads - 1`` helpers), each takes every k-th block and
    has its own ``work``.

    Beyond one block, their number is a multiple of 4 (at most one per configuration) and their
    lengths differ by at most one, so that two or four threads get equal shares; the blocks do
    not depend on the number of threads, so neither do the results."""
    if count <= block:  # at most one block: this thread, at once
        if count:
            job(0, count, make_work(count))
        return
    blocks = -(-count // block)
    blocks = min(blocks + -blocks % 4, count)
    spans = [(k * count // blocks, (k + 1) * count // blocks) for k in range(blocks)]
    threads = min(workers(count), blocks)
    size = -(-count // blocks)

    def share(k: int) -> None:
        work = make_work(size)
        for lo, hi in spans[k::threads]:
            job(lo, hi, work)

    if threads == 1:
        share(0)
        return
    helpers = [_pool(threads - 1).submit(share, k) for k in range(1, threads)]
    share(0)  # this thread takes a share too: it is awake, its caches warm
    for done in helpers:
        done.result()
