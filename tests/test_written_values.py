"""Table files carry no round-off: no -0.0, no 2.4e-33 where the geometry says 0, no
1.5707963267948968 where it says pi/2 -- and the self-check is of the numbers as written."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from urdf2dh import DEFAULT, load
from urdf2dh.cli import main
from urdf2dh.conventions import NAMES
from urdf2dh.conventions.convert import build_table, self_check, to_table
from urdf2dh.io.catalog import ROBOTS

ROUND_OFF = DEFAULT.written


def _values(record):
    for name, quantity in type(record).quantities().items():
        value = getattr(record, name)
        yield quantity, (value if isinstance(value, tuple) else (value,))


@pytest.mark.parametrize("robot", sorted(ROBOTS))
def test_parameters_are_exact_where_round_off_would_show(robot, capsys):
    model = load(robot)
    size = model.size()
    for conv in NAMES:
        table = to_table(model, conv)
        for record in [table.base, table.tool, *(r.params for r in table.rows)]:
            for quantity, values in _values(record):
                for v in values:
                    if quantity == "angle":
                        off = abs(v - round(v / (math.pi / 2)) * math.pi / 2)
                        assert off == 0.0 or off > ROUND_OFF, (robot, conv, v)
                        assert -math.pi < v <= math.pi
                    elif quantity == "direction":
                        assert all(
                            abs(v - t) == 0.0 or abs(v - t) > ROUND_OFF for t in (-1.0, 0.0, 1.0)
                        ), (robot, conv, v)
                    else:
                        assert v == 0.0 or abs(v) > ROUND_OFF * size, (robot, conv, v)
                    assert math.copysign(1.0, v) > 0 or v != 0.0, (robot, conv, "-0.0")
        assert main(["convert", robot, "--convention", conv, "--format", "json"]) == 0
        text = capsys.readouterr().out
        assert "-0.0," not in text and "-0.0\n" not in text and "e-3" not in text, (robot, conv)


def test_the_check_is_of_the_numbers_as_written():
    model = load("ur3")
    raw, _ = build_table(model, "dh", DEFAULT)
    assert raw.rows[3].params.alpha == 1.5707963267948968  # pi/2 and round-off, before
    assert 0.0 < abs(raw.rows[3].params.a) < 1e-16
    table = to_table(model, "dh")
    assert table.rows[3].params.alpha == math.pi / 2 and table.rows[3].params.a == 0.0
    assert table.check == self_check(model, table)  # the same numbers, the same check


def test_matrices_are_written_without_round_off(capsys):
    assert main(["convert", "ur5", "--format", "json"]) == 0
    tree = json.loads(capsys.readouterr().out)
    for part in ("base", "tool"):
        m = np.array(tree[part]["matrix"])
        assert set(np.unique(m[:3, :3])) <= {-1.0, 0.0, 1.0}, m
    assert main(["convert", "ur5", "--style", "ur", "--format", "json"]) == 0
    base = json.loads(capsys.readouterr().out)["base"]["matrix"]
    assert base[0][:3] == [-1.0, 0.0, 0.0]  # UR's base frame: base_link turned by pi
