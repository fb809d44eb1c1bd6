"""Forward kinematics of chains in link form: the one reference evaluation.

Every table, whatever its convention, and every POE model is evaluated the same way
(:meth:`urdf2dh.conventions.table.Table.link_form`, :meth:`urdf2dh.model.poe.PoeModel.link_form`)::

    T(q) = G_0 . Q_1(q_1) . G_1 . Q_2(q_2) ... Q_n(q_n) . G_n,    Q_i(q) = Rz(r_i q) Tz(t_i q)

with constant links ``G_i`` (4x4) and, per joint, its rotation ``r_i`` and translation ``t_i``
per unit of its position (a revolute joint has ``t = 0``, a prismatic one ``r = 0``, a helical
one both; the joint's scale is folded in).

The poses of ``m`` configurations are computed together, as the top three rows of each:
``F[r, k, :]`` is row ``r`` of configuration ``k``'s pose. Then

* ``F G`` is one matrix product of the ``(3 m, 4)`` rows with ``G``;
* ``F Rz(a)`` turns the x and y entries of every row: read as the complex number ``x + i y``,
  it becomes ``(x + i y) e^{-i a}`` (``x' = x cos a + y sin a``, ``y' = y cos a - x sin a``);
* ``F Tz(t)`` moves the origin along z: ``p' = p + t z``.

Several chains at the same configurations (the self-check's table and model, ``verify``'s model
and tables) are evaluated together so that a joint turning at the same rate in several of them
has its sines and cosines computed once.

The self-check, ``verify`` and the tests use this module as it is; the public batch FK
(``Table.fk_batch``, ``PoeModel.fk_batch``) runs it with sines from a table for large batches
(:mod:`urdf2dh.model._fastfk`, the FK fast path).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence

import numpy as np
from numpy.typing import NDArray

from ..geometry.se3 import errors_from_squares

__all__ = ["BLOCK", "chain_fk", "chains_errors", "chains_fk", "numpy_expi"]

BLOCK = 16384  # configurations evaluated together (their rows: 1.5 MiB)

Mat = NDArray[np.float64]
Chain = tuple[Mat, Mat]  # links (n + 1, 4, 4), motions (n, 2)
Expi = Callable[[Mat], NDArray[np.complex128]]
Turns = tuple[dict[tuple[int, float], NDArray[np.complex128]], Expi]


def numpy_expi(x: Mat) -> NDArray[np.complex128]:
    """``e^{ix}`` ``(m,)`` for angles ``(m,)``: ``cos x + i sin x``, by numpy."""
    out: NDArray[np.complex128] = np.exp(1j * x)
    return out


def chain_fk(links: Mat, motions: Mat, q: Mat) -> Mat:
    """Poses ``(N, 4, 4)`` of a chain in link form.

    Parameters
    ----------
    links
        ``(n + 1, 4, 4)``: the constant transforms ``G_0 .. G_n``.
    motions
        ``(n, 2)``: per joint, rotation (rad) and translation (length) per unit of ``q_i``.
    q
        ``(N, n)``: joint positions, one configuration per row.

    Returns
    -------
    numpy.ndarray
        ``(N, 4, 4)`` homogeneous transforms ``T(q)``.
    """
    return chains_fk([(links, motions)], q)[0]


def chains_fk(chains: Sequence[Chain], q: Mat, expi: Expi = numpy_expi) -> list[Mat]:
    """Poses ``(N, 4, 4)`` of each of several chains (each as in :func:`chain_fk`, all with
    ``n`` joints) at the same configurations ``q`` ``(N, n)``; ``expi(x)`` gives ``e^{ix}``
    (numpy's; the fast batch path, :mod:`urdf2dh.model._fastfk`, passes its own)."""
    q = np.asarray(q, dtype=float)
    # each chain's poses held row by row, (4, N, 4), as the blocks compute them; the poses
    # (N, 4, 4) are a view of that (no copy to another layout)
    rows = [np.empty((4, q.shape[0], 4)) for _ in chains]
    for held in rows:
        held[3] = (0.0, 0.0, 0.0, 1.0)
    for lo, c, f, _ in _blocks(chains, q, expi):
        rows[c][:3, lo : lo + f.shape[1]] = f
    return [held.transpose(1, 0, 2) for held in rows]


def chains_errors(chains: Sequence[Chain], q: Mat, reference: Mat) -> list[tuple[float, float]]:
    """Worst position and rotation error of each chain's poses at ``q`` ``(N, n)`` against
    ``reference`` ``(N, 4, 4)``: ``pose_errors(chains_fk(chains, q)[c], reference)`` for each
    chain ``c`` (:func:`urdf2dh.geometry.se3.pose_errors`), compared block by block as the poses are
    computed instead of holding them all (``verify``'s 10,000 configurations)."""
    q = np.asarray(q, dtype=float)
    reference = np.asarray(reference, dtype=float)
    if reference.shape != (q.shape[0], 4, 4):
        raise ValueError(f"reference poses {reference.shape}, expected ({q.shape[0]}, 4, 4)")
    moved, turned = np.zeros(len(chains)), np.zeros(len(chains))
    block_of_reference = (-1, reference[:0])  # (first configuration, its top rows (3, m, 4))
    with np.errstate(invalid="ignore", over="ignore"):  # non-finite poses: NaN, no warning
        for lo, c, f, spare in _blocks(chains, q, numpy_expi):
            if block_of_reference[0] != lo:  # laid out as the blocks are, once for all chains
                rows = reference[lo : lo + f.shape[1], :3].transpose(1, 0, 2)
                block_of_reference = (lo, np.ascontiguousarray(rows))
            squares = np.square(np.subtract(f, block_of_reference[1], out=spare), out=spare)
            columns = squares[0] + squares[1] + squares[2]  # (m, 4): each column's difference
            # np.maximum, not max(): a NaN must stay NaN
            moved[c] = np.maximum(moved[c], columns[:, 3].max())
            turned[c] = np.maximum(turned[c], (columns[:, 0] + columns[:, 1] + columns[:, 2]).max())
    return [errors_from_squares(float(a), float(b)) for a, b in zip(moved, turned, strict=True)]


def _blocks(chains: Sequence[Chain], q: Mat, expi: Expi) -> Iterator[tuple[int, int, Mat, Mat]]:
    """Each chain's poses, ``BLOCK`` configurations at a time: ``(first configuration, chain
    index, rows (3, m, 4), spare (3, m, 4))``. Both arrays are scratch space that the next step
    overwrites (fresh arrays at each step would cost more in page faults than the products)."""
    chains = [(np.asarray(g, dtype=float), np.asarray(m, dtype=float).reshape(-1, 2))
              for g, m in chains]  # fmt: skip
    work = np.empty((2, 12 * min(q.shape[0], BLOCK)))
    for lo in range(0, q.shape[0], BLOCK):
        per_joint = np.ascontiguousarray(q[lo : lo + BLOCK].T)  # (n, m)
        turns: Turns = ({}, expi)  # the block's e^{-i rate q_i}, shared by the chains
        for c, (links, motions) in enumerate(chains):
            yield (lo, c, *_block(links, motions, per_joint, turns, work))


def _turn(i: int, rate: float, per_joint: Mat, turns: Turns) -> NDArray[np.complex128]:
    """``e^{-i rate q_i}`` ``(m,)`` for the block, computed once per joint and rate."""
    known, expi = turns
    if (i, rate) not in known:
        known[i, rate] = expi(-rate * per_joint[i])
    return known[i, rate]


def _block(links: Mat, motions: Mat, per_joint: Mat, turns: Turns, work: Mat) -> tuple[Mat, Mat]:
    """The top three rows ``(3, m, 4)`` of the poses of ``m`` configurations (``per_joint``:
    ``(n, m)``, each joint's positions side by side), computed in ``work`` ``(2, >= 12 m)``;
    and the other half of ``work``, free."""
    m = per_joint.shape[1]
    # each half of work as the poses' rows (3, m, 4), as one matrix (3 m, 4) and as the rows'
    # x + i y (3, m), made once for every joint
    halves = [
        (rows, rows.reshape(-1, 4), rows.view(np.complex128)[:, :, 0])
        for rows in (w[: 12 * m].reshape(3, m, 4) for w in work)
    ]
    halves[0][0][...] = links[0, :3, None, :]
    for i, (rotation, translation) in enumerate(motions.tolist()):
        f, flat, xy = halves[i % 2]
        if rotation:  # each row's x + i y, times e^{-i a}
            xy *= _turn(i, rotation, per_joint, turns)
        if translation:
            f[:, :, 3] += translation * per_joint[i] * f[:, :, 2]
        np.matmul(flat, links[i + 1], out=halves[(i + 1) % 2][1])
    last = len(motions) % 2
    return halves[last][0], halves[1 - last][0]
