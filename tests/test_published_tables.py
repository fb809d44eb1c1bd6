"""Published kinematics recovered from the models: Universal Robots' D-H tables, Franka's Panda
table, Wu, Crawford & Roberts 2019 Table II and Sumenkov's Table III (PUMA 560) cell by cell."""

from __future__ import annotations

import math

import pytest

from urdf2dh import load, to_table
from urdf2dh.check.papers import sumenkov_table3, wu2019_table2


def test_ur5_recovers_universal_robots_geometry():
    # Universal Robots, "DH parameters for calculations of kinematics and dynamics" (UR5):
    # d1 0.089159, a2 -0.425, a3 -0.39225, d4 0.10915, d5 0.09465, d6 0.0823,
    # alpha pi/2, 0, 0, pi/2, -pi/2, 0.
    table = to_table(load("ur5"), "dh")
    rows = [r.params.values() for r in table.rows]
    d = [abs(r["d"]) for r in rows]
    a = [abs(r["a"]) for r in rows]
    alpha = [abs(math.degrees(r["alpha"])) for r in rows]
    assert d == pytest.approx([0.089159, 0, 0, 0.10915, 0.09465, 0.0823], abs=1e-12)
    assert a == pytest.approx([0, 0.425, 0.39225, 0, 0, 0], abs=1e-12)
    assert alpha == pytest.approx([90, 0, 0, 90, 90, 0], abs=1e-9)
    assert table.tool.d == pytest.approx(0.0, abs=1e-12)
    assert table.warnings == ()


def test_panda_recovers_franka_geometry():
    # Franka Emika, "Robot and interface specifications", Denavit-Hartenberg parameters (Craig):
    # d1 0.333, d3 0.316, a4 0.0825, a5 -0.0825, d5 0.384, a7 0.088, flange d 0.107.
    table = to_table(load("panda"), "mdh")
    rows = [r.params.values() for r in table.rows]
    assert [abs(r["d"]) for r in rows] == pytest.approx(
        [0.333, 0, 0.316, 0, 0.384, 0, 0.107], abs=1e-12
    )
    assert [abs(r["a"]) for r in rows] == pytest.approx(
        [0, 0, 0, 0.0825, 0.0825, 0, 0.088], abs=1e-12
    )
    assert [abs(math.degrees(r["alpha"])) for r in rows] == pytest.approx(
        [0, 90, 90, 90, 90, 90, 90], abs=1e-9
    )


@pytest.mark.parametrize("robot", ["puma560-nominal", "puma560-actual"])
def test_wu2019_table_ii_cell_by_cell(robot):
    """Wu, Crawford & Roberts 2019, Table II (robots/wu2019-table2.yaml), every printed cell."""
    cells = wu2019_table2(robot)
    assert len(cells) == 4 + 6 * 6 + 2
    assert [c for c in cells if not c.ok] == []


def test_sumenkov_table_iii():
    """Sumenkov, Table III (robots/sumenkov-table3.yaml): what follows from which model."""
    printed_model = sumenkov_table3()
    rows = {c.row for c in printed_model}
    assert len(rows) == 7 and len(printed_model) == 49
    wrong = [(c.row, c.column) for c in printed_model if not c.ok]
    # rows V_0..V_3 agree to the printed digits; V_4 all but l_x (6.59245 vs 6.593)
    assert [w for w in wrong if w[0] in ("V_0", "V_1", "V_2", "V_3", "V_4")] == [("V_4", "l_x")]
    assert next(
        c for c in printed_model if (c.row, c.column) == ("V_4", "l_x")
    ).ours == pytest.approx(6.593, abs=6e-4)
    # rows V_5, V_6 do not follow from the printed joint 6 ...
    assert sum(w[0] in ("V_5", "V_6") for w in wrong) >= 8
    # ... but from joint 6 with w_x, w_y negated (Sumenkov's own printed h_6 = -2.874)
    corrected = sumenkov_table3(joint6_as_behind_rows_6_7=True)
    last = [c for c in corrected if c.row in ("V_5", "V_6")]
    off = [(c.row, c.column) for c in last if not c.ok]
    assert off == [("V_6", "l_y"), ("V_6", "l_z"), ("V_6", "beta")]
    assert all(abs(c.ours - float(c.printed)) < 1e-3 for c in last)


# Universal Robots' published D-H parameters (support article "DH parameters for calculations of
# kinematics and dynamics"): (d, a, alpha) per joint, theta offsets all 0.
UR_TABLES = {
    "ur3": [
        (0.1519, 0, math.pi / 2),
        (0, -0.24365, 0),
        (0, -0.21325, 0),
        (0.11235, 0, math.pi / 2),
        (0.08535, 0, -math.pi / 2),
        (0.0819, 0, 0),
    ],
    "ur5": [
        (0.089159, 0, math.pi / 2),
        (0, -0.425, 0),
        (0, -0.39225, 0),
        (0.10915, 0, math.pi / 2),
        (0.09465, 0, -math.pi / 2),
        (0.0823, 0, 0),
    ],
    "ur10": [
        (0.1273, 0, math.pi / 2),
        (0, -0.612, 0),
        (0, -0.5723, 0),
        (0.163941, 0, math.pi / 2),
        (0.1157, 0, -math.pi / 2),
        (0.0922, 0, 0),
    ],
}


@pytest.mark.parametrize("robot", sorted(UR_TABLES))
def test_style_ur_prints_universal_robots_own_table(robot):
    model = load(robot)
    table = to_table(model, "dh", style="ur")
    for row, (d, a, alpha) in zip(table.rows, UR_TABLES[robot], strict=True):
        p = row.params.values()
        assert abs(p["theta"]) < 1e-11  # zero offsets (up to the URDF's rounded pi/2)
        assert (p["d"], p["a"], p["alpha"]) == pytest.approx((d, a, alpha), abs=1e-11)
    # base_link is UR's "base" frame turned by pi about z
    assert table.base.theta == pytest.approx(math.pi)
    assert table.check.max_position_error < 1e-12 * model.size()
    wu = to_table(model, "dh")
    # the default keeps a >= 0 (intersecting axes keep their exact, round-off sized a)
    assert all(r.params.a >= -1e-15 for r in wu.rows)
    assert sum(r.params.a < -1e-15 for r in table.rows) == 2  # UR: a2, a3 < 0
