"""``urdf2dh export --to TARGET``: a controller or toolbox configuration file of a chain (or one
per chain of several)."""

from __future__ import annotations

import argparse

from ..errors import UsageError
from ..io.files import write_output
from . import options
from .chains import one_tip, several_of, to_directory

__all__ = ["EXAMPLE", "HELP", "NAME", "add_arguments", "run"]

NAME = "export"
HELP = "write a controller or toolbox configuration file"
EXAMPLE = "urdf2dh export ur10 --to ur -o default_kinematics.yaml"
UNIT_TARGETS = ("linuxcnc", "ikdh")  # the targets that take --units


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..conventions import STYLES
    from ..emit.export import TARGETS

    options.add_chain(p, several=True)
    p.add_argument(
        "--to",
        required=True,
        choices=tuple(TARGETS),
        metavar="TARGET",
        help="; ".join(f"{t.name}: {t.summary}" for t in TARGETS.values()),
    )
    p.add_argument(
        "--convention",
        choices=tuple(dict.fromkeys(c for t in TARGETS.values() for c in t.conventions)),
        default=None,
        help="convention of the file, where the target takes several (default: the "
        "target's first: "
        + ", ".join(f"{t.name} {'/'.join(t.conventions)}" for t in TARGETS.values())
        + ")",
    )
    p.add_argument(
        "--style",
        choices=STYLES,
        default=None,
        help="D-H choices (default ur for ur, zero for linuxcnc, wu otherwise)",
    )
    p.add_argument(
        "--units",
        choices=("mm", "inch", "m"),
        default=None,
        help="linuxcnc: length unit of A and D, mm or inch; ikdh: of the file, mm or m "
        "(default mm)",
    )
    p.add_argument(
        "-o",
        "--output",
        metavar="FILE|DIR/",
        help="write to FILE instead of stdout; with several tips (required) a directory, "
        "DIR/ (a trailing slash, or an existing directory): DIR/<tip> plus the target's "
        "suffix, all or nothing",
    )
    options.add_tolerances(p)


def run(args: argparse.Namespace) -> int:
    from ..emit.export import TARGETS, ExportOptions, export, table_choices

    if args.units is not None and args.to not in UNIT_TARGETS:
        raise UsageError(f"--units applies to --to linuxcnc or ikdh, not --to {args.to}")
    table_choices(args.to, args.convention, args.style)  # bad choices fail before any reading
    if several_of(args) and not to_directory(args):
        from .chains import DIRECTORY_HINT

        raise UsageError(f"export with several tips writes one file per tip; give {DIRECTORY_HINT}")
    tol = options.tolerances(args)
    source = options.source(args, tol)
    opts = ExportOptions(args.units, tol)
    if not several_of(args):
        model = source.model(args.base, one_tip(args), args.ignore_mimic)
        text = export(model, args.to, args.convention, args.style, opts, samples=args.check_samples)
        write_output(text, args.output)
        return 0
    from .chains import chains_of, naming_tip, per_chain, write_tips

    suffix = TARGETS[args.to].suffix
    texts = []
    models = chains_of(args, source, suffix)
    for model in per_chain(models, "export"):
        with naming_tip(model.tip_link):
            text = export(
                model, args.to, args.convention, args.style, opts, samples=args.check_samples
            )
            texts.append((model, text))
    write_tips(args, source, texts, suffix)
    return 0
