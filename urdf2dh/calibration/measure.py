"""Synthetic measurements of a model (``urdf2dh measure``), for trying calibration and testing it.

* Configurations: ``N`` drawn uniformly within the joint limits (``[-pi, pi]`` for rotating
  joints without limits; :meth:`urdf2dh.model.poe.PoeModel.sample`), seeded by ``seed``.
* Pose measurements: the tool origin plus isotropic Gaussian noise of ``noise_pos`` per
  coordinate; the tool orientation turned by ``exp([e])``, ``e`` Gaussian with ``noise_rot``
  per coordinate (in the device frame); written as quaternions ``[x, y, z, w]``, ``w >= 0``.
* Position measurements with ``K`` markers: every configuration measures every marker (one row
  each, ``marker`` = 0 .. K-1). Marker ``k`` sits at a seeded point of the tool frame: a
  uniformly random direction at a distance uniform in [0.05, 0.15] x the robot's size (so they
  are off the last joint's axis and not collinear, almost surely). Without markers, the one
  point measured is the tool origin.

The noise and marker streams are separate from the configurations' (``(seed, 1)`` and
``(seed, 2)``): the same seed gives the same configurations whatever the noise.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..checks import (
    check_configurations,
    check_count,
    check_flag,
    check_instance,
    check_real,
    check_seed,
)
from ..errors import InputError
from ..geometry.lie import exp_so3, quaternion_of
from ..geometry.se3 import twist_exp
from ..model.poe import Joint, PoeModel
from ..tolerances import MAX_MARKERS
from .chart import line_motion
from .measurements import MAX_MEASUREMENTS, Measurements, check_noise

__all__ = ["MARKER_DISTANCE", "marker_layout", "measure", "perturb", "synthesize"]

Mat = NDArray[np.float64]

MARKER_DISTANCE = (0.05, 0.15)  # markers' distance from the tool origin, x robot size


def marker_layout(model: PoeModel, markers: int, seed: int) -> dict[int, Mat]:
    """Seeded marker positions in the tool frame (module docstring)."""
    rng = np.random.default_rng((seed, 2))
    direction = rng.normal(size=(markers, 3))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    lo, hi = MARKER_DISTANCE
    distance = rng.uniform(lo, hi, size=markers) * model.size()
    return {k: direction[k] * distance[k] for k in range(markers)}


def measure(
    model: PoeModel,
    configs: int,
    noise_pos: float = 0.0,
    noise_rot: float = 0.0,
    seed: int = 0,
    markers: int | None = None,
    pose: bool = True,
    configurations: Mat | None = None,
) -> Measurements:
    """Synthetic measurements of ``model`` (module docstring); with ``markers``, their seeded
    layout on the tool is the result's ``layout``.

    Parameters
    ----------
    model
        What is measured.
    configs
        How many configurations, drawn within the joint limits (ignored with
        ``configurations``).
    noise_pos, noise_rot
        Gaussian noise per coordinate: length unit, rad.
    seed
        Seeds the configurations, the noise and the markers.
    markers
        Position measurements of this many markers at seeded points of the tool.
    pose
        Pose measurements (without ``markers``); else positions of the tool origin.
    configurations
        ``(N, n)`` the configurations to measure at.

    Returns
    -------
    Measurements
        ``N`` rows (``N x markers`` with markers): joint values, tool points (length unit of
        ``model``) and, for poses, unit quaternions ``[x, y, z, w]``.

    Raises
    ------
    InputError
        More than :data:`~.measurements.MAX_MEASUREMENTS` rows would be written, or a noise
        level no device has (as large as the robot, or a radian:
        :func:`~.measurements.check_noise`).
    """
    check_instance(model, PoeModel, "measure: model", "urdf2dh.load(SOURCE) reads one")
    if configurations is None:
        check_count(configs, "measure: configs")
    else:
        n = model.dof
        configurations = check_configurations(configurations, n, "measure: configurations", True)
    for value, where in ((noise_pos, "measure: noise_pos"), (noise_rot, "measure: noise_rot")):
        if check_real(value, where) < 0.0:
            raise ValueError(f"{where} must not be negative, not {value}")
    check_noise(noise_pos, noise_rot, model.size(), model.length_unit, exact=True)
    check_seed(seed, "measure: seed")
    if markers is not None:
        check_count(markers, "measure: markers", 1, MAX_MARKERS)
    check_flag(pose, "measure: pose")
    count = configs if configurations is None else len(configurations)
    rows = count * (markers or 1)
    if rows > MAX_MEASUREMENTS:
        raise InputError(
            f"{count} configurations x {markers or 1} markers are {rows} measurements, more than "
            f"the {MAX_MEASUREMENTS} calibration reads"
        )
    layout = marker_layout(model, markers, seed) if markers else None
    return synthesize(
        model, count, noise_pos, noise_rot, seed, layout, pose and not markers, configurations
    )


def synthesize(
    model: PoeModel,
    configs: int,
    noise_pos: float = 0.0,
    noise_rot: float = 0.0,
    seed: int = 0,
    layout: dict[int, Mat] | None = None,
    pose: bool = True,
    configurations: Mat | None = None,
) -> Measurements:
    """Measurements of ``model`` at ``configs`` seeded configurations (or at
    ``configurations``).

    ``pose`` gives pose measurements of the tool frame; otherwise positions of the points of
    ``layout`` (marker -> point in the tool frame; ``None``: the tool origin, no marker column).
    """
    q = (
        model.sample(configs, seed)
        if configurations is None
        else np.asarray(configurations, dtype=float)
    )
    configs = len(q)
    poses = model.fk_batch(q)
    noise = np.random.default_rng((seed, 1))
    names = tuple(j.name for j in model.joints)
    if pose:
        points = poses[:, :3, 3] + noise.normal(scale=noise_pos, size=(configs, 3))
        turn = exp_so3(noise.normal(scale=noise_rot, size=(configs, 3)))
        quats = quaternion_of(turn @ poses[:, :3, :3])
        return Measurements(names, q, points, quats, None, model.name)
    marks = layout if layout is not None else {0: np.zeros(3)}
    ids = sorted(marks)
    local = np.array([marks[k] for k in ids])  # (K, 3)
    pts = np.einsum("nij,kj->nki", poses[:, :3, :3], local) + poses[:, None, :3, 3]
    count = configs * len(ids)
    points = pts.reshape(count, 3) + noise.normal(scale=noise_pos, size=(count, 3))
    qs = np.repeat(q, len(ids), axis=0)
    rows = np.tile(np.array(ids, dtype=np.int64), configs) if layout is not None else None
    return Measurements(names, qs, points, None, rows, model.name, layout)


def perturb(
    model: PoeModel,
    seed: int,
    angle: float,
    length: float,
    scale: float = 0.0,
    tool_on_axis: bool = False,
) -> PoeModel:
    """A robot "as built" near ``model``, to try and test calibration with.

    Every joint's line moves rigidly: tilted by ``angle`` rad about, and shifted by ``length``
    along, each of two directions normal to it (Gaussian deviations, seeded); its scale changes
    by ``scale`` (relative). The tool turns by ``angle`` and moves by ``length`` per axis, or,
    with ``tool_on_axis``, moves with the last joint's line and then only turns about and
    slides along it (as a flange defined by the last axis does). Kinds, pitches and limits are
    kept.
    """
    rng = np.random.default_rng((seed, 4))
    joints = []
    motion = np.eye(4)
    for j in model.joints:
        a, b, c, d = rng.normal(size=4)
        if j.kind == "prismatic":
            c = d = 0.0
        p = j.point if j.point is not None else np.zeros(3)
        motion = twist_exp(line_motion(j.axis, p, angle * a, angle * b, length * c, length * d))
        axis = motion[:3, :3] @ j.axis
        point = None if j.point is None else motion[:3, :3] @ j.point + motion[:3, 3]
        s = j.scale * (1.0 + scale * rng.normal())
        joints.append(Joint(j.name, j.kind, axis, point, j.pitch, s, j.lower, j.upper))
    if tool_on_axis and joints and joints[-1].point is not None:
        last = joints[-1]
        assert last.point is not None
        turn, slide = rng.normal(size=2)
        screw = np.concatenate([last.axis, np.cross(last.point, last.axis)]) * angle * turn
        screw[3:] += last.axis * length * slide
        home = twist_exp(screw) @ motion @ model.home
    else:
        zeta = np.concatenate([angle * rng.normal(size=3), length * rng.normal(size=3)])
        home = model.home @ twist_exp(zeta)
    return PoeModel(
        tuple(joints),
        home,
        f"{model.name}-as-built",
        model.source,
        model.base_link,
        model.tip_link,
        model.length_unit,
    )
