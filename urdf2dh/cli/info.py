"""``urdf2dh info``: what a SOURCE holds, the chain that would be converted, identifiability."""

from __future__ import annotations

import argparse

from ..io.files import write_stdout
from . import options

__all__ = ["EXAMPLE", "HELP", "NAME", "add_arguments", "run"]

NAME = "info"
HELP = "links, joints, the chain, candidate tips, identifiability"
EXAMPLE = "urdf2dh info ur5"


def add_arguments(p: argparse.ArgumentParser) -> None:
    options.add_chain(p)


def run(args: argparse.Namespace) -> int:
    from ..check.info import info

    write_stdout(info(options.source(args), args.base, args.tip, args.ignore_mimic).text())
    return 0
