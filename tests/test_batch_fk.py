"""Batched forward kinematics against plain per-configuration products, across block boundaries:
the POE model's closed-form exponentials against se3.twist_exp, and a table's blocked evaluation
against its links multiplied one by one."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from chains import random_chain_urdf

from urdf2dh import chainfk, screws, se3, trig
from urdf2dh.convert import sample_configurations, to_table
from urdf2dh.screws import Joint, PoeModel
from urdf2dh.table import CONVENTIONS
from urdf2dh.urdf import parse_tree, tree_to_poe

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
        joints.append(Joint(f"j{i}", kind, unit(RNG.normal(size=3)), point, pitch,
                            RNG.uniform(0.5, 2.0) * RNG.choice([-1.0, 1.0])))
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
        t = table.links[0]
        for r, value, link in zip(table.rows, row, table.links[1:], strict=True):
            s = r.scale * value
            turn = 0.0 if r.kind == "prismatic" else s
            shift = s if r.kind == "prismatic" else r.pitch * s
            t = t @ se3.rot_z(turn) @ se3.trans(z=shift) @ link
        out.append(t)
    return np.array(out).reshape(-1, 4, 4)


@pytest.mark.parametrize(("block", "poly"), [(1, False), (3, True), (4096, False), (4096, True)])
def test_poe_fk_batch_is_the_product_of_exponentials(monkeypatch, block, poly):
    monkeypatch.setattr(screws, "FK_BLOCK", block)
    monkeypatch.setattr(trig, "POLY_MIN", 0 if poly else 10**9)
    for n in (1, 5, 12):
        model = mixed_model(n)
        q = RNG.uniform(-math.pi, math.pi, size=(10, n))
        diff = np.abs(model.fk_batch(q) - product_of_exponentials(model, q)).max()
        assert diff <= 1e-13 * model.size(), (n, diff)
        assert np.allclose(model.fk(q[3]), model.fk_batch(q)[3], rtol=0, atol=1e-15)


@pytest.mark.parametrize(("block", "threads", "poly"), [
    (1, 1, False), (3, 1, True), (3, 2, False), (3, 2, True), (16384, 1, True),
])
def test_table_fk_batch_is_its_links_one_by_one(monkeypatch, block, threads, poly):
    """Across block boundaries, on one thread and on two, with the C library's sines and
    cosines and with urdf2dh.trig's."""
    monkeypatch.setattr(chainfk, "BLOCK", block)
    monkeypatch.setattr(chainfk, "THREADS_FROM", 0)
    monkeypatch.setenv("URDF2DH_THREADS", str(threads))
    monkeypatch.setattr(trig, "POLY_MIN", 0 if poly else 10**9)
    text, _ = random_chain_urdf(5, 9)
    urdf_model = tree_to_poe(parse_tree(text.encode(), "r.urdf"), "base", "tool")
    for model in (urdf_model, mixed_model(7)):
        q = sample_configurations(model, 10, 1)
        for conv in CONVENTIONS:
            table = to_table(model, conv)
            diff = np.abs(table.fk_batch(q) - links_one_by_one(table, q)).max()
            assert diff <= 1e-13 * model.size(), (conv, diff)


def test_empty_batches():
    model = mixed_model(3)
    assert model.fk_batch(np.zeros((0, 3))).shape == (0, 4, 4)
    for conv in CONVENTIONS:
        assert to_table(model, conv).fk_batch(np.zeros((0, 3))).shape == (0, 4, 4)


def test_self_check_samples_are_generator_uniform_draws():
    """sample_configurations computes low + (high - low) * random() itself: the same numbers
    as Generator.uniform(low, high, size), without its slow broadcasting path."""
    model = mixed_model(6)
    lim = model.limits()
    for seed in range(5):
        expected = np.random.default_rng(seed).uniform(lim[:, 0], lim[:, 1], size=(50, 6))
        assert np.array_equal(sample_configurations(model, 50, seed), expected)


def test_fk_takes_one_configuration_or_a_stack():
    model = mixed_model(4)
    table = to_table(model, "mdh")
    q = RNG.uniform(-1.0, 1.0, size=(2, 3, 4))
    for fk, batch in ((model.fk, model.fk_batch), (table.fk, table.fk_batch)):
        assert fk(q[0, 0]).shape == (4, 4)
        assert np.array_equal(fk(q[0, 0]), batch(q[0, :1])[0])
        assert np.array_equal(fk(q), batch(q.reshape(-1, 4)).reshape(2, 3, 4, 4))
        with pytest.raises(ValueError, match=r"expected \(\.\.\., 4\)"):
            fk(q[0, 0, :3])


@pytest.mark.parametrize(("block", "threads"), [(3, 1), (3, 2), (16384, 1)])
def test_link_forms_are_the_same_fk(monkeypatch, block, threads):
    """The self-check's evaluation: a POE model's exponentials written as C Q C^-1 and a
    table's links, each alone and side by side, against the products one by one."""
    monkeypatch.setattr(chainfk, "BLOCK", block)
    monkeypatch.setattr(chainfk, "THREADS_FROM", 0)
    monkeypatch.setenv("URDF2DH_THREADS", str(threads))
    text, _ = random_chain_urdf(6, 9)
    urdf_model = tree_to_poe(parse_tree(text.encode(), "r.urdf"), "base", "tool")
    for model in (urdf_model, mixed_model(7)):
        q = sample_configurations(model, 10, 2)
        frames, motions = model.link_form()
        alone = chainfk.run_links(se3.stack(frames)[None], np.array(motions)[None], q)[0]
        diff = np.abs(alone - product_of_exponentials(model, q)).max()
        assert diff <= 1e-13 * model.size(), diff
        for conv in CONVENTIONS:
            table = to_table(model, conv)
            table_frames, table_motions = table.link_form()
            pair = chainfk.run_links(
                se3.stack(table_frames + frames).reshape(2, -1, 4, 4),
                np.array(table_motions + motions).reshape(2, -1, 2), q)
            assert np.array_equal(pair[1], alone), conv
            diff = np.abs(pair[0] - links_one_by_one(table, q)).max()
            assert diff <= 1e-13 * model.size(), (conv, diff)


def test_compare_links_is_pose_errors_of_the_poses(monkeypatch):
    """The self-check's comparison without poses measures what se3.pose_errors measures."""
    monkeypatch.setattr(chainfk, "BLOCK", 7)
    model = mixed_model(6)
    q = sample_configurations(model, 30, 4)
    frames, motions = model.link_form()
    table_frames, table_motions = to_table(model, "mdh").link_form()
    links = se3.stack(table_frames + frames).reshape(2, -1, 4, 4)
    moved = links.copy()
    moved[0, 3, 0, 3] += 1e-6  # one link off by a micrometre: a measurable difference
    for pair in (links, moved):
        mot = np.array(table_motions + motions).reshape(2, -1, 2)
        poses = chainfk.run_links(pair, mot, q)
        expected = se3.pose_errors(poses[0], poses[1])
        assert chainfk.compare_links(pair, mot, q) == pytest.approx(expected, rel=1e-9, abs=1e-30)
    broken = links.copy()
    broken[1, 2, 0, 3] = np.nan
    with np.errstate(invalid="ignore"):
        pos, _ = chainfk.compare_links(broken, mot, q)
    assert math.isnan(pos)


def test_blocks_share_evenly_and_threads_change_no_bit(monkeypatch):
    """Beyond one block the blocks come in multiples of 4, at most BLOCK long, whatever the
    number of threads; so the poses of every convention (cpc's dense products included) are
    bit for bit the same on one, two or three threads."""
    monkeypatch.setattr(chainfk, "BLOCK", 5)
    monkeypatch.setattr(chainfk, "THREADS_FROM", 0)
    for count, block in ((5, 5), (6, 5), (21, 5), (40, 5), (41, 5), (6, 1), (100_000, 16384)):
        spans: list[tuple[int, int]] = []
        chainfk.map_blocks(count, block, lambda lo, hi, _, found=spans: found.append((lo, hi)),
                           lambda m: None)
        spans.sort()
        lengths = [hi - lo for lo, hi in spans]
        assert spans[0][0] == 0 and sum(lengths) == count, (count, spans)
        assert all(a[1] == b[0] for a, b in itertools.pairwise(spans)), spans
        assert max(lengths) <= block and max(lengths) - min(lengths) <= 1, (count, lengths)
        assert len(spans) in (1, count) or len(spans) % 4 == 0, (count, lengths)
    model = mixed_model(6)
    q = sample_configurations(model, 41, 5)
    for conv in CONVENTIONS:
        table = to_table(model, conv)
        poses = []
        for threads in (1, 2, 3):
            monkeypatch.setenv("URDF2DH_THREADS", str(threads))
            poses.append(table.fk_batch(q))
        assert np.array_equal(poses[0], poses[1]) and np.array_equal(poses[0], poses[2]), conv
        diff = np.abs(poses[0] - links_one_by_one(table, q)).max()
        assert diff <= 1e-13 * model.size(), (conv, diff)
