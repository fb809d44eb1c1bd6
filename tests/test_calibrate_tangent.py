"""The prior's tangent, the derivative of its link errors' coordinates by the chart's free
coordinates, in closed form: against a sixth-order central difference through the chart's own
retraction (truncation ~1e-18, round-off ~1e-13), on real robots' joints (revolute, a prismatic
torso, helical joints) moved by random charts, near and far from the prior's centre."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import urdf2dh
from urdf2dh.calibration.chart import Estimate, LineCoordinates, count, retract
from urdf2dh.calibration.levels import FULL, GEOMETRY
from urdf2dh.calibration.prior import link_errors
from urdf2dh.model.poe import Joint

DATA = Path(__file__).resolve().parents[1] / "examples" / "calibration-data"
_STEP = 1e-3  # of the sixth-order difference
_WEIGHTS = ((1, 45.0 / 60.0), (2, -9.0 / 60.0), (3, 1.0 / 60.0))  # its stencil's weights


def _nominal(name: str) -> tuple[Joint, ...]:
    if name == "ur10":
        src, tip = DATA / "ur10" / "ur10_robot.urdf", "wrist_3_link"
        return urdf2dh.load(str(src), tip=tip).joints
    if name == "tiago":  # a prismatic torso, then seven revolute joints
        src, tip = DATA / "tiago" / "tiago_48_schunk.urdf", "wrist_ft_tool_link"
        return urdf2dh.load(str(src), tip=tip).joints
    joints = urdf2dh.load("panda").joints  # with helical joints: lines of five coordinates
    return tuple(
        Joint(j.name, "helical", j.axis, j.point, 0.01 * (k + 1), j.scale) if k % 2 else j
        for k, j in enumerate(joints)
    )


def _difference(errors, est: Estimate, k: int) -> np.ndarray:
    """The sixth-order central difference of the prior's coordinates along coordinate ``k``."""
    move = np.zeros(count(est))
    move[k] = _STEP
    return (
        sum(
            w
            * (
                errors.deviations(retract(est, j * move))
                - errors.deviations(retract(est, -j * move))
            )
            for j, w in _WEIGHTS
        )
        / _STEP
    )


@pytest.mark.parametrize("robot", ["ur10", "tiago", "panda-helical"])
@pytest.mark.parametrize("level", [GEOMETRY, FULL])
def test_the_tangent_equals_a_sixth_order_difference(robot, level):
    """At the centre and at random charts about it (turns from 1e-3 to 0.3 rad: both the series
    and the closed forms of the turn's coefficients), every entry of the tangent agrees with
    the difference to 1e-11 (central differences at 1e-7, what it was made of before, are off
    by ~1e-9)."""
    joints = _nominal(robot)
    home = np.eye(4)
    home[:3, 3] = [0.1, 0.2, 1.0]
    start = Estimate.of(joints, home).with_level(level)
    rng = np.random.default_rng(32)
    locations = start.chain.point + rng.normal(0.0, 0.1, start.chain.point.shape)
    errors = link_errors(start, locations)
    assert errors is not None
    for scale in (0.0, 1e-3, 3e-2, 0.3):
        est = retract(start, rng.normal(0.0, scale, count(start)))
        tangent = errors.tangent(est)
        assert tangent.shape == (len(errors.coords), count(est))
        for k in range(count(est)):
            assert np.abs(tangent[:, k] - _difference(errors, est, k)).max() < 1e-11, (scale, k)


def test_the_line_tangent_at_the_centre_is_the_identity():
    """Seen from themselves, lines move in their own chart: the tangent is the identity (each
    line's turn1, turn2, shift1, shift2 by the same), to round-off."""
    joints = _nominal("ur10")
    est = Estimate.of(joints, np.eye(4))
    u, p = est.chain.axis, est.chain.point
    tangent = LineCoordinates.of(u, p, u, p).tangent()
    assert np.abs(tangent - np.eye(4)).max() < 1e-15
