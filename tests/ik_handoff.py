"""How the analytic IK exports are proven in their solvers: at seeded configurations within the
joint limits, the pose the source's URDF gives there (Pinocchio), the solver's solutions for that
pose, and each solution's pose again by Pinocchio.

:func:`judge` measures, for one robot and one solver, the worst distance of any returned solution's
pose from the target (position relative to the robot's size, rotation in radians), the number of
solutions per pose, and the poses whose configuration is not among the solutions (modulo 2 pi).
:func:`record` writes the result to the consumers' report (scripts/check-consumers prints it).

Nothing here uses urdf2dh's own kinematics: the oracle is Pinocchio on the source.
"""

from __future__ import annotations

import json
import math
import os
import re
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from urdf2dh import PoeModel
from urdf2dh.check.verify import pinocchio_evaluator
from urdf2dh.geometry.se3 import pose_errors
from urdf2dh.io.sources import Source

BOUND = 1e-9  # the issue's: every solution's pose within 1e-9 x size and 1e-9 rad of the target
SAME = 1e-6  # rad: a solution is the sampled configuration (each joint, modulo 2 pi)
REPORT_ENV = "URDF2DH_CONSUMER_REPORT"

Solve = Callable[[np.ndarray], np.ndarray]  # pose (4, 4) in the source's unit -> (k, n) radians


@dataclass
class HandOff:
    """One solver on one robot (:func:`judge`)."""

    target: str
    consumer: str
    robot: str
    size: float
    poses: int = 0
    position: float = 0.0  # worst, x size
    rotation: float = 0.0  # worst, rad
    branches: Counter[int] = field(default_factory=Counter)  # solutions per pose -> poses
    missed: list[tuple[np.ndarray, float]] = field(default_factory=list)  # (q, nearest)
    beyond: list[np.ndarray] = field(default_factory=list)  # q whose pose got a solution > BOUND
    seconds: float = 0.0  # in the solver
    derived: float | None = None  # seconds the solver took to be made (roboticstoolbox)
    form: str = ""  # which of the consumer's answers (rtb: "raw", its own; "solve()", polished)
    steps: int | None = None  # the most Gauss-Newton steps a branch took (rtb's solve())
    recovered: int | None = None  # branches solve() has that the consumer's own answer lacks
    moved: float | None = None  # rad: the farthest a polished branch is from where it started

    def within(self, bound: float = BOUND) -> bool:
        return self.position <= bound and self.rotation <= bound

    def text(self) -> str:
        counts = ", ".join(f"{k}: {v}" for k, v in sorted(self.branches.items()))
        form = f" ({self.form})" if self.form else ""
        return (
            f"{self.target} {self.robot}{form}: worst {self.position:.2g} x size, "
            f"{self.rotation:.2g} "
            f"rad over {self.poses} poses ({len(self.beyond)} beyond {BOUND:g}); branches per pose "
            f"{{{counts}}}; configuration missed {len(self.missed)}"
        )


def angle_gaps(solutions: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Each solution's largest joint difference from ``q``, modulo 2 pi (radians)."""
    if len(solutions) == 0:
        return np.array([math.inf])
    return np.abs(np.remainder(solutions - q + math.pi, 2 * math.pi) - math.pi).max(axis=1)


def judge(
    target: str,
    consumer: str,
    robot: str,
    source: Source,
    model: PoeModel,
    q: np.ndarray,
    solve: Solve,
) -> HandOff:
    """Ask ``solve`` for the source's pose at each configuration of ``q`` and judge its answers
    by Pinocchio (module doc)."""
    fk = pinocchio_evaluator(source, model)
    targets = fk(q)
    out = HandOff(target, consumer, robot, model.size(), poses=len(q))
    for row, pose in zip(q, targets, strict=True):
        start = time.perf_counter()
        solutions = np.asarray(solve(pose), dtype=float).reshape(-1, model.dof)
        out.seconds += time.perf_counter() - start
        out.branches[len(solutions)] += 1
        if len(solutions):
            reached = fk(solutions)
            position, rotation = pose_errors(reached, np.broadcast_to(pose, reached.shape))
            out.position = max(out.position, position / out.size)
            out.rotation = max(out.rotation, rotation)
            if position > BOUND * out.size or rotation > BOUND:
                out.beyond.append(row)
        nearest = float(angle_gaps(solutions, row).min())
        if nearest > SAME:
            out.missed.append((row, nearest))
    return out


def declared(text: str) -> tuple[float, float]:
    """The deviation from the source a generated file declares (its length unit, radians; 0
    for an exact file): ``declared bound against the source: X unit, Y rad``."""
    m = re.search(r"declared bound against the source: (\S+) \S+, (\S+) rad", text)
    return (0.0, 0.0) if m is None else (float(m[1]), float(m[2]))


@dataclass
class Scripted:
    """A Python export run: the source, its model, the script, the robot it defines and the
    script's namespace (its functions)."""

    source: Source
    model: PoeModel
    script: str
    robot: Any
    namespace: dict[str, Any]


def scripted(target: str, consumer: str, label: str, path: str,
             fk: Callable[[Any, np.ndarray], np.ndarray], poses: int,
             ) -> tuple[Scripted, np.ndarray]:  # fmt: skip
    """Export ``path`` as the Python script of ``target``, run it, and hold its ``robot``'s
    forward kinematics (``fk(robot, q)``, a pose) to Pinocchio's on the source, within the
    deviation the script declares, at ``poses`` seeded configurations within the limits (which
    it returns for the IK checks); the error goes to the consumers' report."""
    from consumers import report
    from oracle import EXACT, assert_fk_matches

    from urdf2dh import export
    from urdf2dh.check.verify import pinocchio_fk
    from urdf2dh.io.sources import open_source

    source = open_source(path)
    model = source.model()
    script = export(model, target)
    namespace: dict[str, Any] = {"__name__": f"generated_{target}"}
    exec(compile(script, f"generated_{target}.py", "exec"), namespace)
    robot = namespace["robot"]
    q = model.sample(poses, 17)
    position, rotation = declared(script)
    errors = assert_fk_matches(f"{target} {label}", np.array([fk(robot, row) for row in q]),
                               pinocchio_fk(source, model, q), model.size(), q,
                               rel=EXACT + position / model.size(),
                               rot=EXACT + rotation)  # fmt: skip
    report(target, consumer, errors, model.size())
    return Scripted(source, model, script, robot, namespace), q


def eaik_solutions(robot: Any, pose: np.ndarray, n: int = 6) -> np.ndarray:
    """EAIK's exact solutions for ``pose`` (its ``is_LS`` rows are left out)."""
    solution = robot.IK(pose)
    return solution.Q[~solution.is_LS] if solution.num_solutions() else np.zeros((0, n))


class IkdhFile:
    """A written file as ikdh reads it, with the ``base`` and ``tool`` beside."""

    def __init__(self, text: str, directory: Path) -> None:
        path = directory / "robot.yaml"
        path.write_text(text)
        import ikdh

        self.robot = ikdh.load_robot(str(path))  # the consumer's own reader
        self.solver = ikdh.Solver(self.robot.dh, self.robot.limits)
        blocks = yaml.safe_load(text)
        self.base, self.tool = (np.array(blocks[k], dtype=float) for k in ("base", "tool"))
        self.unit = re.search(r"Lengths in (\w+),", text)[1]  # type: ignore[index]

    def to_file(self, pose: np.ndarray, metres: float) -> np.ndarray:
        """A pose of the source (its unit: ``metres`` each) as the solver is asked for it."""
        scaled = pose.copy()
        scaled[:3, 3] *= metres / {"mm": 1e-3, "m": 1.0}[self.unit]
        return np.linalg.inv(self.base) @ scaled @ np.linalg.inv(self.tool)

    def fk(self, q: np.ndarray, metres: float) -> np.ndarray:
        """ikdh's forward kinematics with base and tool, in the source's unit."""
        import ikdh

        out = np.array([self.base @ ikdh.forward_kin(self.robot.dh, np.degrees(r)) @ self.tool
                        for r in q])  # fmt: skip
        out[:, :3, 3] *= {"mm": 1e-3, "m": 1.0}[self.unit] / metres
        return out

    def solve(self, pose: np.ndarray, metres: float) -> np.ndarray:
        return np.radians(np.array(self.solver.solve(self.to_file(pose, metres)))).reshape(-1, 6)

    def reaches(self, pose: np.ndarray, q: np.ndarray, metres: float) -> bool:
        """ikdh's Newton step from ``q`` (``solve_from_seed``) stays at ``q``: the file's robot
        reaches the pose there."""
        found = self.solver.solve_from_seed(self.to_file(pose, metres), np.degrees(q), 100)
        return len(found) == 1 and angle_gaps(np.radians(np.array(found)), q)[0] <= SAME


def record(result: HandOff) -> None:
    """Add ``result`` to the consumers' report (``$URDF2DH_CONSUMER_REPORT``, one JSON line;
    nothing when it is unset): scripts/check-consumers prints each target's and robot's."""
    path = os.environ.get(REPORT_ENV)
    if not path:
        return
    line = {
        "kind": "ik",
        "target": result.target,
        "consumer": result.consumer,
        "robot": result.robot,
        "poses": result.poses,
        "position": result.position,
        "rotation": result.rotation,
        "branches": {str(k): v for k, v in sorted(result.branches.items())},
        "missed": len(result.missed),
        "beyond": len(result.beyond),
        "ms_per_pose": 1e3 * result.seconds / max(result.poses, 1),
        "derived_s": result.derived,
        "form": result.form,
        "steps": result.steps,
        "recovered": result.recovered,
        "moved": result.moved,
    }
    with open(path, "a") as f:
        f.write(json.dumps(line) + "\n")


def refusal(target: str, robot: str, reason: str) -> None:
    """Add a refusal to the consumers' report (as :func:`record`)."""
    path = os.environ.get(REPORT_ENV)
    if path:
        with open(path, "a") as f:
            line = {"kind": "ik-refused", "target": target, "robot": robot, "reason": reason}
            f.write(json.dumps(line) + "\n")
