"""The command line's shared options: value types that say what they take and what they got,
and the option groups several commands have (SOURCE, --base/--tip, mimic and xacro options, the
tolerance judgements; calibration's levels, markers and measurement files). Each command's
module builds its parser from these."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..errors import InputError, UsageError, choices, shown
from ..tolerances import MAX_MARKERS, MAX_SAMPLES, MAX_SEED

if TYPE_CHECKING:
    from ..io.fields import JointBound
    from ..io.sources import Source
    from ..io.xacro import XacroOptions
    from ..model.poe import PoeModel
    from ..tolerances import Tolerances

__all__ = [
    "add_chain",
    "add_chain_options",
    "add_format",
    "add_like",
    "add_markers",
    "add_reading",
    "add_tolerances",
    "check_like",
    "fraction",
    "integer",
    "like",
    "names",
    "nominal",
    "nonnegative_float",
    "output_format",
    "package_path",
    "parallel_angle",
    "positive_float",
    "positive_int",
    "prior",
    "renames",
    "samples",
    "seed",
    "source",
    "tolerances",
    "xacro_arg",
    "xacro_options",
]

MAX_PARALLEL_ANGLE = 0.1  # rad: beyond, "nearly parallel" would take in perpendicular axes


def integer(text: str, low: int, high: int) -> int:
    """An option's integer: decimal ASCII digits with an optional sign (no ``1_000``, no
    ``１``, which Python's ``int`` takes), from ``low`` to ``high``."""
    from ..numerals import integer as read_integer

    value = read_integer(text)
    if value is None:
        raise argparse.ArgumentTypeError(f"'{text}' is not an integer")
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


def number(text: str) -> float:
    """An option's number, by the grammar of urdf2dh's files (:mod:`urdf2dh.numerals`)."""
    from ..numerals import decimal, why_not

    value = decimal(text)
    if value is None:
        reason = why_not(text)
        said = "" if reason == "not a decimal number" else f" ({reason})"
        raise argparse.ArgumentTypeError(f"'{text}' is not a number{said}")
    return value


def nonnegative_float(text: str) -> float:
    value = number(text)
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
    from ..io.sources import source_kinds

    p.add_argument(
        "source",
        metavar="SOURCE",
        help=f"{source_kinds()} file, or bundled robot name",
    )
    add_chain_options(p, several)


def add_chain_options(p: argparse.ArgumentParser, several: bool = False, of: str = "") -> None:
    """The chain options; ``several``: the command takes several chains of a tree (``--tip``
    repeated, into ``args.tips``, or ``--all-tips``); ``of``: which of the command's sources
    they apply to, where it reads several (words appended to both helps)."""
    p.add_argument("--base", metavar="LINK", help=f"base link{of} (default: the URDF root link)")
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
            help=f"tip link{of} (default: the single deepest leaf below the base)",
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
        "and package://NAME; the expansion reads only beneath these and the SOURCE's "
        "directory (repeatable)",
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


def add_format(p: argparse.ArgumentParser, formats: tuple[str, ...], also: str = "") -> None:
    """``--format``, one of ``formats``; without it, the suffix of ``-o FILE`` chooses
    (:func:`output_format`), else the first of ``formats``. ``also``: more help text."""
    p.add_argument(
        "--format",
        choices=formats,
        default=None,
        help=f"output format (default: the one the suffix of -o FILE names, else {formats[0]}"
        f"{also})",
    )


def output_format(
    args: argparse.Namespace, formats: tuple[str, ...], poe_file: bool = False
) -> str:
    """The format a command writes: ``--format``, or the one the suffix of ``-o FILE`` names
    (``.json``, ``.yaml``, ``.csv``, ...: :data:`urdf2dh.emit.formats.SUFFIXES`), or the first of
    ``formats``. Called before anything is read. ``poe_file``: the command writes a POE model
    file, whose YAML form a ``.poe.yaml`` name names.

    Raises
    ------
    UsageError
        The suffix names a format that ``--format`` contradicts, or one the command does not
        write (``diff -o d.yaml``).
    """
    from ..emit.formats import format_of
    from .chains import names_directory

    output = args.output
    named = None if output is None or names_directory(output) else format_of(output)
    if poe_file and named == "poe":
        named = "yaml"
    if named is not None and named not in formats:
        raise UsageError(
            f"-o {shown(output)}: a file of that name is {named}, which {args.command} does not "
            f"write; its formats are {choices(formats)}"
        )
    if args.format is None:
        return named or formats[0]
    if named == "yaml" and args.format == "poe":
        return "poe"  # a POE model file is a YAML document: x.yaml says no other
    if named is not None and named != args.format:
        raise UsageError(
            f"-o {shown(output)} names a {named} file, --format {args.format} another: leave "
            "--format out (the suffix chooses), or name the file for its format"
        )
    return str(args.format)


def add_like(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--like",
        metavar="NOMINAL",
        help="with --format urdf: write NOMINAL (a URDF) with only its joint origins and axes "
        "changed, so that its forward kinematics is the model's while every link keeps its "
        "visual, collision and inertial elements in its own frame",
    )


def like(args: argparse.Namespace, model: PoeModel, tol: Tolerances) -> str:
    """The URDF ``--like NOMINAL`` asks for (``--format urdf`` or no format), its notes on
    stderr."""
    import sys

    from ..emit.urdf_like import urdf_like

    result = urdf_like(model, args.like, tol=tol, xacro=xacro_options(args))
    for note in result.notes:
        print(f"urdf2dh: {note}", file=sys.stderr)
    print(f"urdf2dh: {result.summary()}", file=sys.stderr)
    return result.text


def check_like(args: argparse.Namespace, default: str = "text") -> None:
    """``--like`` writes a URDF: with ``--format urdf`` (or none given), into a NOMINAL that is
    named (an empty one is not taken for none)."""
    from ..errors import UsageError

    if args.like == "":
        raise UsageError("--like: NOMINAL is empty (the path of the URDF to write into)")
    if args.like and args.format not in ("urdf", default):
        raise UsageError(f"--like writes a URDF: --format urdf, not {args.format}")


def add_tolerances(p: argparse.ArgumentParser) -> None:
    from ..tolerances import DEFAULT

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


def tolerances(args: argparse.Namespace) -> Tolerances:
    """The :class:`~urdf2dh.tolerances.Tolerances` the tolerance options ask for."""
    from dataclasses import replace

    from ..tolerances import DEFAULT

    tol = replace(
        DEFAULT, parallel_angle=args.parallel_angle, intersect_distance=args.intersect_distance
    )
    return tol.with_exact() if args.exact else tol


def xacro_options(args: argparse.Namespace) -> XacroOptions:
    """The :class:`~urdf2dh.io.xacro.XacroOptions` the xacro options ask for."""
    from ..io.xacro import XacroOptions

    return XacroOptions(
        dict(args.package_path), dict(args.xacro_arg), args.xacro_timeout, args.xacro_memory
    )


def source(
    args: argparse.Namespace, tol: Tolerances | None = None, bound: JointBound | None = None
) -> Source:
    """The SOURCE the options name, opened with their xacro options (and ``tol`` for reading a
    POE or table file, ``bound`` the command's bound on a URDF's joints)."""
    from ..io.sources import open_source
    from ..tolerances import DEFAULT

    return open_source(args.source, tol or DEFAULT, xacro=xacro_options(args), bound=bound)


# --------------------------------------------------------------------------- calibration


def fraction(text: str) -> float:
    value = number(text)
    if not 0.0 <= value < 1.0:
        raise argparse.ArgumentTypeError(f"must be in [0, 1), not {text}")
    return value


def names(text: str) -> tuple[str, ...]:
    return tuple(n.strip() for n in text.split(",") if n.strip())


def renames(text: str) -> tuple[tuple[str, str], ...]:
    out = []
    for item in names(text):
        old, sep, new = item.partition("=")
        if not sep or not old.strip() or not new.strip():
            raise argparse.ArgumentTypeError(f"'{item}' is not OLD=NEW")
        out.append((old.strip(), new.strip()))
    return tuple(out)


def prior(text: str) -> tuple[float, float] | str:
    if text in ("auto", "none"):  # calibration.prior.CHOICES (not imported: --help stays fast)
        return text
    parts = text.split(",")
    if len(parts) != 2:
        raise argparse.ArgumentTypeError(f"'{text}' is not auto, none or LENGTH,ANGLE")
    try:
        length, angle = float(parts[0]), float(parts[1])
    except ValueError as e:
        raise argparse.ArgumentTypeError(f"'{text}' is not LENGTH,ANGLE (two numbers)") from e
    if not (length > 0.0 and angle > 0.0 and length < float("inf") and angle < float("inf")):
        raise argparse.ArgumentTypeError(f"both deviations must be > 0, not {text}")
    return length, angle


def add_reading(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("reading measurement files as they come")
    g.add_argument(
        "--rename",
        type=renames,
        action="append",
        default=[],
        metavar="OLD=NEW,...",
        help="read the file's column OLD as NEW (a joint's name, x, qw, roll, ...; repeatable)",
    )
    g.add_argument(
        "--ignore",
        type=names,
        action="append",
        default=[],
        metavar="COLUMNS",
        help="skip these columns: names or shell patterns, comma-separated (repeatable)",
    )
    g.add_argument(
        "--degrees",
        action="store_true",
        help="joint angles and roll, pitch, yaw are in degrees (default radians)",
    )
    g.add_argument(
        "--length-unit",
        metavar="UNIT",
        help="the file's length unit, converted to the nominal's (default: the nominal's)",
    )
    g.add_argument(
        "--euler",
        default="xyz",
        metavar="SEQ",
        help="rotation sequence of roll, pitch, yaw (or FIGAROH's phix1..phiz1), scipy's "
        "notation: lower case fixed axes, upper case moving (default xyz: URDF's "
        "R = Rz(yaw) Ry(pitch) Rx(roll))",
    )


def add_markers(p: argparse.ArgumentParser, help_text: str) -> None:

    p.add_argument(
        "--markers",
        type=lambda text: integer(text, 1, MAX_MARKERS),
        default=None,
        metavar="K",
        help=help_text,
    )


def nominal(args: argparse.Namespace, tol: Tolerances | None = None) -> PoeModel:
    """The nominal model of a calibration command: the chain the options name, none of whose
    joints mimics another (calibration identifies each joint on its own)."""
    model = source(args, tol).model(args.base, args.tip, args.ignore_mimic)
    coupled = [f"{shown(j.name)} (mimics {shown(j.mimic.joint)})" for j in model.joints if j.mimic]
    if coupled:
        raise InputError(
            f"{args.source}: joints {', '.join(coupled)} follow another joint; calibration "
            "identifies every joint's screw and scale on its own (--ignore-mimic makes them "
            "independent)"
        )
    return model
