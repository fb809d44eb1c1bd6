"""Shared assertions: a model's forward kinematics against Pinocchio's, with both poses printed
on failure."""

from __future__ import annotations

import numpy as np

from urdf2dh import PoeModel
from urdf2dh.check.verify import pinocchio_fk
from urdf2dh.geometry.se3 import pose_errors
from urdf2dh.io.sources import Source

EXACT = 1e-12  # the exactness promised: relative to the robot's size, and in radians


def pin_reference(source: Source, model: PoeModel, samples: int = 200, seed: int = 7):
    """Seeded configurations and Pinocchio's poses for them."""
    q = model.sample(samples, seed)
    return q, pinocchio_fk(source, model, q)


def assert_fk_matches(
    label: str, poses, reference, size: float, q, rel: float = EXACT, rot: float = EXACT
) -> tuple[float, float]:
    """Assert the worst position error <= rel * size and rotation error <= rot (radians)."""
    pos_err, rot_err = pose_errors(poses, reference)
    if not (pos_err <= rel * size and rot_err <= rot):
        dp = np.linalg.norm(poses[:, :3, 3] - reference[:, :3, 3], axis=1)
        k = int(np.argmax(dp))
        raise AssertionError(
            f"{label}: FK differs from Pinocchio by {pos_err:.3g} (size {size:.3g}, allowed "
            f"{rel * size:.3g}) and {rot_err:.3g} rad (allowed {rot:.3g})\n"
            f"q = {q[k].tolist()}\nours =\n{poses[k]}\nPinocchio =\n{reference[k]}"
        )
    return pos_err, rot_err
