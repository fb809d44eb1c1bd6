"""The self-check's number of configurations: 100 settle exactness, 1000 measure a deviation
that a reported judgement introduced, and an explicit number is taken as given."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

from urdf2dh import CONVENTIONS, DEFAULT, load
from urdf2dh.cli import main
from urdf2dh.conventions.convert import (
    DEFAULT_SAMPLES,
    JUDGED_SAMPLES,
    build_table,
    self_check,
    to_table,
)
from urdf2dh.geometry.se3 import pose_errors
from urdf2dh.io.sources import open_source


@pytest.mark.parametrize("conv", CONVENTIONS)
def test_an_exact_table_is_checked_at_the_default(conv):
    table = to_table(load("panda"), conv)
    assert table.check is not None and table.check.samples == DEFAULT_SAMPLES == 100
    assert table.warnings == ()


def test_a_reported_judgement_is_measured_at_more_configurations():
    """so100's base z and first axis are 6.3e-6 rad from parallel: treated as parallel, with
    the deviation measured at 1000 configurations and stated."""
    model = load("so100")
    table = to_table(model, "dh")
    assert table.check is not None and table.check.samples == JUDGED_SAMPLES == 1000
    assert any(f"worst of {JUDGED_SAMPLES} checked" in w for w in table.warnings)
    assert table.check.max_position_error > 1e-9 * model.size()  # a deviation, measured
    # ... under the bound declared for every configuration
    assert table.check.max_position_error < table.check.declared_position
    assert table.check.max_rotation_error < table.check.declared_rotation
    exact = to_table(model, "dh", DEFAULT.with_exact())
    assert exact.check is not None and exact.check.samples == DEFAULT_SAMPLES


def test_an_explicit_number_is_taken(capsys):
    model = load("ur5")
    table = to_table(model, "mdh", samples=250)
    assert table.check is not None and table.check.samples == 250
    assert main(["convert", "so100", "--format", "json", "--check-samples", "123"]) == 0
    assert json.loads(capsys.readouterr().out)["check"]["samples"] == 123


@pytest.mark.parametrize("robot", ["ur5", "panda", "kinova", "puma560-actual"])
@pytest.mark.parametrize(("param", "relative"), [("d", 1e-9), ("alpha", 1e-8), ("theta", 1e-8)])
def test_the_default_catches_a_slightly_wrong_table(robot, param, relative):
    """The reason 100 configurations suffice: a table that is off, even slightly, is off at
    almost every configuration. Each row's parameter moved in turn (d by `relative` x size,
    an angle by `relative` rad), ten times the check's tolerance: every one is caught by a
    check at the default number of configurations."""
    model = load(robot)
    table, _ = build_table(model, "dh", DEFAULT)
    size = model.size()
    step = relative * size if param == "d" else relative
    for k, row in enumerate(table.rows):
        params = replace(row.params, **{param: getattr(row.params, param) + step})
        rows = (*table.rows[:k], replace(row, params=params), *table.rows[k + 1 :])
        check = self_check(model, replace(table, rows=rows))
        assert check.samples == DEFAULT_SAMPLES
        assert (
            check.max_position_error > DEFAULT.check_position * size
            or check.max_rotation_error > DEFAULT.check_rotation
        ), (row.name, check)


@pytest.mark.parametrize("robot", ["so100", "so101"])
def test_verify_never_exceeds_the_declared_bound(robot):
    """The bound is one for every configuration, not a sample maximum: Pinocchio, at 20,000
    configurations other than the check's, stays within it (with no allowance beyond it)."""
    from urdf2dh.check.verify import pinocchio_fk

    source = open_source(robot)
    model = source.model()
    q = model.sample(20_000, (5, 5))
    reference = pinocchio_fk(source, model, q)
    for conv in ("dh", "mdh"):
        table = to_table(model, conv)
        pos, rot = pose_errors(table.fk_batch(q), reference)
        assert pos <= table.check.declared_position + 1e-12 * model.size(), (conv, pos)
        assert rot <= table.check.declared_rotation + 1e-12, (conv, rot)
