"""The ``urdf2dh`` command (SPEC §1): ``convert``, ``verify``, ``diff``, ``info``, ``export``,
``plot``, ``robots``; the options of each, and the one place errors become exit codes.

Exit codes: 0 success, 1 verification failed (or a table failed its own check), 2 bad usage or
bad input. Errors are one line on stderr naming the file, link or joint; output files are
written to a temporary file and renamed, so a failure never leaves one behind. The commands
themselves are in :mod:`urdf2dh.commands`.
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from typing import Any

from . import __version__
from .errors import MESSAGE_LENGTH, Urdf2DhError
from .io import files, interrupts
from .io.files import drop_stdout, flush_stdout, write_stdout

__all__ = ["console", "get_argument_parser", "main", "version_text"]


#: What ``--version`` names besides urdf2dh: the distributions it runs on (PyPI names; the
#: Pinocchio wheel is ``pin``).
RUNS_ON = (("yourdfpy", "yourdfpy"), ("Pinocchio", "pin"), ("numpy", "numpy"), ("xacro", "xacro"))


def version_text() -> str:
    """``urdf2dh X (yourdfpy Y, Pinocchio Z, numpy W, xacro V; Python U)``, from the installed
    distributions' metadata (nothing is imported)."""
    from importlib.metadata import PackageNotFoundError, version

    parts = []
    for label, dist in RUNS_ON:
        try:
            parts.append(f"{label} {version(dist)}")
        except PackageNotFoundError:
            parts.append(f"{label} not installed")
    python = ".".join(map(str, sys.version_info[:3]))
    return f"urdf2dh {__version__} ({', '.join(parts)}; Python {python})"


class _Version(argparse.Action):
    """``--version``: the text is made only when asked for (metadata look-ups cost time)."""

    def __init__(self, option_strings: list[str], dest: str, **kwargs: object) -> None:
        super().__init__(option_strings, dest, nargs=0, help="show the versions and exit")

    def __call__(self, parser: argparse.ArgumentParser, *args: object) -> None:
        parser._print_message(version_text() + "\n", sys.stdout)  # a failed write is an error
        parser.exit()


class ArgumentParser(argparse.ArgumentParser):
    """argparse's parser, except that help, usage and version text that cannot be written to
    stdout (a full disk, ``> /dev/full``) is an error, as any other failed write
    (:func:`urdf2dh.io.files.write_stdout`); argparse itself ignores it. Every command's parser is
    one (``add_subparsers`` makes its parsers of the parent's class)."""

    def _print_message(self, message: str, file: Any = None) -> None:
        # the one place argparse writes: help, usage, --version and its error messages
        if not message or file is not sys.stdout:
            super()._print_message(message, file)
            return
        try:
            write_stdout(message)
        except BrokenPipeError:  # the reader went away (`| head`): not an error
            drop_stdout()


def get_argument_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``urdf2dh`` command."""
    # imported here, not with this module: main() handles Ctrl-C from its first line on
    from . import options
    from .conventions import NAMES, STYLES
    from .emit.export import TARGETS
    from .emit.formats import FORMATS
    from .tolerances import DIFF_ANGLE_DEG, DIFF_LENGTH_M

    parser = ArgumentParser(
        prog="urdf2dh",
        description="Turn a robot's URDF (or POE model) into exact Denavit-Hartenberg, "
        "modified D-H and CPC tables, checked against the source and against Pinocchio.",
    )
    parser.add_argument("--version", action=_Version)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    p = sub.add_parser("convert", help="print or write the parameter table of a chain")
    options.add_chain(p, several=True)
    p.add_argument(
        "--convention",
        choices=NAMES,
        default=NAMES[0],
        help="parameter convention (default %(default)s)",
    )
    p.add_argument(
        "--format", choices=FORMATS, default="text", help="output format (default %(default)s)"
    )
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
    options.add_tolerances(p)

    p = sub.add_parser("verify", help="compare every convention's FK with Pinocchio's")
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

    p = sub.add_parser("diff", help="compare two parameter sets (calibration: nominal vs actual)")
    p.add_argument("nominal", metavar="NOMINAL", help="URDF, POE model, table file or robot")
    p.add_argument("actual", metavar="ACTUAL", help="URDF, POE model, table file or robot")
    options.add_chain_options(p)
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
        default=5.0,
        metavar="DEG",
        help="name axis pairs this close to parallel in either model as "
        "ill-conditioned for D-H (default %(default)g)",
    )
    p.add_argument("--format", choices=("text", "json"), default="text")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    options.add_tolerances(p)

    p = sub.add_parser("info", help="links, joints, the chain, candidate tips, identifiability")
    options.add_chain(p)

    p = sub.add_parser("export", help="write a controller or toolbox configuration file")
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
        choices=("mm", "inch"),
        default=None,
        help="linuxcnc: length unit of A and D (default mm)",
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

    p = sub.add_parser(
        "plot", help="draw the arm at home with its frames (png, svg, pdf; html: interactive 3-D)"
    )
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

    sub.add_parser("robots", help="list the bundled robots")
    from .calibrate.cli import add_parsers as add_calibration_parsers

    add_calibration_parsers(sub)
    return parser


def _one_line(text: str) -> str:
    """``text`` with line breaks and other control characters written as escapes, so that an
    error message naming a hostile name stays one line, and at most :data:`MESSAGE_LENGTH`
    characters (names in messages are shortened already, :func:`~urdf2dh.errors.shown`; this
    is the last guard against a library's message quoting a whole input)."""
    line = "".join(c if c.isprintable() or c == " " else repr(c)[1:-1] for c in text)
    if len(line) <= MESSAGE_LENGTH:
        return line
    keep = MESSAGE_LENGTH // 2
    return f"{line[:keep]} ... ({len(line):,} characters) ... {line[-keep:]}"


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code.

    Ctrl-C and ``SIGTERM`` end the run with 130 and 143 and leave every output as it was
    (:mod:`urdf2dh.io.interrupts`); no output replaces a file the run read
    (:mod:`urdf2dh.io.files`).
    """
    return _main(argv, restore=True)


def console() -> None:
    """The ``urdf2dh`` program: :func:`main` on ``sys.argv``, then exit with its code; a signal
    after the run changes nothing."""
    sys.exit(_main(None, restore=False))


def _main(argv: list[str] | None, restore: bool) -> int:
    with interrupts.handled(restore), files.one_run():
        try:
            parser = get_argument_parser()
            args = parser.parse_args(argv)
            if args.command is None:
                parser.print_help()
                return 2
            code = _run(args)
        except KeyboardInterrupt:  # while the parser was built
            code = 130
        except Urdf2DhError as e:  # help or usage that could not be written
            code = _report(e)
        except SystemExit as e:  # SIGTERM (interrupts.handled), or argparse's --help and errors
            if not interrupts.pending():
                raise
            code = e.code if isinstance(e.code, int) else 2
        return interrupts.exit_code(code)


def _run(args: argparse.Namespace) -> int:
    """The command, its errors turned into exit codes and one-line messages."""
    try:
        with warnings.catch_warnings():
            # numerical trouble is reported by the checks (a one-line error), never as a
            # library's warning text
            warnings.simplefilter("ignore")
            from .commands import COMMANDS

            code: int = COMMANDS[args.command](args)
        interrupts.check()  # a signal some library swallowed still ends the run
        flush_stdout()  # what the command printed is written, or the run fails
        return code
    except KeyboardInterrupt:
        return 130
    except Exception as e:
        if interrupts.pending():  # the aftermath of a signal some library swallowed
            return 2  # main turns it into the signal's exit code
        if os.environ.get("URDF2DH_DEBUG") and not isinstance(
            e, Urdf2DhError | BrokenPipeError | RecursionError
        ):
            raise
        return _report(e)


def _report(e: Exception) -> int:
    """The exit code of a run that raised ``e``; its message on stderr."""
    if isinstance(e, Urdf2DhError):
        try:
            print(f"urdf2dh: error: {_one_line(str(e))}", file=sys.stderr)
        except OSError:  # stderr too cannot be written: the exit code still says it
            pass
        return e.exit_code
    if isinstance(e, BrokenPipeError):
        drop_stdout()  # the reader went away (`| head`); keep Python from complaining at exit
        return 0
    if isinstance(e, RecursionError):
        print("urdf2dh: error: input nested too deeply", file=sys.stderr)
        return 2
    # a bug, or bad input we failed to foresee: still no traceback
    print(
        f"urdf2dh: internal error: {type(e).__name__}: {_one_line(str(e))} (set "
        "URDF2DH_DEBUG=1 for the traceback, and please report it)",
        file=sys.stderr,
    )
    return 2


if __name__ == "__main__":  # pragma: no cover
    console()
