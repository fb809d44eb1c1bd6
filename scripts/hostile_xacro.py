"""Run the hostile xacro corpus (tests/xacro_corpus.py) and report the counts.

    python scripts/hostile_xacro.py [--verbose]

Every attack (sandbox escapes, fork bombs, background processes, private attributes, floods,
endless and huge expressions) in every place of a xacro document (link name, property, macro
argument, condition, included file, YAML unit tag), each expanded by the urdf2dh program in a
working directory and a ``PYTHONPATH`` full of planted modules. Once all have run, and the
background processes of any attack that got through would have written their markers, the
markers and the processes are looked for again. Exit status 1 if any case failed.
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

from xacro_corpus import FAILURES, LATE, Verdict, cases, failed, judge, markers, run_case, survivors


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--verbose", action="store_true", help="one line per case")
    args = parser.parse_args(argv)
    verdicts: list[Verdict] = []
    tokens: list[str] = []
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="hostile-xacro-") as tmp:
        for c in cases():
            directory = Path(tmp) / f"case{c.seed}"
            directory.mkdir()
            proc, token, t0 = run_case(c, directory)
            verdict = judge(c, directory, proc, t0)
            verdicts.append(verdict)
            tokens.append(token)
            if args.verbose:
                print(f"{c.seed:>4} {c.attack:<22} {c.place:<15} {verdict.result:<10} "
                      f"{verdict.seconds:5.2f} s {verdict.max_rss / 2**20:5.0f} MiB")  # fmt: skip
        time.sleep(LATE + 1.0)  # the background processes of an attack that ran would write now
        late = {v.case.seed: markers(Path(tmp) / f"case{v.case.seed}") for v in verdicts}
        alive = [t for t in tokens if survivors(t)]
    seconds = time.perf_counter() - started
    results = Counter(v.result for v in verdicts)
    attacks, places = len({v.case.attack for v in verdicts}), len({v.case.place for v in verdicts})
    print(
        f"{len(verdicts)} hostile xacro cases ({attacks} attacks x {places} places), "
        f"{seconds:.0f} s"
    )
    for result in ("refused", "expanded", *FAILURES):
        print(f"  {result:<16} {results[result]}")
    ran = sorted(seed for seed, found in late.items() if found)
    print(f"  markers after {LATE + 1.0:g} s: {len(ran)} cases; processes left: {len(alive)}")
    print(
        f"  largest urdf2dh: {max(v.max_rss for v in verdicts) / 2**20:.0f} MiB resident; "
        f"longest run {max(v.seconds for v in verdicts):.1f} s"
    )
    print("\nrefusals by attack:")
    for attack, n in Counter(v.case.attack for v in verdicts if v.result == "refused").items():
        reason = next(
            v.detail for v in verdicts if v.case.attack == attack and v.result == "refused"
        )
        print(f"  {n:>3}  {attack}: {reason.split(': ', 2)[-1][:90]}")
    bad = [v for v in verdicts if failed(v)]
    if bad or ran or alive:
        print("\nFAILURES:")
        for v in bad:
            print(f"  case {v.case.seed} {v.case.attack} / {v.case.place}: {v.result}: {v.detail}")
        for seed in ran:
            print(f"  case {seed}: markers {late[seed]}")
        for token in alive:
            print(f"  processes left: {token}")
        return 1
    print("\n0 code execution, 0 processes left, 0 internal errors; every attack refused, one line")
    return 0


if __name__ == "__main__":
    sys.exit(main())
