"""``urdf2dh diff NOMINAL ACTUAL``: two parameter sets side by side (calibration: nominal and
actual)."""

from __future__ import annotations

import argparse
import math

from ..io.files import write_output
from . import options

__all__ = ["EXAMPLE", "HELP", "NAME", "add_arguments", "run"]

NAME = "diff"
HELP = "compare two parameter sets (calibration: nominal vs actual)"
EXAMPLE = "urdf2dh diff puma560-nominal puma560-actual --convention cpc"


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..conventions import NAMES, STYLES
    from ..emit.formats import DIFF_FORMATS
    from ..io.sources import source_kinds
    from ..tolerances import DIFF_ANGLE_DEG, DIFF_LENGTH_M, DIFF_PARALLEL_DEG

    kinds = f"{source_kinds()} file, or bundled robot name"
    p.add_argument("nominal", metavar="NOMINAL", help=kinds)
    p.add_argument("actual", metavar="ACTUAL", help=kinds)
    options.add_chain_options(
        p,
        of=" of each source with a tree of links (URDF, xacro, MJCF); a POE or table file "
        "is one chain",
    )
    p.add_argument(
        "--convention",
        choices=NAMES,
        default=NAMES[0],
        help="convention to compare in (default %(default)s)",
    )
    p.add_argument("--style", choices=STYLES, default="wu", help="D-H choices (see convert)")
    p.add_argument(
        "--angle-threshold",
        type=options.nonnegative_float,
        default=DIFF_ANGLE_DEG,
        metavar="DEG",
        help="mark angle changes over this, modulo 180 (default %(default)g; Wu 2019 "
        "Table II's marks: 60)",
    )
    p.add_argument(
        "--length-threshold",
        type=options.nonnegative_float,
        metavar="LENGTH",
        help=f"mark length changes over this, in the tables' unit (default {DIFF_LENGTH_M * 1e3:g} "
        "mm; Wu 2019 Table II's marks: 30 mm)",
    )
    p.add_argument(
        "--parallel-within",
        type=options.nonnegative_float,
        default=DIFF_PARALLEL_DEG,
        metavar="DEG",
        help="name axis pairs this close to parallel in either model as "
        "ill-conditioned for D-H (default %(default)g)",
    )
    options.add_format(p, DIFF_FORMATS)
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    options.add_tolerances(p)


def run(args: argparse.Namespace) -> int:
    from ..check.diff import diff
    from ..emit.formats import DIFF_FORMATS

    args.format = options.output_format(args, DIFF_FORMATS)  # before anything is read
    result = diff(
        args.nominal,
        args.actual,
        args.convention,
        style=args.style,
        tol=options.tolerances(args),
        angle_threshold=math.radians(args.angle_threshold),
        length_threshold=args.length_threshold,
        parallel_within=math.radians(args.parallel_within),
        base=args.base,
        tip=args.tip,
        ignore_mimic=args.ignore_mimic,
        samples=args.check_samples,
        xacro=options.xacro_options(args),
    )
    write_output(result.render(args.format), args.output)
    return 0
