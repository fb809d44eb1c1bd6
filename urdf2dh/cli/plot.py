"""``urdf2dh plot -o FILE``: the arm at home with its frames, as a picture or an interactive
view."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import InputError, UsageError, choices, shown
from ..io.files import write_output
from . import options

__all__ = ["EXAMPLE", "HELP", "NAME", "add_arguments", "run"]

NAME = "plot"
HELP = "draw the arm at home with its frames (png, svg, pdf; html: interactive 3-D)"
EXAMPLE = "urdf2dh plot panda --convention mdh -o panda-frames.png"


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..conventions import NAMES, STYLES

    options.add_chain(p)
    p.add_argument(
        "-o",
        "--output",
        required=True,
        metavar="FILE",
        help="output file; its suffix picks the format: .png, .svg, .pdf (a picture) or .html "
        "(an interactive 3-D view in one self-contained page)",
    )
    p.add_argument(
        "--convention",
        choices=NAMES,
        default=NAMES[0],
        help="whose frames to draw (default %(default)s)",
    )
    p.add_argument(
        "--style", choices=STYLES, default="wu", help="D-H choices (default %(default)s)"
    )
    options.add_tolerances(p)


def run(args: argparse.Namespace) -> int:
    from ..conventions.convert import to_table
    from ..emit.plot import FORMATS, plot
    from ..emit.scene import check_size

    fmt = Path(args.output).suffix.lower().lstrip(".") or "png"
    if fmt not in FORMATS:
        raise UsageError(
            f"plot: unknown format '.{fmt}' of -o {shown(args.output)}: its suffix picks the "
            f"format, one of {choices(FORMATS)}"
        )
    tol = options.tolerances(args)
    source = options.source(args, tol)
    model = source.model(args.base, args.tip, args.ignore_mimic)
    try:
        check_size(len(model.joints))
    except InputError as e:
        raise InputError(f"{source.display}: {e} (pick a shorter chain with --base/--tip)") from e
    table = to_table(model, args.convention, tol, samples=args.check_samples, style=args.style)
    write_output(plot(table, fmt), args.output)
    return 0
