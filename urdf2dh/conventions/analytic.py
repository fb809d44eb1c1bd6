"""A standard D-H table as the analytic inverse-kinematics solvers read it: its relations exact.

The solvers that take a D-H chain (roboticstoolbox-python's ``DHRobot.analytic_ik``, EAIK's robots
from joint frames, :mod:`urdf2dh.conventions.families`) recognise a spherical wrist or parallel
axes by exact relations between the parameters (``a = d = 0``, ``alpha`` a multiple of pi), and
roboticstoolbox-python 1.5 derives its closed form symbolically from the numbers it is given: an
angle becomes ``nsimplify(x, [pi])`` and every length that is not 0 a symbol. An exact table of a
URDF keeps what its source rounded (``rpy="0 0 1.570796327"`` leaves 4.9e-12 rad where the
maker meant 0; the Kinova Jaco2's wrist axes pass 5e-13 m from one point), and each such value
is a new symbol there: no closed form within its default 120 s (UR5, Jaco2, measured). So
:func:`analytic_form` writes the table as a chain

    T(q) = B . prod_i [Rz(q_i + theta_i) Tz(d_i) Rx(alpha_i) Tx(a_i)] . T

(joint variables the table's, so the source's: zeros and directions) in which

* every ``theta`` and ``alpha`` within ``tol.solver_snap`` rad of a multiple of pi/2 is that
  multiple, and every ``d`` and ``a`` within ``tol.solver_snap`` x the robot's size of 0 is 0;
* the last row's ``alpha`` and ``a`` (the tip's tilt and offset from the last axis, no relation
  between axes) are moved into the tool ``T = Rx(alpha_n) Tx(a_n) . Rz(theta_T) Tz(d_T)``, a
  full transform, exactly; ``B`` is the table's base.

A snap beyond the files' round-off (``tol.written``) is a judgement. A turn of ``delta`` about
or between axes moves no point by more than ``2 delta`` times its distance from the axis (at
most twice the robot's reach) and turns the tip by at most ``2 delta``; a length changed by
``delta`` shifts an axis, which moves a point by at most ``2 delta``. The snaps' sum of those is
the bound the chain declares (:class:`~urdf2dh.conventions.table.Check`), and its forward
kinematics is measured against the table's at 1000 seeded configurations (100 without a
judgement): beyond the bound plus ``tol.check_position`` x size and ``tol.check_rotation`` rad,
:class:`~urdf2dh.errors.ConversionError`, nothing written.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ..errors import ConversionError, UsageError
from ..geometry import se3
from ..geometry.frames import compose, frame_of, rx_tx
from ..geometry.se3 import pose_errors
from ..model._fastfk import chain_fk
from ..model.mimic import row_positions
from ..tolerances import DEFAULT, Tolerances
from .base import written_angle, written_length
from .convert import DEFAULT_SAMPLES, JUDGED_SAMPLES
from .dh import DhLink
from .table import Check, Row, Table

__all__ = ["AnalyticChain", "Snap", "analytic_form", "pi_text"]

Mat = NDArray[np.float64]
ANGLES, LENGTHS = ("theta", "alpha"), ("d", "a")


@dataclass(frozen=True, slots=True)
class Snap:
    """A parameter the analytic form writes exactly: ``row`` (a joint's name), ``parameter``
    (``theta``, ``d``, ``alpha`` or ``a``), the table's ``value`` and the ``exact`` one."""

    row: str
    parameter: str
    value: float
    exact: float

    @property
    def change(self) -> float:
        """How far the parameter moved (an angle modulo 2 pi: ``-pi + 1e-12`` is written
        ``pi``)."""
        gap = self.exact - self.value
        return abs(math.remainder(gap, 2.0 * math.pi) if self.parameter in ANGLES else gap)

    def text(self, unit: str) -> str:
        """``theta of 'j2': pi - 4.9e-12 rad, written pi`` (the name as the source spells it:
        files write it through their language's function, :mod:`urdf2dh.escape`)."""
        angle = self.parameter in ANGLES
        exact = (pi_text(self.exact) or f"{self.exact:g}") if angle else "0"
        sign = "-" if math.remainder(self.exact - self.value, 2.0 * math.pi) > 0 else "+"
        return (
            f"{self.parameter} of '{self.row}': {exact} {sign} {self.change:.2g} "
            f"{'rad' if angle else unit}, written {exact}"
        )


def pi_text(x: float) -> str | None:
    """An angle that is exactly a multiple of pi/2 in ``[-pi, pi]`` (as float64 holds it) as
    ``0.0``, ``pi/2``, ``-pi/2``, ``pi`` or ``-pi``; ``None`` for any other angle."""
    quarters = round(x / (0.5 * math.pi))
    text = {0: "0.0", 1: "pi/2", -1: "-pi/2", 2: "pi", -2: "-pi"}.get(quarters)
    return text if text is not None and x == quarters * (0.5 * math.pi) else None


@dataclass(frozen=True, slots=True)
class AnalyticChain:
    """A D-H chain with exact relations (module doc).

    Attributes
    ----------
    table
        The ``dh`` table it was made from (names, kinds, limits, provenance, its own check).
    rows
        The table's rows with the snapped parameters; the last row's ``alpha`` and ``a`` are 0.
    base, tool
        ``(4, 4)`` transforms ``B`` and ``T``, lengths in the table's unit.
    snaps
        Every parameter changed beyond the files' round-off.
    check
        Its forward kinematics against the table's (``declared_*``: the bound the snaps allow,
        plus the table's own declared deviation from its source).
    """

    table: Table
    rows: tuple[Row, ...]
    base: Mat
    tool: Mat
    snaps: tuple[Snap, ...]
    check: Check

    def __post_init__(self) -> None:
        for name in ("base", "tool"):
            m = np.array(getattr(self, name), dtype=float)
            m.flags.writeable = False
            object.__setattr__(self, name, m)

    @property
    def n(self) -> int:
        return len(self.rows)

    @property
    def size(self) -> float:
        return self.table.size

    @property
    def length_unit(self) -> str:
        return self.table.length_unit

    def links(self) -> tuple[DhLink, ...]:
        """Each row's ``(theta, d, alpha, a)``."""
        return tuple(r.params for r in self.rows)  # type: ignore[misc]

    def link_form(self) -> tuple[Mat, Mat]:
        """The FK as links ``G_0 .. G_n`` and motions (as :meth:`Table.link_form`)."""
        frames = [frame_of(self.base)]
        for row in self.rows[:-1]:
            frames.append(row.params.frame())
        frames.append(compose(self.rows[-1].params.frame(), frame_of(self.tool)))
        motions = [(r.rotation * r.scale, r.translation * r.scale) for r in self.rows]
        return se3.stack(frames), np.array(motions, dtype=float).reshape(-1, 2)

    def fk_batch(self, q: Mat) -> Mat:
        """Poses ``(N, 4, 4)`` of the tip for configurations ``q`` ``(N, n)``."""
        return chain_fk(*self.link_form(), row_positions(self.rows, np.asarray(q, dtype=float)))

    def joint_frames(self) -> Mat:
        """``(n + 1, 4, 4)``: each joint's frame at ``q = 0`` in the base (its z axis the joint's
        axis, pointing as the joint turns positively), then the tip's."""
        links = self.link_form()[0]
        out = [links[0]]
        for g in links[1:]:
            out.append(out[-1] @ g)
        return np.array(out)

    def warnings(self) -> tuple[str, ...]:
        """The table's warnings, then the snaps and the deviation they cost where it shows
        (beyond ``tol.report``)."""
        c = self.check
        out = list(self.table.warnings)
        if self.snaps and (c.declared_position > 0.0 or c.declared_rotation > 0.0):
            unit = self.length_unit
            out.append(
                "made exact for the analytic solvers (--exact keeps them): "
                + "; ".join(s.text(unit) for s in self.snaps)
            )
            out.append(
                f"analytic form: FK deviation from the table {c.max_position_error:.3g} {unit}, "
                f"{c.max_rotation_error:.3g} rad (worst of {c.samples} configurations)"
            )
        return tuple(out)


def _snapped(row: Row, tol: Tolerances, size: float, last: bool) -> tuple[Row, list[Snap]]:
    p = row.params
    if not isinstance(p, DhLink):
        raise UsageError(f"the analytic form reads standard D-H rows, not {type(p).__name__}")
    values = {
        "theta": p.theta,
        "d": p.d,
        "alpha": 0.0 if last else p.alpha,
        "a": 0.0 if last else p.a,
    }
    snaps = []
    for name, value in list(values.items()):
        if name in ANGLES:
            exact, within = written_angle(value, tol.solver_snap), tol.written
        else:
            exact, within = written_length(value, tol.solver_snap * size), tol.written * size
        snap = Snap(row.name, name, value, exact)
        if snap.change > within:
            snaps.append(snap)
        values[name] = exact
    return replace(row, params=DhLink(**values)), snaps


def _bound(snaps: tuple[Snap, ...], reach: float) -> tuple[float, float]:
    """What the snaps can cost at any configuration (module doc): ``(position, rotation)``."""
    turns = [s.change for s in snaps if s.parameter in ANGLES]
    shifts = [s.change for s in snaps if s.parameter in LENGTHS]
    return math.fsum(4.0 * t * reach for t in turns) + math.fsum(2.0 * s for s in shifts), (
        math.fsum(2.0 * t for t in turns)
    )


def analytic_form(
    table: Table, tol: Tolerances = DEFAULT, samples: int | None = None, seed: int = 0
) -> AnalyticChain:
    """The analytic solvers' form of a checked standard D-H ``table`` (module doc).

    Raises
    ------
    UsageError
        A table in another convention.
    ConversionError
        The chain's forward kinematics deviates from the table's beyond what its snaps allow.
    """
    if table.convention != "dh":
        raise UsageError(f"the analytic form is made from a dh table, not {table.convention}")
    if not table.rows:
        raise UsageError("the analytic form needs at least one joint")
    rows, snaps = [], []
    for i, row in enumerate(table.rows):
        made, found = _snapped(row, tol, table.size, i == table.n - 1)
        rows.append(made)
        snaps += found
    last = table.rows[-1].params
    assert isinstance(last, DhLink)  # _snapped refused any other record
    tool = se3.matrix_of(compose(rx_tx(last.alpha, last.a), table.tool.frame()))
    judged = tuple(snaps)
    reach = max(table.to_poe().reach(), table.size)
    bound_pos, bound_rot = _bound(judged, reach)
    samples = samples or (JUDGED_SAMPLES if judged else DEFAULT_SAMPLES)
    q = table.to_poe().sample(samples, seed)
    chain = AnalyticChain(table, tuple(rows), table.base_matrix, tool, judged, Check(1, 0.0, 0.0))
    pos, rot = pose_errors(chain.fk_batch(q), table.fk_batch(q))
    allowed_pos = tol.check_position * table.size + bound_pos
    allowed_rot = tol.check_rotation + bound_rot
    if not (pos <= allowed_pos and rot <= allowed_rot):
        raise ConversionError(
            f"{table.source or table.robot}: the analytic form's forward kinematics deviates from "
            f"the table by {pos:.3g} {table.length_unit} and {rot:.3g} rad (allowed "
            f"{allowed_pos:.3g} {table.length_unit}, {allowed_rot:.3g} rad); not written"
        )
    shows = pos > tol.report * table.size or rot > tol.report
    own = table.check or Check(1, 0.0, 0.0)
    declared = (
        (own.declared_position + bound_pos, own.declared_rotation + bound_rot)
        if shows
        else (own.declared_position, own.declared_rotation)
    )
    return replace(chain, check=Check(samples, pos, rot, *declared))
