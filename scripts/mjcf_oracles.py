"""Every chain of MJCF models converted in every convention and checked against both oracles,
MuJoCo and Pinocchio (``verify --oracle both``), with the errors relative to the robot's size.

    PYTHONPATH=. python scripts/mjcf_oracles.py                       # tests/data/mjcf, its chains
    PYTHONPATH=. python scripts/mjcf_oracles.py DIR_OR_FILE ... [--samples 1000]

The shipped models (tests/data/mjcf) are checked on the chains their README names
(:data:`CHAINS`); any other file on the chain from its world to every leaf below it that has a
moving joint on its way (``--all-tips``), each body or site a leaf. A chain a file cannot give
(a ball or free joint on it, a coupling no mimic relation describes) is counted as refused, with
the reason. Per chain and oracle: the worst position error of the POE model and of the four
tables, relative to the robot's size, and the worst rotation error; an oracle that did not judge
says why; and how far the two oracles are from each other on the same configurations.

The promise: every model within :data:`PROMISE` (x size, and rad) of MuJoCo, which defines MJCF,
and of Pinocchio within that plus the two oracles' own distance (Pinocchio's rounding reaches
1.3e-14 rad on these arms), each plus what a table declared. The script exits 1 if a model is
beyond it.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from urdf2dh.check.verify import ORACLES, VERIFY_STREAM, compare_with_oracles  # noqa: E402
from urdf2dh.errors import ChainError, OracleError, Urdf2DhError  # noqa: E402
from urdf2dh.geometry.se3 import pose_errors  # noqa: E402
from urdf2dh.io.sources import Source, open_source  # noqa: E402
from urdf2dh.model.poe import PoeModel  # noqa: E402
from urdf2dh.tolerances import DEFAULT  # noqa: E402

DATA = ROOT / "tests" / "data" / "mjcf"
PROMISE = DEFAULT.report  # 1e-14: x size for positions, rad for rotations

#: The shipped models' arm chains (tests/data/mjcf/README.md): file -> (base, tip) pairs.
CHAINS = {
    "arx_l5.xml": (("base_link", "link6"), ("base_link", "link7")),
    "dynamixel_2r.xml": (("base", "end"),),
    "fr3.xml": (("base", "attachment_site"), ("fr3_link0", "attachment_site")),
    "lite6.xml": (("link_base", "attachment_site"),),
    "low_cost_robot_arm.xml": (
        ("base_link", "gripper_static_finger"),
        ("base_link", "gripper_moving_finger"),
    ),
    "sawyer.xml": (("base", "attachment_site"),),
    "so_arm100.xml": (("Base", "Fixed_Jaw"), ("Base", "Moving_Jaw")),
    "ur5e.xml": (("base", "wrist_3_link"),),
    "ur5e_nomesh.xml": (("base", "wrist_3_link"),),
    "xarm7_nohand.xml": (("link_base", "attachment_site"),),
    "z1.xml": (("link00", "link06"),),
}


@dataclass(frozen=True)
class Measure:
    """One model of one chain against one oracle: errors, size, what was declared."""

    chain: str
    oracle: str
    label: str
    position: float  # relative to size
    rotation: float
    declared_position: float  # relative to size
    declared_rotation: float

    def within(self, apart: tuple[float, float] = (0.0, 0.0)) -> bool:
        """Whether it keeps the promise, the oracles ``apart`` (position / size, rotation)
        allowed on top against Pinocchio."""
        extra = apart if self.oracle == "pinocchio" else (0.0, 0.0)
        return (
            self.position <= PROMISE + self.declared_position + extra[0]
            and self.rotation <= PROMISE + self.declared_rotation + extra[1]
        )


@dataclass(frozen=True)
class Outcome:
    """A chain's measures, the oracles that did not judge it (and why), the two oracles'
    distance from each other (position / size, rotation), or why it was refused."""

    chain: str
    measures: tuple[Measure, ...] = ()
    abstained: tuple[str, ...] = ()
    refused: str = ""
    apart: tuple[float, float] = (0.0, 0.0)

    @property
    def within(self) -> bool:
        return all(m.within(self.apart) for m in self.measures)


def oracles_apart(source: Source, model: PoeModel, samples: int, seed: int) -> tuple[float, float]:
    """How far Pinocchio's and MuJoCo's poses are from each other at verify's configurations
    (position / size, rotation); zeros where one of them does not judge the chain."""
    try:
        poses = [o.evaluator(source, model) for o in ORACLES.values()]
    except OracleError:
        return 0.0, 0.0
    q = model.sample(samples, (seed, VERIFY_STREAM))
    pos, rot = pose_errors(poses[0](q), poses[1](q))
    return pos / model.size(), rot


def chains_of(source: Source, path: Path) -> list[tuple[str, str]]:
    """The chains to check: the README's for a shipped model, else world -> every leaf with a
    moving joint on its way."""
    if path.parent.resolve() == DATA.resolve() and path.name in CHAINS:
        return list(CHAINS[path.name])
    tree = source.tree
    assert tree is not None
    leaves = [t for t in tree.leaves(tree.root)
              if any(j.type != "fixed" for j in tree.chain(tree.root, t))]  # fmt: skip
    return [(tree.root, t) for t in leaves]


def measure(path: Path, samples: int = 200, seed: int = 0) -> list[Outcome]:
    """Every chain of one file against both oracles."""
    source = open_source(str(path))
    out = []
    for base, tip in chains_of(source, path):
        name = f"{path.name} {base} -> {tip}"
        try:
            model = source.model(base, tip)
        except ChainError as e:
            out.append(Outcome(name, refused=str(e)))
            continue
        try:
            checks, abstentions = compare_with_oracles(source, model, samples, seed, oracle="both")
        except Urdf2DhError as e:
            out.append(Outcome(name, refused=str(e)))
            continue
        size = model.size()
        measures = []
        for c in checks:
            check = c.table.check if c.table is not None else None
            declared = (0.0, 0.0) if check is None else (check.declared_position / size,
                                                         check.declared_rotation)  # fmt: skip
            measures.append(
                Measure(name, c.oracle, c.label, c.position / size, c.rotation, *declared)
            )
        apart = oracles_apart(source, model, samples, seed)
        out.append(Outcome(name, tuple(measures), tuple(a.reason for a in abstentions), "", apart))
    return out


def report(outcomes: list[Outcome]) -> str:
    """Per chain and oracle, the worst relative position and rotation errors; refusals;
    abstentions; and the worst over all."""
    lines = [f"{'chain':<58} {'oracle':<10} {'position/size':>13} {'rotation':>10}"]
    for o in outcomes:
        if o.refused:
            lines.append(f"{o.chain:<58} refused: {o.refused[:150]}")
            continue
        for oracle in dict.fromkeys(m.oracle for m in o.measures):
            ms = [m for m in o.measures if m.oracle == oracle]
            flag = "" if all(m.within(o.apart) for m in ms) else "  BEYOND"
            lines.append(
                f"{o.chain:<58} {oracle:<10} {max(m.position for m in ms):>13.2e} "
                f"{max(m.rotation for m in ms):>10.2e}{flag}"
            )
        if o.apart != (0.0, 0.0):
            lines.append(f"{'':<58} {'apart':<10} {o.apart[0]:>13.2e} {o.apart[1]:>10.2e}")
        lines += [f"{'':<58} not judged: {a[:150]}" for a in o.abstained]
    everything = [m for o in outcomes for m in o.measures]
    for oracle in dict.fromkeys(m.oracle for m in everything):
        ms = [m for m in everything if m.oracle == oracle]
        plain = [m for m in ms if not (m.declared_position or m.declared_rotation)]
        lines.append(
            f"worst against {oracle}: position {max(m.position for m in plain):.2e} x size, "
            f"rotation {max(m.rotation for m in plain):.2e} rad, over {len(plain)} models of "
            f"{len({m.chain for m in ms})} chains that declare nothing; {len(ms) - len(plain)} "
            "tables declare a deviation (nearly parallel axes made parallel) and keep within it"
        )
    refused = sum(1 for o in outcomes if o.refused)
    lines.append(f"chains refused: {refused} of {len(outcomes)}")
    return "\n".join(lines)


def files_of(paths: list[str]) -> list[Path]:
    out: list[Path] = []
    for p in map(Path, paths or [str(DATA)]):
        out += sorted(p.glob("*.xml")) if p.is_dir() else [p]
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "paths", nargs="*", help="MJCF files or directories (default tests/data/mjcf)"
    )
    parser.add_argument("--samples", type=int, default=1000, help="configurations (default 1000)")
    args = parser.parse_args(argv)
    outcomes = []
    for path in files_of(args.paths):
        try:
            outcomes += measure(path, args.samples)
        except Urdf2DhError as e:
            outcomes.append(Outcome(path.name, refused=str(e)))
    print(report(outcomes))
    return 0 if all(o.within for o in outcomes) else 1


if __name__ == "__main__":
    sys.exit(main())
