"""Every numerical judgement the converter makes, named for what it decides, in one place.

The defaults are documented in README.md and overridable per call (keyword) and per command
(CLI flag). No bare tolerance literal appears in the geometry modules.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, replace

__all__ = ["DEFAULT", "EXACT", "Tolerances"]

EPS = sys.float_info.epsilon  # float64's; not numpy's, so that `urdf2dh --help` needs no numpy


@dataclass(frozen=True)
class Tolerances:
    """Tolerances of one conversion.

    Attributes
    ----------
    parallel_angle
        Radians. Consecutive lines (joint axes, the base z and the tool z) whose directions are
        within this angle of parallel or anti-parallel are treated as exactly parallel by the
        D-H conventions (``dh``, ``mdh``). Rounded URDF angles (``rpy="0 1.5708 0"``) leave such
        pairs 1e-9 to 1e-4 rad apart, where the exact common normal lies 10^3 to 10^8 lengths
        away. Each such judgement is listed in the table's ``warnings`` with the forward
        kinematics deviation it caused. 0 means exact (``--exact``): then only float round-off
        (``noise``) is treated as parallel.
    meet_angle
        Radians. Below this angle from parallel the common-normal formula is ill-conditioned;
        a line that passes within ``intersect_distance`` of the pivot (the previous frame's
        origin, or for the tool z the tool origin on the previous axis) is then taken to meet
        the previous axis there: ``a = 0`` and its exact direction is kept. This is exact, so it
        applies with ``--exact`` too.
    intersect_distance
        Source length unit. Lines closer than this count as intersecting: non-parallel pairs
        get ``alpha > 0`` (their tiny ``a`` is kept, exactly), parallel pairs are treated as
        coincident (``a = 0``, ``theta = 0``).
    check_position, check_rotation
        The self-check: a table whose forward kinematics deviates from the source's by more than
        ``check_position`` x robot size (position) or ``check_rotation`` rad (orientation), beyond
        what the judgements above account for, is never written.
    cpc_reverse_below
        CPC's R(b) is singular at b = -z. A CPC frame whose axis direction has
        ``b_z < cpc_reverse_below`` in the previous frame is reversed (its joint gets
        ``scale = -scale``), as SPEC §2 allows.
    far_factor
        A D-H ``|d|`` or ``|a|`` larger than ``far_factor`` x the robot's extent is warned about.
    rotation_input
        A rotation typed into a file (POE tool matrix, table matrix) may be off orthonormal by
        this much (it is then orthonormalised, with a warning); more is an input error.
    noise
        Float round-off: relative size below which a difference is not geometry (an axis
        this close to parallel is parallel even with ``--exact``; a pitch this small is zero).
    report
        A judgement whose effect is below ``report`` (rad, or x robot size) is under the
        exactness urdf2dh promises and is not listed in ``warnings``; it still counts in the
        self-check.
    """

    parallel_angle: float = 1e-4
    meet_angle: float = 1e-3
    intersect_distance: float = 1e-9
    check_position: float = 1e-10
    check_rotation: float = 1e-10
    cpc_reverse_below: float = -0.5
    far_factor: float = 10.0
    rotation_input: float = 1e-6
    noise: float = 256 * EPS
    report: float = 1e-12

    @property
    def exact(self) -> bool:
        """True when no geometric snapping is done (``--exact``)."""
        return self.parallel_angle == 0.0 and self.intersect_distance == 0.0

    def with_exact(self) -> Tolerances:
        """The same tolerances with snapping turned off."""
        return replace(self, parallel_angle=0.0, intersect_distance=0.0)


DEFAULT = Tolerances()
EXACT = DEFAULT.with_exact()
