"""Property-based tests (hypothesis, derandomized so every run draws the same examples) over
random chains that include the degenerate cases: parallel, anti-parallel, intersecting,
coincident axes; prismatic and helical joints; scale factors, reversed joints; zero joints.

* every convention's FK equals the POE model's;
* convention -> POE -> convention is idempotent;
* convention A -> POE -> convention B moves like the source.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from urdf2dh import CONVENTIONS, Joint, PoeModel, to_table
from urdf2dh.geometry import se3

RELATIONS = ("parallel", "antiparallel", "intersecting", "coincident", "perpendicular", "skew")
SETTINGS = settings(
    derandomize=True, max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)

unit = st.floats(-1.0, 1.0, allow_nan=False)


def _normal_to(u):
    helper = np.array([1.0, 0, 0]) if abs(u[0]) < 0.9 else np.array([0, 1.0, 0])
    v = np.cross(u, helper)
    return v / np.linalg.norm(v)


@st.composite
def chains(draw):
    n = draw(st.integers(0, 8))
    size = draw(st.sampled_from([1e-3, 1.0, 1e3]))
    axis = np.array([0.0, 0.0, 1.0])
    point = np.zeros(3)
    joints = []
    for i in range(n):
        rel = draw(st.sampled_from(RELATIONS))
        kind = draw(st.sampled_from(["revolute", "revolute", "prismatic", "helical"]))
        v3 = np.array([draw(unit), draw(unit), draw(unit)])
        if np.linalg.norm(v3) < 1e-3:
            v3 = np.array([0.3, -0.2, 0.5])
        if rel == "parallel":
            point = point + size * np.cross(axis, v3)
        elif rel == "antiparallel":
            axis, point = -axis, point + size * np.cross(axis, v3)
        elif rel == "intersecting":
            axis = se3.rot_axis(_normal_to(axis), draw(st.floats(0.2, 3.0))) @ axis
        elif rel == "coincident":
            point = point + size * draw(unit) * axis
        elif rel == "perpendicular":
            axis = _normal_to(axis)
            point = point + size * v3
        else:
            axis = v3 / np.linalg.norm(v3)
            point = point + size * np.array([draw(unit), draw(unit), draw(unit)])
        axis = axis / np.linalg.norm(axis)
        scale = draw(st.sampled_from([1.0, 1.0, -1.0, 0.5, 1.7]))
        pitch = size * draw(st.floats(-0.5, 0.5)) if kind == "helical" else 0.0
        if kind == "helical" and abs(pitch) < 1e-3 * size:
            pitch = 0.1 * size
        located = kind != "prismatic" or draw(st.booleans())
        joints.append(
            Joint(
                f"j{i + 1}",
                kind,
                axis.copy(),
                point.copy() if located else None,
                pitch,
                scale,
                -2.0,
                2.0,
            )
        )
    tool = se3.twist_exp(
        np.array([draw(unit), draw(unit), draw(unit)] + [size * draw(unit) for _ in range(3)])
    )
    if draw(st.booleans()) and joints and joints[-1].point is not None:
        # the tool z on the last axis: the coincident tool case
        frame = np.eye(4)
        frame[:3, 2] = joints[-1].axis
        frame[:3, 0] = _normal_to(joints[-1].axis)
        frame[:3, 1] = np.cross(frame[:3, 2], frame[:3, 0])
        frame[:3, 3] = joints[-1].point + size * draw(unit) * joints[-1].axis
        tool = frame
    unit_name = {1e-3: "mm", 1.0: "m", 1e3: "km"}[size]
    return PoeModel(tuple(joints), tool, "random", length_unit=unit_name)


def _assert_close(model, poses, q, label, declared=None):
    """Exact (1e-12 relative), or, for a table that reported a judgement, within twice the
    deviation it declared in its own check."""
    ref = model.fk_batch(q)
    pos = np.abs(poses[:, :3, 3] - ref[:, :3, 3]).max(initial=0.0)
    rot = np.abs(poses[:, :3, :3] - ref[:, :3, :3]).max(initial=0.0)
    allowed_pos, allowed_rot = 1e-12 * model.size(), 1e-12
    if declared is not None and any("treated as" in w for w in declared.warnings):
        allowed_pos += 2 * declared.check.max_position_error
        allowed_rot += 2 * declared.check.max_rotation_error
    assert pos <= allowed_pos and rot <= allowed_rot, (label, pos, rot)


def _conditioning(table, size: float) -> float:
    """1 / sin(alpha) of the most nearly parallel (but not parallel) pair in a D-H table: the
    common normal of two lines at angle alpha is known to eps / sin(alpha) only, so that is
    how well two exact conversions of the same geometry can agree on d, a and theta. Where the
    x axis points from one axis to the other instead (a Hayati row: to where the next axis
    crosses the xy plane; a D-H row of parallel axes: along their common normal), at a
    distance a (round-off for nearly coincident axes) its direction is known to eps size / a
    only, and with it theta."""
    if table.convention == "cpc":
        return 1.0
    alphas = [getattr(table.base, "alpha", None), getattr(table.tool, "alpha", None)]
    alphas += [r.params.alpha for r in table.rows]
    sines = [abs(math.sin(x)) for x in alphas if x is not None and abs(math.sin(x)) > 1e-15]
    links = [table.base, *(r.params for r in table.rows)]
    crossings = [
        abs(p.a) / size
        for p in links
        if getattr(p, "a", 0.0) != 0.0
        and (hasattr(p, "beta") or abs(math.sin(getattr(p, "alpha", 1.0))) <= 1e-15)
    ]
    return 1.0 / min(sines + crossings, default=1.0)


def _same_params(a, b, size, label):
    cond = max(1.0, 1e-6 * _conditioning(a, size))  # 1e-9 * cond stays >= 1e-15 / sin(alpha)
    pairs = [(a.base.values(), b.base.values()), (a.tool.values(), b.tool.values())]
    pairs += [(x.params.values(), y.params.values()) for x, y in zip(a.rows, b.rows, strict=True)]
    for pa, pb in pairs:
        for k in pa:
            va, vb = np.atleast_1d(pa[k]).astype(float), np.atleast_1d(pb[k]).astype(float)
            diff = np.abs(va - vb)
            if k in ("theta", "alpha", "beta"):
                diff = np.abs(np.remainder(va - vb + math.pi, 2 * math.pi) - math.pi)
            tol = 1e-9 * cond * (1.0 if k in ("theta", "alpha", "beta", "b") else size)
            assert diff.max() <= tol, (label, k, va, vb, cond)
    assert [(r.kind, r.scale) for r in a.rows] == [(r.kind, r.scale) for r in b.rows]


@SETTINGS
@given(chains())
def test_every_convention_moves_like_the_poe_model(model):
    q = model.sample(40, 11)
    for conv in CONVENTIONS:
        table = to_table(model, conv)
        _assert_close(model, table.fk_batch(q), q, conv, declared=table)
        if conv == "cpc":  # parametrically continuous: never a judgement
            assert not [w for w in table.warnings if "treated as" in w]


@SETTINGS
@given(chains())
def test_convention_to_poe_to_convention_is_idempotent(model):
    for conv in CONVENTIONS:
        table = to_table(model, conv)
        again = to_table(table.to_poe(), conv)
        _same_params(table, again, model.size(), conv)


@SETTINGS
@given(chains(), st.sampled_from(CONVENTIONS), st.sampled_from(CONVENTIONS))
def test_any_convention_to_any_other(model, first, second):
    q = model.sample(30, 5)
    first_table = to_table(model, first)
    via = to_table(first_table.to_poe(), second)
    _assert_close(model, via.fk_batch(q), q, f"{first}->{second}", declared=first_table)
    # the second conversion starts from geometry the first one already made D-H friendly
    assert not [w for w in via.warnings if "treated as" in w]
