"""The ``urdf2dh`` command (SPEC §1): ``convert``, ``verify``, ``info``, ``export``, ``plot``,
``robots``; ``measure`` and ``calibrate`` live in :mod:`urdf2dh.calibrate.cli`.

Exit codes: 0 success, 1 verification failed (or a table failed its own check), 2 bad usage or
bad input. Errors are one line on stderr naming the file, link or joint; output files are
written to a temporary file and renamed, so a failure never leaves one behind.

Heavy imports (numpy, yourdfpy, Pinocchio) happen inside the commands that need them, so
``urdf2dh --help`` starts instantly and ``convert`` never imports Pinocchio.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any

from . import __version__
from .calibrate.cli import COMMANDS as calibration_commands
from .errors import Urdf2DhError
from .files import write_output

__all__ = ["get_argument_parser", "main"]

FORMATS = ("text", "json", "yaml", "csv", "markdown", "urdf", "poe")
CONVENTIONS = ("dh", "mdh", "cpc")
STYLES = ("wu", "ur", "zero")  # dh.STYLES
EXPORT_TARGETS = ("ur", "linuxcnc", "rtb", "matlab", "kdl", "corke-matlab")  # export.TARGETS


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(f"'{text}' is not an integer") from e
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, not {value}")
    return value


def _nonnegative_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from e
    if not value >= 0.0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0, not {text}")
    return value


def _package_path(text: str) -> tuple[str, str]:
    name, sep, directory = text.partition("=")
    if not sep or not name or not directory:
        raise argparse.ArgumentTypeError(f"expected NAME=DIR, not '{text}'")
    return name, directory


def _add_chain(p: argparse.ArgumentParser) -> None:
    p.add_argument("source", metavar="SOURCE",
                   help="URDF file, POE model file, table file, or bundled robot name")
    _add_chain_options(p)


def _add_chain_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--base", metavar="LINK", help="base link (default: the URDF root link)")
    p.add_argument("--tip", metavar="LINK",
                   help="tip link (default: the single deepest leaf below the base)")
    p.add_argument("--ignore-mimic", action="store_true",
                   help="treat mimic joints on the chain as independent joints (with a warning)")
    p.add_argument("--package-path", type=_package_path, action="append", default=[],
                   metavar="NAME=DIR",
                   help="for .xacro sources: the directory of ROS package NAME, for $(find NAME) "
                        "and package://NAME (repeatable)")


def _add_tolerances(p: argparse.ArgumentParser) -> None:
    from .tolerances import DEFAULT

    g = p.add_argument_group("tolerance judgements (D-H conventions)")
    g.add_argument("--exact", action="store_true",
                   help="no snapping: keep nearly parallel or nearly intersecting axes as they are")
    g.add_argument("--parallel-angle", type=_nonnegative_float, metavar="RAD",
                   default=DEFAULT.parallel_angle,
                   help="treat axes this close to parallel as parallel (default %(default)g rad)")
    g.add_argument("--intersect-distance", type=_nonnegative_float, metavar="LENGTH",
                   default=None,
                   help="treat lines this close as intersecting or coincident, in the source's "
                        f"length unit (default {DEFAULT.intersect_relative:g} x the robot's size)")
    g.add_argument("--check-samples", type=_positive_int, default=None, metavar="N",
                   help="configurations of the self-check (default 100; 1000 where axes were "
                        "treated as parallel, to measure the deviation)")


def get_argument_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``urdf2dh`` command."""
    parser = argparse.ArgumentParser(
        prog="urdf2dh",
        description="Turn a robot's URDF (or POE model) into exact Denavit-Hartenberg, "
        "modified D-H and CPC tables, checked against the source and against Pinocchio.",
    )
    parser.add_argument("--version", action="version", version=f"urdf2dh {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    p = sub.add_parser("convert", help="print or write the parameter table of a chain")
    _add_chain(p)
    p.add_argument("--convention", choices=CONVENTIONS, default="dh",
                   help="dh (standard), mdh (modified, Craig) or cpc (default %(default)s)")
    p.add_argument("--format", choices=FORMATS, default="text",
                   help="output format (default %(default)s)")
    p.add_argument("--style", choices=STYLES, default="wu",
                   help="D-H choices: wu (Wu 2019, a >= 0; default), ur (zero theta offsets, "
                        "Universal Robots' signs) or zero (zero theta offsets wherever possible)")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    _add_tolerances(p)

    p = sub.add_parser("verify", help="compare every convention's FK with Pinocchio's")
    _add_chain(p)
    p.add_argument("--samples", type=_positive_int, default=1000, metavar="N",
                   help="random configurations within joint limits (default %(default)s)")
    p.add_argument("--seed", type=int, default=0, metavar="S",
                   help="random seed (default %(default)s)")
    _add_tolerances(p)

    p = sub.add_parser("diff", help="compare two parameter sets (calibration: nominal vs actual)")
    p.add_argument("nominal", metavar="NOMINAL", help="URDF, POE model, table file or robot")
    p.add_argument("actual", metavar="ACTUAL", help="URDF, POE model, table file or robot")
    _add_chain_options(p)
    p.add_argument("--convention", choices=CONVENTIONS, default="dh",
                   help="convention to compare in (default %(default)s)")
    p.add_argument("--style", choices=STYLES, default="wu", help="D-H choices (see convert)")
    p.add_argument("--angle-threshold", type=_nonnegative_float, default=60.0, metavar="DEG",
                   help="mark angle changes over this, modulo 180 (default %(default)g, as "
                        "Wu 2019 Table II)")
    p.add_argument("--length-threshold", type=_nonnegative_float, metavar="LENGTH",
                   help="mark length changes over this (default 30 mm in the tables' unit)")
    p.add_argument("--parallel-within", type=_nonnegative_float, default=5.0, metavar="DEG",
                   help="name axis pairs this close to parallel in either model as "
                        "ill-conditioned for D-H (default %(default)g)")
    p.add_argument("--format", choices=("text", "json"), default="text")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    _add_tolerances(p)

    p = sub.add_parser("info", help="links, joints, the chain, candidate tips, identifiability")
    _add_chain(p)

    p = sub.add_parser("export", help="write a controller or toolbox configuration file")
    _add_chain(p)
    p.add_argument("--to", required=True, choices=EXPORT_TARGETS, metavar="TARGET",
                   help="ur (UR default_kinematics.yaml), linuxcnc (genserkins HAL), rtb "
                        "(roboticstoolbox-python), matlab (Robotics System Toolbox), kdl (PyKDL), "
                        "corke-matlab (Robotics Toolbox for MATLAB)")
    p.add_argument("--convention", choices=("dh", "mdh"), default=None,
                   help="D-H convention of rtb, matlab, kdl and corke-matlab files (default dh; "
                        "ur is dh, linuxcnc mdh)")
    p.add_argument("--style", choices=STYLES, default=None,
                   help="D-H choices (default ur for ur, zero for linuxcnc, wu otherwise)")
    p.add_argument("--units", choices=("mm", "inch"), default=None,
                   help="linuxcnc: length unit of A and D (default mm)")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    _add_tolerances(p)

    p = sub.add_parser("plot", help="draw the arm at home with its D-H frames (png, svg, pdf)")
    _add_chain(p)
    p.add_argument("-o", "--output", required=True, metavar="FILE",
                   help="image file; its suffix picks the format (.png, .svg, .pdf)")
    p.add_argument("--convention", choices=("dh", "mdh"), default="dh",
                   help="which D-H frames to draw (default %(default)s)")
    p.add_argument("--style", choices=STYLES, default="wu",
                   help="D-H choices (default %(default)s)")
    _add_tolerances(p)

    sub.add_parser("robots", help="list the bundled robots")
    from .calibrate.cli import add_parsers as add_calibration_parsers

    add_calibration_parsers(sub)
    return parser


# --------------------------------------------------------------------------- helpers


def _tolerances(args: argparse.Namespace) -> Any:
    from dataclasses import replace

    from .tolerances import DEFAULT

    tol = replace(DEFAULT, parallel_angle=args.parallel_angle,
                  intersect_distance=args.intersect_distance)
    return tol.with_exact() if args.exact else tol


def _open(args: argparse.Namespace, tol: Any = None) -> Any:
    from .sources import open_source
    from .tolerances import DEFAULT

    return open_source(args.source, tol or DEFAULT, dict(args.package_path))


# --------------------------------------------------------------------------- commands


def _convert(args: argparse.Namespace) -> int:
    from .convert import to_table
    from .formats import render

    tol = _tolerances(args)
    source = _open(args, tol)
    model = source.model(args.base, args.tip, args.ignore_mimic)
    table = to_table(model, args.convention, tol, samples=args.check_samples, style=args.style)
    write_output(render(table, args.format), args.output)
    return 0


def _verify(args: argparse.Namespace) -> int:
    from .verify import verify

    tol = _tolerances(args)
    source = _open(args, tol)
    model = source.model(args.base, args.tip, args.ignore_mimic)
    results = verify(source, model, args.samples, args.seed, tol,
                     check_samples=args.check_samples)
    unit, size = model.length_unit, model.size()
    chain = f"{model.base_link} -> {model.tip_link}, " if model.base_link else ""
    print(f"{source.name}: {chain}{model.n} joints; against Pinocchio at {args.samples} "
          f"configurations (seed {args.seed}); robot size {size:.4g} {unit}")
    print(f"  {'model':<10} {'position error':>16} {'relative':>10} {'rotation error':>16}  result")
    for r in results:
        print(f"  {r.label:<10} {r.position:>13.2e} {unit:<2} {r.position / size:>10.2e} "
              f"{r.rotation:>12.2e} rad  {'ok' if r.ok else 'FAILED'}")
    for r in results:
        for w in r.table.warnings if r.table is not None else ():
            print(f"  warning: {w}")
    failed = [r.label for r in results if not r.ok]
    if failed:
        print(f"verify: FAILED for {', '.join(failed)} (allowed {results[0].allowed_position:.2g}"
              f" {unit} + declared deviations)", file=sys.stderr)
        return 1
    print("verify: all conventions agree with Pinocchio")
    return 0


def _diff(args: argparse.Namespace) -> int:
    import math

    from .diff import diff_sources, render_diff

    info, changes, pairs = diff_sources(
        args.nominal, args.actual, args.convention, _tolerances(args),
        angle_threshold=math.radians(args.angle_threshold),
        length_threshold=args.length_threshold,
        parallel_within=math.radians(args.parallel_within),
        base=args.base, tip=args.tip, ignore_mimic=args.ignore_mimic, style=args.style,
        samples=args.check_samples, package_paths=dict(args.package_path),
    )
    write_output(render_diff(info, changes, pairs, args.format), args.output)
    return 0


def _info(args: argparse.Namespace) -> int:
    from .info import describe

    source = _open(args)
    sys.stdout.write(describe(source, args.base, args.tip, args.ignore_mimic))
    return 0


def _export(args: argparse.Namespace) -> int:
    from .convert import to_table
    from .errors import UsageError
    from .export import Options, export_table, table_choices

    if args.units is not None and args.to != "linuxcnc":
        raise UsageError(f"--units applies to --to linuxcnc, not --to {args.to}")
    convention, style = table_choices(args.to, args.convention, args.style)
    tol = _tolerances(args)
    model = _open(args, tol).model(args.base, args.tip, args.ignore_mimic)
    table = to_table(model, convention, tol, samples=args.check_samples, style=style)
    write_output(export_table(table, args.to, Options(args.units, tol)), args.output)
    return 0


def _plot(args: argparse.Namespace) -> int:
    from pathlib import Path

    from .convert import to_table
    from .plot import render

    fmt = Path(args.output).suffix.lower().lstrip(".") or "png"
    tol = _tolerances(args)
    model = _open(args, tol).model(args.base, args.tip, args.ignore_mimic)
    table = to_table(model, args.convention, tol, samples=args.check_samples, style=args.style)
    write_output(render(table, fmt), args.output)
    return 0


def _robots(args: argparse.Namespace) -> int:
    from .catalog import ROBOTS

    width = max(len(n) for n in ROBOTS)
    for r in ROBOTS.values():
        chain = f"{r.base} -> {r.tip}" if r.base else "POE model"
        print(f"{r.name:<{width}}  {r.description}  [{chain}]")
    return 0


COMMANDS = {
    "convert": _convert,
    "verify": _verify,
    "diff": _diff,
    "info": _info,
    "export": _export,
    "plot": _plot,
    "robots": _robots,
}
COMMANDS.update(calibration_commands)


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    parser = get_argument_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    try:
        return COMMANDS[args.command](args)
    except Urdf2DhError as e:
        print(f"urdf2dh: error: {e}", file=sys.stderr)
        return e.exit_code
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:
        return 0
    except Exception as e:  # a bug, or bad input we failed to foresee: still no traceback
        if os.environ.get("URDF2DH_DEBUG"):
            raise
        print(f"urdf2dh: internal error: {type(e).__name__}: {e} (set URDF2DH_DEBUG=1 for the "
              "traceback, and please report it)", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
