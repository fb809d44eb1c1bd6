"""The ``measure`` and ``calibrate`` commands (issue 15, SPEC §5).

Registered by :mod:`urdf2dh.cli` through :func:`add_parsers` and :data:`COMMANDS`. Nothing heavy
is imported at module level: ``urdf2dh --help`` builds these parsers without numpy.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from ..errors import InputError, UsageError, choices, shown
from ..files import check_outputs, write_outputs

__all__ = ["COMMANDS", "add_parsers", "calibrate_command", "measure_command"]


def _fraction(text: str) -> float:
    try:
        value = float(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from e
    if not 0.0 <= value < 1.0:
        raise argparse.ArgumentTypeError(f"must be in [0, 1), not {text}")
    return value


MAX_MARKERS = 100  # markers on one tool (more add nothing a calibration could use)


def add_parsers(sub: Any) -> None:
    """Add ``measure`` and ``calibrate`` to the ``urdf2dh`` subparsers."""
    from .. import options as main  # its option helpers
    from ..conventions import NAMES, STYLES
    from ..formats import FORMATS

    p = sub.add_parser("measure", help="synthetic measurements of a model (for calibrate)")
    main.add_chain(p)
    p.add_argument(
        "--configs",
        type=main.samples,
        required=True,
        metavar="N",
        help="number of configurations, drawn uniformly within the joint limits",
    )
    p.add_argument(
        "--noise-pos",
        type=main.nonnegative_float,
        default=0.0,
        metavar="SIGMA",
        help="position noise per coordinate, source length unit (default 0)",
    )
    p.add_argument(
        "--noise-rot",
        type=main.nonnegative_float,
        default=0.0,
        metavar="SIGMA",
        help="rotation noise per axis, rad (default 0)",
    )
    p.add_argument(
        "--measure",
        choices=("pose", "position"),
        default=None,
        help="pose (default) or position of the tool origin; --markers implies position",
    )
    p.add_argument(
        "--markers",
        type=lambda text: main.integer(text, 1, MAX_MARKERS),
        default=None,
        metavar="K",
        help="measure the positions of K markers at seeded points of the tool",
    )
    p.add_argument(
        "--marker-layout",
        metavar="FILE",
        help="also write the markers' positions on the tool (marker,x,y,z)",
    )
    p.add_argument("--seed", type=main.seed, default=0, metavar="S", help="random seed (default 0)")
    p.add_argument("-o", "--output", metavar="FILE", help="CSV file (default stdout)")

    p = sub.add_parser("calibrate", help="identify a model's parameters from measurements")
    p.add_argument(
        "source",
        metavar="NOMINAL",
        help="the nominal model: URDF, POE model, table file or bundled robot",
    )
    p.add_argument("measurements", metavar="MEASUREMENTS", help="CSV file of measurements")
    main.add_chain_options(p)
    p.add_argument(
        "--measure",
        choices=("pose", "position"),
        default=None,
        help="use the poses (default when the file has qx..qw) or only positions",
    )
    p.add_argument(
        "--convention",
        choices=(*NAMES, "poe"),
        default="dh",
        help="convention of the output (default %(default)s); poe writes a POE model file",
    )
    p.add_argument(
        "--format",
        choices=FORMATS,
        default="text",
        help="output format (default %(default)s; with --convention poe: yaml or json)",
    )
    p.add_argument("--style", choices=STYLES, default="wu", help="D-H choices (see convert)")
    p.add_argument("-o", "--output", metavar="FILE", help="write the model to FILE")
    p.add_argument("--report", metavar="FILE.json", help="write the calibration report (JSON)")
    p.add_argument(
        "--holdout",
        type=_fraction,
        default=0.0,
        metavar="FRACTION",
        help="hold this fraction of the measurements out of the fit, to judge it (default 0)",
    )
    p.add_argument(
        "--seed",
        type=main.seed,
        default=0,
        metavar="S",
        help="seed of the held-out draw (default 0)",
    )
    p.add_argument(
        "--noise-pos",
        type=main.nonnegative_float,
        default=None,
        metavar="SIGMA",
        help="position noise per coordinate (weights; default: estimated)",
    )
    p.add_argument(
        "--noise-rot",
        type=main.nonnegative_float,
        default=None,
        metavar="SIGMA",
        help="rotation noise per axis, rad (weights; default: estimated)",
    )
    p.add_argument(
        "--helical",
        metavar="JOINTS",
        default="",
        help="identify these revolute joints' pitch too: comma-separated names, or "
        "'all' (helical joints of the nominal always are)",
    )
    p.add_argument(
        "--keep-scale",
        action="store_true",
        help="keep the nominal's joint scales (controllers without a joint scale)",
    )
    p.add_argument(
        "--keep-tool-axis",
        action="store_true",
        help="keep the tool's placement relative to the last joint axis; identify "
        "only its turn about and slide along it (UR: flange on D-H frame 6)",
    )
    p.add_argument(
        "--frame",
        choices=("device", "nominal"),
        default="device",
        help="frame of the output model: the measuring device's (default) or the "
        "nominal base, anchored on joint 1's axis and fitted to the nominal",
    )
    p.add_argument(
        "--marker-layout",
        metavar="FILE",
        help="the markers' nominal positions on the tool (marker,x,y,z): they define "
        "the tool frame of position measurements (needed for 2 or more markers)",
    )
    p.add_argument(
        "--max-iterations",
        type=main.positive_int,
        default=100,
        metavar="N",
        help="Levenberg-Marquardt iterations at most (default %(default)s)",
    )
    main.add_tolerances(p)


def _model(args: argparse.Namespace, tol: Any = None) -> Any:
    from ..options import xacro_options
    from ..sources import open_source
    from ..tolerances import DEFAULT

    source = open_source(args.source, tol or DEFAULT, xacro=xacro_options(args))
    model = source.model(args.base, args.tip, args.ignore_mimic)
    coupled = [f"{shown(j.name)} (mimics {shown(j.mimic.joint)})" for j in model.joints if j.mimic]
    if coupled:
        raise InputError(
            f"{args.source}: joints {', '.join(coupled)} follow another joint; calibration "
            "identifies every joint's screw and scale on its own (--ignore-mimic makes them "
            "independent)"
        )
    return model


def measure_command(args: argparse.Namespace) -> int:
    """``urdf2dh measure``: write synthetic measurements (module :mod:`.measure`)."""
    from .measure import marker_layout, synthesize
    from .measurements import write_layout, write_measurements

    model = _model(args)
    pose = args.measure != "position" and args.markers is None
    if args.markers is not None and args.measure == "pose":
        raise UsageError("--markers measures positions; it does not go with --measure pose")
    if args.marker_layout and args.markers is None:
        raise UsageError("--marker-layout writes the layout of --markers K")
    layout = marker_layout(model, args.markers, args.seed) if args.markers else None
    m = synthesize(model, args.configs, args.noise_pos, args.noise_rot, args.seed, layout, pose)
    outputs = [(args.output, write_measurements(m))]
    if args.marker_layout and layout is not None:
        outputs.append((args.marker_layout, write_layout(layout)))
    write_outputs(outputs)
    return 0


def _helical(text: str, joints: tuple[str, ...]) -> tuple[str, ...]:
    names = tuple(n.strip() for n in text.split(",") if n.strip())
    if names == ("all",):
        return names
    unknown = [n for n in names if n not in joints]
    if unknown:
        raise UsageError(
            f"--helical: {shown(unknown[0])} is not a joint of the chain; valid: "
            f"{choices(joints)} or all"
        )
    return names


def calibrate_command(args: argparse.Namespace) -> int:
    """``urdf2dh calibrate``: identify, convert, report (see README "Calibration")."""
    from ..options import tolerances
    from .measurements import read_layout, read_measurements
    from .run import Request, run

    tol = tolerances(args)
    nominal = _model(args, tol)
    joints = tuple(j.name for j in nominal.joints)
    m = read_measurements(args.measurements, joints)
    if args.measure == "pose" and m.quaternions is None:
        raise InputError(f"{args.measurements}: --measure pose needs the columns qx, qy, qz, qw")
    pose = m.quaternions is not None and args.measure != "position"
    if pose and m.markers is not None:
        raise InputError(
            f"{args.measurements}: a 'marker' column goes with position "
            "measurements (--measure position)"
        )
    layout = read_layout(args.marker_layout) if args.marker_layout else None
    check_outputs([args.output, args.report])  # before the fit, which may take long
    request = Request(
        nominal=nominal,
        measurements=m,
        pose=pose,
        convention=args.convention,
        fmt=args.format,
        style=args.style,
        tol=tol,
        check_samples=args.check_samples,
        holdout=args.holdout,
        seed=args.seed,
        noise_pos=args.noise_pos,
        noise_rot=args.noise_rot,
        helical=_helical(args.helical, joints),
        keep_scale=args.keep_scale,
        keep_tool_axis=args.keep_tool_axis,
        frame=args.frame,
        layout=layout,
        max_iterations=args.max_iterations,
    )
    outcome = run(request)
    outputs = [(args.output, outcome.text)]
    if args.report:
        outputs.append((args.report, outcome.report))
    write_outputs(outputs)
    print(outcome.summary, end="", file=sys.stdout if args.output else sys.stderr)
    return 0


COMMANDS = {"measure": measure_command, "calibrate": calibrate_command}
