"""``urdf2dh verify``: every convention's forward kinematics against Pinocchio's, on a chain (or
on several)."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from . import options
from .chains import one_tip, several_of
from .run import say

if TYPE_CHECKING:
    from ..io.sources import Source
    from ..model.poe import PoeModel
    from ..tolerances import Tolerances

NAME = "verify"
HELP = "compare every convention's FK with Pinocchio's"


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
    options.add_tolerances(p)


def run(args: argparse.Namespace) -> int:
    tol = options.tolerances(args)
    source = options.source(args, tol)
    if not several_of(args):
        model = source.model(args.base, one_tip(args), args.ignore_mimic)
        if _verify_chain(args, source, model, tol):
            say("verify: all conventions agree with Pinocchio")
            return 0
        return 1
    from ..errors import shown
    from .chains import TipError, chains_of, naming_tip, per_chain

    models = chains_of(args, source)
    failed = []
    for i, model in enumerate(per_chain(models, "verify")):
        if i:
            say()
        try:
            with naming_tip(model.tip_link):
                ok = _verify_chain(args, source, model, tol)
        except TipError as e:
            if e.exit_code != 1:
                raise
            print(f"verify: {e}", file=sys.stderr)  # a table failed its own check: go on
            ok = False
        if not ok:
            failed.append(model.tip_link)
    if failed:
        print(
            f"verify: FAILED on {len(failed)} of {len(models)} chains: "
            f"{', '.join(shown(t) for t in failed)}",
            file=sys.stderr,
        )
        return 1
    say(f"verify: all conventions agree with Pinocchio on all {len(models)} chains")
    return 0


def _verify_chain(
    args: argparse.Namespace, source: Source, model: PoeModel, tol: Tolerances
) -> bool:
    """Verify one chain and print its report; whether every model agrees with Pinocchio."""
    from ..check.verify import verify
    from ..errors import visible as v

    results = verify(source, model, args.samples, args.seed, tol, check_samples=args.check_samples)
    unit, size = v(model.length_unit), model.size()
    chain = f"{v(model.base_link)} -> {v(model.tip_link)}, " if model.base_link else ""
    say(
        f"{v(source.name)}: {chain}{model.n} joints; against Pinocchio at {args.samples} "
        f"configurations (seed {args.seed}); robot size {size:.4g} {unit}"
    )
    say(f"  {'model':<10} {'position error':>16} {'relative':>10} {'rotation error':>16}  result")
    for r in results:
        say(
            f"  {r.label:<10} {r.position:>13.2e} {unit:<2} {r.position / size:>10.2e} "
            f"{r.rotation:>12.2e} rad  {'ok' if r.ok else 'FAILED'}"
        )
    for r in results:
        for w in r.table.warnings if r.table is not None else ():
            say(f"  warning: {v(w)}")
    failed = [r.label for r in results if not r.ok]
    if failed:
        where = f" on {chain[:-2]}" if chain and several_of(args) else ""
        print(
            f"verify: FAILED{where} for {', '.join(failed)} (allowed "
            f"{results[0].allowed_position:.2g} {unit} + declared deviations)",
            file=sys.stderr,
        )
        return False
    return True
