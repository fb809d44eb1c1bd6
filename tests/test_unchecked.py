"""The converter's internal paths make tables without running the constructors' checks again
(:func:`urdf2dh.checks.unchecked`): what they make equals what the public constructors make of
the same values, field by field and type by type; the public constructors still refuse bad
values; a table chosen by :func:`~urdf2dh.conventions.choice.choose` is checked exactly as
:func:`~urdf2dh.conventions.convert.to_table` checks it on its own."""

from __future__ import annotations

import math
from dataclasses import fields, replace

import numpy as np
import pytest

from urdf2dh import CONVENTIONS, Tolerances, load
from urdf2dh.check.diff import ill_conditioned
from urdf2dh.checks import unchecked, unchecked_replace
from urdf2dh.conventions.choice import choose
from urdf2dh.conventions.convert import to_table
from urdf2dh.conventions.table import Check, Row, Table


def _checked_copy(table: Table) -> Table:
    """The same table made again by the public constructors (every check run)."""
    rows = tuple(
        Row(r.name, r.kind, r.params, r.pitch, r.scale, r.lower, r.upper, r.mimic)
        for r in table.rows
    )
    return Table(*(rows if f.name == "rows" else getattr(table, f.name) for f in fields(Table)))


def _types(table: Table) -> list[object]:
    out: list[object] = [type(getattr(table, f.name)) for f in fields(Table)]
    for r in table.rows:
        out += [type(getattr(r, f.name)) for f in fields(Row)]
    for params in (table.base, *(r.params for r in table.rows), table.tool):
        for value in params.values().values():  # floats, and tuples of floats
            out += [type(value), *(type(x) for x in value)] if isinstance(value, tuple) else [
                type(value)]  # fmt: skip
    return out


@pytest.mark.parametrize("robot", ["panda", "ur5", "so100"])
@pytest.mark.parametrize("conv", CONVENTIONS)
def test_an_internal_table_is_what_the_constructors_make(robot, conv):
    table = to_table(load(robot), conv)
    again = _checked_copy(table)
    records = (table.base, *(r.params for r in table.rows), table.tool)
    # each record as its constructor makes it of the same values
    assert all(type(p)(**p.values()) == p for p in records)
    assert again == table
    assert _types(again) == _types(table)


def test_the_public_constructors_still_refuse_bad_values():
    table = to_table(load("panda"), "dh")
    row = table.rows[0]
    with pytest.raises(ValueError, match="pitch must be finite"):
        Row(row.name, row.kind, row.params, math.nan)
    with pytest.raises(ValueError, match="scale must not be 0"):
        replace(row, scale=0.0)
    with pytest.raises(ValueError, match="Table: size must be finite"):
        replace(table, size=math.nan)
    with pytest.raises(TypeError, match="Table: tool"):
        replace(table, tool=row.params)
    with pytest.raises(TypeError, match=r"Table: rows\[0\]"):
        replace(table, rows=(row.params,))
    with pytest.raises(ValueError, match="samples must be from 1"):
        Check(0, 0.0, 0.0)


def test_unchecked_takes_the_fields_it_has_only():
    table = to_table(load("panda"), "dh")
    with pytest.raises(TypeError, match="no field colour"):
        unchecked_replace(table, colour="red")
    with pytest.raises(TypeError, match="takes 8 fields"):
        unchecked(Row, *range(9))
    with pytest.raises(TypeError, match="field kind is missing"):
        unchecked(Row, "j")
    assert unchecked_replace(table, warnings=("w",)) == replace(table, warnings=("w",))


@pytest.mark.parametrize("fallback", ["hayati", None])
def test_choose_checks_as_to_table_does(fallback):
    """so100's base z and first axis, 6.3e-6 rad from parallel, are beyond a parallel angle of
    1e-9: the D-H table is objected to; the hayati table, checked at the model's poses that the
    D-H table's check made, is the table to_table makes, the reason added."""
    model, tol = load("so100"), Tolerances(parallel_angle=1e-9)
    chosen = choose(model, "dh", tol, fallback=fallback)
    assert chosen.objection is not None
    alone = to_table(model, fallback or "dh", tol)
    assert chosen.table.check == alone.check
    expected = alone.warnings if chosen.reason is None else (chosen.reason, *alone.warnings)
    assert chosen.table == replace(alone, warnings=expected)


def test_ill_conditioned_pairs_are_the_angles_between_consecutive_lines():
    rng = np.random.default_rng(7)
    model = load("ur5")
    axes = rng.normal(size=(len(model.joints), 3))
    axes[2] = axes[1] + 1e-4 * rng.normal(size=3)  # a nearly parallel pair
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    other = replace(
        model, joints=tuple(replace(j, axis=a) for j, a in zip(model.joints, axes, strict=True))
    )
    lines = [np.array([0.0, 0.0, 1.0]), *axes, model.home[:3, 2]]
    names = ["base z", *(j.name for j in model.joints), "tool z"]
    lines_nominal = [np.array([0.0, 0.0, 1.0]), *(j.axis for j in model.joints), model.home[:3, 2]]

    def angle(u, v):
        return math.atan2(float(np.linalg.norm(np.cross(u, v))), abs(float(u @ v)))

    pairs = ill_conditioned(model, other, 0.01)
    expected = [
        (names[k], names[k + 1], angle(lines_nominal[k], lines_nominal[k + 1]),
         angle(lines[k], lines[k + 1]))
        for k in range(len(lines) - 1)
        if min(angle(lines_nominal[k], lines_nominal[k + 1]), angle(lines[k], lines[k + 1])) <= 0.01
    ]  # fmt: skip
    assert [(p.first, p.second) for p in pairs] == [e[:2] for e in expected]
    assert ("shoulder_lift_joint", "elbow_joint") in [(p.first, p.second) for p in pairs]
    for p, e in zip(pairs, expected, strict=True):
        assert p.nominal_angle == pytest.approx(e[2], rel=1e-15, abs=1e-15)
        assert p.actual_angle == pytest.approx(e[3], rel=1e-15, abs=1e-15)
