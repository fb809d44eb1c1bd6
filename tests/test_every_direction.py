"""Any convention to any other through table files; the URDF writer; identifiability counts."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from oracle import assert_fk_matches, pin_reference

import urdf2dh
from urdf2dh import CONVENTIONS, load, to_table
from urdf2dh.cli import main
from urdf2dh.emit.urdf import table_to_urdf
from urdf2dh.geometry.se3 import rpy
from urdf2dh.io.sources import open_source
from urdf2dh.model.identifiability import BASE, TOOL

ROBOTS = ["ur5", "panda", "stanford", "scara", "tiago-arm", "puma560-actual", "puma560-nominal"]


def close_tables(a, b, size):
    assert [r.name for r in a.rows] == [r.name for r in b.rows]
    records = [(a.base, b.base), (a.tool, b.tool)]
    records += [(x.params, y.params) for x, y in zip(a.rows, b.rows, strict=True)]
    for pa, pb in ((x.values(), y.values()) for x, y in records):
        for k in pa:
            va, vb = np.atleast_1d(pa[k]), np.atleast_1d(pb[k])
            scale = 1.0 if k in ("theta", "alpha", "beta", "b") else size
            diff = np.abs(va - vb)
            if k in ("theta", "beta"):
                diff = np.abs(np.remainder(va - vb + math.pi, 2 * math.pi) - math.pi)
            assert diff.max() <= 1e-12 * scale, (k, va, vb)


@pytest.mark.parametrize("robot", ROBOTS)
def test_any_convention_to_any_other_through_table_files(robot, tmp_path, capsys):
    model = load(robot)
    q = model.sample(100, 1)
    reference = model.fk_batch(q)
    size = model.size()
    for first in CONVENTIONS:
        path = tmp_path / f"{first}.json"
        assert (
            main(["convert", robot, "--convention", first, "--format", "json", "-o", str(path)])
            == 0
        )
        source = open_source(str(path))
        assert source.kind == "table"
        for second in CONVENTIONS:
            table = to_table(source.model(), second)
            assert_fk_matches(f"{robot} {first}->{second}", table.fk_batch(q), reference, size, q)
            if second == first:  # convention -> POE -> convention is idempotent
                close_tables(table, to_table(model, first), size)


@pytest.mark.parametrize("robot", ROBOTS)
def test_urdf_writer_matches_pinocchio_and_round_trips(robot, tmp_path):
    model = load(robot)
    for conv in CONVENTIONS:
        table = to_table(model, conv)
        text, _ = table_to_urdf(table)
        path = tmp_path / f"{robot}-{conv}.urdf"
        path.write_text(text)
        written = open_source(str(path))
        again = written.model()
        q, reference = pin_reference(written, again, samples=100)
        metres = 1e-3 if model.length_unit == "mm" else 1.0
        # a URDF joint's position is |scale| q (URDF joints have no scale)
        q_table = q / np.array([abs(r.scale) for r in table.rows])
        ours = table.fk_batch(q_table)
        ours[:, :3, 3] *= metres
        assert_fk_matches(f"{robot} {conv} -> URDF (Pinocchio)", ours, reference, again.size(), q)
        if conv == "dh" and model.length_unit == "m":
            # URDF -> dh -> URDF -> dh returns the same table, limits included
            first = to_table(again, "dh")
            second_path = tmp_path / "again.urdf"
            second_path.write_text(table_to_urdf(first)[0])
            second = to_table(load(str(second_path)), "dh")
            close_tables(first, second, again.size())
            assert [(r.lower, r.upper) for r in second.rows] == [
                (j.lower, j.upper) for j in model.joints
            ]


def test_rpy_round_trip_including_gimbal_lock():
    from urdf2dh.geometry import se3

    rng = np.random.default_rng(9)
    angles = [rng.uniform(-math.pi, math.pi, 3) for _ in range(200)]
    angles += [np.array([0.3, s * math.pi / 2, -1.1]) for s in (1, -1)]
    for r, p, y in angles:
        m = (se3.rot_z(y) @ se3.rot_y(p) @ se3.rot_x(r))[:3, :3]
        r2, p2, y2 = rpy(m)
        back = (se3.rot_z(y2) @ se3.rot_y(p2) @ se3.rot_x(r2))[:3, :3]
        assert np.abs(back - m).max() < 1e-15


def test_identifiability_counts():
    # Wu 2019 eq. (23) and (22): PUMA actual has r = 2, h = 4
    ident = urdf2dh.info("puma560-actual").identifiable
    assert ident is not None
    assert (ident.maximum, ident.conventional) == (5 * 4 + 4 * 2 + 6 + 6, 4 * 6 + 6)
    ident = urdf2dh.info("stanford").identifiable  # 5 revolute, 1 prismatic
    assert ident is not None
    assert (ident.maximum, ident.conventional) == (4 * 5 + 2 + 6 + 6, 4 * 5 + 2 + 6)
    assert (BASE, TOOL) == (4, 2)


def test_table_file_errors(tmp_path, capsys):
    good = json.loads(_convert_json(capsys, "ur5"))
    cases = {
        "schema": ({**good, "schema": "other/2"}, "not a table file"),
        "params": (
            {**good, "joints": [{**good["joints"][0], "params": {"theta": 0}}]},
            "params must be exactly",
        ),
        "matrix": (
            {
                **good,
                "base": {**good["base"], "matrix": np.eye(4).tolist()}
                | {"params": {**good["base"]["params"], "d": 1.0}},
            },
            "matrix disagrees with params",
        ),
        "pitch": (
            {**good, "joints": [{**good["joints"][0], "pitch": 0.1}]},
            "type revolute contradicts pitch",
        ),
    }
    for name, (tree, message) in cases.items():
        path = tmp_path / f"{name}.json"
        path.write_text(json.dumps(tree))
        assert main(["convert", str(path)]) == 2, name
        assert message in capsys.readouterr().err, name


def _convert_json(capsys, robot):
    assert main(["convert", robot, "--format", "json"]) == 0
    return capsys.readouterr().out
