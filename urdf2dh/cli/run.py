"""A run of the ``urdf2dh`` command, and the one place errors become exit codes.

Exit codes: 0 success, 1 verification failed (or a table failed its own check, or a calibration
did not converge), 2 bad usage or bad input, 3 a calibration the measurements contradict (its
cause named), 130 and 143 for Ctrl-C and ``SIGTERM``. Errors are
one line on stderr naming the file, link or joint (:func:`urdf2dh.errors.one_line`); output
files are written all together through temporary files, so a failure never leaves one behind
(:mod:`urdf2dh.io.files`); a signal ends the run with every output as it was
(:mod:`urdf2dh.io.interrupts`).
"""

from __future__ import annotations

import argparse
import gc
import os
import sys
import warnings

from ..errors import Urdf2DhError, one_line
from ..io import files, interrupts
from ..io.files import drop_stdout, flush_stdout, write_stdout

__all__ = ["console", "main", "say"]


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code.

    Ctrl-C and ``SIGTERM`` end the run with 130 and 143 and leave every output as it was
    (:mod:`urdf2dh.io.interrupts`); no output replaces a file the run read
    (:mod:`urdf2dh.io.files`).
    """
    return _main(argv, restore=True)


# the collector's thresholds (allocations beyond frees, then collections of each younger
# generation; Python's are 700, 10, 10): start-up's long-lived objects stay unscanned
_COLLECT_AFTER = (100_000, 50, 100)


def console() -> None:
    """The ``urdf2dh`` program: :func:`main` on ``sys.argv``, then exit with its code; a signal
    after the run changes nothing.

    The program runs Python's cyclic garbage collector less often (:data:`_COLLECT_AFTER`): its
    start-up allocates some 40,000 objects (modules, classes, functions) that live until the
    process ends, which the collector would only scan (54 collections, 3 % of ``convert``'s CPU
    time, at the default thresholds; none at these); a long command's cycles are still
    collected. :func:`main`, for a library user's process, leaves the collector as it is.
    """
    gc.set_threshold(*_COLLECT_AFTER)
    sys.exit(_main(None, restore=False))


def _main(argv: list[str] | None, restore: bool) -> int:
    with interrupts.handled(restore), files.one_run():
        files.standard_streams()  # before anything is opened: a closed stdout is no file's number
        try:
            # imported here, not with this module: the run handles Ctrl-C from its first line on
            from .parser import command_of, get_argument_parser

            given = sys.argv[1:] if argv is None else list(argv)
            parser = get_argument_parser(command_of(given) or None)
            args = parser.parse_args(given)
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
            code: int = args.run(args)
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


#: The option of each Python API argument that a :class:`~urdf2dh.errors.Remedy` names.
OPTIONS = {
    "tip": "--tip",
    "ignore_mimic": "--ignore-mimic",
    "convention": "--convention",
    "xacro.packages": "--package-path",
    "xacro.args": "--xacro-arg",
    "xacro.timeout": "--xacro-timeout",
    "xacro.memory": "--xacro-memory",
    "tol.parallel_angle": "--parallel-angle",
    "tol.intersect_distance": "--intersect-distance",
    "reading.degrees": "--degrees",
    "reading.length_unit": "--length-unit",
    "reading.rename": "--rename",
    "reading.euler": "--euler",
    "helical": "--helical",
    "level": "--identify",
    "fixed": "--fix",
    "noise_pos, noise_rot": "--noise-pos and --noise-rot",
    "accept": "--accept-implausible",
}


def _with_option(e: Urdf2DhError) -> str:
    """The error's message, and the options that get past it."""
    remedies = ([] if e.remedy is None else [e.remedy]) + list(e.also)
    return str(e) + "".join(r.said(OPTIONS.get(r.argument, r.argument)) for r in remedies)


def _report(e: Exception) -> int:
    """The exit code of a run that raised ``e``; its message on stderr."""
    if isinstance(e, Urdf2DhError):
        try:
            print(f"urdf2dh: error: {one_line(_with_option(e))}", file=sys.stderr)
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
        f"urdf2dh: internal error: {type(e).__name__}: {one_line(str(e))} (set "
        "URDF2DH_DEBUG=1 for the traceback, and please report it)",
        file=sys.stderr,
    )
    return 2


def say(line: str = "") -> None:
    """A line of a command's report on stdout, written now (a failed write is an error)."""
    write_stdout(line + "\n")
