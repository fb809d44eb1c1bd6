"""The seed papers' published tables, cell by cell against our conversions.

Reference data live in ``robots/wu2019-table2.yaml`` and ``robots/sumenkov-table3.yaml`` with
their provenance. A cell *agrees* when our value rounds to the printed one: it is within half a
unit of the printed number's last digit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..conventions import Params
from ..conventions.convert import to_table
from ..io.catalog import our_robots_dir
from ..io.sources import open_source
from ..model.poe import joint_from_twist
from ..tolerances import DEFAULT

__all__ = ["Cell", "agrees", "sumenkov_table3", "wu2019_table2"]


@dataclass(frozen=True, slots=True)
class Cell:
    """One published cell: where it is, our value (in the paper's units) and the printed text."""

    row: str
    column: str
    ours: float
    printed: str

    @property
    def ok(self) -> bool:
        return agrees(self.ours, self.printed)


def agrees(value: float, printed: str) -> bool:
    """``value`` rounds to ``printed`` (within half a unit of its last digit)."""
    decimals = len(printed.split(".")[1]) if "." in printed else 0
    return abs(value - float(printed)) <= 0.5 * 10.0**-decimals + 1e-12


def _reference(name: str) -> Any:
    from ..io.mappings import read_mapping

    path = our_robots_dir() / name
    return read_mapping(path, name, path.read_bytes())


def wu2019_table2(robot: str) -> list[Cell]:
    """Wu 2019 Table II for ``puma560-nominal`` or ``puma560-actual``: 42 cells each."""
    ref = _reference("wu2019-table2.yaml")[robot]
    table = to_table(open_source(robot).model(), "dh")

    def dh(p: Params) -> list[float]:
        v = p.scalars()
        return [math.degrees(v["theta"]), v["d"], math.degrees(v["alpha"]), v["a"]]

    cells = [
        Cell("B->0", c, v, s)
        for c, v, s in zip(("theta", "d", "alpha", "a"), dh(table.base), ref["base"], strict=True)
    ]
    for i, (row, printed) in enumerate(zip(table.rows, ref["rows"], strict=True)):
        ours = [*dh(row.params), row.pitch * math.pi / 180.0, row.scale]
        cols = ("theta", "d", "alpha", "a", "h", "q_bar")
        cells += [
            Cell(f"{i}->{i + 1}", c, v, s) for c, v, s in zip(cols, ours, printed, strict=True)
        ]
    t = table.tool.scalars()
    tool = [math.degrees(t["theta"]), t["d"]]
    cells += [
        Cell("6->T", c, v, s) for c, v, s in zip(("theta", "d"), tool, ref["tool"], strict=True)
    ]
    return cells


def sumenkov_table3(joint6_as_behind_rows_6_7: bool = False) -> list[Cell]:
    """Sumenkov's Table III (CPC of the actual PUMA 560): 7 rows of ``b``, ``l``, ``beta``.

    With ``joint6_as_behind_rows_6_7`` joint 6's twist is replaced by the one that the printed
    rows 6-7 follow from (see the reference file); otherwise the model is used as printed.
    """
    ref = _reference("sumenkov-table3.yaml")
    model = open_source("puma560-actual").model()
    if joint6_as_behind_rows_6_7:
        xi = np.array(ref["joint6_twist_behind_rows_6_7"], dtype=float)
        joints = (*model.joints[:5], joint_from_twist("j6", xi, DEFAULT.noise))
        model = replace(model, joints=joints, warnings=())
    table = to_table(model, "cpc")
    cells = []
    for k, (params, printed) in enumerate(
        zip([table.base, *(r.params for r in table.rows)], ref["rows"], strict=True)
    ):
        v = params.vectors()
        ours = [*v["b"], *v["l"], params.scalars()["beta"]]
        text = [*printed["b"], *printed["l"], printed["beta"]]
        cols = ("b_x", "b_y", "b_z", "l_x", "l_y", "l_z", "beta")
        cells += [Cell(f"V_{k}", c, v, s) for c, v, s in zip(cols, ours, text, strict=True)]
    return cells
