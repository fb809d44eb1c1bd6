"""What each ``urdf2dh`` command does, given its parsed options (:mod:`urdf2dh.cli` parses them).

Heavy imports (numpy, yourdfpy, Pinocchio) happen inside the commands that need them, so
``urdf2dh --help`` starts instantly and ``convert`` never imports Pinocchio.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from .calibrate.cli import COMMANDS as calibration_commands
from .files import write_output

__all__ = ["COMMANDS"]


def _tolerances(args: argparse.Namespace) -> Any:
    from dataclasses import replace

    from .tolerances import DEFAULT

    tol = replace(DEFAULT, parallel_angle=args.parallel_angle,
                  intersect_distance=args.intersect_distance)
    return tol.with_exact() if args.exact else tol


def _xacro(args: argparse.Namespace) -> Any:
    from .xacro import XacroOptions

    return XacroOptions(dict(args.package_path), dict(args.xacro_arg), args.xacro_timeout,
                        args.xacro_memory)


def _open(args: argparse.Namespace, tol: Any = None) -> Any:
    from .sources import open_source
    from .tolerances import DEFAULT

    return open_source(args.source, tol or DEFAULT, xacro=_xacro(args))


# --------------------------------------------------------------------------- commands


def _convert(args: argparse.Namespace) -> int:
    from .convert import to_table
    from .formats import render

    tol = _tolerances(args)
    source = _open(args, tol)
    model = source.model(args.base, args.tip, args.ignore_mimic)
    table = to_table(model, args.convention, tol, samples=args.check_samples, style=args.style)
    write_output(render(table, args.format), args.output, [args.source])
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
        samples=args.check_samples, xacro=_xacro(args),
    )
    write_output(render_diff(info, changes, pairs, args.format), args.output,
                 [args.nominal, args.actual])
    return 0


def _info(args: argparse.Namespace) -> int:
    from .info import describe

    source = _open(args)
    sys.stdout.write(describe(source, args.base, args.tip, args.ignore_mimic))
    return 0


def _export(args: argparse.Namespace) -> int:
    from .errors import UsageError
    from .export import Options, export, table_choices

    if args.units is not None and args.to != "linuxcnc":
        raise UsageError(f"--units applies to --to linuxcnc, not --to {args.to}")
    table_choices(args.to, args.convention, args.style)  # bad choices fail before any reading
    tol = _tolerances(args)
    model = _open(args, tol).model(args.base, args.tip, args.ignore_mimic)
    text = export(model, args.to, args.convention, args.style, Options(args.units, tol),
                  samples=args.check_samples)
    write_output(text, args.output, [args.source])
    return 0


def _plot(args: argparse.Namespace) -> int:
    from pathlib import Path

    from .convert import to_table
    from .plot import render

    fmt = Path(args.output).suffix.lower().lstrip(".") or "png"
    tol = _tolerances(args)
    model = _open(args, tol).model(args.base, args.tip, args.ignore_mimic)
    table = to_table(model, args.convention, tol, samples=args.check_samples, style=args.style)
    write_output(render(table, fmt), args.output, [args.source])
    return 0


def _robots(args: argparse.Namespace) -> int:
    from .catalog import ROBOTS

    width = max(len(n) for n in ROBOTS)
    for r in ROBOTS.values():
        chain = f"{r.base} -> {r.tip}" if r.base else "POE model"
        print(f"{r.name:<{width}}  {r.description}  [{chain}]")
    return 0


COMMANDS = {
    **calibration_commands,
    "convert": _convert,
    "verify": _verify,
    "diff": _diff,
    "info": _info,
    "export": _export,
    "plot": _plot,
    "robots": _robots,
}
