"""``urdf2dh match TABLE SOURCE``: which table is this? What differs between a table written by
hand (a datasheet's, a paper's) and a robot's model, in words (docs/commands/match.md)."""

from __future__ import annotations

import argparse
import sys

from . import options
from .run import say

__all__ = ["EXAMPLE", "HELP", "NAME", "add_arguments", "run"]

NAME = "match"
HELP = "find how a hand-written D-H table differs from a robot's model"
EXAMPLE = "urdf2dh match ur5-dh ur5"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "table",
        metavar="TABLE",
        help="a table written by hand (CSV or YAML rows of theta, d, a, alpha), a table file, "
        "or a shipped reference (urdf2dh robots)",
    )
    options.add_chain(p)
    p.add_argument(
        "--convention",
        choices=("dh", "mdh"),
        default=None,
        help="TABLE's convention, where it does not say (default: found)",
    )
    p.add_argument(
        "--length-unit",
        metavar="UNIT",
        default=None,
        help="TABLE's length unit (m, mm, cm, in), where it does not say (default: found)",
    )
    p.add_argument(
        "--angle-unit",
        choices=("deg", "rad"),
        default=None,
        help="TABLE's angle unit, where it does not say (default: found)",
    )
    p.add_argument(
        "--samples",
        type=options.samples,
        default=200,
        metavar="N",
        help="configurations the residual is measured at (default %(default)s)",
    )
    p.add_argument(
        "--seed", type=options.seed, default=0, metavar="S", help="their seed (default 0)"
    )
    p.add_argument(
        "-o",
        "--output",
        metavar="FILE",
        help="write TABLE corrected: SOURCE's table in TABLE's convention and layout, as a "
        "table file (FILE.json: JSON, else YAML); only where TABLE matches",
    )
    options.add_tolerances(p)


def run(args: argparse.Namespace) -> int:
    from ..check.match import match
    from ..errors import ConversionError
    from ..io.files import check_outputs, write_output

    check_outputs([args.output])
    result = match(
        args.table,
        args.source,
        base=args.base,
        tip=args.tip,
        convention=args.convention,
        length_unit=args.length_unit,
        angle_unit=args.angle_unit,
        tol=options.tolerances(args),
        samples=args.samples,
        seed=args.seed,
        xacro=options.xacro_options(args),
    )
    for line in result.text().splitlines():
        say(line)
    if not result.matched:
        if args.output:
            print(f"urdf2dh: {args.output} not written: TABLE does not match", file=sys.stderr)
        return 1
    if args.output:
        if result.corrected is None:
            raise ConversionError(f"{args.output} not written: {'; '.join(result.notes)}")
        from ..emit.formats import render

        fmt = "json" if args.output.lower().endswith(".json") else "yaml"
        write_output(render(result.corrected, fmt), args.output)
    return 0
