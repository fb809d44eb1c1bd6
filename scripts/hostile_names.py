"""Run the hostile-name corpus through every export target and format and report the counts.

    PYTHONPATH=. python scripts/hostile_names.py [--robots 200] [--start 0] [--verbose]

Robot ``seed`` (tests/corpus.py) is a real chain whose robot, link, joint and file names are
drawn, seeded, from characters and snippets that end strings, comments and lines (quotes,
``\"\"\"``, backslash, LF, CR, U+2028, ``%``, ``#``, ``;``, ``--``, ``]]>``, ``${}``, HAL and
MATLAB payloads, control characters in POE files, invisible characters: bidi controls,
zero-width characters, BOM, soft hyphen, tag characters; spreadsheet formula starts). Then the
robots named as the writers name what they make up (tests/hostile.py's ``COLLIDING``: MATLAB's
``body2``, ``dh_base_fixed``, ``tool_fixed``, KDL's segments, the URDF writer's links), each as
a URDF, as MJCF and as POE files. Every run of ``urdf2dh export``/``convert``
is written and safe (its file reads, in its language, as its clean twin's with the names put
in), or refused (exit 2, one line); anything else is a failure, listed, and the exit status is
1. The test suite runs a sample of the same robots (tests/test_hostile_names.py).
"""

from __future__ import annotations

import argparse
import re
import sys
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from corpus import FAILURES, Corpus, Verdict
from hostile import COLLIDING, KINDS


def _reason(v: Verdict) -> str:
    """A refusal's message without the names in it."""
    text = v.detail.removeprefix("urdf2dh: error: ")
    text = re.sub(r"(?<!\w)(?:'(?:[^'\\]|\\.)*'|\"(?:[^\"\\]|\\.)*\")", "NAME", text)
    return re.sub(r"NAME\.\.\. \(\d+ characters\)", "NAME", text)[:110]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robots", type=int, default=200, help="how many (default 200)")
    parser.add_argument("--start", type=int, default=0, help="first seed (default 0)")
    parser.add_argument("--verbose", action="store_true", help="one line per robot")
    args = parser.parse_args(argv)
    corpus = Corpus()
    verdicts: list[Verdict] = []
    started = time.perf_counter()
    try:
        for seed in range(args.start, args.start + args.robots):
            got = corpus.robot(seed)
            verdicts += got
            if args.verbose:
                print(f"robot {seed} ({got[0].kind}): {dict(Counter(v.result for v in got))}")
        for i, names in enumerate(COLLIDING):
            for kind in KINDS:
                got = corpus.check(names, "genser6", kind, seed=-1 - i)
                verdicts += got
                if args.verbose:
                    print(f"colliding {i} ({kind}): {dict(Counter(v.result for v in got))}")
    finally:
        corpus.close()
    seconds = time.perf_counter() - started
    results = Counter(v.result for v in verdicts)
    kinds = Counter(v.kind for v in {v.seed: v for v in verdicts if v.seed >= 0}.values())
    print(
        f"{args.robots} hostile robots ({', '.join(f'{n} {k}' for k, n in kinds.items())}) and "
        f"{len(COLLIDING)} colliding ones x {len(KINDS)} kinds, {len(verdicts)} runs in "
        f"{seconds:.0f} s"
    )
    for result in ("written", "refused", *FAILURES):
        print(f"  {result:<15} {results[result]}")
    print("\nper target / format (written, refused):")
    for run in dict.fromkeys(v.run for v in verdicts):
        c = Counter(v.result for v in verdicts if v.run == run)
        print(
            f"  {run:<22} {c['written']:>5} {c['refused']:>5}"
            + "".join(f"  {k} {c[k]}" for k in FAILURES if c[k])
        )
    print("\nrefusals:")
    for (run, reason), n in Counter(
        (v.run, _reason(v)) for v in verdicts if v.result == "refused"
    ).most_common():
        print(f"  {n:>5}  {run}: {reason}")
    failures = [v for v in verdicts if v.result in FAILURES]
    if failures:
        print("\nFAILURES:")
        for v in failures:
            print(f"  robot {v.seed} ({v.kind}) {v.run}: {v.result}: {v.detail[:400]!r}")
        return 1
    print("\nno tracebacks, no internal errors, no unsafe exports; every refusal one line, exit 2")
    return 0


if __name__ == "__main__":
    sys.exit(main())
