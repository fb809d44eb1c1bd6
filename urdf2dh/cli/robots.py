"""``urdf2dh robots``: the bundled robots, their chains and descriptions, and the reference
tables."""

from __future__ import annotations

import argparse

from ..io.files import write_stdout

__all__ = ["EXAMPLE", "HELP", "NAME", "add_arguments", "run"]

NAME = "robots"
HELP = "list the bundled robots and reference tables"
EXAMPLE = "urdf2dh robots"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """No options."""


def run(args: argparse.Namespace) -> int:
    from ..io.catalog import REFERENCES, ROBOTS

    width = max(len(n) for n in (*ROBOTS, *REFERENCES))
    lines = []
    for r in ROBOTS.values():
        chain = f"{r.base} -> {r.tip}" if r.base else "POE model"
        lines.append(f"{r.name:<{width}}  {r.description}  [{chain}]\n")
    lines.append("\nreference tables (TABLE for urdf2dh match; a SOURCE too):\n")
    lines += [f"{r.name:<{width}}  {r.description}\n" for r in REFERENCES.values()]
    write_stdout("".join(lines))
    return 0
