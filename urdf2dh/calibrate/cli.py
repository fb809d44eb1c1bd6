"""The ``measure``, ``calibrate`` and ``plan`` commands: parse, call the library, print, write.

Registered by :mod:`urdf2dh.cli` through :func:`add_parsers` and :data:`COMMANDS`. Nothing heavy
is imported at module level: ``urdf2dh --help`` builds these parsers without numpy.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from ..errors import InputError, UsageError, choices, shown
from ..files import check_outputs, write_outputs

__all__ = ["COMMANDS", "add_parsers", "calibrate_command", "measure_command", "plan_command"]

LEVEL_CHOICES = ("auto", "base-tool", "offsets", "geometry", "full")
MAX_MARKERS = 100  # markers on one tool (more add nothing a calibration could use)


def _fraction(text: str) -> float:
    try:
        value = float(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from e
    if not 0.0 <= value < 1.0:
        raise argparse.ArgumentTypeError(f"must be in [0, 1), not {text}")
    return value


def _names(text: str) -> tuple[str, ...]:
    return tuple(n.strip() for n in text.split(",") if n.strip())


def _renames(text: str) -> tuple[tuple[str, str], ...]:
    out = []
    for item in _names(text):
        old, sep, new = item.partition("=")
        if not sep or not old.strip() or not new.strip():
            raise argparse.ArgumentTypeError(f"'{item}' is not OLD=NEW")
        out.append((old.strip(), new.strip()))
    return tuple(out)


def _prior(text: str) -> tuple[float, float] | str:
    if text in ("auto", "none"):  # .prior.CHOICES (not imported here: --help stays fast)
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


def _add_reading(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("reading measurement files as they come")
    g.add_argument(
        "--rename",
        type=_renames,
        action="append",
        default=[],
        metavar="OLD=NEW,...",
        help="read the file's column OLD as NEW (a joint's name, x, qw, roll, ...; repeatable)",
    )
    g.add_argument(
        "--ignore",
        type=_names,
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


def _add_markers(p: argparse.ArgumentParser, help_text: str) -> None:
    from .. import options as main

    p.add_argument(
        "--markers",
        type=lambda text: main.integer(text, 1, MAX_MARKERS),
        default=None,
        metavar="K",
        help=help_text,
    )


def add_parsers(sub: Any) -> None:
    """Add ``measure``, ``calibrate`` and ``plan`` to the ``urdf2dh`` subparsers."""
    from .. import options as main  # its option helpers
    from ..conventions import NAMES, STYLES
    from ..formats import FORMATS

    p = sub.add_parser("measure", help="synthetic measurements of a model (for calibrate)")
    main.add_chain(p)
    p.add_argument(
        "--configs",
        type=main.samples,
        default=None,
        metavar="N",
        help="number of configurations, drawn uniformly within the joint limits (or give "
        "--configurations)",
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
    _add_markers(p, "measure the positions of K markers at seeded points of the tool")
    p.add_argument(
        "--marker-layout",
        metavar="FILE",
        help="also write the markers' positions on the tool (marker,x,y,z)",
    )
    p.add_argument(
        "--configurations",
        metavar="FILE",
        help="measure at these configurations (a CSV with a column per joint, e.g. what "
        "plan writes) instead of random ones",
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
        help="use the poses (default when the file has an orientation) or only positions",
    )
    p.add_argument(
        "--identify",
        choices=LEVEL_CHOICES,
        default="auto",
        help="how much to identify: base and tool only, and joint offsets, and every joint's "
        "line, and joint scales; auto (default) chooses the level that best predicts "
        "configurations left out of the fit",
    )
    p.add_argument(
        "--fix",
        type=_names,
        action="append",
        default=[],
        metavar="NAMES",
        help="hold these parameters at the nominal's values: names or shell patterns "
        "(j1.turn1, *.scale, arm_7_joint.*), comma-separated (repeatable)",
    )
    p.add_argument(
        "--prior",
        type=_prior,
        default="auto",
        metavar="auto|none|LENGTH,ANGLE",
        help="pull the joints' parameters toward the nominal's as errors of its links: auto "
        "(default) with the deviations the measurements support, at the geometry and full "
        "levels; none; or these standard deviations at every level (lengths in the nominal's "
        "unit; angles in rad, also for scales)",
    )
    p.add_argument(
        "--convention",
        choices=(*NAMES, "poe"),
        default=None,
        help="convention of the output (default: dh where it is exact and sane, else hayati); "
        "poe writes a POE model file",
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
        "--plot",
        metavar="FILE",
        help="draw residuals before and after, their distribution and the largest parameter "
        "changes: FILE.png, or FILE.html (interactive, self-contained)",
    )
    p.add_argument(
        "--holdout",
        type=_fraction,
        default=0.0,
        metavar="FRACTION",
        help="hold this fraction of the configurations out of the fit, to judge it (default 0)",
    )
    p.add_argument(
        "--validate",
        metavar="FILE",
        help="judge the identified model on the measurements of FILE too",
    )
    p.add_argument(
        "--seed",
        type=main.seed,
        default=0,
        metavar="S",
        help="seed of the held-out draw and of --folds (default 0)",
    )
    p.add_argument(
        "--folds",
        type=lambda text: main.integer(text, 2, 1000),
        default=None,
        metavar="K",
        help="judge the levels by leaving out K seeded folds of configurations in turn "
        "(default: each configuration alone)",
    )
    p.add_argument(
        "--choose",
        choices=("simplest", "best"),
        default="simplest",
        help="with --identify auto: the simplest level whose error on left-out configurations "
        "is within one standard error of the best's (default), or the best",
    )
    outliers = p.add_mutually_exclusive_group()
    outliers.add_argument(
        "--reject-outliers",
        dest="reject",
        action="store_const",
        const=True,
        default=None,
        help="reject the measurements the fit cannot explain (a chance below 1e-6 of so large "
        "a residual from the noise) and fit again without them; by default they are rejected "
        "when that predicts the other configurations better",
    )
    outliers.add_argument(
        "--keep-outliers",
        dest="reject",
        action="store_const",
        const=False,
        help="keep them (they are listed)",
    )
    p.add_argument(
        "--noise-pos",
        type=float,
        default=None,
        metavar="SIGMA",
        help="position noise per coordinate, > 0 (weights; default: estimated)",
    )
    p.add_argument(
        "--noise-rot",
        type=float,
        default=None,
        metavar="SIGMA",
        help="rotation noise per axis, rad, > 0 (weights; default: estimated)",
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
        default=200,
        metavar="N",
        help="Levenberg-Marquardt iterations of one fit at most (default %(default)s)",
    )
    _add_reading(p)
    main.add_tolerances(p)

    p = sub.add_parser("plan", help="choose configurations to measure for a calibration")
    main.add_chain(p)
    p.add_argument(
        "--configs",
        type=lambda text: main.integer(text, 1, 100_000),
        required=True,
        metavar="N",
        help="number of configurations to choose",
    )
    p.add_argument(
        "--identify",
        choices=LEVEL_CHOICES[1:],
        default="full",
        help="the level to plan for (default %(default)s)",
    )
    p.add_argument(
        "--candidates",
        metavar="FILE",
        help="choose among these configurations (a CSV with a column per joint) instead of "
        "random ones within the joint limits",
    )
    p.add_argument(
        "--measure",
        choices=("pose", "position"),
        default="pose",
        help="what will be measured (default %(default)s)",
    )
    _add_markers(p, "position measurements of K markers at seeded points of the tool")
    p.add_argument(
        "--noise-pos",
        type=main.positive_float,
        default=None,
        metavar="SIGMA",
        help="position noise per coordinate, for the expected uncertainty (default 0.1 mm)",
    )
    p.add_argument(
        "--noise-rot",
        type=main.positive_float,
        default=None,
        metavar="SIGMA",
        help="rotation noise per axis, rad (default 1e-4)",
    )
    p.add_argument("--seed", type=main.seed, default=0, metavar="S", help="random seed (default 0)")
    p.add_argument("-o", "--output", metavar="FILE", help="CSV file (default stdout)")


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
    from .measure import measure
    from .measurements import read_configurations, write_layout, write_measurements

    model = _model(args)
    pose = args.measure != "position" and args.markers is None
    if args.markers is not None and args.measure == "pose":
        raise UsageError("--markers measures positions; it does not go with --measure pose")
    if args.marker_layout and args.markers is None:
        raise UsageError("--marker-layout writes the layout of --markers K")
    if (args.configs is None) == (args.configurations is None):
        raise UsageError("measure takes --configs N or --configurations FILE (one of them)")
    configurations = None
    if args.configurations:
        joints = tuple(j.name for j in model.joints)
        configurations = read_configurations(args.configurations, joints)
    m, layout = measure(
        model,
        args.configs or 0,
        args.noise_pos,
        args.noise_rot,
        args.seed,
        args.markers,
        pose,
        configurations,
    )
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
            f"--helical: {unknown[0]!r} is not a joint of the chain; valid: "
            f"{choices(joints)} or all"
        )
    return names


def _reading(args: argparse.Namespace) -> Any:
    from .measurements import Reading

    return Reading(
        rename=tuple(pair for group in args.rename for pair in group),
        ignore=tuple(name for group in args.ignore for name in group),
        degrees=args.degrees,
        length_unit=args.length_unit,
        euler=args.euler,
    )


def calibrate_command(args: argparse.Namespace) -> int:
    """``urdf2dh calibrate``: identify, convert, report (docs/calibration.md)."""
    from ..options import tolerances
    from .calibration import calibrate, check_noise
    from .measurements import read_layout, read_measurements
    from .prior import Prior
    from .report import summary, to_dict

    tol = tolerances(args)
    nominal = _model(args, tol)
    joints = tuple(j.name for j in nominal.joints)
    sliding = tuple(j.name for j in nominal.joints if j.kind == "prismatic")
    reading = _reading(args)

    def read(path: str) -> Any:
        return read_measurements(
            path, joints, reading=reading, sliding=sliding, length_unit=nominal.length_unit
        )

    m = read(args.measurements)
    validation = read(args.validate) if args.validate else None
    if args.measure == "pose" and m.quaternions is None:
        raise InputError(
            f"{args.measurements}: --measure pose needs an orientation (qx, qy, qz, qw, or "
            "roll, pitch, yaw)"
        )
    pose = m.quaternions is not None and args.measure != "position"
    if pose and m.markers is not None:
        raise InputError(
            f"{args.measurements}: a 'marker' column goes with position "
            "measurements (--measure position)"
        )
    if args.plot and Path(args.plot).suffix.lower() not in (".png", ".html", ".htm"):
        raise UsageError(f"--plot {args.plot}: FILE.png or FILE.html")
    layout = read_layout(args.marker_layout) if args.marker_layout else None
    if not pose and layout is None and len(m.marker_ids()) > 1:
        raise InputError(
            f"{args.measurements}: {len(m.marker_ids())} markers; give their positions on the "
            "tool (--marker-layout FILE, marker,x,y,z) to define the tool frame"
        )
    check_outputs([args.output, args.report, args.plot])  # before the fit, which may take long
    if args.convention == "poe" and args.format not in ("yaml", "poe", "text", "json"):
        raise UsageError(
            f"--convention poe writes a POE model file: --format yaml or json, not {args.format}"
        )
    for flag, value in (("--noise-pos", args.noise_pos), ("--noise-rot", args.noise_rot)):
        try:
            check_noise(
                value if flag == "--noise-pos" else None,
                value if flag == "--noise-rot" else None,
                nominal.size(),
                nominal.length_unit,
            )
        except InputError as e:
            raise UsageError(f"{flag} {value:g}: {e}") from e
    cal = calibrate(
        nominal,
        m,
        identify_level=args.identify,
        pose=pose,
        fixed=tuple(name for group in args.fix for name in group),
        prior=args.prior if isinstance(args.prior, str) else Prior(*args.prior),
        holdout=args.holdout,
        validation=validation,
        seed=args.seed,
        folds=args.folds,
        rule=args.choose,
        noise_pos=args.noise_pos,
        noise_rot=args.noise_rot,
        helical=_helical(args.helical, joints),
        keep_scale=args.keep_scale,
        keep_tool_axis=args.keep_tool_axis,
        frame=args.frame,
        layout=layout,
        reject=args.reject,
        convention=args.convention,
        style=args.style,
        tol=tol,
        max_iterations=args.max_iterations,
        check_samples=args.check_samples,
    )
    text = _model_text(cal, args.format)
    outputs: list[tuple[str | None, str | bytes]] = [(args.output, text)]
    if args.report:
        import json

        outputs.append((args.report, json.dumps(to_dict(cal), indent=2) + "\n"))
    if args.plot:
        from .plot import plot_calibration

        plot = plot_calibration(cal, Path(args.plot).suffix.lower().lstrip("."))
        outputs.append((args.plot, plot))
    write_outputs(outputs)
    print(summary(cal), end="", file=sys.stdout if args.output else sys.stderr)
    return 0


def _model_text(cal: Any, fmt: str) -> str:
    """The identified model in the chosen convention and format."""
    from ..formats import render

    if cal.table is not None:
        return render(cal.table, fmt)
    import json

    from ..poefile import poe_to_dict

    tree = poe_to_dict(cal.model)
    if fmt == "json":
        return json.dumps(tree, indent=2) + "\n"
    import yaml

    return str(yaml.safe_dump(tree, sort_keys=False, default_flow_style=None))


def plan_command(args: argparse.Namespace) -> int:
    """``urdf2dh plan``: choose configurations to measure (module :mod:`.plan`)."""
    from .measurements import read_configurations, write_configurations
    from .plan import plan

    model = _model(args)
    joints = tuple(j.name for j in model.joints)
    candidates = read_configurations(args.candidates, joints) if args.candidates else None
    result = plan(
        model,
        args.configs,
        level=args.identify,
        pose=args.measure == "pose" and args.markers is None,
        markers=args.markers,
        candidates=candidates,
        noise_pos=args.noise_pos,
        noise_rot=args.noise_rot,
        seed=args.seed,
    )
    write_outputs([(args.output, write_configurations(joints, result.configurations))])
    print(result.summary(), end="", file=sys.stdout if args.output else sys.stderr)
    return 0


COMMANDS = {"measure": measure_command, "calibrate": calibrate_command, "plan": plan_command}
