"""What each ``urdf2dh`` command does, given its parsed options (:mod:`urdf2dh.cli` parses them).

Heavy imports (numpy, yourdfpy, Pinocchio) happen inside the commands that need them, so
``urdf2dh --help`` starts instantly and ``convert`` never imports Pinocchio.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from .calibrate.cli import COMMANDS as calibration_commands
from .io.files import write_output, write_stdout
from .options import tolerances, xacro_options

__all__ = ["COMMANDS"]


def _open(args: argparse.Namespace, tol: Any = None) -> Any:
    from .io.sources import open_source
    from .tolerances import DEFAULT

    return open_source(args.source, tol or DEFAULT, xacro=xacro_options(args))


def _say(line: str = "") -> None:
    """A line of a command's report on stdout, written now (a failed write is an error)."""
    write_stdout(line + "\n")


# --------------------------------------------------------------------------- commands


def _one_tip(args: argparse.Namespace) -> str | None:
    """The tip of a single-chain run of a command that takes several (``args.tips``)."""
    return args.tips[0] if args.tips else None


def _several(args: argparse.Namespace) -> bool:
    from .tips import several

    return several(args.all_tips, args.tips)


def _chains(args: argparse.Namespace, source: Any, suffix: str | None = None) -> list[Any]:
    """The models of a run over several chains; ``suffix``: of the files of ``-o DIR/``, whose
    names are checked before any conversion."""
    from .tips import chain_models, chain_tips, file_names

    base, tips = chain_tips(source, args.base, args.tips, args.all_tips)
    if suffix is not None:
        file_names(source.display, tips, suffix)
    return chain_models(source, base, tips, args.ignore_mimic)


def _per_chain(models: list[Any], what: str) -> Any:
    """The chains of a run, with a progress bar on a terminal."""
    from .progress import progress

    return progress(models, len(models), what)


def _to_directory(args: argparse.Namespace) -> bool:
    """Whether a run over several chains writes one file per chain (``-o DIR/``)."""
    from .tips import names_directory

    return args.output is not None and names_directory(args.output)


def _write_tips(
    args: argparse.Namespace, source: Any, texts: list[tuple[Any, str]], suffix: str
) -> None:
    """Write ``(model, text)`` pairs as ``-o DIR/<tip><suffix>``, all or nothing."""
    from .io.files import write_directory
    from .tips import file_names

    names = file_names(source.display, [m.tip_link for m, _ in texts], suffix)
    write_directory({names[m.tip_link]: text for m, text in texts}, args.output)


def _convert(args: argparse.Namespace) -> int:
    from .conventions.convert import to_table
    from .emit.formats import render

    tol = tolerances(args)
    if _several(args):
        return _convert_tips(args, tol)
    source = _open(args, tol)
    model = source.model(args.base, _one_tip(args), args.ignore_mimic)
    table = to_table(model, args.convention, tol, samples=args.check_samples, style=args.style)
    write_output(render(table, args.format), args.output)
    return 0


def _convert_tips(args: argparse.Namespace, tol: Any) -> int:
    from .conventions.convert import to_table
    from .emit.formats import render
    from .tips import FORMAT_SUFFIXES, check_stdout_format, join_tables, naming_tip

    directory = _to_directory(args)
    if not directory:
        check_stdout_format(args.format)  # before any reading
    source = _open(args, tol)
    suffix = FORMAT_SUFFIXES[args.format]
    models = _chains(args, source, suffix if directory else None)
    tables = []
    for model in _per_chain(models, "convert"):
        with naming_tip(model.tip_link):
            tables.append(
                to_table(model, args.convention, tol, samples=args.check_samples, style=args.style)
            )
    if not directory:  # stdout, or -o FILE: the one document
        write_output(join_tables(tables, args.format), args.output)
        return 0
    texts = []
    for model, table in zip(models, tables, strict=True):
        with naming_tip(model.tip_link):
            texts.append((model, render(table, args.format)))
    _write_tips(args, source, texts, suffix)
    return 0


def _verify(args: argparse.Namespace) -> int:
    tol = tolerances(args)
    source = _open(args, tol)
    if not _several(args):
        model = source.model(args.base, _one_tip(args), args.ignore_mimic)
        if _verify_chain(args, source, model, tol):
            _say("verify: all conventions agree with Pinocchio")
            return 0
        return 1
    from .tips import TipError, naming_tip

    models = _chains(args, source)
    failed = []
    for i, model in enumerate(_per_chain(models, "verify")):
        if i:
            _say()
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
        from .errors import shown

        print(
            f"verify: FAILED on {len(failed)} of {len(models)} chains: "
            f"{', '.join(shown(t) for t in failed)}",
            file=sys.stderr,
        )
        return 1
    _say(f"verify: all conventions agree with Pinocchio on all {len(models)} chains")
    return 0


def _verify_chain(args: argparse.Namespace, source: Any, model: Any, tol: Any) -> bool:
    """Verify one chain and print its report; whether every model agrees with Pinocchio."""
    from .check.verify import verify
    from .errors import visible as v

    results = verify(source, model, args.samples, args.seed, tol, check_samples=args.check_samples)
    unit, size = v(model.length_unit), model.size()
    chain = f"{v(model.base_link)} -> {v(model.tip_link)}, " if model.base_link else ""
    _say(
        f"{v(source.name)}: {chain}{model.n} joints; against Pinocchio at {args.samples} "
        f"configurations (seed {args.seed}); robot size {size:.4g} {unit}"
    )
    _say(f"  {'model':<10} {'position error':>16} {'relative':>10} {'rotation error':>16}  result")
    for r in results:
        _say(
            f"  {r.label:<10} {r.position:>13.2e} {unit:<2} {r.position / size:>10.2e} "
            f"{r.rotation:>12.2e} rad  {'ok' if r.ok else 'FAILED'}"
        )
    for r in results:
        for w in r.table.warnings if r.table is not None else ():
            _say(f"  warning: {v(w)}")
    failed = [r.label for r in results if not r.ok]
    if failed:
        where = f" on {chain[:-2]}" if chain and _several(args) else ""
        print(
            f"verify: FAILED{where} for {', '.join(failed)} (allowed "
            f"{results[0].allowed_position:.2g} {unit} + declared deviations)",
            file=sys.stderr,
        )
        return False
    return True


def _diff(args: argparse.Namespace) -> int:
    import math

    from .check.diff import diff_sources, render_diff

    info, changes, pairs, forms = diff_sources(
        args.nominal,
        args.actual,
        args.convention,
        tolerances(args),
        angle_threshold=math.radians(args.angle_threshold),
        length_threshold=args.length_threshold,
        parallel_within=math.radians(args.parallel_within),
        base=args.base,
        tip=args.tip,
        ignore_mimic=args.ignore_mimic,
        style=args.style,
        samples=args.check_samples,
        xacro=xacro_options(args),
    )
    write_output(render_diff(info, changes, pairs, args.format, forms), args.output)
    return 0


def _info(args: argparse.Namespace) -> int:
    from .check.info import describe

    source = _open(args)
    write_stdout(describe(source, args.base, args.tip, args.ignore_mimic))
    return 0


def _export(args: argparse.Namespace) -> int:
    from .emit.export import TARGETS, Options, export, table_choices
    from .errors import UsageError

    if args.units is not None and args.to != "linuxcnc":
        raise UsageError(f"--units applies to --to linuxcnc, not --to {args.to}")
    table_choices(args.to, args.convention, args.style)  # bad choices fail before any reading
    if _several(args) and not _to_directory(args):
        from .tips import DIRECTORY_HINT

        raise UsageError(f"export with several tips writes one file per tip; give {DIRECTORY_HINT}")
    tol = tolerances(args)
    source = _open(args, tol)
    opts = Options(args.units, tol)
    if not _several(args):
        model = source.model(args.base, _one_tip(args), args.ignore_mimic)
        text = export(model, args.to, args.convention, args.style, opts, samples=args.check_samples)
        write_output(text, args.output)
        return 0
    from .tips import naming_tip

    suffix = TARGETS[args.to].suffix
    texts = []
    models = _chains(args, source, suffix)
    for model in _per_chain(models, "export"):
        with naming_tip(model.tip_link):
            texts.append(
                (
                    model,
                    export(
                        model,
                        args.to,
                        args.convention,
                        args.style,
                        opts,
                        samples=args.check_samples,
                    ),
                )
            )
    _write_tips(args, source, texts, suffix)
    return 0


def _plot(args: argparse.Namespace) -> int:
    from pathlib import Path

    from .conventions.convert import to_table
    from .emit.plot import FORMATS, plot
    from .emit.scene import check_size
    from .errors import InputError, UsageError, choices, shown

    fmt = Path(args.output).suffix.lower().lstrip(".") or "png"
    if fmt not in FORMATS:
        raise UsageError(
            f"plot: unknown format '.{fmt}' of -o {shown(args.output)}: its suffix picks the "
            f"format, one of {choices(FORMATS)}"
        )
    tol = tolerances(args)
    source = _open(args, tol)
    model = source.model(args.base, args.tip, args.ignore_mimic)
    try:
        check_size(len(model.joints))
    except InputError as e:
        raise InputError(f"{source.display}: {e} (pick a shorter chain with --base/--tip)") from e
    table = to_table(model, args.convention, tol, samples=args.check_samples, style=args.style)
    write_output(plot(table, fmt), args.output)
    return 0


def _robots(args: argparse.Namespace) -> int:
    from .io.catalog import ROBOTS

    width = max(len(n) for n in ROBOTS)
    lines = []
    for r in ROBOTS.values():
        chain = f"{r.base} -> {r.tip}" if r.base else "POE model"
        lines.append(f"{r.name:<{width}}  {r.description}  [{chain}]\n")
    write_stdout("".join(lines))
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
