"""The prior: how far a robot as built may be from its nominal, as errors of its links.

A robot is built with small errors in its links and in the zero settings of its joints. The
prior models them as independent Gaussian errors, and the identification becomes a maximum a
posteriori estimate (what regularised calibration does: Tikhonov, with a physical metric):

* each link, from one joint to the next, is displaced by a small rigid motion: a rotation about
  the next joint's location (the nominal's joint origin), deviation ``s_k`` about each axis
  normal to that joint's axis, and a shift, deviation ``s_k`` x ``length_per_angle`` along each
  axis; every link has its own deviation (links are made and assembled one by one: automatic
  relevance determination, MacKay 1994, where a link the measurements find exact keeps the
  nominal's geometry while another moves);
* the rotation about the next joint's own axis (a turning joint), or the shift along it (a
  sliding one), is that joint's offset, its zero setting: one deviation for all offsets (x
  ``length_per_angle`` for sliding joints), set apart because zero settings and machining are
  different errors;
* the joints' scales (relative: a scale error ``s`` turns the next link by ``s`` per radian of
  travel) share one deviation, and helical joints' pitches the same x ``length_per_angle``;
* the base (where the robot stands in the device frame), the tool and the markers have no
  prior: they are unknown by nature.

A link's error carries every later joint with it, so in the level's coordinates (each joint's
line in the device frame, :mod:`.chart`) the errors are correlated. With ``delta`` the level's
joint coordinates measured from the reference (the nominal joints as the base-and-tool fit
placed them), ``A`` the linearised effect of the link errors ``z`` on them and ``B`` that of a
motion of the base, ``delta = A z + B b`` with ``b`` free: the prior is Gaussian with covariance
``A S A^T`` (``S``: the deviations squared) on the complement of ``B``'s columns, and its
residuals are ``L^-1 N^T delta`` (``N``: an orthonormal basis of that complement,
``L L^T = N^T A S A^T N``). At the ``offsets`` level the coordinates are the offsets themselves
(the base is a coordinate of its own): each offset over its deviation. The effects are exact to
first order: a rotation ``w`` about ``c`` and a shift ``t`` turn line ``(u, p)`` by ``w``'s part
normal to ``u`` and move its point by ``w x (p - c) + t``, read in the line's chart basis.

Deviations are stated (:class:`Prior`: ``LENGTH,ANGLE`` for every link, the offsets and the
scales alike) or estimated from the measurements by their marginal likelihood
(:mod:`.evidence`), ``length_per_angle`` being then the robot's size. A deviation near zero
holds those errors at the nominal's; a large one leaves them to the measurements.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..geometry.lie import cross_rows
from ..tolerances import CHOLESKY_RIDGE, RANK_RELATIVE
from .chart import Chain, Estimate, LineCoordinates, joint_columns, normal_bases, sizes

__all__ = [
    "AUTO",
    "CHOICES",
    "NONE",
    "Deviations",
    "LinkErrors",
    "Prior",
    "Regulariser",
    "Seen",
    "link_errors",
    "ridged",
]

Mat = NDArray[np.float64]

AUTO = "auto"  # deviations estimated from the measurements (geometry and full levels)
NONE = "none"  # no prior: maximum likelihood
CHOICES = (AUTO, NONE)


def ridged(a: Mat) -> Mat:
    """``a`` (a new matrix, changed in place) with :data:`~urdf2dh.tolerances.CHOLESKY_RIDGE`
    times its mean diagonal added to its diagonal: what a Cholesky factor is taken of."""
    diagonal = np.einsum("ii->i", a)  # a writeable view
    diagonal += CHOLESKY_RIDGE * float(diagonal.sum()) / max(len(a), 1)
    return a


@dataclass(frozen=True, slots=True)
class Prior:
    """Stated standard deviations of the joints' parameters about the nominal.

    Attributes
    ----------
    length
        Of lengths, in the nominal's length unit (> 0): a link's shift, a sliding joint's
        offset, a pitch per radian.
    angle
        Of angles, in radians (> 0): a link's turn, a turning joint's offset; and of scales.
    """

    length: float
    angle: float

    def __post_init__(self) -> None:
        for what, value in (("length", self.length), ("angle", self.angle)):
            if not (math.isfinite(value) and value > 0.0):
                raise InputError(f"the prior's {what} deviation must be a number > 0, not {value}")


@dataclass(frozen=True, slots=True)
class Deviations:
    """Standard deviations of the errors (module docstring).

    Attributes
    ----------
    links
        Each link's, rad (the links before the second joint, the third, ...; its shifts'
        deviation is this x ``length_per_angle``).
    offsets
        The offsets', rad (x ``length_per_angle`` for sliding joints).
    scales
        The scales' (relative; pitches: x ``length_per_angle``).
    length_per_angle
        Lengths' deviations per radian of angles' (length unit per rad).
    """

    links: tuple[float, ...]
    offsets: float
    scales: float
    length_per_angle: float

    @classmethod
    def stated(cls, prior: Prior, links: int) -> Deviations:
        return cls((prior.angle,) * links, prior.angle, prior.angle, prior.length / prior.angle)

    @classmethod
    def of_groups(cls, values: Mat, links: int, length_per_angle: float) -> Deviations:
        """From :meth:`groups`' order."""
        return cls(
            tuple(float(v) for v in values[:links]),
            float(values[links]),
            float(values[links + 1]),
            length_per_angle,
        )

    def groups(self) -> Mat:
        """``(links + 2,)``: each link's, the offsets', the scales'."""
        return np.array([*self.links, self.offsets, self.scales])


@dataclass(frozen=True)
class LinkErrors:
    """How one level's joint coordinates move with the link errors, at a reference.

    Attributes
    ----------
    reference
        The prior's centre (the level's start from the base-and-tool fit, with its free mask).
    coords
        ``(m,)`` the coordinates with a prior, as indices of the level's coordinates.
    at
        ``(m,)`` the same as positions in the free coordinates.
    slots
        ``(m, 2)`` each one's joint and slot (0-3: turn1, turn2, shift1, shift2; 4 pitch;
        5 offset; 6 scale).
    project
        ``(k, m)`` ``N^T``, the complement of the base's motions.
    effect
        ``(k, z)`` ``N^T A``, the errors' effect on the projected coordinates.
    group
        ``(z,)`` each error's deviation, an index of :meth:`Deviations.groups`.
    length
        ``(z,)`` whether the error is a length (its deviation x ``length_per_angle``).
    links
        How many links have errors of their own (``n - 1`` at the line levels, else 0).
    """

    reference: Estimate
    coords: NDArray[np.int64]
    at: NDArray[np.int64]
    slots: NDArray[np.int64]
    project: Mat
    effect: Mat
    group: NDArray[np.int64]
    length: NDArray[np.bool_]
    links: int

    def present(self) -> NDArray[np.int64]:
        """The groups of :meth:`Deviations.groups` whose errors act here."""
        return np.unique(self.group)

    def parts(self, length_per_angle: float) -> list[Mat]:
        """``(k, k)`` per present group: the covariance at unit deviation."""
        unit = np.where(self.length, length_per_angle, 1.0)
        return [
            (self.effect * np.where(self.group == g, unit, 0.0) ** 2) @ self.effect.T
            for g in self.present()
        ]

    def covariance(self, dev: Deviations) -> Mat:
        """``(k, k)`` the prior covariance of the projected coordinates."""
        sigma = dev.groups()[self.group] * np.where(self.length, dev.length_per_angle, 1.0)
        return ridged((self.effect * sigma**2) @ self.effect.T)

    def seen(self, est: Estimate) -> Seen:
        """The coordinates of ``est`` seen from the reference, their tangent when asked."""
        ref, at = self.reference, self._where
        out = np.empty(len(self.coords))
        lines = None
        if len(at.line_rows):
            lines = LineCoordinates.of(
                ref.chain.axis, ref.chain.point, est.chain.axis, est.chain.point
            )
            out[at.line_rows] = lines.values.ravel()[at.line_from]
        for rows, joints, here, there in (
            (*at.pitch, est.chain.pitch, ref.chain.pitch),
            (*at.offset, est.joint_offsets(), ref.joint_offsets()),
            (*at.scale, est.chain.scale, ref.chain.scale),
        ):
            out[rows] = here[joints] - there[joints]
        return Seen(self, est, out, lines)

    def deviations(self, est: Estimate) -> Mat:
        """``(m,)`` the coordinates of ``est`` seen from the reference (:func:`.chart.
        local_coordinates` at the prior's coordinates, lines all at once)."""
        return self.seen(est).values

    def evaluate(self, est: Estimate) -> tuple[Mat, Mat]:
        """:meth:`deviations` and :meth:`tangent` at ``est``."""
        seen = self.seen(est)
        return seen.values, seen.tangent()

    def tangent(self, est: Estimate) -> Mat:
        """``(m, p)`` the derivatives of :meth:`deviations` by ``est``'s free coordinates
        (:meth:`Seen.tangent`)."""
        return self.seen(est).tangent()

    @cached_property
    def _where(self) -> _Where:
        return _Where.of(self)


@dataclass(frozen=True, slots=True)
class Seen:
    """An estimate's coordinates seen by the prior (:meth:`LinkErrors.seen`), and their tangent
    when asked, from the same line coordinates (the solver's refused steps need no tangent).

    Attributes
    ----------
    errors, estimate
        Whose, and where.
    values
        ``(m,)`` :meth:`LinkErrors.deviations`.
    lines
        The level's line coordinates (:class:`.chart.LineCoordinates`), ``None`` without lines.
    """

    errors: LinkErrors
    estimate: Estimate
    values: Mat
    lines: LineCoordinates | None

    def tangent(self) -> Mat:
        """``(m, p)`` the derivatives of :attr:`values` by the estimate's free coordinates: 1 for
        pitches, offsets and scales; for a line's, :meth:`.chart.LineCoordinates.tangent`
        (each line's coordinates depend on that line alone)."""
        at = self.errors._where
        out = np.zeros((len(self.values), sum(sizes(self.estimate))))
        out[at.plain] = 1.0
        if self.lines is not None:
            out[at.moved] = self.lines.tangent().ravel()[at.moved_from]
        return out


@dataclass(frozen=True, slots=True)
class _Where:
    """Where :meth:`LinkErrors.seen` and :meth:`Seen.tangent` read and write, found
    once per :class:`LinkErrors` (indices; ``(rows, joints)`` pairs).

    Attributes
    ----------
    line_rows, line_from
        The line coordinates' rows, and their places in the flattened ``(n, 4)`` of
        :func:`.chart.line_coordinates`.
    pitch, offset, scale
        The other coordinates' rows and their joints.
    plain
        The tangent's entries that are 1 (rows, free positions).
    moved, moved_from
        The tangent's line entries (rows, free positions), and their places in the flattened
        line tangent ``(joint, coordinate, slot moved)`` (:meth:`.chart.LineCoordinates.
        tangent`).
    """

    line_rows: NDArray[np.int64]
    line_from: NDArray[np.int64]
    pitch: tuple[NDArray[np.int64], NDArray[np.int64]]
    offset: tuple[NDArray[np.int64], NDArray[np.int64]]
    scale: tuple[NDArray[np.int64], NDArray[np.int64]]
    plain: tuple[NDArray[np.int64], NDArray[np.int64]]
    moved: tuple[NDArray[np.int64], NDArray[np.int64]]
    moved_from: NDArray[np.int64]

    @classmethod
    def of(cls, errors: LinkErrors) -> _Where:
        """The places of ``errors``' coordinates (:attr:`LinkErrors.slots`)."""
        joint, slot = errors.slots[:, 0], errors.slots[:, 1]
        chain = errors.reference.chain
        n = len(chain)
        rows = np.arange(len(joint))
        line = slot < 4
        column = np.full((n, 4), -1, dtype=np.int64)  # (joint, slot) -> free position
        column[joint[line], slot[line]] = errors.at[line]
        parts = []
        for s in range(4):
            mine = line & (column[joint, s] >= 0)  # rows whose joint has this coordinate
            parts.append(
                (rows[mine], column[joint[mine], s], (joint[mine] * 4 + slot[mine]) * 4 + s)
            )
        moved = tuple(np.concatenate([p[k] for p in parts]) for k in range(3))

        def rows_of(kind: int) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
            return rows[slot == kind], joint[slot == kind]

        plain = slot >= 4
        return cls(
            rows[line],
            joint[line] * 4 + slot[line],
            rows_of(4),
            rows_of(5),
            rows_of(6),
            (rows[plain], errors.at[plain]),
            (moved[0], moved[1]),
            moved[2],
        )


@dataclass(frozen=True)
class Regulariser:
    """The prior's rows of one level, for given deviations: ``W delta(est)`` with the
    whitening ``W = L^-1 N^T`` (module docstring)."""

    errors: LinkErrors
    deviations: Deviations
    whiten: Mat

    @classmethod
    def of(cls, errors: LinkErrors, dev: Deviations) -> Regulariser:
        factor = np.linalg.cholesky(errors.covariance(dev))
        return cls(errors, dev, np.linalg.solve(factor, errors.project))

    def residuals(self, est: Estimate) -> Mat:
        """The prior's residuals ``(k,)`` at ``est`` (their Jacobian: ``whiten`` times
        :meth:`LinkErrors.evaluate`'s tangent, which the solver's linearisation carries)."""
        out: Mat = self.whiten @ self.errors.deviations(est)
        return out


def link_errors(reference: Estimate, locations: Mat) -> LinkErrors | None:
    """The link errors of ``reference``'s level (module docstring); ``locations`` ``(n, 3)``:
    each joint's location in the device frame (the centre of the previous link's rotation).
    ``None`` when no free coordinate has a prior."""
    ref = reference
    level, chain = ref.level, ref.chain
    total = sum(sizes(ref, every=True))
    free = np.ones(total, dtype=bool) if ref.free is None else ref.free
    position = np.cumsum(free) - 1
    line_at, offset_at, scale_at = joint_columns(ref)
    # (coordinate, joint, slot) of each joint coordinate with a prior, in the level's order
    at = np.hstack([line_at, offset_at[:, None], scale_at[:, None]])
    joint, slot = np.nonzero(at >= 0)
    coords = at[joint, slot]
    order = np.argsort(coords, kind="stable")
    order = order[free[coords[order]]]
    if not len(order):
        return None
    coords, slots = coords[order], np.stack([joint[order], slot[order]], axis=1)
    links = len(chain) - 1 if level.lines else 0
    plain = slots[:, 1] >= 4  # pitch, offset, scale: errors of their own
    columns = np.eye(len(slots))[plain]
    kind = slots[plain, 1]
    group = np.where(kind == 5, links, links + 1)
    length = (kind == 4) | ((kind == 5) & ~chain.turning[slots[plain, 0]])
    project = np.eye(len(slots))
    if level.lines:
        flat, moves, moves_group, moves_length = _link_columns(chain, slots, locations)
        columns = np.vstack([moves, columns])
        group = np.concatenate([moves_group, group])
        length = np.concatenate([moves_length, length])
        u_b, s_b, _ = np.linalg.svd(flat, full_matrices=True)
        rank = int(np.sum(s_b > RANK_RELATIVE * float(s_b.max(initial=0.0))))
        project = u_b[:, rank:].T
    if not len(project):
        return None
    return LinkErrors(
        ref,
        coords,
        position[coords].astype(np.int64),
        slots,
        project,
        project @ columns.T,
        group.astype(np.int64),
        length,
        links,
    )


def _link_columns(
    chain: Chain, slots: NDArray[np.int64], locations: Mat
) -> tuple[Mat, Mat, NDArray[np.int64], NDArray[np.bool_]]:
    """The effects of the base's motions ``(m, 6)`` and of every link error ``(6 (n - 1), m)``
    (their groups and whether each is a length: ``(6 (n - 1),)``) on the line coordinates
    ``slots`` (module docstring): the error of the link before joint ``k`` moves the lines of
    joints ``k, k+1, ...``; a unit rotation ``w`` about ``c`` changes a line's turn along ``e``
    by ``w . e`` and its shift along ``e`` by ``w . ((p - c) x e)``, a unit shift ``t`` its
    shift by ``t . e``; each motion about and along the joint's axis and its two normals
    (:func:`.chart.normal_bases`), all joints at once."""
    joint, slot = slots[:, 0], slots[:, 1]
    n, m = len(chain), len(slots)
    e1, e2 = normal_bases(chain.axis)
    e = np.where((slot % 2 == 0)[:, None], e1[joint], e2[joint])
    is_line, is_turn = slot < 4, slot < 2
    moved = (is_line & (joint >= np.arange(n)[:, None]))[:, :, None]  # (n, m, 1)
    lever = cross_rows(chain.point[joint] - locations[:, None], e)  # (n, m, 3)
    rotation = np.where(is_turn[:, None], e, lever) * moved  # (n, m, 3): . w
    shift = np.where(is_turn[:, None], 0.0, e) * moved  # (n, m, 3): . t
    directions = np.stack([chain.axis, e1, e2], axis=1).transpose(0, 2, 1)  # the axis first
    effects = np.concatenate([rotation @ directions, shift @ directions], axis=2)  # (n, m, 6)
    # about and along a joint's own axis: its offset (turning, or sliding, joint)
    turning = chain.turning[1:, None]
    own = np.arange(n - 1)[:, None]
    offsets = n - 1  # the offsets' group, after the links'
    group = np.repeat(own, 6, axis=1)
    group[:, :1] = np.where(turning, offsets, own)
    group[:, 3:4] = np.where(turning, own, offsets)
    length = np.tile([False, False, False, True, True, True], n - 1)
    return effects[0], effects[1:].transpose(0, 2, 1).reshape(-1, m), group.ravel(), length
