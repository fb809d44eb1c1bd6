"""The command line's shared options: value types that say what they take and what they got,
and the option groups every chain command has (SOURCE, --base/--tip, mimic and xacro options,
the tolerance judgements). :mod:`urdf2dh.cli` and :mod:`urdf2dh.calibrate.cli` build their
parsers from these."""

from __future__ import annotations

import argparse
from typing import Any

from .tolerances import MAX_SAMPLES, MAX_SEED

__all__ = [
    "MAX_SAMPLES",
    "add_chain",
    "add_chain_options",
    "add_tolerances",
    "integer",
    "nonnegative_float",
    "package_path",
    "parallel_angle",
    "positive_float",
    "positive_int",
    "samples",
    "seed",
    "tolerances",
    "xacro_arg",
    "xacro_options",
]

MAX_PARALLEL_ANGLE = 0.1  # rad: beyond, "nearly parallel" would take in perpendicular axes


def integer(text: str, low: int, high: int) -> int:
    try:
        value = int(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(f"'{text}' is not an integer") from e
    if not low <= value <= high:
        raise argparse.ArgumentTypeError(f"must be from {low} to {high}, not {value}")
    return value


def positive_int(text: str) -> int:
    return integer(text, 1, 2**31 - 1)


def samples(text: str) -> int:
    return integer(text, 1, MAX_SAMPLES)


def seed(text: str) -> int:
    return integer(text, 0, MAX_SEED)


def parallel_angle(text: str) -> float:
    value = nonnegative_float(text)
    if value > MAX_PARALLEL_ANGLE:
        raise argparse.ArgumentTypeError(f"must be at most {MAX_PARALLEL_ANGLE} rad, not {text}")
    return value


def nonnegative_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from e
    if not value >= 0.0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0, not {text}")
    return value


def package_path(text: str) -> tuple[str, str]:
    name, sep, directory = text.partition("=")
    if not sep or not name or not directory:
        raise argparse.ArgumentTypeError(f"expected NAME=DIR, not '{text}'")
    return name, directory


def xacro_arg(text: str) -> tuple[str, str]:
    name, sep, value = text.partition(":=")
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"expected NAME:=VALUE, not '{text}'")
    return name, value


def positive_float(text: str) -> float:
    value = nonnegative_float(text)
    if value == 0.0:
        raise argparse.ArgumentTypeError("must be greater than 0")
    return value


def add_chain(p: argparse.ArgumentParser, several: bool = False) -> None:
    p.add_argument(
        "source",
        metavar="SOURCE",
        help="URDF file, POE model file, table file, or bundled robot name",
    )
    add_chain_options(p, several)


def add_chain_options(p: argparse.ArgumentParser, several: bool = False) -> None:
    """The chain options; ``several``: the command takes several chains of a tree (``--tip``
    repeated, into ``args.tips``, or ``--all-tips``)."""
    p.add_argument("--base", metavar="LINK", help="base link (default: the URDF root link)")
    if several:
        tips = p.add_mutually_exclusive_group()
        tips.add_argument(
            "--tip",
            metavar="LINK",
            action="append",
            dest="tips",
            help="tip link (default: the single deepest leaf below the base); "
            "given several times, one chain per tip",
        )
        tips.add_argument(
            "--all-tips",
            action="store_true",
            help="one chain per leaf below the base (leaves reached through "
            "fixed joints only are skipped)",
        )
    else:
        p.add_argument(
            "--tip",
            metavar="LINK",
            help="tip link (default: the single deepest leaf below the base)",
        )
    p.add_argument(
        "--ignore-mimic",
        action="store_true",
        help="treat mimic joints on the chain as independent joints (with a warning)",
    )
    p.add_argument(
        "--package-path",
        type=package_path,
        action="append",
        default=[],
        metavar="NAME=DIR",
        help="for .xacro sources: the directory of ROS package NAME, for $(find NAME) "
        "and package://NAME (repeatable)",
    )
    p.add_argument(
        "--xacro-arg",
        type=xacro_arg,
        action="append",
        default=[],
        metavar="NAME:=VALUE",
        help="for .xacro sources: an argument (repeatable)",
    )
    p.add_argument(
        "--xacro-timeout",
        type=positive_float,
        default=20.0,
        metavar="SECONDS",
        help="for .xacro sources: time the expansion may take (default %(default)g)",
    )
    p.add_argument(
        "--xacro-memory",
        type=positive_int,
        default=1024,
        metavar="MIB",
        help="for .xacro sources: memory the expansion may use (default %(default)s)",
    )


def add_tolerances(p: argparse.ArgumentParser) -> None:
    from .tolerances import DEFAULT

    g = p.add_argument_group("tolerance judgements (D-H conventions)")
    g.add_argument(
        "--exact",
        action="store_true",
        help="no snapping: keep nearly parallel or nearly intersecting axes as they are",
    )
    g.add_argument(
        "--parallel-angle",
        type=parallel_angle,
        metavar="RAD",
        default=DEFAULT.parallel_angle,
        help="treat axes this close to parallel as parallel (default %(default)g rad)",
    )
    g.add_argument(
        "--intersect-distance",
        type=nonnegative_float,
        metavar="LENGTH",
        default=None,
        help="treat lines this close as intersecting or coincident, in the source's "
        f"length unit (default {DEFAULT.intersect_relative:g} x the robot's size)",
    )
    g.add_argument(
        "--check-samples",
        type=samples,
        default=None,
        metavar="N",
        help="configurations of the self-check (default 100; 1000 where axes were "
        "treated as parallel, to measure the deviation)",
    )


def tolerances(args: argparse.Namespace) -> Any:
    """The :class:`~urdf2dh.tolerances.Tolerances` the tolerance options ask for."""
    from dataclasses import replace

    from .tolerances import DEFAULT

    tol = replace(
        DEFAULT, parallel_angle=args.parallel_angle, intersect_distance=args.intersect_distance
    )
    return tol.with_exact() if args.exact else tol


def xacro_options(args: argparse.Namespace) -> Any:
    """The :class:`~urdf2dh.io.xacro.XacroOptions` the xacro options ask for."""
    from .io.xacro import XacroOptions

    return XacroOptions(
        dict(args.package_path), dict(args.xacro_arg), args.xacro_timeout, args.xacro_memory
    )
