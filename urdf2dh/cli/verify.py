"""``urdf2dh verify``: every convention's forward kinematics against Pinocchio's or MuJoCo's (or
both), on a chain (or on several)."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from . import options
from .chains import one_tip, several_of
from .run import say

if TYPE_CHECKING:
    from ..io.sources import Source
    from ..tolerances import Tolerances

__all__ = ["EXAMPLE", "HELP", "NAME", "ORACLE_CHOICES", "add_arguments", "run"]

ORACLE_CHOICES = ("pinocchio", "mujoco", "both")  # urdf2dh.check.verify.ORACLE_CHOICES: --help
# imports no numpy

NAME = "verify"
HELP = "compare every convention's FK with Pinocchio's or MuJoCo's"
EXAMPLE = "urdf2dh verify panda --samples 200"


def add_arguments(p: argparse.ArgumentParser) -> None:
    options.add_chain(p, several=True)
    p.add_argument(
        "--samples",
        type=options.samples,
        default=1000,
        metavar="N",
        help="random configurations within joint limits (default %(default)s)",
    )
    p.add_argument(
        "--seed",
        type=options.seed,
        default=0,
        metavar="S",
        help="random seed (default %(default)s)",
    )
    p.add_argument(
        "--oracle",
        choices=ORACLE_CHOICES,
        default="pinocchio",
        help="the forward kinematics to compare with: Pinocchio's, MuJoCo's, or both (with "
        "both, an oracle that cannot judge the chain says why and leaves it to the other; "
        "default %(default)s)",
    )
    options.add_tolerances(p)


def run(args: argparse.Namespace) -> int:
    from ..check.verify import VERIFY_BOUND

    tol = options.tolerances(args)
    source = options.source(args, tol, VERIFY_BOUND)
    if not several_of(args):
        judged = _verify_chain(args, source, args.base, one_tip(args), tol)
        if judged:
            say(f"verify: all conventions agree with {judged}")
            return 0
        return 1
    from ..errors import shown
    from .chains import TipError, chains_of, naming_tip, per_chain

    models = chains_of(args, source)
    failed, judges = [], set()
    for i, model in enumerate(per_chain(models, "verify")):
        if i:
            say()
        try:
            with naming_tip(model.tip_link):
                judged = _verify_chain(args, source, model.base_link, model.tip_link, tol)
        except TipError as e:
            if e.exit_code != 1:
                raise
            print(f"verify: {e}", file=sys.stderr)  # a table failed its own check: go on
            judged = ""
        if not judged:
            failed.append(model.tip_link)
        judges.add(judged)
    if failed:
        print(
            f"verify: FAILED on {len(failed)} of {len(models)} chains: "
            f"{', '.join(shown(t) for t in failed)}",
            file=sys.stderr,
        )
        return 1
    who = judges.pop() if len(judges) == 1 else "the oracles that judged them"
    say(f"verify: all conventions agree with {who} on all {len(models)} chains")
    return 0


def _verify_chain(
    args: argparse.Namespace, source: Source, base: str | None, tip: str | None, tol: Tolerances
) -> str:
    """Verify one chain and print its report; the oracles every model agrees with (as the
    report names them), or ``""`` where one does not."""
    from ..check.verify import labels, verify
    from ..errors import visible

    report = verify(
        source, base, tip, args.ignore_mimic, samples=args.samples, seed=args.seed, tol=tol,
        check_samples=args.check_samples, oracle=args.oracle,
    )  # fmt: skip
    for line in report.lines():
        say(line)
    if report.ok:
        return labels(report.oracles)
    where = f" on {report.chain}" if report.chain and several_of(args) else ""
    print(
        f"verify: FAILED{where} for {', '.join(report.failed)} (allowed "
        f"{report.checks[0].allowed_position:.2g} {visible(report.length_unit)} + declared "
        "deviations)",
        file=sys.stderr,
    )
    return ""
