"""The ``urdf2dh`` command's argument parser: the commands, in the order ``--help`` lists them,
each registered with its options and the function that runs it (:class:`Command`).

Building the parser imports no numpy, yourdfpy or Pinocchio: ``urdf2dh --help`` starts at once.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import Any, Protocol

from .. import _version
from ..errors import near
from ..io.files import drop_stdout, write_stdout

__all__ = [
    "RUNS_ON",
    "ArgumentParser",
    "Command",
    "command_of",
    "get_argument_parser",
    "version_text",
]

#: What ``--version`` names besides urdf2dh: the distributions it runs on (PyPI names; the
#: Pinocchio wheel is ``pin``).
RUNS_ON = (("yourdfpy", "yourdfpy"), ("Pinocchio", "pin"), ("numpy", "numpy"), ("xacro", "xacro"))


class Command(Protocol):
    """A command of ``urdf2dh``: a module with its name, its one-line help, one example that runs
    as written (its ``-h`` ends with it; the command's page under docs/commands/ has more), its
    options, and the function that runs it on the parsed options and returns the exit code."""

    NAME: str
    HELP: str
    EXAMPLE: str

    def add_arguments(self, p: argparse.ArgumentParser) -> None: ...

    def run(self, args: argparse.Namespace) -> int: ...


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
    return f"urdf2dh {_version.__version__} ({', '.join(parts)}; Python {python})"


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
    (:func:`urdf2dh.io.files.write_stdout`); argparse itself ignores it; and that a misspelled
    command, choice or option is answered with the closest valid ones ("did you mean ...?").
    Every command's parser is one (``add_subparsers`` makes its parsers of the parent's
    class)."""

    def _check_value(self, action: argparse.Action, value: Any) -> None:
        # argparse's check of a value against the choices (commands, conventions, formats, ...)
        if action.choices is None or value in action.choices:
            return
        listed = ", ".join(map(repr, action.choices))
        hint = near(str(value), [str(c) for c in action.choices])
        raise argparse.ArgumentError(
            action, f"invalid choice: {value!r}{hint} (choose from {listed})"
        )

    def parse_args(  # type: ignore[override]
        self, args: Sequence[str] | None = None, namespace: argparse.Namespace | None = None
    ) -> argparse.Namespace:
        parsed, extras = self.parse_known_args(args, namespace)
        if extras:
            parser = self._command_parser(parsed)
            options = [o for o in parser._option_string_actions if o.startswith("--")]
            hints = "".join(
                near(extra.split("=", 1)[0], options, quoted=False)
                for extra in extras
                if extra.startswith("--")
            )
            parser.error(f"unrecognized arguments: {' '.join(extras)}{hints}")
        return parsed

    def _command_parser(self, parsed: argparse.Namespace) -> argparse.ArgumentParser:
        """The parser of the command ``parsed`` names (this one where it names none)."""
        for action in self._actions:
            if isinstance(action, argparse._SubParsersAction):
                found = action.choices.get(getattr(parsed, "command", None) or "")
                if isinstance(found, argparse.ArgumentParser):
                    return found
        return self

    def _print_message(self, message: str, file: Any = None) -> None:
        # the one place argparse writes: help, usage, --version and its error messages
        if not message or file is not sys.stdout:
            super()._print_message(message, file)
            return
        try:
            write_stdout(message)
        except BrokenPipeError:  # the reader went away (`| head`): not an error
            drop_stdout()


def commands() -> tuple[Command, ...]:
    """The commands, in the order ``--help`` lists them."""
    from . import (
        calibrate,
        convert,
        diff,
        export,
        info,
        match,
        measure,
        plan,
        plot,
        robots,
        verify,
    )

    return convert, verify, diff, match, info, export, plot, robots, measure, calibrate, plan


def command_of(argv: list[str]) -> str:
    """The command a command line names: its first argument, unless that is an option (``""``:
    then no command's options are needed, or all are, for ``--help``)."""
    return argv[0] if argv and not argv[0].startswith("-") else ""


def get_argument_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The argument parser of the ``urdf2dh`` command; each command's parser holds the function
    that runs it (``args.run``). With ``only``, the options of that command alone are declared
    (a run parses one command's: :func:`urdf2dh.cli.run.main` builds no other's); every command
    is listed all the same."""
    parser = ArgumentParser(
        prog="urdf2dh",
        description="Turn a robot's URDF (or POE model) into exact Denavit-Hartenberg, "
        "modified D-H and CPC tables, checked against the source and against Pinocchio.",
    )
    parser.add_argument("--version", action=_Version)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for command in commands():
        p = sub.add_parser(
            command.NAME,
            help=command.HELP,
            epilog=f"example:\n  {command.EXAMPLE}",
            formatter_class=argparse.RawDescriptionHelpFormatter,  # the example on its own line
        )
        if only is None or only == command.NAME:
            command.add_arguments(p)
        p.set_defaults(run=command.run)
    return parser
