"""Ctrl-C at seeded moments of runs of several commands (tests/interrupting.py), judged.

    python scripts/interrupt_corpus.py [--runs 20] [--seed 18]

Each command writes existing files (holding "old"); SIGINT is sent at ``--runs`` moments drawn
uniformly over 1.2 times the command's own duration. Every run must end with 130 and every
output as it was, or complete (exit 0) with every output written before the signal. Exit status
1 if any run did otherwise.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this checkout's urdf2dh

from interrupting import OLD, interrupted_run, judge

from urdf2dh.cli import main as urdf2dh

ARM = Path(__file__).resolve().parents[1] / "tests" / "data" / "xacro" / "arm_description"
COMMANDS = {  # name -> (arguments, outputs)
    "convert": (["convert", "ur5", "-o", "out.txt"], ["out.txt"]),
    "export": (["export", "panda", "--to", "matlab", "-o", "out.m"], ["out.m"]),
    "convert xacro": (["convert", str(ARM / "urdf" / "arm.urdf.xacro"), "--package-path",
                       f"arm_description={ARM}", "--xacro-arg", "name:=a", "--xacro-arg",
                       "arm_type:=large", "--format", "json", "-o", "out.json"], ["out.json"]),
    "measure": (["measure", "puma560-actual", "--configs", "50", "--markers", "3",
                 "--marker-layout", "layout.csv", "-o", "m.csv"], ["m.csv", "layout.csv"]),
    "calibrate": (["calibrate", "puma560-nominal", "../poses.csv", "-o", "cal.txt", "--report",
                   "report.json"], ["cal.txt", "report.json"]),
}  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=20, help="moments per command (default 20)")
    parser.add_argument("--seed", type=int, default=18, help="seed of the moments (default 18)")
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    results: Counter[tuple[str, str]] = Counter()
    failures = []
    with tempfile.TemporaryDirectory(prefix="interrupt-") as tmp:
        poses = Path(tmp) / "poses.csv"
        assert urdf2dh(["measure", "puma560-actual", "--configs", "60", "-o", str(poses)]) == 0
        for name, (command, outputs) in COMMANDS.items():
            work = Path(tmp) / name.replace(" ", "-")
            work.mkdir()
            started = time.perf_counter()
            whole = interrupted_run(command, work, None)  # no signal: its duration
            duration = time.perf_counter() - started
            if whole.code != 0:
                print(f"{name}: does not run uninterrupted (exit {whole.code})")
                return 1
            for delay in np.sort(rng.uniform(0.0, 1.2 * duration, args.runs)):
                paths = [work / o for o in outputs]
                for p in paths:
                    p.write_text(OLD)
                try:
                    outcome = judge(interrupted_run(command, work, float(delay)), paths)
                except AssertionError as e:
                    outcome = "FAILED"
                    failures.append(f"{name} at {delay:.2f} s: {e}")
                    for left in work.glob(".*"):  # so that the next run is judged on its own
                        left.unlink()
                results[name, outcome] += 1
            print(f"{name:<14} {duration:5.2f} s: {results[name, 'interrupted']:>3} interrupted "
                  f"(130, outputs as they were), {results[name, 'before urdf2dh']:>2} while "
                  f"Python started, {results[name, 'completed']:>3} completed before the "
                  f"signal, {results[name, 'FAILED']} failed")  # fmt: skip
    if failures:
        print("\nFAILURES:")
        for f in failures:
            print(f"  {f}")
        return 1
    print("\nevery run: 130 with its outputs as they were, or complete before the signal")
    return 0


if __name__ == "__main__":
    sys.exit(main())
