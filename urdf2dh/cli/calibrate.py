"""``urdf2dh calibrate NOMINAL MEASUREMENTS``: identify a model's parameters, write the
calibrated model, its report and its pictures (``docs/calibration.md``)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from ..errors import InputError, UsageError, choices, shown
from ..io.files import check_outputs, write_outputs
from . import options

__all__ = ["EXAMPLE", "HELP", "NAME", "add_arguments", "run"]

NAME = "calibrate"
HELP = "identify a model's parameters from measurements"
EXAMPLE = "urdf2dh calibrate puma560-nominal m.csv --helical all --format json -o puma-id.json"


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..calibration.levels import AUTO
    from ..calibration.levels import NAMES as LEVELS
    from ..conventions import NAMES, STYLES
    from ..emit.formats import FORMATS
    from ..io.sources import source_kinds

    p.add_argument(
        "source",
        metavar="NOMINAL",
        help=f"the nominal model: {source_kinds()} file, or bundled robot name",
    )
    p.add_argument("measurements", metavar="MEASUREMENTS", help="CSV file of measurements")
    options.add_chain_options(p)
    p.add_argument(
        "--measure",
        choices=("pose", "position"),
        default=None,
        help="use the poses (default when the file has an orientation) or only positions",
    )
    p.add_argument(
        "--identify",
        choices=(AUTO, *LEVELS),
        default=AUTO,
        help="how much to identify: base and tool only, and joint offsets, and every joint's "
        "line, and joint scales; auto (default) chooses the level that best predicts "
        "configurations left out of the fit",
    )
    p.add_argument(
        "--fix",
        type=options.names,
        action="append",
        default=[],
        metavar="NAMES",
        help="hold these parameters at the nominal's values: names or shell patterns "
        "(j1.turn1, *.scale, arm_7_joint.*), comma-separated (repeatable)",
    )
    p.add_argument(
        "--prior",
        type=options.prior,
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
        help="convention of the output (default dh, or hayati where a D-H table is not the one "
        "to write: docs/parallel-axes.md); poe writes a POE model file",
    )
    options.add_format(p, FORMATS, "; with --convention poe: yaml or json")
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
        type=options.fraction,
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
        type=options.seed,
        default=0,
        metavar="S",
        help="seed of the held-out draw and of --folds (default 0)",
    )
    p.add_argument(
        "--folds",
        type=lambda text: options.integer(text, 2, 1000),
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
        help="position noise per coordinate, > 0, in the measurement file's length unit "
        "(--length-unit, else the nominal's) (weights; default: estimated)",
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
        default=None,
        help="frame of the output model: the measuring device's (default) or the "
        "nominal base, anchored on joint 1's axis and fitted to the nominal (default with "
        "--like)",
    )
    options.add_like(p)
    p.add_argument(
        "--marker-layout",
        metavar="FILE",
        help="the markers' nominal positions on the tool (marker,x,y,z): they define "
        "the tool frame of position measurements (needed for 2 or more markers)",
    )
    p.add_argument(
        "--accept-implausible",
        action="store_true",
        help="write a calibration the measurements contradict all the same (residuals beyond "
        "any device's or the noise given, a file that another reading explains: by default "
        "the run stops with exit 3, naming the cause and the option that fixes it)",
    )
    p.add_argument(
        "--max-iterations",
        type=options.positive_int,
        default=200,
        metavar="N",
        help="Levenberg-Marquardt iterations of one fit at most (default %(default)s)",
    )
    options.add_reading(p)
    options.add_tolerances(p)


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


def _reading(args: argparse.Namespace) -> Any:
    from ..calibration.measurements import Reading

    return Reading(
        rename=tuple(pair for group in args.rename for pair in group),
        ignore=tuple(name for group in args.ignore for name in group),
        degrees=args.degrees,
        length_unit=args.length_unit,
        euler=args.euler,
    )


def run(args: argparse.Namespace) -> int:
    """``urdf2dh calibrate``: identify, convert, report (docs/calibration.md)."""
    from ..calibration.calibration import calibrate
    from ..calibration.measurements import check_noise, read_layout, read_measurements
    from ..calibration.prior import Prior
    from ..calibration.report import summary, to_dict
    from ..calibration.userunits import UserUnits
    from ..emit.formats import FORMATS
    from .options import tolerances

    # before anything is read
    args.format = options.output_format(args, FORMATS, poe_file=args.convention == "poe")
    tol = tolerances(args)
    options.check_like(args)
    if args.like and args.frame == "device":
        raise UsageError(
            "--like writes the model into NOMINAL's base link: --frame nominal, not device"
        )
    frame = args.frame or ("nominal" if args.like else "device")
    if args.like and args.convention:
        raise UsageError("--like writes a URDF; --convention does not apply")
    nominal = options.nominal(args, tol)
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
    user = UserUnits.of(nominal.length_unit, m)
    for flag, value in (("--noise-pos", args.noise_pos), ("--noise-rot", args.noise_rot)):
        try:
            check_noise(
                value if flag == "--noise-pos" else None,
                value if flag == "--noise-rot" else None,
                user.shown(nominal.size()),
                user.length,
            )
        except InputError as e:
            raise UsageError(f"{flag} {value:g}: {e}") from e
    cal = calibrate(
        nominal,
        m,
        level=args.identify,
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
        frame=frame,
        layout=layout,
        reject=args.reject,
        convention="poe" if args.like else args.convention,
        style=args.style,
        tol=tol,
        max_iterations=args.max_iterations,
        check_samples=args.check_samples,
        accept=args.accept_implausible,
    )
    text = options.like(args, cal.model, tol) if args.like else _model_text(cal, args.format)
    outputs: list[tuple[str | None, str | bytes]] = [(args.output, text)]
    if args.report:
        import json

        outputs.append((args.report, json.dumps(to_dict(cal), indent=2) + "\n"))
    if args.plot:
        from ..calibration.plot import plot_calibration

        plot = plot_calibration(cal, Path(args.plot).suffix.lower().lstrip("."))
        outputs.append((args.plot, plot))
    shown = summary(cal)  # made before anything is written: it reads the diff, made when read
    write_outputs(outputs)
    print(shown, end="", file=sys.stdout if args.output else sys.stderr)
    return 0


def _model_text(cal: Any, fmt: str) -> str:
    """The identified model in the chosen convention and format."""
    from ..emit.formats import render

    if cal.table is not None:
        return render(cal.table, fmt)
    import json

    from ..io.poefile import poe_to_dict

    tree = poe_to_dict(cal.model)
    if fmt == "json":
        return json.dumps(tree, indent=2) + "\n"
    import yaml

    return str(yaml.safe_dump(tree, sort_keys=False, default_flow_style=None))
