"""The property tests of tests/test_properties.py under a seeded random search (the suite runs
them derandomized, 120 examples each): how many examples fail, out of how many.

    PYTHONPATH=. python scripts/property_search.py idempotent --examples 4000 --seeds 0,1,2,3,4

(``file-idempotent``: the same through the table file, tests/test_table_size.py.)

Each example is checked as the test checks it, and a failure is counted and the search goes on
(no shrinking), so the count is a failure rate. The failing chains are printed as the test's
assertion reports them. Hypothesis draws some constants from the modules imported, so the
examples of a seed depend on the code too.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from hypothesis import HealthCheck, Phase, given, seed, settings
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

import test_properties as props  # noqa: E402

from urdf2dh import CONVENTIONS  # noqa: E402


def _file_round_trip() -> Any:
    """tests/test_table_size.py's idempotence through the table file, imported only when asked
    for: its imports (the file readers, jsonschema) change the examples the others draw."""
    import test_table_size

    return test_table_size.test_a_table_read_back_from_its_file_converts_again_to_itself


PAIR = (st.sampled_from(CONVENTIONS), st.sampled_from(CONVENTIONS))
# name -> (the test, given on use; the strategies drawn beside the chain)
PROPERTIES: dict[str, tuple[Callable[[], Any], tuple[Any, ...]]] = {
    "every-convention": (lambda: props.test_every_convention_moves_like_the_poe_model, ()),
    "idempotent": (lambda: props.test_convention_to_poe_to_convention_is_idempotent, ()),
    "any-to-other": (lambda: props.test_any_convention_to_any_other, PAIR),
    "file-idempotent": (_file_round_trip, ()),
}


def search(name: str, examples: int, seeds: list[int]) -> tuple[int, list[str]]:
    """The examples run and each failure's assertion, over ``seeds``."""
    test, extra = PROPERTIES[name]
    inner: Callable[..., None] = test().hypothesis.inner_test
    count, failures = 0, []

    def check(*args: Any) -> None:
        nonlocal count
        count += 1
        try:
            inner(*args)
        except AssertionError as e:
            failures.append(repr(e)[:300])

    def one(model: Any) -> None:
        check(model)

    def three(model: Any, first: str, second: str) -> None:
        check(model, first, second)

    for s in seeds:
        run = settings(
            derandomize=False,
            max_examples=examples,
            deadline=None,
            database=None,
            phases=[Phase.generate],
            suppress_health_check=list(HealthCheck),
        )(seed(s)(given(props.chains(), *extra)(three if extra else one)))
        run()
    return count, failures


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("property", choices=sorted(PROPERTIES))
    parser.add_argument("--examples", type=int, default=4000, help="per seed (default 4000)")
    parser.add_argument("--seeds", default="0,1,2,3,4", help="comma-separated (default 0-4)")
    args = parser.parse_args()
    seeds = [int(s) for s in args.seeds.split(",")]
    count, failures = search(args.property, args.examples, seeds)
    for f in failures:
        print(f"  {f}")
    print(f"{args.property}: {len(failures)} failures in {count} examples (seeds {args.seeds})")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
