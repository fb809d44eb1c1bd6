"""The reference forward kinematics (urdf2dh.model.fk) against plain per-configuration products,
across block boundaries: a POE model against se3.twist_exp multiplied out, and a table against
its links and joint motions multiplied one by one."""

from __future__ import annotations

import math

import numpy as np
import pytest
from chains import random_chain_urdf

from urdf2dh import Joint, PoeModel, to_table
from urdf2dh.conventions import NAMES
from urdf2dh.geometry import se3
from urdf2dh.io.urdf import parse_tree, tree_to_poe
from urdf2dh.model import fk

RNG = np.random.default_rng(20261121)


def unit(v):
    return v / np.linalg.norm(v)


def mixed_model(n: int) -> PoeModel:
    """Revolute, prismatic (with and without a located axis) and helical joints, odd scales."""
    joints = []
    for i in range(n):
        kind = ("revolute", "prismatic", "helical", "revolute")[i % 4]
        point = None if kind == "prismatic" and i % 8 == 1 else RNG.normal(size=3)
        pitch = RNG.normal() if kind == "helical" else 0.0
        joints.append(
            Joint(
                f"j{i}",
                kind,
                unit(RNG.normal(size=3)),
                point,
                pitch,
                RNG.uniform(0.5, 2.0) * RNG.choice([-1.0, 1.0]),
            )
        )
    return PoeModel(tuple(joints), se3.twist_exp(RNG.normal(size=6)))


def product_of_exponentials(model: PoeModel, q):
    out = []
    for row in q:
        t = np.eye(4)
        for j, value in zip(model.joints, row, strict=True):
            point = np.zeros(3) if j.point is None else j.point  # prismatic: any point on it
            if j.kind == "prismatic":
                xi = np.concatenate([np.zeros(3), j.axis])
            else:
                xi = np.concatenate([j.axis, np.cross(point, j.axis) + j.pitch * j.axis])
            t = t @ se3.twist_exp(j.scale * xi, value)
        out.append(t @ model.home)
    return np.array(out).reshape(-1, 4, 4)


def links_one_by_one(table, q):
    out = []
    for row in q:
        links = table.link_form()[0]
        t = links[0]
        for r, value, link in zip(table.rows, row, links[1:], strict=True):
            s = r.scale * value
            turn = 0.0 if r.kind == "prismatic" else s
            shift = s if r.kind == "prismatic" else r.pitch * s
            t = t @ se3.rot_z(turn) @ se3.trans(z=shift) @ link
        out.append(t)
    return np.array(out).reshape(-1, 4, 4)


@pytest.mark.parametrize("block", [1, 3, 16384])
def test_poe_fk_is_the_product_of_exponentials(monkeypatch, block):
    """A POE model's link form (its exponentials written as C Q C^-1), across block
    boundaries, against exp(xi_1 q_1) ... exp(xi_n q_n) M multiplied out with se3.twist_exp."""
    monkeypatch.setattr(fk, "BLOCK", block)
    for n in (1, 5, 12):
        model = mixed_model(n)
        q = RNG.uniform(-math.pi, math.pi, size=(10, n))
        diff = np.abs(model.fk_batch(q) - product_of_exponentials(model, q)).max()
        assert diff <= 1e-13 * model.size(), (n, diff)
        assert np.allclose(model.fk(q[3]), model.fk_batch(q)[3], rtol=0, atol=1e-15)


@pytest.mark.parametrize("block", [1, 3, 16384])
def test_table_fk_is_its_links_one_by_one(monkeypatch, block):
    """Every convention's table, across block boundaries, against its links and joint
    motions multiplied one by one as 4x4 matrices."""
    monkeypatch.setattr(fk, "BLOCK", block)
    text, _ = random_chain_urdf(5, 9)
    urdf_model = tree_to_poe(parse_tree(text.encode(), "r.urdf"), "base", "tool")
    for model in (urdf_model, mixed_model(7)):
        q = model.sample(10, 1)
        for conv in NAMES:
            table = to_table(model, conv)
            diff = np.abs(table.fk_batch(q) - links_one_by_one(table, q)).max()
            assert diff <= 1e-13 * model.size(), (conv, diff)


def test_table_links_are_its_records_transforms():
    """The links of a table are its base, rows and tool records' own transforms, grouped
    around each joint motion (what each convention's FK formula says)."""
    model = mixed_model(5)
    for conv in NAMES:
        table = to_table(model, conv)
        links, motions = table.link_form()
        expected = [se3.matrix_of(table.base.frame())]
        for row in table.rows:
            before, after = row.params.around_joint()
            if before is not None:
                expected[-1] = expected[-1] @ se3.matrix_of(before)
            expected.append(se3.matrix_of(after))
        expected[-1] = expected[-1] @ table.tool_matrix
        assert np.allclose(links, np.array(expected), rtol=0, atol=1e-15), conv
        assert np.array_equal(motions[:, 0], [r.scale * r.rotation for r in table.rows])


def test_empty_batches():
    model = mixed_model(3)
    assert model.fk_batch(np.zeros((0, 3))).shape == (0, 4, 4)
    for conv in NAMES:
        assert to_table(model, conv).fk_batch(np.zeros((0, 3))).shape == (0, 4, 4)


def test_fk_takes_one_configuration_or_a_stack():
    model = mixed_model(4)
    table = to_table(model, "mdh")
    q = RNG.uniform(-1.0, 1.0, size=(2, 3, 4))
    for fk_one, batch in ((model.fk, model.fk_batch), (table.fk, table.fk_batch)):
        assert fk_one(q[0, 0]).shape == (4, 4)
        assert np.array_equal(fk_one(q[0, 0]), batch(q[0, :1])[0])
        assert np.array_equal(fk_one(q), batch(q.reshape(-1, 4)).reshape(2, 3, 4, 4))
        with pytest.raises(ValueError, match=r"q must have shape \(4,\) or \(\.\.\., 4\)"):
            fk_one(q[0, 0, :3])


def test_pose_errors_measures_position_and_rotation():
    """A micrometre along x and a 1e-9 rad turn are measured as such; NaN propagates."""
    a = np.repeat(np.eye(4)[None], 3, axis=0)
    b = a.copy()
    b[1, 0, 3] += 1e-6
    b[2, :3, :3] = se3.rot_z(1e-9)[:3, :3]
    pos, rot = se3.pose_errors(a, b)
    assert pos == pytest.approx(1e-6, rel=1e-12) and rot == pytest.approx(1e-9, rel=1e-6)
    b[0, 2, 3] = np.nan
    assert math.isnan(se3.pose_errors(a, b)[0])


@pytest.mark.parametrize("block", [1, 3, 16384])
def test_chains_errors_is_pose_errors_of_each_chain(monkeypatch, block):
    """verify's block-by-block comparison gives what pose_errors gives on the whole stacks,
    for every convention's table and the POE model, across block boundaries; the worst
    configuration may lie in any block, and a NaN in any block makes that chain's error NaN."""
    monkeypatch.setattr(fk, "BLOCK", block)
    model = mixed_model(6)
    q = model.sample(10, 2)
    chains = [model.link_form(), *(to_table(model, conv).link_form() for conv in NAMES)]
    reference = model.fk_batch(q)
    for k in (0, 4, 9):  # the worst configuration in the first, a middle and the last block
        moved = reference.copy()
        moved[k, :3, 3] += (1e-6, -2e-6, 0.5e-6)
        moved[k, :3, :3] = moved[k, :3, :3] @ se3.rot_x(3e-7)[:3, :3]
        poses = fk.chains_fk(chains, q)
        expected = [se3.pose_errors(p, moved) for p in poses]
        got = fk.chains_errors(chains, q, moved)
        assert len(got) == len(chains)
        for (pos, rot), (want_pos, want_rot) in zip(got, expected, strict=True):
            assert pos == pytest.approx(want_pos, rel=1e-9, abs=1e-15)
            assert rot == pytest.approx(want_rot, rel=1e-6, abs=1e-15)
            assert pos == pytest.approx(math.sqrt(5.25) * 1e-6, rel=1e-6)
    broken = reference.copy()
    broken[7, 1, 1] = np.nan
    errors = fk.chains_errors(chains, q, broken)
    assert all(math.isnan(rot) and not math.isnan(pos) for pos, rot in errors)
    assert fk.chains_errors(chains, q[:0], reference[:0]) == [(0.0, 0.0)] * len(chains)
    with pytest.raises(ValueError, match="reference poses"):
        fk.chains_errors(chains, q, reference[:5])


def test_model_figures_are_computed_once_and_not_carried_into_a_changed_model():
    """size(), extent() and limits() are remembered per model; a model made from it with
    other fields (scaled, replaced) has its own, and the remembered limits cannot be edited."""
    from dataclasses import replace

    model = mixed_model(5)
    size, limits = model.size(), model.limits()
    assert model.limits() is limits and model.size() == size
    with pytest.raises(ValueError, match="read-only"):
        limits[0, 0] = 0.0
    bigger = model.scaled(1000.0, "mm")
    assert bigger.size() == pytest.approx(1000.0 * size, rel=1e-12)
    assert bigger.extent() == pytest.approx(1000.0 * model.extent(), rel=1e-12)
    moved = replace(model, home=model.home @ se3.trans(x=50.0))
    assert moved.extent() >= 49.0 > model.extent()
    tight = replace(model, joints=tuple(replace(j, lower=-0.5, upper=0.25) for j in model.joints))
    assert np.array_equal(tight.limits(), np.tile([-0.5, 0.25], (tight.dof, 1)))


def test_fast_expi_is_within_an_ulp_of_numpys_and_falls_back_beyond_its_reach():
    """The fast path's table e^{ix} against numpy's exp: within one unit in the last place of
    1 in each part, for angles near 0, near multiples of the table's step, negative and up to
    its reach; beyond it (and for inf, NaN) it is numpy's own result."""
    from urdf2dh.model import _fastfk

    rng = np.random.default_rng(7)
    step = 2.0 * math.pi / _fastfk.STEPS
    reach = _fastfk.REACH_STEPS * step
    x = np.concatenate([
        rng.uniform(-4.0, 4.0, 200_000),
        rng.uniform(-reach, reach, 200_000),
        np.arange(-3000, 3000) * step + rng.uniform(-1e-12, 1e-12, 6000),
        (np.arange(-3000, 3000) + 0.5) * step,  # the polynomial's widest argument
        [0.0, -0.0, 1e-300, -5e-324, math.pi, -math.pi, 0.5 * math.pi],
    ])  # fmt: skip
    fast, exact = _fastfk.expi(x), np.exp(1j * x)
    ulp = np.spacing(1.0)
    assert np.abs(fast.real - exact.real).max() <= ulp
    assert np.abs(fast.imag - exact.imag).max() <= ulp
    for beyond in ([reach * 1.01, 1.0], [1.0, np.inf], [np.nan, 0.5], [1e300, -1e300]):
        with np.errstate(invalid="ignore"):  # numpy's exp of inf or NaN: NaN, as it says
            got, want = _fastfk.expi(np.array(beyond)), np.exp(1j * np.array(beyond))
        assert np.array_equal(got, want, equal_nan=True), beyond
    assert _fastfk.expi(np.zeros(0)).shape == (0,)


def test_fast_batch_fk_agrees_with_the_reference_for_every_convention():
    """Table.fk_batch and PoeModel.fk_batch take the fast path from FAST_MIN configurations on:
    every convention's table and the POE model (revolute, prismatic, helical joints, odd
    scales) agree with the reference FK to 1e-14 of the robot's size; below FAST_MIN they are
    the reference, bit for bit."""
    from urdf2dh.model import _fastfk

    model = mixed_model(9)
    q = model.sample(_fastfk.FAST_MIN + 17, 4)
    tables = [to_table(model, conv) for conv in NAMES]
    for source in (model, *tables):
        links, motions = source.link_form()
        reference = fk.chain_fk(links, motions, source.positions(q))
        fast = source.fk_batch(q)
        assert np.abs(fast - reference).max() <= 1e-14 * model.size(), source
        assert not np.array_equal(fast, reference)  # the table's sines, not numpy's
        few = q[: _fastfk.FAST_MIN - 1]
        assert np.array_equal(source.fk_batch(few), reference[: len(few)])
