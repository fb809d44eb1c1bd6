"""The OPW model: its parameters and forward kinematics, as the OPW solvers evaluate them.

The model of Brandstötter, Angerer & Hofbaur ("An analytical solution of the inverse kinematics
problem of industrial serial manipulators with an ortho-parallel basis and a spherical wrist",
Austrian Robotics Workshop 2014), as ``opw_kinematics`` (MoveIt, Tesseract) and
``rs-opw-kinematics`` evaluate it, with OPW joint angles ``theta_i = sign_i q_i - offset_i``::

    F(theta) = Rz(t1) T(a1, 0, c1) Ry(t2) Tz(c2) Ry(t3) T(a2, b, c3) Rz(t4) Ry(t5) Rz(t6) Tz(c4)

At ``theta = 0`` the arm stands upright in OPW's base frame: axis 1 is its z axis; axes 2 and 3
point along y, ``a1`` in front of axis 1 at heights ``c1`` and ``c1 + c2``; axis 4 is vertical,
``a2`` in front of axis 3 and ``b`` beside axis 1; axes 4, 5 (along y) and 6 meet in the wrist
centre ``(a1 + a2, b, c1 + c2 + c3)``; the flange is ``c4`` above it, turned as the base.
:func:`urdf2dh.opw.opw_from_poe` finds the parameters of a chain.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

__all__ = ["GEOMETRY", "OpwParameters", "opw_fk", "rot_y", "rot_z"]

Mat = NDArray[np.float64]
GEOMETRY = ("a1", "a2", "b", "c1", "c2", "c3", "c4")


@dataclass(frozen=True, slots=True)
class OpwParameters:
    """An arm in OPW's terms: ``pose(q) = base . F(sign q - offsets) . tool`` (module doc).

    Lengths (``a1`` ... ``c4``, the translations of ``base`` and ``tool``) in the source's unit;
    ``offsets`` in radians; ``signs`` +1 or -1; ``base`` and ``tool`` are 4x4 transforms.
    ``check`` is ``(samples, worst position error, worst rotation error)`` of :func:`opw_fk`
    against the source; ``warnings`` the judgements made and the deviation they cost.
    """

    a1: float
    a2: float
    b: float
    c1: float
    c2: float
    c3: float
    c4: float
    offsets: tuple[float, ...]
    signs: tuple[int, ...]
    base: Mat
    tool: Mat
    check: tuple[int, float, float] = (0, 0.0, 0.0)
    warnings: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        if len(self.offsets) != 6 or len(self.signs) != 6:
            raise ValueError("OPW has six joint offsets and six sign corrections")
        if any(s not in (1, -1) for s in self.signs):
            raise ValueError(f"sign corrections must be 1 or -1, not {self.signs}")
        values = [*self.geometry().values(), *self.offsets]
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f"non-finite OPW parameter in {values}")
        for name in ("base", "tool"):
            m = np.array(getattr(self, name), dtype=float)
            if m.shape != (4, 4):
                raise ValueError(f"{name} must be a 4x4 transform, not shape {m.shape}")
            m.flags.writeable = False
            object.__setattr__(self, name, m)

    def geometry(self) -> dict[str, float]:
        """``{a1, a2, b, c1, c2, c3, c4}``."""
        return {k: getattr(self, k) for k in GEOMETRY}

    def fk_batch(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Poses ``(N, 4, 4)`` of the chain's tip for joint positions ``q`` ``(N, 6)``."""
        theta = np.asarray(q, dtype=float) * np.array(self.signs) - np.array(self.offsets)
        return self.base @ opw_fk(self, theta) @ self.tool


def rot_z(t: Mat) -> Mat:
    """``Rz(t)`` ``(..., 3, 3)`` for angles ``t`` of any shape."""
    c, s, z, o = np.cos(t), np.sin(t), np.zeros_like(t), np.ones_like(t)
    return np.stack([c, -s, z, s, c, z, z, z, o], axis=-1).reshape(*t.shape, 3, 3)


def rot_y(t: Mat) -> Mat:
    """``Ry(t)`` ``(..., 3, 3)`` for angles ``t`` of any shape."""
    c, s, z, o = np.cos(t), np.sin(t), np.zeros_like(t), np.ones_like(t)
    return np.stack([c, z, s, z, o, z, -s, z, c], axis=-1).reshape(*t.shape, 3, 3)


def opw_fk(p: OpwParameters, theta: NDArray[np.float64]) -> NDArray[np.float64]:
    """OPW's flange pose ``F(theta)`` ``(N, 4, 4)`` for OPW joint angles ``theta`` ``(N, 6)``,
    in OPW's base frame (the product in the module doc; no base, tool, signs or offsets)."""
    t = np.atleast_2d(np.asarray(theta, dtype=float))
    r1, r23 = rot_z(t[:, 0]), rot_y(t[:, 1] + t[:, 2])
    elbow = np.array([0.0, 0.0, p.c2]) + rot_y(t[:, 2]) @ np.array([p.a2, p.b, p.c3])
    centre = (
        r1 @ (np.array([p.a1, 0.0, p.c1]) + (rot_y(t[:, 1]) @ elbow[..., None])[..., 0])[..., None]
    )
    rot = r1 @ r23 @ rot_z(t[:, 3]) @ rot_y(t[:, 4]) @ rot_z(t[:, 5])
    out = np.zeros((len(t), 4, 4))
    out[:, :3, :3] = rot
    out[:, :3, 3] = centre[..., 0] + p.c4 * rot[:, :, 2]
    out[:, 3, 3] = 1.0
    return out
