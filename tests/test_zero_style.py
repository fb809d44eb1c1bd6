"""`--style zero`: zero theta offsets wherever the geometry allows, the base's included."""

from __future__ import annotations

from pathlib import Path

import pytest
from oracle import assert_fk_matches, pin_reference

from urdf2dh import load, to_table
from urdf2dh.io.sources import open_source

DATA = Path(__file__).parent / "data"


def test_an_arm_written_without_offsets_gets_none():
    model = load(str(DATA / "genser6.urdf"))
    for convention in ("dh", "mdh"):
        table = to_table(model, convention, style="zero")
        assert [r.params.theta for r in table.rows] == [0.0] * 6, convention
        assert table.base.theta == 0.0 and table.tool.theta == 0.0
    # the other styles put half turns somewhere for the same arm
    assert to_table(model, "mdh", style="ur").base.theta != 0.0
    assert any(r.params.theta != 0.0 for r in to_table(model, "mdh", style="wu").rows)


@pytest.mark.parametrize("robot", ["ur5", "panda", "kinova", "stanford", "tiago-arm"])
def test_zero_style_tables_are_exact(robot):
    source = open_source(robot)
    model = source.model()
    q, reference = pin_reference(source, model, samples=50, seed=4)
    for convention in ("dh", "mdh"):
        table = to_table(model, convention, style="zero")
        assert_fk_matches(
            f"{robot} {convention} zero", table.fk_batch(q), reference, model.size(), q
        )
