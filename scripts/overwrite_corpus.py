"""Run the overwrite corpus (tests/overwrite_cases.py) and report the counts.

    python scripts/overwrite_corpus.py [--verbose]

Every command with every input it reads named as one of its outputs (as given, ``./``,
absolute, a symbolic link, a hard link, through a linked directory; ``-o``, ``--report``,
``--marker-layout``, a file of ``-o DIR``), two outputs of a run naming one file, and the second
output of a run failing at its rename or its temporary file. Exit status 1 if any case failed.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this checkout's urdf2dh

from overwrite_cases import FAILURES, Workspace, cases, run_case


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--verbose", action="store_true", help="one line per case")
    args = parser.parse_args(argv)
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="overwrite-") as tmp:
        ws = Workspace(Path(tmp))
        verdicts = []
        for case in cases(ws):
            verdict = run_case(ws, case)
            verdicts.append(verdict)
            if args.verbose:
                print(f"{case.n:>4} {verdict.result:<10} {' '.join(case.argv)[:100]}")
    seconds = time.perf_counter() - started
    print(f"{len(verdicts)} overwrite cases in {seconds:.0f} s")
    for kind in dict.fromkeys(v.case.kind for v in verdicts):
        c = Counter(v.result for v in verdicts if v.case.kind == kind)
        print(f"  {kind:<16} " + ", ".join(f"{n} {r}" for r, n in c.items()))
    print("\nby command (cases, refused):")
    for command in dict.fromkeys(v.case.argv[0] for v in verdicts):
        mine = [v for v in verdicts if v.case.argv[0] == command]
        print(f"  {command:<10} {len(mine):>4} {sum(v.result == 'refused' for v in mine):>4}")
    results = Counter(v.result for v in verdicts)
    print()
    for result in FAILURES:
        print(f"  {result:<18} {results[result]}")
    bad = [v for v in verdicts if v.result in FAILURES]
    if bad:
        print("\nFAILURES:")
        for v in bad:
            print(f"  case {v.case.n} ({v.case.detail}) {' '.join(v.case.argv)}: {v.result}: "
                  f"{v.detail}")  # fmt: skip
        return 1
    print("\n0 inputs overwritten, 0 half-written outputs, 0 internal errors; every case refused")
    return 0


if __name__ == "__main__":
    sys.exit(main())
