"""Reproduce Table II of Wu, Crawford & Roberts (ICRA 2019): the D-H parameterization of the
PUMA 560 from its nominal and actual POE models (their Table I), cell by cell.

    python examples/reproduce_table_ii.py

Prints each row as computed (in the paper's units: degrees, mm, mm/degree) and, under it, the
printed row; a cell that does not round to the printed value is marked. Exits 1 if any does.
"""

from __future__ import annotations

import sys
from itertools import groupby

from urdf2dh.check.papers import wu2019_table2


def main() -> int:
    failures = 0
    for robot in ("puma560-nominal", "puma560-actual"):
        cells = wu2019_table2(robot)
        print(f"{robot}: Table II, {len(cells)} cells")
        print(f"  {'':6} {'theta':>10} {'d':>10} {'alpha':>10} {'a':>10} {'h':>12} {'q_bar':>10}")
        for row, group in groupby(cells, key=lambda c: c.row):
            group = list(group)
            ours = " ".join(f"{c.ours:>{12 if c.column == 'h' else 10}.6g}" for c in group)
            printed = " ".join(f"{c.printed:>{12 if c.column == 'h' else 10}}" for c in group)
            marks = (
                ""
                if all(c.ok for c in group)
                else "   <- differs: " + ", ".join(c.column for c in group if not c.ok)
            )
            print(f"  {row:6} {ours}\n  {'paper':6} {printed}{marks}")
            failures += sum(not c.ok for c in group)
        print()
    print(
        "all cells agree with the printed table"
        if not failures
        else f"{failures} cells differ from the printed table"
    )
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
