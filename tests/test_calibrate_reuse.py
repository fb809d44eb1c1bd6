"""Work shared between the levels of one calibration gives what each level's own gives."""

from __future__ import annotations

import numpy as np
import pytest

import urdf2dh
from urdf2dh.calibration.chart import Estimate, line_point
from urdf2dh.calibration.identifiable import carried_at_levels, redundant
from urdf2dh.calibration.levels import BASE_TOOL, LEVELS
from urdf2dh.calibration.measurements import Measurements
from urdf2dh.calibration.residuals import Data, errors, observed
from urdf2dh.calibration.solver import Linearisation
from urdf2dh.geometry.lie import exp_so3
from urdf2dh.model.poe import Joint


def _estimate(robot: str, markers: bool, helical: bool, keep_tool_axis: bool) -> Estimate:
    model = urdf2dh.load(robot)
    joints = tuple(
        Joint(
            j.name,
            "helical" if helical and j.kind == "revolute" else j.kind,
            j.axis,
            None if j.point is None or j.kind == "prismatic" else line_point(j.axis, j.point),
            j.pitch,
            j.scale,
        )
        for j in model.joints
    )
    if markers:
        points = np.array([[0.2, 0.06, -0.01], [0.26, 0.03, 0.005]]) * model.size()
        return Estimate.of(joints, model.home.copy(), points, level=BASE_TOOL)
    return Estimate.of(joints, model.home.copy(), level=BASE_TOOL, keep_tool_axis=keep_tool_axis)


@pytest.mark.parametrize(
    ("robot", "markers", "helical", "keep_tool_axis"),
    [
        ("ur5", False, False, False),
        ("puma560-actual", False, True, True),
        ("stanford", True, False, False),
        ("panda", False, False, False),
    ],
)
def test_carried_at_every_level_at_once_is_each_levels_own(robot, markers, helical, keep_tool_axis):
    est = _estimate(robot, markers, helical, keep_tool_axis)
    model = urdf2dh.load(robot)
    limits, size = model.limits(), model.size()
    together = carried_at_levels(est, tuple(LEVELS.values()), limits, size)
    assert list(together) == list(LEVELS)
    for name, level in LEVELS.items():
        alone = redundant(est.with_level(level), limits, size)
        np.testing.assert_array_equal(together[name], alone)
    assert together["offsets"].any()  # the first offset and the base's turn: a pair to find


def test_every_levels_columns_are_among_one_jacobians_at_their_union():
    """:func:`.identifiable.carried_at_levels` tests every level on one Jacobian: each level's
    own columns are among it bit for bit, and with offsets to absorb (levels without them are
    tested on the absorbed model) each level's answer is its own all the same."""
    from dataclasses import replace

    from urdf2dh.calibration.chart import all_names
    from urdf2dh.calibration.identifiable import _probe, _union
    from urdf2dh.calibration.residuals import evaluate

    model = urdf2dh.load("ur5")
    limits, size = model.limits(), model.size()
    est = _estimate("ur5", False, False, False)
    q = model.sample(20, 4)
    levels = list(LEVELS.values())
    every = _probe(est, _union(levels))
    _, jac = evaluate(every, observed(every, q), size, 1.0)
    column = {n: k for k, n in enumerate(all_names(every))}
    for level in levels:
        own = _probe(est, level)
        _, alone = evaluate(own, observed(own, q), size, 1.0)
        assert np.array_equal(jac[:, [column[n] for n in all_names(own)]], alone), level.name
    shifted = replace(est.with_level(LEVELS["offsets"]), offsets=np.linspace(0.1, 0.6, 6))
    together = carried_at_levels(shifted, tuple(levels), limits, size)
    for level in levels:
        alone = redundant(shifted.with_level(level), limits, size)
        np.testing.assert_array_equal(together[level.name], alone)


@pytest.mark.parametrize("markers", [False, True])
def test_a_linearisations_errors_are_the_residuals_errors(markers):
    """The fit's errors read off its linearisation are :func:`.residuals.errors`, bit for bit."""
    robot = "stanford" if markers else "ur5"
    model = urdf2dh.load(robot)
    est = _estimate(robot, markers, False, False).with_level(LEVELS["geometry"])
    rng = np.random.default_rng(7)
    q = model.sample(12, 3)
    seen = observed(est, q)
    data = Data(
        seen.q,
        seen.points + rng.normal(size=seen.points.shape) * 1e-3 * model.size(),
        seen.markers,
        None
        if seen.rotations is None
        else seen.rotations @ exp_so3(rng.normal(size=(12, 3)) * 0.01),
    )
    lin = Linearisation.at(est, data)
    assert np.array_equal(lin.errors(), errors(est, data))
    assert lin.errors().shape == (len(data), 1 if markers else 2)


def test_configurations_number_the_distinct_rows_in_file_order():
    """:meth:`.Measurements.configurations` against numpy's unique rows: equal rows (``0.0``
    and ``-0.0`` too) one configuration, each NaN row its own, numbered by their first row."""
    rng = np.random.default_rng(11)
    for n, k in ((1, 3), (16, 6), (80, 7), (300, 2)):
        rows = rng.integers(-2, 3, size=(max(1, n // 3), k)).astype(float)
        q = rows[rng.integers(0, len(rows), n)]
        if n > 2:
            q[1] = -q[0]  # -0.0 where q[0] is 0.0: equal rows
            q[1][q[0] != 0.0] = q[0][q[0] != 0.0]
            q[2, 0] = np.nan
        m = Measurements(tuple(f"j{i}" for i in range(k)), q, np.zeros((n, 3)))
        index, count = m.configurations()
        _, first, inverse = np.unique(q, axis=0, return_index=True, return_inverse=True)
        numbered = np.empty(len(first), dtype=np.int64)
        numbered[np.argsort(first, kind="stable")] = np.arange(len(first))
        assert count == len(first)
        np.testing.assert_array_equal(index, numbered[inverse.ravel()])
        assert index[0] == 0 and np.all(np.diff(np.maximum.accumulate(index)) <= 1)


def test_what_measurements_give_is_found_once_and_equals_the_plain_computation():
    """:meth:`.Measurements.remembered`: the configurations and :func:`.start.to_data` are made
    once per measurements (read-only), equal to what they make afresh; a copy made by
    ``replace``, ``subset`` or pickling starts with nothing remembered."""
    import pickle
    from dataclasses import replace

    from urdf2dh.calibration.measure import measure
    from urdf2dh.calibration.start import _data, to_data

    model = urdf2dh.load("ur5")
    m = measure(model, 12, seed=3)
    m = Measurements(m.joints, np.vstack([m.q, m.q[:4]]), np.vstack([m.points, m.points[:4]]),
                     np.vstack([m.quaternions, m.quaternions[:4]]))  # fmt: skip
    index, count = m.configurations()
    assert m.configurations()[0] is index and count == 12
    plain, plain_count = m._configurations()
    np.testing.assert_array_equal(index, plain)
    assert plain_count == count and not index.flags.writeable
    for pose in (True, False):
        data = to_data(m, pose, [0])
        assert to_data(m, pose, [0]) is data
        fresh = _data(m, pose, (0,))
        for name in ("q", "points", "markers"):
            np.testing.assert_array_equal(getattr(data, name), getattr(fresh, name))
        assert (data.rotations is None) == (not pose)
        if pose:
            np.testing.assert_array_equal(data.rotations, fresh.rotations)
            assert not data.rotations.flags.writeable
    copies = (
        replace(m, source="other"),
        m.subset(np.arange(len(m))),
        pickle.loads(pickle.dumps(m)),
    )
    for copy in copies:
        assert copy._memo == {}
        np.testing.assert_array_equal(copy.configurations()[0], index)
    again = copies[2]
    assert again.joints == m.joints and again.source == m.source
    for a, b in ((again.q, m.q), (again.points, m.points), (again.quaternions, m.quaternions)):
        np.testing.assert_array_equal(a, b)
    assert m == m and "_memo" not in repr(m)


def test_the_identified_estimate_absorbed_is_made_once_and_is_chart_absorbed():
    """:attr:`.identify.Identified.flat` (what the model and the figures read) is
    :func:`.chart.absorbed` of the identified estimate, bit for bit."""
    from urdf2dh.calibration.chart import absorbed
    from urdf2dh.calibration.identify import identify
    from urdf2dh.calibration.measure import perturb, synthesize
    from urdf2dh.calibration.start import FitOptions

    nominal = urdf2dh.load("ur5")
    m = synthesize(perturb(nominal, 2, 1e-3, 1e-3 * nominal.size()), 20, seed=1)
    result = identify(nominal, m, FitOptions(level="offsets"))
    plain = absorbed(result.estimate)
    assert result.estimate.offsets is not None and result.estimate.offsets.any()
    for a, b in (
        (result.flat.chain.axis, plain.chain.axis),
        (result.flat.chain.point, plain.chain.point),
        (result.flat.home, plain.home),
        (result.flat.markers, plain.markers),
    ):
        assert np.array_equal(a, b)
    assert result.flat.offsets is None and plain.offsets is None


def test_the_passs_placement_is_start_placement_and_identify_reads_it_unchanged():
    """:attr:`.select.Pass.placed` is :func:`.start.placement` of the pass's measurements, bit
    for bit, and :func:`.identify.identify` given it (markers: the tool's fit reads it) gives
    the same model and markers as finding it afresh."""
    from dataclasses import replace

    from urdf2dh.calibration.chart import MARKERS
    from urdf2dh.calibration.identify import identify
    from urdf2dh.calibration.measure import marker_layout, perturb, synthesize
    from urdf2dh.calibration.problem import CalibrationProblem, LevelChoice, Options, fit_options
    from urdf2dh.calibration.select import judge_levels
    from urdf2dh.calibration.start import placement

    nominal = urdf2dh.load("ur5")
    actual = perturb(nominal, 2, 1e-3, 1e-3 * nominal.size())
    layout = marker_layout(actual, 3, seed=4)
    m = synthesize(actual, 24, 1e-5, seed=5, layout=layout, pose=False)
    problem = CalibrationProblem.of(nominal, m, False, (None, None), layout, 0.0, 0, None)
    opts = replace(fit_options(problem), level="geometry")
    first = judge_levels(problem, Options(opts, LevelChoice("geometry")))
    ids = problem.markers
    g = placement(nominal, m, opts, ids)
    assert np.array_equal(first.placed, g) and not np.allclose(g, np.eye(4))
    given = identify(nominal, m, opts, ids, (first.start, first.before), None, first.placed)
    fresh = identify(nominal, m, opts, ids, (first.start, first.before))
    assert given.estimate.tool == MARKERS  # the tool's fit reads the placement
    assert np.array_equal(given.model.home, fresh.model.home)
    for a, b in zip(given.model.joints, fresh.model.joints, strict=True):
        assert np.array_equal(a.axis, b.axis) and np.array_equal(a.point, b.point)
    for k in ids:
        assert np.array_equal(given.markers_on_tool[k], fresh.markers_on_tool[k])
