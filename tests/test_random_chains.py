"""Seeded random chains with parallel, anti-parallel, intersecting, coincident and skew axes and
prismatic joints, written as URDF and read by both urdf2dh and Pinocchio."""

from __future__ import annotations

import pytest
from chains import random_chain_urdf
from oracle import EXACT, assert_fk_matches, pin_reference

from urdf2dh import CONVENTIONS, to_table
from urdf2dh.io.sources import Source
from urdf2dh.io.urdf import parse_tree, tree_to_poe


def source_of(text: str) -> Source:
    tree = parse_tree(text.encode(), "random.urdf")
    return Source("urdf", "random.urdf", tree.name, tree, text.encode())


@pytest.mark.parametrize("seed", range(40))
def test_random_chain_all_conventions(seed):
    n = 2 + seed % 9
    text, drawn = random_chain_urdf(seed, n, scale=0.5 + seed % 3)
    source = source_of(text)
    model = tree_to_poe(source.tree, "base", "tool")
    q, reference = pin_reference(source, model, samples=100, seed=seed)
    size = model.size()
    assert_fk_matches(f"seed {seed} POE", model.fk_batch(q), reference, size, q)
    for conv in CONVENTIONS:
        table = to_table(model, conv)
        assert_fk_matches(f"seed {seed} {conv} {drawn}", table.fk_batch(q), reference, size, q)
        # exact geometry: nothing was snapped that a user would need to hear about
        assert not [w for w in table.warnings if "treated as" in w], table.warnings


@pytest.mark.parametrize(
    "relation", ["parallel", "antiparallel", "intersecting", "coincident", "prismatic"]
)
def test_chains_of_one_relation(relation):
    """Long runs of the same degenerate relation (e.g. 8 parallel axes in a row)."""
    for seed in range(5):
        text, _ = random_chain_urdf(100 + seed, 8, relations=(relation,))
        source = source_of(text)
        model = tree_to_poe(source.tree, "base", "tool")
        q, reference = pin_reference(source, model, samples=60, seed=seed)
        for conv in CONVENTIONS:
            table = to_table(model, conv)
            assert_fk_matches(
                f"{relation} seed {seed} {conv}", table.fk_batch(q), reference, model.size(), q
            )


def test_parallel_rule_d_is_zero():
    """Wu 2019 (docs/conventions/dh.md): for parallel consecutive axes the D-H offset d is 0."""
    text, _drawn = random_chain_urdf(3, 6, relations=("parallel",), tool=False)
    model = tree_to_poe(source_of(text).tree, "base", "link6")
    table = to_table(model, "dh")
    for row in table.rows[:-1]:
        assert row.params.d == 0.0
        assert row.params.alpha in (0.0, 3.141592653589793)
        assert row.params.a >= 0.0


def test_exactness_scales_with_robot_size():
    """The same chain in millimetres: errors stay at ~1e-16 relative."""
    for scale in (1e-3, 1.0, 1e3):
        text, _ = random_chain_urdf(11, 7, scale=scale)
        source = source_of(text)
        model = tree_to_poe(source.tree, "base", "tool")
        q, reference = pin_reference(source, model, samples=50)
        for conv in CONVENTIONS:
            table = to_table(model, conv)
            assert_fk_matches(
                f"scale {scale} {conv}", table.fk_batch(q), reference, model.size(), q, rel=EXACT
            )
