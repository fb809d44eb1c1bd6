"""The analytic IK hand-offs on every real 6R description at hand: each D-H table ikdh ships
(1,178 arms from RoboDK's library, made URDFs as tests/ik_corpus.py makes them) and any URDF
given, exported to ``eaik`` and ``ikdh`` and solved by them, as the tests do for a sample.

    PYTHONPATH=. python scripts/ik_handoffs.py [--poses N] [--limit N] [--targets eaik,ikdh]
                                               [URDF ...]

For each arm and target: the export's refusal and its reason, or at ``--poses`` seeded
configurations within the limits, every returned solution's pose by Pinocchio against the pose
Pinocchio gives the configuration (tests/ik_handoff.py), the configuration among the solutions,
and the branches per pose. Prints each arm beyond the issue's bound (1e-9 x size, 1e-9 rad) or
whose configuration a solver that returns every branch missed, then a summary per target: arms
solved and refused (by reason), the worst errors, the poses missed, the branches; exits 1 if an
arm is beyond the bound. (roboticstoolbox derives its solver in seconds to minutes per arm: its
hand-off is tests/test_export_rtb_ik.py, ``URDF2DH_RTB_IK=all`` for every bundled arm.)
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT))  # this checkout's urdf2dh

from ik_corpus import dh_urdf, ikdh_robots  # noqa: E402
from ik_handoff import BOUND, HandOff, IkdhFile, eaik_solutions, judge  # noqa: E402

from urdf2dh import export  # noqa: E402
from urdf2dh.errors import ExportError  # noqa: E402
from urdf2dh.io.sources import open_source  # noqa: E402


def hand_off(target: str, label: str, path: str, poses: int, work: Path) -> HandOff | str:
    """One arm to one target: the judged hand-off, or the refusal's reason."""
    source = open_source(path)
    model = source.model()
    try:
        text = export(model, target)
    except ExportError as e:
        return str(e).removeprefix(f"{target}: ")
    q = model.sample(poses, 17)
    if target == "eaik":
        namespace: dict[str, object] = {"__name__": "generated_eaik"}
        exec(compile(text, "generated_eaik.py", "exec"), namespace)
        robot = namespace["robot"]
        return judge("eaik", "EAIK", label, source, model, q,
                     lambda T: eaik_solutions(robot, T))  # fmt: skip
    metres = {"mm": 1e-3, "m": 1.0}[model.length_unit]
    consumer = IkdhFile(text, work)
    return judge("ikdh", "ikdh", label, source, model, q, lambda T: consumer.solve(T, metres))


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("urdfs", nargs="*", help="URDF files to add to ikdh's D-H tables")
    p.add_argument("--poses", type=int, default=20, help="configurations per arm (20)")
    p.add_argument("--limit", type=int, default=None, help="the first N of ikdh's tables only")
    p.add_argument("--targets", default="eaik,ikdh", help="eaik,ikdh (default)")
    args = p.parse_args(argv)
    targets = args.targets.split(",")
    failed = False
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        arms = [(Path(u).name, str(u)) for u in args.urdfs]
        for table in ikdh_robots()[: args.limit]:
            urdf = work / f"{table.stem}.urdf"
            urdf.write_text(dh_urdf(table))
            arms.append((f"ikdh:{table.stem}", str(urdf)))
        for target in targets:
            start = time.perf_counter()
            solved: list[HandOff] = []
            refused: Counter[str] = Counter()
            for label, path in arms:
                result = hand_off(target, label, path, args.poses, work)
                if isinstance(result, str):
                    refused[result.split(":")[0] if ": " in result else result] += 1
                    continue
                solved.append(result)
                if not result.within(BOUND) or result.missed:
                    print(f"  {result.text()}")
                    failed = failed or not result.within(BOUND)
            branches = sum((r.branches for r in solved), Counter())
            missed = sum(len(r.missed) for r in solved)
            poses = sum(r.poses for r in solved)
            print(f"{target}: {len(solved)} arms solved, {sum(refused.values())} refused in "
                  f"{time.perf_counter() - start:.0f} s")  # fmt: skip
            for reason, count in refused.most_common():
                print(f"  refused ({count}): {reason}")
            if solved:
                worst = max(solved, key=lambda r: r.position)
                turned = max(solved, key=lambda r: r.rotation)
                print(f"  worst position {worst.position:.2g} x size ({worst.robot}), worst "
                      f"rotation {turned.rotation:.2g} rad ({turned.robot})")  # fmt: skip
                print(f"  configuration missed at {missed} of {poses} poses, in "
                      f"{sum(1 for r in solved if r.missed)} arms")  # fmt: skip
                print(
                    "  branches per pose (poses): "
                    + ", ".join(f"{k}: {v}" for k, v in sorted(branches.items()))
                )
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
