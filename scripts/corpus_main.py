"""The command line every seeded corpus script shares: ``--count`` cases from ``--seed``, the
report printed, exit status 1 if any case broke an invariant."""

from __future__ import annotations

import argparse
from collections.abc import Callable, Sequence
from typing import Any


def corpus_main(
    doc: str,
    run_corpus: Callable[[int, int], Sequence[Any]],
    report: Callable[[Any], str],
    count: int,
    argv: list[str] | None = None,
) -> int:
    """Parse ``--count`` (default ``count``) and ``--seed`` (default 0), run the corpus, print
    its report; 1 if an outcome has problems, else 0."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--count", type=int, default=count, help="cases (default %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="seed (default %(default)s)")
    args = parser.parse_args(argv)
    outcomes = run_corpus(args.count, args.seed)
    print(report(list(outcomes)))
    return 1 if any(o.problems for o in outcomes) else 0
