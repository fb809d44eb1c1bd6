"""``urdf2dh plan``: configurations worth measuring for a calibration."""

from __future__ import annotations

import argparse
import sys

from ..io.files import check_outputs, write_outputs
from . import options

__all__ = ["EXAMPLE", "HELP", "NAME", "add_arguments", "run"]

NAME = "plan"
HELP = "choose configurations to measure for a calibration"
EXAMPLE = "urdf2dh plan ur5 --configs 15 -o plan.csv"


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..calibration.levels import FULL, NAMES

    options.add_chain(p)
    p.add_argument(
        "--configs",
        type=lambda text: options.integer(text, 1, 10_000),
        required=True,
        metavar="N",
        help="number of configurations to choose (at least as many as give one equation per "
        "parameter of the level; at most 10000)",
    )
    p.add_argument(
        "--identify",
        choices=NAMES,
        default=FULL.name,
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
    options.add_markers(p, "position measurements of K markers at seeded points of the tool")
    p.add_argument(
        "--noise-pos",
        type=options.positive_float,
        default=None,
        metavar="SIGMA",
        help="position noise per coordinate, for the expected uncertainty (default 0.1 mm)",
    )
    p.add_argument(
        "--noise-rot",
        type=options.positive_float,
        default=None,
        metavar="SIGMA",
        help="rotation noise per axis, rad (default 1e-4)",
    )
    p.add_argument(
        "--seed", type=options.seed, default=0, metavar="S", help="random seed (default 0)"
    )
    p.add_argument("-o", "--output", metavar="FILE", help="CSV file (default stdout)")


def run(args: argparse.Namespace) -> int:
    """``urdf2dh plan``: choose configurations to measure (module :mod:`.plan`)."""
    from ..calibration.measurements import read_configurations, write_configurations
    from ..calibration.plan import plan

    model = options.nominal(args)
    joints = tuple(j.name for j in model.joints)
    candidates = read_configurations(args.candidates, joints) if args.candidates else None
    check_outputs([args.output])  # before the choice, which may take a while
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
