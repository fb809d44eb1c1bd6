"""Speed and scale of urdf2dh, measured side by side with Pinocchio on one machine.

    python benchmarks/run.py            # the full run (a few minutes)
    python benchmarks/run.py --quick    # CI's run: fewer repeats and sizes (under a minute)
    python benchmarks/run.py --startup  # only the whole commands' start-up, against Pinocchio's

Every figure is printed beside its Pinocchio counterpart with the ratio ours / Pinocchio's, and
the goal it is held to. Goals are reported, never asserted: speed is measured, not tested. Times
are the best of several interleaved runs; each section says what "ours" includes.
"""

from __future__ import annotations

import argparse
import compileall
import os
import platform
import sys
import tempfile
from pathlib import Path

import numpy as np
import pinocchio as pin
import yourdfpy

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(Path(__file__).resolve().parent)]

from scale import at_the_bounds, chain_lengths  # noqa: E402
from timing import (  # noqa: E402
    Figure,
    best_of,
    import_ms,
    paired,
    peak_alloc,
    print_table,
    run_process,
)

from urdf2dh.check.verify import pinocchio_fk, verify  # noqa: E402
from urdf2dh.conventions import NAMES  # noqa: E402
from urdf2dh.conventions.convert import (  # noqa: E402
    DEFAULT_SAMPLES,
    JUDGED_SAMPLES,
    build_table,
    self_check,
    to_table,
)
from urdf2dh.geometry.se3 import pose_errors  # noqa: E402
from urdf2dh.io.catalog import ROBOTS, robot_path  # noqa: E402
from urdf2dh.io.files import read_file  # noqa: E402
from urdf2dh.io.sources import open_source  # noqa: E402
from urdf2dh.io.urdf import parse_tree, tree_to_poe  # noqa: E402
from urdf2dh.io.urdf.parse import document, parse_xml, yourdfpy_robot  # noqa: E402 - the stages
from urdf2dh.io.urdf.tree import build_tree  # noqa: E402
from urdf2dh.io.urdf.validate import check_robot  # noqa: E402
from urdf2dh.model.fk import chain_fk  # noqa: E402
from urdf2dh.tolerances import DEFAULT  # noqa: E402

ARM = "panda"  # the 7-DOF arm of the engine and batch figures


def engine(repeat: int) -> list[Figure]:
    """In one process: reading the URDF + chain walk + dh + self-check vs buildModelFromUrdf."""
    bundled = ROBOTS[ARM]
    path = robot_path(bundled)
    data = path.read_bytes()
    root = parse_xml(document(data, path.name), path.name)
    robot = yourdfpy_robot(root, path.name)  # yourdfpy's part, timed separately below
    tree = parse_tree(data, path.name)
    model = tree_to_poe(tree, bundled.base, bundled.tip)
    table, _ = build_table(model, "dh", DEFAULT)

    def ours_tree(text: bytes) -> object:
        """parse_tree without yourdfpy's part (its Robot of this file is made once, above)."""
        xml = document(text, path.name)
        check_robot(parse_xml(xml, path.name), path.name)
        return build_tree(robot, path.name, xml)

    def ours(samples: int) -> object:
        tree = ours_tree(read_file(path, path.name))
        return to_table(tree_to_poe(tree, bundled.base, bundled.tip), "dh", samples=samples)

    def whole(samples: int) -> object:
        tree = parse_tree(read_file(path, path.name), path.name)
        return to_table(tree_to_poe(tree, bundled.base, bundled.tip), "dh", samples=samples)

    def from_tree(samples: int) -> object:
        return to_table(tree_to_poe(tree, bundled.base, bundled.tip), "dh", samples=samples)

    stages = {
        "read + decode + lxml parse": lambda: parse_xml(document(read_file(path, ""), ""), ""),
        "our strict check of the elements": lambda: check_robot(root, ""),
        "tree from yourdfpy's Robot": lambda: build_tree(robot, "", data),
        "chain walk -> POE": lambda: tree_to_poe(tree, bundled.base, bundled.tip),
        "dh conversion (no check)": lambda: build_table(model, "dh", DEFAULT),
        f"self-check at {DEFAULT_SAMPLES} configurations": lambda: self_check(model, table),
        f"self-check at {JUDGED_SAMPLES} configurations": lambda: self_check(
            model, table, JUDGED_SAMPLES
        ),
    }
    times = best_of(
        [
            lambda: pin.buildModelFromUrdf(str(path)),
            lambda: ours(DEFAULT_SAMPLES),
            lambda: ours(JUDGED_SAMPLES),
            lambda: from_tree(DEFAULT_SAMPLES),
            lambda: whole(DEFAULT_SAMPLES),
        ],
        repeat,
    )
    stage_times = best_of(list(stages.values()), repeat)
    load = best_of([lambda: yourdfpy_robot(root, "")], max(3, repeat // 10))[0]
    print(
        f"\n{ARM}: {model.n} joints, {path.stat().st_size} bytes of URDF. Ours = reading the "
        "file, its one XML parse (lxml) and our strict check of every element, the tree built "
        "from yourdfpy's Robot, the chain walk to the POE model, the dh conversion and its "
        "self-check. yourdfpy's part (its Robot made from the parsed elements by its own "
        "element parsers) is reported separately, and included in the 'whole' line. "
        "Pinocchio = buildModelFromUrdf(path), which reads and parses the file too. Stages, "
        "best of each:"
    )
    for (name, _), t in zip(stages.items(), stage_times, strict=True):
        print(f"  {name:<38} {t * 1e3:7.3f} ms")
    pin_t = times[0]
    return [
        Figure(
            f"engine, self-check at {DEFAULT_SAMPLES} configurations (the default)",
            times[1],
            pin_t,
            "ms",
        ),
        Figure(
            f"engine, self-check at {JUDGED_SAMPLES} configurations (where axes were "
            "treated as parallel)",
            times[2],
            pin_t,
            "ms",
        ),
        Figure(
            f"from the parsed tree: chain walk + dh + self-check at {DEFAULT_SAMPLES} (no XML)",
            times[3],
            pin_t,
            "ms",
        ),
        Figure("yourdfpy's Robot from the parsed elements (not ours)", load, pin_t, "ms"),
        Figure(
            f"whole: parse_tree (yourdfpy's part included) + dh + self-check at {DEFAULT_SAMPLES}",
            times[4],
            pin_t,
            "ms",
        ),
    ]


# Pinocchio's counterpart of a conversion as a new process: its import, the model built from the
# same URDF, and forward kinematics (at the neutral configuration), the last joint's pose printed.
PIN_FK = """import pinocchio
model = pinocchio.buildModelFromUrdf({path!r})
data = model.createData()
pinocchio.forwardKinematics(model, data, pinocchio.neutral(model))
print(data.oMi[model.njoints - 1])
"""
START_UP = "ur5"  # the start-up goal is stated for `urdf2dh convert ur5`


def whole_command(runs: int) -> list[Figure]:
    """New processes taking turns: `urdf2dh convert` vs Pinocchio importing itself, building the
    model of the same URDF and computing its FK; CPU time (user + system), wall time, peak
    memory. And `urdf2dh --help` vs `import pinocchio`."""
    figures = []
    for robot, extra in ((START_UP, []), (ARM, ["--format", "json"])):
        command = " ".join(["urdf2dh convert", robot, *extra])
        path = str(robot_path(ROBOTS[robot]))
        ours, theirs = paired(
            [["-m", "urdf2dh.cli", "convert", robot, *extra], ["-c", PIN_FK.format(path=path)]],
            runs,
        )
        goal = robot == START_UP
        figures += [
            Figure(
                f"whole command, CPU: {command} vs Pinocchio's import + build + FK",
                ours.cpu,
                theirs.cpu,
                "s",
                "<= 1.2x (aim: 1.0x)" if goal else "",
                ours.cpu <= 1.2 * theirs.cpu if goal else None,
            ),
            Figure(f"whole command, wall: {command}", ours.seconds, theirs.seconds, "s"),
            Figure(
                f"peak memory: {command} vs Pinocchio's",
                ours.peak_bytes,
                theirs.peak_bytes,
                "MiB",
                "<= 1.0x" if goal else "",
                ours.peak_bytes <= theirs.peak_bytes if goal else None,
            ),
        ]
    help_, only_pin = paired([["-m", "urdf2dh.cli", "--help"], ["-c", "import pinocchio"]], runs)
    print(
        f"\nNew processes, {runs} of each taking turns, medians (peak memory: the largest): "
        f"urdf2dh's package compiled to bytecode as `pip install` leaves it. Pinocchio's side "
        "imports it, builds the model from the same URDF (buildModelFromUrdf) and computes "
        "its forward kinematics; CPU time is user + system (numpy's BLAS threads included, on "
        "both sides)."
    )
    return [
        *figures,
        Figure(
            "start-up, CPU: urdf2dh --help vs python -c 'import pinocchio'",
            help_.cpu,
            only_pin.cpu,
            "s",
        ),
    ]


def imports() -> list[Figure]:
    """Import times (-X importtime, cumulative, new processes) against `import pinocchio`."""
    pin_ms = import_ms("import pinocchio")["total"]
    cli = import_ms("import urdf2dh.cli")
    convert = import_ms(
        "import urdf2dh.conventions.convert, urdf2dh.io.sources, urdf2dh.emit.formats, "
        "urdf2dh.io.urdf, urdf2dh.io.urdf._yourdfpy"
    )
    yd = import_ms("import yourdfpy")
    hygiene = run_process(
        [
            "-c",
            "import sys; from urdf2dh.cli import main\ntry: main(['--help'])\n"
            "except SystemExit: pass\nprint(sorted({m.split('.')[0] for m in "
            "sys.modules} & {'numpy', 'yourdfpy', 'pinocchio', 'lxml'}))",
        ],
        1,
    )
    print(
        f"\nModules `urdf2dh --help` imports of numpy, yourdfpy, pinocchio, lxml: "
        f"{hygiene.stdout.strip().splitlines()[-1]}"
    )
    return [
        Figure(
            "import urdf2dh.cli (all that --help needs)",
            cli["total"] / 1e3,
            pin_ms / 1e3,
            "ms",
            "no yourdfpy, no Pinocchio",
            "yourdfpy" not in cli and "pinocchio" not in cli,
        ),
        Figure(
            "import of convert's modules (ours, numpy, lxml, yourdfpy's element parsers)",
            convert["total"] / 1e3,
            pin_ms / 1e3,
            "ms",
            "no Pinocchio, no trimesh package",
            "pinocchio" not in convert and "trimesh" not in convert,
        ),
        Figure(
            "import yourdfpy (not ours; with trimesh's package)",
            yd["total"] / 1e3,
            pin_ms / 1e3,
            "ms",
        ),
    ]


def batch_fk(count: int, repeat: int) -> list[Figure]:
    """Table.fk_batch over (N, 7) against Pinocchio's forwardKinematics in a Python loop."""
    source = open_source(ARM)
    model = source.model()
    table = to_table(model, "dh")
    q = model.sample(count, 3)
    full = pin.buildModelFromUrdf(str(robot_path(ROBOTS[ARM])))
    arm = {j.name for j in model.joints}
    lock = [i for i in range(1, full.njoints) if full.names[i] not in arm]  # the fingers
    reduced = pin.buildReducedModel(full, lock, pin.neutral(full))
    data, tip = reduced.createData(), reduced.getFrameId(model.tip_link)
    order = [reduced.joints[reduced.getJointId(j.name)].idx_q for j in model.joints]
    qp = np.zeros((count, reduced.nq))
    qp[:, order] = q  # the base link is Pinocchio's root: poses compare as they are

    def loop() -> np.ndarray:
        out = np.empty((count, 4, 4))
        for k, config in enumerate(qp):
            pin.forwardKinematics(reduced, data, config)
            out[k] = pin.updateFramePlacement(reduced, data, tip).homogeneous
        return out

    def fk_only() -> None:
        for config in qp:
            pin.forwardKinematics(reduced, data, config)

    def reference() -> np.ndarray:  # the reference FK alone: no fast path (model/_fastfk.py)
        return chain_fk(*table.link_form(), table.positions(q))

    ours_t, poe_t, loop_t, bare_t, reference_t = best_of(
        [lambda: table.fk_batch(q), lambda: model.fk_batch(q), loop, fk_only, reference], repeat
    )
    ours, theirs = table.fk_batch(q), loop()
    pos, rot = pose_errors(ours, theirs)
    print(
        f"\n{ARM}, N = {count:,} configurations within the joint limits; Pinocchio's model is "
        f"the URDF's reduced to the 7 arm joints. Max difference of the poses: {pos:.2e} m, "
        f"{rot:.2e} rad; largest entry {np.abs(ours - theirs).max():.2e}. One thread. The fast "
        f"path (urdf2dh/model/_fastfk.py: sines from a table) is {reference_t / ours_t:.2f}x as "
        f"fast as the reference FK with numpy {np.__version__}'s exp (it stays while it saves"
        f" time); they differ by {np.abs(ours - reference()).max():.1e}."
    )
    return [
        Figure(
            "batch FK: Table.fk_batch vs loop of forwardKinematics + tip pose",
            ours_t,
            loop_t,
            "ms",
            "<= 0.1x (10x throughput)",
            ours_t <= 0.1 * loop_t,
        ),
        Figure(
            "batch FK by the reference FK alone (numpy's exp, no fast path) vs the loop",
            reference_t,
            loop_t,
            "ms",
        ),
        Figure(
            "batch FK vs the loop's forwardKinematics alone (poses not read out)",
            ours_t,
            bare_t,
            "ms",
        ),
        Figure("batch FK of the POE model vs the loop", poe_t, loop_t, "ms"),
        Figure(
            "batch FK peak allocation vs the loop's",
            peak_alloc(lambda: table.fk_batch(q)),
            peak_alloc(loop),
            "MiB",
        ),
    ]


ORACLE = """import numpy as np, pinocchio as pin
model = pin.buildModelFromUrdf({path!r})
data, tip = model.createData(), model.getFrameId({tip!r})
q = np.random.default_rng(0).uniform(model.lowerPositionLimit, model.upperPositionLimit,
                                     size=({samples}, model.nq))
out = np.empty(({samples}, 4, 4))
for k, config in enumerate(q):
    pin.forwardKinematics(model, data, config)
    out[k] = pin.updateFramePlacement(model, data, tip).homogeneous
"""


def verify_run(samples: int, runs: int, repeat: int) -> list[Figure]:
    """`urdf2dh verify`: in one process, against a Pinocchio-only check of the same
    configurations (build the model from the same text, its FK of the tip in the base at every
    configuration), at ``samples`` and at the command's default 1000; and as a new process
    against one in which Pinocchio does that."""
    source = open_source(ARM)
    model = source.model()
    checked = f"POE + {len(NAMES)} tables + their conversions"
    figures = []
    for count, goal in ((samples, "<= 2x"), (1000, None)):
        q = model.sample(count, 3)

        def ours_only(count: int = count) -> object:
            return verify(source, samples=count)

        def pinocchio_only(q: np.ndarray = q) -> object:
            return pinocchio_fk(source, model, q)

        ours_t, theirs_t = best_of([ours_only, pinocchio_only], repeat)
        figures.append(Figure(
            f"verify {ARM} at {count} configurations ({checked}) vs Pinocchio alone at them, "
            "in one process",
            ours_t, theirs_t, "ms", goal or "", None if goal is None else ours_t <= 2.0 * theirs_t,
        ))  # fmt: skip
    ours = run_process(["-m", "urdf2dh.cli", "verify", ARM, "--samples", str(samples)], runs)
    bundled = ROBOTS[ARM]
    oracle = ORACLE.format(path=str(robot_path(bundled)), tip=bundled.tip, samples=samples)
    theirs = run_process(["-c", oracle], runs)
    return [
        *figures,
        Figure(
            f"urdf2dh verify {ARM} --samples {samples} vs Pinocchio's FK at as many, new processes",
            ours.seconds,
            theirs.seconds,
            "s",
        ),
        Figure(
            "peak memory of the verify run vs Pinocchio's",
            ours.peak_bytes,
            theirs.peak_bytes,
            "MiB",
        ),
    ]


MATCHES = [  # (table, source, what the match finds)
    ("ur5-dh", "ur5", "UR's table: base turned"),
    ("panda-mdh", "panda", "Franka's modified D-H"),
    ("ur5-dh", "ur10", "another robot: no match, the best refined"),
]


def match_run(repeat: int) -> list[Figure]:
    """`urdf2dh.match` (both files read, every reading of the table searched, the fits
    refined, the residual and the precision bound measured at its 200 configurations) against
    Pinocchio building the source's model and its FK at as many configurations, in one
    process."""
    from urdf2dh.check.match import CHECK_SAMPLES, match

    figures = []
    for table, robot, what in MATCHES:
        source = open_source(robot)
        model = source.model()
        q = model.sample(CHECK_SAMPLES, 3)

        def ours(table: str = table, robot: str = robot) -> object:
            return match(table, robot)

        def theirs(source: object = source, model: object = model, q: np.ndarray = q) -> object:
            return pinocchio_fk(source, model, q)  # type: ignore[arg-type]

        ours_t, theirs_t = best_of([ours, theirs], repeat)
        figures.append(Figure(
            f"match {table} {robot} ({what}) vs Pinocchio's model and FK at {CHECK_SAMPLES} "
            "configurations", ours_t, theirs_t, "ms",
        ))  # fmt: skip
    return figures


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="CI's short run")
    parser.add_argument(
        "--startup", action="store_true", help="only the whole commands' start-up (new processes)"
    )
    args = parser.parse_args(argv)
    quick = args.quick
    compileall.compile_dir(ROOT / "urdf2dh", quiet=1)  # the bytecode `pip install` writes
    # the new processes run this checkout's urdf2dh, whatever else is installed
    os.environ["PYTHONPATH"] = os.pathsep.join(
        filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])
    )
    print(
        f"# urdf2dh benchmark{' (quick)' if quick else ''}\n\nPython {platform.python_version()}"
        f", Pinocchio {pin.__version__}, yourdfpy {yourdfpy.__version__}, numpy "
        f"{np.__version__}; {os.cpu_count()} CPUs; load average {os.getloadavg()[0]:.2f}"
    )
    if args.startup:
        print_table("Whole command and start-up (new processes)", whole_command(3 if quick else 7))
        return 0
    figures = engine(repeat=20 if quick else 200)
    print_table("Engine (one process)", figures)
    rows = whole_command(runs=3 if quick else 7)
    print_table("Whole command and start-up (new processes)", rows)
    figures += rows
    rows = imports()
    print_table("Import times", rows)
    figures += rows
    sizes = [10, 50, 200] if quick else [10, 20, 50, 100, 200, 500, 1000, 2000]
    rows, notes = chain_lengths(sizes, accuracy_samples=20 if quick else 200)
    print_table("Chain length (random chains, in one process)", rows)
    print("\n" + "\n".join(notes))
    figures += rows
    with tempfile.TemporaryDirectory(prefix="urdf2dh-bench-") as directory:
        notes = at_the_bounds(Path(directory), quick)
    print("\n### Bounds (new processes)\n\n" + "\n".join(notes))
    rows = batch_fk(count=10_000 if quick else 100_000, repeat=2 if quick else 7)
    print_table("Batch forward kinematics", rows)
    figures += rows
    # the goal is stated at 10,000 configurations, so quick mode measures there too
    rows = verify_run(samples=10_000, runs=1 if quick else 3, repeat=3 if quick else 10)
    print_table("verify", rows)
    figures += rows
    rows = match_run(repeat=2 if quick else 7)
    print_table("match", rows)
    figures += rows
    goals = [f for f in figures if f.met is not None]
    print(
        f"\nGoals met: {sum(f.met is True for f in goals)} of {len(goals)}"
        + "".join(
            f"\n  NOT met: {f.name} ({f.ratio:.3g}x; goal {f.goal})" for f in goals if not f.met
        )
        + f"\nLoad average at the end: {os.getloadavg()[0]:.2f}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
