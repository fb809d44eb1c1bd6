"""The benchmark (benchmarks/run.py) runs in CI in its quick mode: it completes and prints every
figure beside its Pinocchio counterpart and their ratio. Speed is measured there, not asserted
here: no figure's value is checked, only that it was measured and reported consistently."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

from urdf2dh.conventions import NAMES

ROOT = Path(__file__).resolve().parents[1]
ROW = re.compile(
    r"^\| (?P<name>[^|]+) \| (?P<ours>\S+) (?P<u1>\S+) \| (?P<pin>\S+) (?P<u2>\S+) "
    r"\| (?P<ratio>\S+)x \| (?P<goal>[^|]*) \|$"
)
SECTIONS = (
    "Engine (one process)",
    "Whole command and start-up (new processes)",
    "Import times",
    "Chain length (random chains, in one process)",
    "Bounds (new processes)",
    "Batch forward kinematics",
    "verify",
    "match",
)


def test_quick_benchmark_reports_every_figure_with_pinocchio_and_ratio():
    proc = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "run.py"), "--quick"],
        capture_output=True,
        text=True,
        timeout=900,
        cwd=ROOT,
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    out = proc.stdout
    for title in SECTIONS:
        assert f"### {title}\n" in out, title
    rows = [m for m in map(ROW.match, out.splitlines()) if m]
    names = [m["name"] for m in rows]
    for expected in (
        "engine, self-check at 100",
        "engine, self-check at 1000",
        "from the parsed tree",
        "whole command, CPU: urdf2dh convert ur5 vs Pinocchio's import + build + FK",
        "whole command, wall: urdf2dh convert ur5",
        "whole command, CPU: urdf2dh convert panda --format json",
        "start-up, CPU: urdf2dh --help",
        "peak memory: urdf2dh convert ur5 vs Pinocchio's",
        "import urdf2dh.cli",
        "import yourdfpy",
        "10 joints",
        "200 joints",
        "batch FK: Table.fk_batch",
        "batch FK of the POE model",
        "verify panda at",
        "urdf2dh verify",
        "peak memory of the verify",
    ):
        assert any(n.startswith(expected) for n in names), (expected, names)
    for m in rows:
        ours, pin, ratio = float(m["ours"]), float(m["pin"]), float(m["ratio"])
        assert m["u1"] == m["u2"] and pin > 0, m.group(0)
        assert abs(ours / pin - ratio) <= 0.01 * abs(ratio) + 1e-3, m.group(0)  # 3 digits
        if m["goal"].strip():
            assert m["goal"].rstrip().endswith(("(met)", "(NOT met)")), m.group(0)
    # accuracy against chain length (ours and Pinocchio's, against an extended-precision FK),
    # and the batch FK's agreement with Pinocchio, are shown
    assert "Worst FK error at" in out and "extended-precision" in out and "log-log slope" in out
    header = next(line for line in out.splitlines() if line.startswith("| joints | size |"))
    assert header == (
        f"| joints | size | POE | {' | '.join(NAMES)} | rotation | Pinocchio | Pinocchio rotation |"
    )
    columns = header.count("|")
    table = out[out.index(header) :].split("\n\n")[0].splitlines()
    assert len(table) >= 5 and all(line.count("|") == columns for line in table), table
    assert re.search(r"Max difference of the poses: \S+ m", out)
    # the bounds: convert at the joint bound and verify of 1,000 joints, with the scaling
    bounds = out[out.index("### Bounds (new processes)") :].split("\n\n")[1]
    assert "convert (whole command) of random chains: 1,000 joints:" in bounds
    assert "10,000 joints:" in bounds and "log-log slope of time" in bounds
    assert "verify (whole command): 100 joints:" in bounds and "1,000 joints:" in bounds
    assert bounds.count("(met)") + bounds.count("(NOT met)") == 2
    assert "Goals met:" in out
