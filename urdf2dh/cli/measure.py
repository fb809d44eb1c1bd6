"""``urdf2dh measure``: synthetic measurements of a model, for trying calibration and testing it."""

from __future__ import annotations

import argparse

from ..errors import InputError, UsageError
from ..io.files import write_outputs
from . import options

__all__ = ["EXAMPLE", "HELP", "NAME", "add_arguments", "run"]

NAME = "measure"
HELP = "synthetic measurements of a model (for calibrate)"
EXAMPLE = "urdf2dh measure puma560-actual --configs 100 --noise-pos 0.01 --noise-rot 1e-5 -o m.csv"


def add_arguments(p: argparse.ArgumentParser) -> None:
    options.add_chain(p)
    p.add_argument(
        "--configs",
        type=options.samples,
        default=None,
        metavar="N",
        help="number of configurations, drawn uniformly within the joint limits (or give "
        "--configurations)",
    )
    p.add_argument(
        "--noise-pos",
        type=options.nonnegative_float,
        default=0.0,
        metavar="SIGMA",
        help="position noise per coordinate, in the source's length unit, below the robot's "
        "size (default 0)",
    )
    p.add_argument(
        "--noise-rot",
        type=options.nonnegative_float,
        default=0.0,
        metavar="SIGMA",
        help="rotation noise per axis, rad, below 1 (default 0)",
    )
    p.add_argument(
        "--measure",
        choices=("pose", "position"),
        default=None,
        help="pose (default) or position of the tool origin; --markers implies position",
    )
    options.add_markers(p, "measure the positions of K markers at seeded points of the tool")
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
    p.add_argument(
        "--seed", type=options.seed, default=0, metavar="S", help="random seed (default 0)"
    )
    p.add_argument("-o", "--output", metavar="FILE", help="CSV file (default stdout)")


def run(args: argparse.Namespace) -> int:
    """``urdf2dh measure``: write synthetic measurements (module :mod:`.measure`)."""
    from ..calibration.measure import measure
    from ..calibration.measurements import read_configurations, write_layout, write_measurements

    model = options.nominal(args)
    pose = args.measure != "position" and args.markers is None
    if args.markers is not None and args.measure == "pose":
        raise UsageError("--markers measures positions; it does not go with --measure pose")
    if args.marker_layout and args.markers is None:
        raise UsageError("--marker-layout writes the layout of --markers K")
    if (args.configs is None) == (args.configurations is None):
        raise UsageError("measure takes --configs N or --configurations FILE (one of them)")
    from ..calibration.measurements import check_noise

    for flag, value in (("--noise-pos", args.noise_pos), ("--noise-rot", args.noise_rot)):
        try:
            check_noise(
                value if flag == "--noise-pos" else None,
                value if flag == "--noise-rot" else None,
                model.size(),
                model.length_unit,
                exact=True,
            )
        except InputError as e:
            raise UsageError(f"{flag} {value:g}: {e}") from e
    configurations = None
    if args.configurations:
        joints = tuple(j.name for j in model.joints)
        configurations = read_configurations(args.configurations, joints)
    m = measure(
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
    if args.marker_layout and m.layout is not None:
        outputs.append((args.marker_layout, write_layout(m.layout)))
    write_outputs(outputs)
    return 0
