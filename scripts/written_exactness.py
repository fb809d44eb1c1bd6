"""How exact written tables are on real robot descriptions: every chain, every convention.

    PYTHONPATH=. python scripts/written_exactness.py                  # bundled robots, tests/data
    PYTHONPATH=. python scripts/written_exactness.py DIR_OR_FILE ...  # URDFs found there too

The chains of a URDF are its root to each leaf with at least one movable joint (the same
joints in the same order counted once); a POE or table file is one chain. Each chain is
converted to every convention and the table measured twice: its numbers evaluated as written,
and the JSON table file read back. Both are compared, at seeded random configurations, with an
extended-precision FK of the URDF text itself (benchmarks/reference.py; chains with mimic
joints, which it does not model, and POE files are compared with the model's float64 FK). The
script prints the worst position error (x the robot's size) and rotation error (rad) per
convention among tables that declare no deviation, the chains behind them, and every table
beyond the promise (1e-14 x size and 1e-14 rad, plus what the table declares); it exits 1 if
there is one. Files urdf2dh refuses, and conversions it refuses, are counted apart.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from reference import chain_fk  # noqa: E402  (benchmarks/reference.py)

from urdf2dh.conventions import NAMES  # noqa: E402
from urdf2dh.conventions.convert import to_table  # noqa: E402
from urdf2dh.conventions.table import Table  # noqa: E402
from urdf2dh.emit.formats import render  # noqa: E402
from urdf2dh.errors import Urdf2DhError  # noqa: E402
from urdf2dh.geometry.se3 import pose_errors  # noqa: E402
from urdf2dh.io.catalog import ROBOTS, robot_path  # noqa: E402
from urdf2dh.io.mappings import read_mapping  # noqa: E402
from urdf2dh.io.sources import open_source  # noqa: E402
from urdf2dh.io.tablefile import read_table  # noqa: E402
from urdf2dh.io.urdf import load_tree, tree_to_poe  # noqa: E402
from urdf2dh.model.poe import PoeModel  # noqa: E402

PROMISE = 1e-14  # x robot size (position) and rad (rotation): tolerances.DEFAULT.report
SAMPLES = 64
SEED = 7

Reference = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Measured:
    """One chain in one convention (or its POE model): the worst errors of the written table
    against the reference, and the deviation the table declares (both x size, and rad)."""

    chain: str
    convention: str
    position: float
    rotation: float
    declared_position: float = 0.0
    declared_rotation: float = 0.0

    @property
    def within(self) -> bool:
        return (
            self.position <= PROMISE + self.declared_position
            and self.rotation <= PROMISE + self.declared_rotation
        )


def default_files() -> list[Path]:
    """Every bundled robot's URDF and POE file and the URDFs under tests/data (the bundled MJCF
    files are measured against MuJoCo and Pinocchio by scripts/mjcf_oracles.py)."""
    return [
        *(robot_path(b) for b in ROBOTS.values() if robot_path(b).suffix != ".xml"),
        *sorted((ROOT / "tests" / "data").rglob("*.urdf")),
    ]


def urdf_files(paths: list[str]) -> list[Path]:
    """The files named, and the URDFs in the directories named."""
    out: list[Path] = []
    for p in map(Path, paths):
        out += sorted(q for q in p.rglob("*") if q.suffix.lower() == ".urdf") if p.is_dir() else [p]
    return out


def chains(path: Path) -> Iterator[tuple[str, PoeModel, Reference | None]]:
    """``(label, model, reference poses)`` of every distinct chain of the file (reference
    ``None``: the model's own FK is the reference)."""
    if path.suffix.lower() not in (".urdf", ".xml"):
        yield path.name, open_source(str(path)).model(), None
        return
    tree = load_tree(path)
    text = path.read_text(encoding="utf-8", errors="replace")
    seen = set()
    for leaf in tree.leaves():
        joints = tuple(j.name for j in tree.chain(tree.root, leaf) if j.type != "fixed")
        if not joints or joints in seen:
            continue
        seen.add(joints)
        try:
            model = tree_to_poe(tree, tree.root, leaf)
        except Urdf2DhError:
            continue
        reference = None
        if not any(j.mimic is not None for j in model.joints):
            q = model.sample(SAMPLES, SEED)
            try:
                reference = chain_fk(text, tree.root, leaf, q).astype(float)
            except (KeyError, AttributeError, ValueError):  # joints it does not model
                reference = None
        yield f"{path.name} {tree.root}->{leaf}", model, reference


def read_back(table: Table) -> Table:
    """The table as its JSON file reads back."""
    data = render(table, "json").encode()
    return read_table(read_mapping(Path("t.json"), "t.json", data), "t.json")


def measure(path: Path) -> tuple[list[Measured], int]:
    """Every chain of the file in every convention, and how many conversions were refused."""
    out, refused = [], 0
    for label, model, reference in chains(path):
        q = model.sample(SAMPLES, SEED)
        size = model.size()
        if reference is None:
            reference = model.fk_batch(q)
        pos, rot = pose_errors(model.fk_batch(q), reference)
        out.append(Measured(label, "POE model", pos / size, rot))
        for conv in NAMES:
            try:
                table = to_table(model, conv)
            except Urdf2DhError:
                refused += 1
                continue
            # the numbers as written, evaluated literally, and the file as urdf2dh reads it back
            literal = pose_errors(table.fk_batch(q), reference)
            back = pose_errors(read_back(table).fk_batch(q), reference)
            check = table.check
            assert check is not None
            out.append(Measured(
                label, conv, max(literal[0], back[0]) / size, max(literal[1], back[1]),
                check.declared_position / size, check.declared_rotation,
            ))  # fmt: skip
    return out, refused


def report(results: list[Measured], files: int, unreadable: int, refused: int) -> str:
    """The figures: worst undeclared errors per convention, and every table beyond."""
    lines = [
        f"{files} files ({unreadable} refused by urdf2dh), "
        f"{len({m.chain for m in results})} chains, {refused} conversions refused",
        "",
        "| convention | worst position / size | worst rotation (rad) | beyond the promise |",
        "|---|---:|---:|---:|",
    ]
    for conv in ("POE model", *NAMES):
        mine = [m for m in results if m.convention == conv]
        plain = [m for m in mine if not (m.declared_position or m.declared_rotation)]
        if not plain:
            continue
        worst_p = max(plain, key=lambda m: m.position)
        worst_r = max(plain, key=lambda m: m.rotation)
        lines.append(
            f"| {conv} | {worst_p.position:.2e} ({worst_p.chain}) | "
            f"{worst_r.rotation:.2e} ({worst_r.chain}) | {sum(not m.within for m in mine)} |"
        )
    declared = [m for m in results if m.declared_position or m.declared_rotation]
    lines += [
        "",
        f"{len(declared)} tables declare a deviation (judgements reported, or the rounding of "
        f"far-reaching rows); beyond it: {sum(not m.within for m in declared)}",
    ]
    lines += [
        f"  BEYOND: {m.convention} {m.chain}: {m.position:.2e} x size, {m.rotation:.2e} rad "
        f"(declared {m.declared_position:.2e}, {m.declared_rotation:.2e})"
        for m in results
        if not m.within
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("paths", nargs="*", help="URDF files or directories searched for them")
    args = parser.parse_args(argv)
    files = default_files() + urdf_files(args.paths)
    results: list[Measured] = []
    unreadable = refused = 0
    for path in files:
        try:
            got, n = measure(path)
        except Urdf2DhError:
            unreadable += 1
            continue
        results += got
        refused += n
    print(report(results, len(files), unreadable, refused))
    return 0 if all(m.within for m in results) else 1


if __name__ == "__main__":
    sys.exit(main())
