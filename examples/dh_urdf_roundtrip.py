"""D-H table -> URDF -> Pinocchio -> D-H: a textbook table becomes a URDF that moves exactly
like it, and reading that URDF back gives the same table.

    python examples/dh_urdf_roundtrip.py [OUT.urdf]

The table is Universal Robots' published UR5 table, typed in as a table file
(docs/formats/table-file.md). Its
forward kinematics is evaluated here straight from the D-H formula, independently of urdf2dh,
and compared with Pinocchio's on the written URDF.
"""

from __future__ import annotations

import json
import math
import sys
import tempfile
from pathlib import Path

import numpy as np

from urdf2dh import load, render, to_table
from urdf2dh.check.verify import pinocchio_fk
from urdf2dh.io.sources import open_source

# Universal Robots UR5: (theta, d, alpha, a); theta offsets 0
UR5 = [
    (0, 0.089159, math.pi / 2, 0),
    (0, 0, 0, -0.425),
    (0, 0, 0, -0.39225),
    (0, 0.10915, math.pi / 2, 0),
    (0, 0.09465, -math.pi / 2, 0),
    (0, 0.0823, 0, 0),
]


def dh(theta: float, d: float, alpha: float, a: float) -> np.ndarray:
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array(
        [
            [ct, -st * ca, st * sa, a * ct],
            [st, ct * ca, -ct * sa, a * st],
            [0, sa, ca, d],
            [0, 0, 0, 1.0],
        ]
    )


def textbook_fk(q: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    for (theta, d, alpha, a), qi in zip(UR5, q, strict=True):
        out = out @ dh(theta + qi, d, alpha, a)
    return out


def main() -> int:
    with tempfile.TemporaryDirectory() as work:  # removed afterwards, whatever happens
        return round_trip(Path(work))


def round_trip(work: Path) -> int:
    tree = {
        "schema": "urdf2dh/1",
        "convention": "dh",
        "robot": "ur5-textbook",
        "base_link": "base",
        "tip_link": "flange",
        "units": {"length": "m", "angle": "rad"},
        "base": {"params": {"theta": 0.0, "d": 0.0, "alpha": 0.0, "a": 0.0}},
        "joints": [
            {
                "name": f"joint{i + 1}",
                "type": "revolute",
                "pitch": 0.0,
                "scale": 1.0,
                "params": {"theta": t, "d": d, "alpha": al, "a": a},
                "limits": [-2 * math.pi, 2 * math.pi],
            }
            for i, (t, d, al, a) in enumerate(UR5)
        ],
        "tool": {"params": {"theta": 0.0, "d": 0.0}},
    }
    table_file = work / "ur5-textbook.json"
    table_file.write_text(json.dumps(tree))
    table = to_table(load(table_file), "dh")
    urdf_text = render(table, "urdf")
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else work / "ur5-textbook.urdf"
    out.write_text(urdf_text)
    print(f"wrote {out}")

    urdf = open_source(str(out))
    model = urdf.model()
    q = np.random.default_rng(5).uniform(-math.pi, math.pi, size=(500, 6))
    pin = pinocchio_fk(urdf, model, q)
    book = np.array([textbook_fk(qk) for qk in q])
    err = float(np.abs(pin - book).max())
    print(f"Pinocchio on the URDF vs the D-H formula, 500 configurations: max |dT| = {err:.2g}")

    again = to_table(model, "dh", style="ur")
    worst = max(
        abs(getattr(r.params, k) - p[i])
        for r, p in zip(again.rows, UR5, strict=True)
        for i, k in enumerate(("theta", "d", "alpha", "a"))
    )
    print(f"URDF -> dh (--style ur) vs the typed table: max parameter difference {worst:.2g}")
    limits = [(r.lower, r.upper) for r in again.rows]
    print(f"joint limits carried through: {limits[0]}")
    ok = err < 1e-12 and worst < 1e-12 and limits[0] == (-2 * math.pi, 2 * math.pi)
    print("round trip exact" if ok else "round trip NOT exact")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
