"""``urdf2dh convert``: print or write the parameter table of a chain (or of several)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..io.files import write_output
from . import options
from .chains import one_tip, several_of

if TYPE_CHECKING:
    from ..conventions.table import Table
    from ..model.poe import PoeModel
    from ..tolerances import Tolerances

__all__ = ["EXAMPLE", "HELP", "NAME", "add_arguments", "run"]

NAME = "convert"
HELP = "print or write the parameter table of a chain"
EXAMPLE = "urdf2dh convert ur5 --convention mdh --format json -o ur5-mdh.json"


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..conventions import NAMES, STYLES
    from ..emit.formats import FORMATS

    options.add_chain(p, several=True)
    p.add_argument(
        "--convention",
        choices=NAMES,
        default=None,
        help=f"parameter convention (default {NAMES[0]}, or hayati where a D-H table is not the "
        "one to write: docs/parallel-axes.md)",
    )
    options.add_format(p, FORMATS)
    p.add_argument(
        "--style",
        choices=STYLES,
        default="wu",
        help="D-H choices: wu (Wu 2019, a >= 0; default), ur (zero theta offsets, "
        "Universal Robots' signs) or zero (zero theta offsets wherever possible)",
    )
    p.add_argument(
        "-o",
        "--output",
        metavar="FILE|DIR/",
        help="write to FILE instead of stdout; with several tips, FILE gets what stdout would "
        "(text, markdown, json: an object keyed by tip, yaml: a document per tip) and DIR/ (a "
        "trailing slash, or an existing directory) one file per tip (DIR/<tip>.txt, .json, "
        ".yaml, .csv, .md, .urdf, .poe.yaml), all or nothing",
    )
    options.add_like(p)
    options.add_tolerances(p)


def run(args: argparse.Namespace) -> int:
    from ..emit.formats import FORMATS, render
    from ..errors import UsageError

    args.format = options.output_format(args, FORMATS)  # before anything is read
    tol = options.tolerances(args)
    options.check_like(args)
    if several_of(args):
        if args.like:
            raise UsageError("--like writes one chain into NOMINAL: give one --tip")
        return _convert_tips(args)
    source = options.source(args, tol)
    model = source.model(args.base, one_tip(args), args.ignore_mimic)
    if args.like:
        write_output(options.like(args, model, tol), args.output)
        return 0
    write_output(render(_table(model, args, tol), args.format), args.output)
    return 0


def _table(model: PoeModel, args: argparse.Namespace, tol: Tolerances) -> Table:
    """The table asked for, or without --convention the one to write
    (:mod:`urdf2dh.conventions.choice`)."""
    from ..conventions import NAMES
    from ..conventions.choice import choose
    from ..conventions.convert import to_table

    samples, style = args.check_samples, args.style
    if args.convention is not None:
        return to_table(model, args.convention, tol, samples=samples, style=style)
    return choose(model, NAMES[0], tol, samples, style).table


def _convert_tips(args: argparse.Namespace) -> int:
    from ..emit.formats import render
    from .chains import (
        FORMAT_SUFFIXES,
        chains_of,
        check_stdout_format,
        join_tables,
        naming_tip,
        per_chain,
        to_directory,
        write_tips,
    )

    tol = options.tolerances(args)
    directory = to_directory(args)
    if not directory:
        check_stdout_format(args.format)  # before any reading
    source = options.source(args, tol)
    suffix = FORMAT_SUFFIXES[args.format]
    models = chains_of(args, source, suffix if directory else None)
    tables = []
    for model in per_chain(models, "convert"):
        with naming_tip(model.tip_link):
            tables.append(_table(model, args, tol))
    if not directory:  # stdout, or -o FILE: the one document
        write_output(join_tables(tables, args.format), args.output)
        return 0
    texts = []
    for model, table in zip(models, tables, strict=True):
        with naming_tip(model.tip_link):
            texts.append((model, render(table, args.format)))
    write_tips(args, source, texts, suffix)
    return 0
