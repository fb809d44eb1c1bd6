"""Published kinematics recovered from the models: Universal Robots' UR5 D-H table, Franka's
Panda table, and Wu, Crawford & Roberts 2019 Table II (PUMA 560) cell by cell."""

from __future__ import annotations

import math

import pytest

from urdf2dh.convert import to_table
from urdf2dh.sources import open_source


def test_ur5_recovers_universal_robots_geometry():
    # Universal Robots, "DH parameters for calculations of kinematics and dynamics" (UR5):
    # d1 0.089159, a2 -0.425, a3 -0.39225, d4 0.10915, d5 0.09465, d6 0.0823,
    # alpha pi/2, 0, 0, pi/2, -pi/2, 0.
    table = to_table(open_source("ur5").model(), "dh")
    rows = [r.params for r in table.rows]
    d = [abs(r["d"]) for r in rows]
    a = [abs(r["a"]) for r in rows]
    alpha = [abs(math.degrees(r["alpha"])) for r in rows]
    assert d == pytest.approx([0.089159, 0, 0, 0.10915, 0.09465, 0.0823], abs=1e-12)
    assert a == pytest.approx([0, 0.425, 0.39225, 0, 0, 0], abs=1e-12)
    assert alpha == pytest.approx([90, 0, 0, 90, 90, 0], abs=1e-9)
    assert table.tool["d"] == pytest.approx(0.0, abs=1e-12)
    assert table.warnings == ()


def test_panda_recovers_franka_geometry():
    # Franka Emika, "Robot and interface specifications", Denavit-Hartenberg parameters (Craig):
    # d1 0.333, d3 0.316, a4 0.0825, a5 -0.0825, d5 0.384, a7 0.088, flange d 0.107.
    table = to_table(open_source("panda").model(), "mdh")
    rows = [r.params for r in table.rows]
    assert [abs(r["d"]) for r in rows] == pytest.approx([0.333, 0, 0.316, 0, 0.384, 0, 0.107],
                                                        abs=1e-12)
    assert [abs(r["a"]) for r in rows] == pytest.approx([0, 0, 0, 0.0825, 0.0825, 0, 0.088],
                                                        abs=1e-12)
    assert [abs(math.degrees(r["alpha"])) for r in rows] == pytest.approx(
        [0, 90, 90, 90, 90, 90, 90], abs=1e-9)


# Wu, Crawford & Roberts, ICRA 2019, Table II: theta(deg), d(mm), alpha(deg), a(mm), h(mm/deg),
# q_bar for B->0, 0->1 ... 5->6 and (theta, d) for 6->T, as printed.
TABLE_II = {
    "puma560-nominal": {
        "base": (0, 0, 0, 0),
        "rows": [
            (0, 0, 90, 0, 0, 1),
            (0, 0, 0, 100, 0, 1),
            (0, -50, 90, 150, 0, 1),
            (180, 20, 90, 0, 0, 1),
            (180, 0, 90, 0, 0, 1),
            (0, 0, 180, 0, 0, 1),
        ],
        "tool": (0, 0),
    },
    "puma560-actual": {
        "base": ("63.4349", "1.0000", "2.5632", "0"),
        "rows": [
            ("116.5421", "-1.0214", "-88.8540", "0.0092", "0", "1.0000005"),
            ("-88.0290", "-567.6554", "10.2538", "0.5114", "0", "1.00002"),
            ("-86.0527", "552.7518", "90.0434", "153.3035", "0.0014", "0.99997"),
            ("-169.8271", "30.1922", "90.7413", "1.8365", "-0.0000009", "1.000008"),
            ("-178.0999", "-0.7927", "91.7710", "3.1761", "0.00000001", "1.00004"),
            ("82.8018", "-37.0573", "175.0748", "-0.7202", "0.0502", "1.000005"),
        ],
        "tool": ("83.1872", "-35.4328"),
    },
}


def _decimals(printed) -> int:
    text = str(printed)
    return len(text.split(".")[1]) if "." in text else 0


def _matches(value: float, printed) -> bool:
    """``value`` rounded to the printed number of decimals equals the printed cell."""
    k = _decimals(printed)
    return round(value, k) == round(float(printed), k) or (
        abs(value - float(printed)) <= 0.5 * 10.0**-k + 1e-12
    )


@pytest.mark.parametrize("robot", sorted(TABLE_II))
def test_wu2019_table_ii_cell_by_cell(robot):
    expected = TABLE_II[robot]
    table = to_table(open_source(robot).model(), "dh")
    cells = []

    def dh(p):
        return (math.degrees(p["theta"]), p["d"], math.degrees(p["alpha"]), p["a"])

    cells += list(zip(("B theta", "B d", "B alpha", "B a"), dh(table.base), expected["base"],
                      strict=True))
    for i, (row, exp) in enumerate(zip(table.rows, expected["rows"], strict=True)):
        h_per_degree = row.pitch * math.pi / 180.0
        got = (*dh(row.params), h_per_degree, row.scale)
        names = [f"{i}H{i + 1} {c}" for c in ("theta", "d", "alpha", "a", "h", "q_bar")]
        cells += list(zip(names, got, exp, strict=True))
    cells += [("6HT theta", math.degrees(table.tool["theta"]), expected["tool"][0]),
              ("6HT d", table.tool["d"], expected["tool"][1])]
    wrong = [(n, g, e) for n, g, e in cells if not _matches(g, e)]
    assert not wrong, wrong
    assert len(cells) == 4 + 6 * 6 + 2


# Universal Robots' published D-H parameters (support article "DH parameters for calculations of
# kinematics and dynamics"): (d, a, alpha) per joint, theta offsets all 0.
UR_TABLES = {
    "ur3": [(0.1519, 0, math.pi / 2), (0, -0.24365, 0), (0, -0.21325, 0),
            (0.11235, 0, math.pi / 2), (0.08535, 0, -math.pi / 2), (0.0819, 0, 0)],
    "ur5": [(0.089159, 0, math.pi / 2), (0, -0.425, 0), (0, -0.39225, 0),
            (0.10915, 0, math.pi / 2), (0.09465, 0, -math.pi / 2), (0.0823, 0, 0)],
    "ur10": [(0.1273, 0, math.pi / 2), (0, -0.612, 0), (0, -0.5723, 0),
             (0.163941, 0, math.pi / 2), (0.1157, 0, -math.pi / 2), (0.0922, 0, 0)],
}


@pytest.mark.parametrize("robot", sorted(UR_TABLES))
def test_style_ur_prints_universal_robots_own_table(robot):
    model = open_source(robot).model()
    table = to_table(model, "dh", style="ur")
    for row, (d, a, alpha) in zip(table.rows, UR_TABLES[robot], strict=True):
        p = row.params
        assert abs(p["theta"]) < 1e-11  # zero offsets (up to the URDF's rounded pi/2)
        assert (p["d"], p["a"], p["alpha"]) == pytest.approx((d, a, alpha), abs=1e-11)
    # base_link is UR's "base" frame turned by pi about z
    assert table.base["theta"] == pytest.approx(math.pi)
    assert table.check.max_position_error < 1e-12 * model.size()
    wu = to_table(model, "dh")
    # the default keeps a >= 0 (intersecting axes keep their exact, round-off sized a)
    assert all(r.params["a"] >= -1e-15 for r in wu.rows)
    assert sum(r.params["a"] < -1e-15 for r in table.rows) == 2  # UR: a2, a3 < 0
