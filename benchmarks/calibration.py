"""Kinematic calibration side by side (issue 15): urdf2dh, robotkinecal and FIGAROH, one run,
the same data.

    python benchmarks/calibration.py [--poses 1000] [--repeats 3] [--datasets 1]

The data: a UR5 as built (every joint axis tilted by ~2 mrad and shifted by ~1 mm about the
nominal, the tool turned and moved likewise; joint scales exact, as robotkinecal's model has
none), its flange poses measured in its base frame at ``--poses`` seeded configurations with
0.01 mm and 1e-5 rad of Gaussian noise per coordinate (issue 15's levels). Each tool starts from
the nominal UR5 and is judged by its model's forward kinematics against the robot as built at
2000 fresh configurations (RMS and max of the position and rotation errors). urdf2dh runs
twice: with ``--keep-scale``, which identifies exactly robotkinecal's parameters (4 per joint and
the tool's 6), the like-for-like comparison whose time the ratios divide by; and by default,
with the 6 joint scales too (which this robot as built does not need, so they cost a little
variance). Times are wall clock of the identification alone (data in memory, model built: for
urdf2dh ``identify``, for robotkinecal ``set_observations`` + ``solve``, for FIGAROH
``initialize`` + ``solve``), best of ``--repeats`` runs each (the machine may be shared). The
whole ``urdf2dh calibrate`` command, start-up and files included, is timed once too. With
``--datasets K`` the accuracies of urdf2dh and robotkinecal are also compared on K further data
sets (as-built UR5s and noise drawn with seeds 0 .. K-1).

robotkinecal 0.1.0 (PyPI) pins numpy < 2; it is installed without its dependencies
(``pip install --no-deps robotkinecal``) and runs on numpy 2 with roboticstoolbox-python 1.5.
FIGAROH (``figaroh`` on PyPI) needs a configuration file and a CSV in its own layout; both are
written here (base and tool frames unknown, ``full_params``: 6 parameters per joint, reduced by
its QR selection), and its default solve (Levenberg-Marquardt with outlier rounds) is used.
"""

from __future__ import annotations

import argparse
import math
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import urdf2dh  # noqa: E402
from urdf2dh.calibrate.identify import identify  # noqa: E402
from urdf2dh.calibrate.lie import log_so3, rotation_of  # noqa: E402
from urdf2dh.calibrate.measure import perturb, synthesize  # noqa: E402
from urdf2dh.calibrate.measurements import Measurements, write_measurements  # noqa: E402
from urdf2dh.calibrate.start import Options  # noqa: E402
from urdf2dh.catalog import ROBOTS, robot_path  # noqa: E402
from urdf2dh.convert import sample_configurations, to_table  # noqa: E402
from urdf2dh.formats import render  # noqa: E402
from urdf2dh.poefile import joint_from_twist  # noqa: E402
from urdf2dh.screws import PoeModel  # noqa: E402

NOISE = 1e-5  # m and rad


def accuracy(poses: np.ndarray, truth: np.ndarray) -> dict[str, float]:
    """RMS and max position (m) and rotation (rad) errors of (N, 4, 4) stacks."""
    pos = np.linalg.norm(poses[:, :3, 3] - truth[:, :3, 3], axis=1)
    rot = np.linalg.norm(log_so3(poses[:, :3, :3] @ np.swapaxes(truth[:, :3, :3], 1, 2)), axis=1)
    return {
        "rms_pos": float(np.sqrt(np.mean(pos**2))),
        "max_pos": float(pos.max()),
        "rms_rot": float(np.sqrt(np.mean(rot**2))),
        "max_rot": float(rot.max()),
    }


def ours(nominal: PoeModel, m: Measurements, repeats: int, opts: Options) -> tuple[float, Any]:
    best, model = math.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        result = identify(nominal, m, opts)
        best = min(best, time.perf_counter() - start)
        model = result.model
    return best, model.fk_batch


def whole_command(m: Measurements, work: Path) -> float:
    (work / "poses.csv").write_text(write_measurements(m))
    start = time.perf_counter()
    subprocess.run(
        [
            sys.executable,
            "-m",
            "urdf2dh.cli",
            "calibrate",
            "ur5",
            str(work / "poses.csv"),
            "-o",
            str(work / "cal.json"),
            "--format",
            "json",
            "--report",
            str(work / "report.json"),
        ],
        check=True,
        capture_output=True,
        cwd=ROOT,
    )
    return time.perf_counter() - start


def robotkinecal(nominal: PoeModel, m: Measurements, work: Path) -> tuple[float, Any]:
    import roboticstoolbox as rtb
    from robotkinecal import SerialRobotKineCal
    from spatialmath import SE3

    # robotkinecal takes joint screws as the z axes of the links' frames: the nominal goes in
    # as urdf2dh's URDF of its D-H frames (every joint axis along its frame's z). (Its PoERobot
    # path reads roboticstoolbox 1.5's added base and tool links as joints and fails.)
    path = work / "ur5-dh.urdf"
    path.write_text(render(to_table(nominal, "dh"), "urdf"))
    robot = rtb.Robot.URDF(str(path))
    rotations = rotation_of(m.quaternions)
    observations = [SE3.Rt(r, t, check=False) for r, t in zip(rotations, m.points, strict=True)]
    np.random.seed(0)  # noqa: NPY002 -- its joint bases come from numpy's global generator
    start = time.perf_counter()
    cal = SerialRobotKineCal(robot, ee_name="tool0", verbose=False)
    cal.set_observations(list(m.q), observations)
    result = cal.solve()
    elapsed = time.perf_counter() - start
    screws = result.get_screw_axes()  # [v, w] (spatialmath's order)
    joints = tuple(
        joint_from_twist(j.name, np.r_[s[3:], s[:3]], 1e-12)
        for j, s in zip(nominal.joints, screws, strict=True)
    )
    model = PoeModel(joints, np.array(result.get_zero_conf_EE_pose().A), "robotkinecal")
    return elapsed, model.fk_batch


def figaroh(m: Measurements, work: Path) -> tuple[float, Any]:
    import pandas as pd
    import pinocchio as pin
    import yaml
    from figaroh.calibration.base_calibration import BaseCalibration
    from figaroh.calibration.calibration_tools import calc_updated_fkm
    from pinocchio.robot_wrapper import RobotWrapper

    robot = RobotWrapper(pin.buildModelFromUrdf(str(robot_path(ROBOTS["ur5"]))))
    names = [robot.model.names[i] for i in range(1, robot.model.njoints)]
    rpy = np.array([pin.rpy.matrixToRpy(r) for r in rotation_of(m.quaternions)])
    columns = {f"{k}1": v for k, v in zip(("x", "y", "z"), m.points.T, strict=True)}
    columns |= {f"{k}1": v for k, v in zip(("phix", "phiy", "phiz"), rpy.T, strict=True)}
    columns |= {n: m.q[:, i] for i, n in enumerate(names)}
    pd.DataFrame(columns).to_csv(work / "figaroh.csv", index=False)
    config = {
        "schema_version": "2.0",
        "robot": {"name": "ur5"},
        "tasks": {
            "calibration": {
                "type": "kinematic_calibration",
                "kinematics": {"base_frame": "base_link", "tool_frame": "tool0"},
                "measurements": {"markers": [{"measurable_dof": [True] * 6}]},
                "parameters": {"calibration_level": "full_params"},
                "data": {"source_file": str(work / "figaroh.csv"), "number_of_samples": len(m)},
            }
        },
    }
    (work / "figaroh.yaml").write_text(yaml.safe_dump(config))

    class Calibration(BaseCalibration):
        pass

    start = time.perf_counter()
    cal = Calibration(robot, str(work / "figaroh.yaml"))
    cal.calib_config["known_baseframe"] = False  # the device frame and the tool are unknown
    cal.calib_config["known_tipframe"] = False
    cal.initialize()
    cal.solve(enable_logging=False)
    elapsed = time.perf_counter() - start
    var = cal.LM_result.x

    def fk(q: np.ndarray) -> np.ndarray:
        config = dict(cal.calib_config, NbSample=len(q))
        flat = calc_updated_fkm(robot.model, robot.data, var, q, config).reshape(6, len(q))
        out = np.zeros((len(q), 4, 4))
        out[:, 3, 3] = 1.0
        out[:, :3, 3] = flat[:3].T
        out[:, :3, :3] = [pin.rpy.rpyToMatrix(*angles) for angles in flat[3:].T]
        return out

    return elapsed, fk


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=1000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--datasets", type=int, default=1)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    nominal = urdf2dh.load("ur5")
    actual = perturb(nominal, seed=3, angle=0.002, length=0.001)
    m = synthesize(actual, args.poses, NOISE, NOISE, seed=5)
    fresh = sample_configurations(actual, 2000, 99)
    truth = actual.fk_batch(fresh)
    rows: list[tuple[str, float, dict[str, float]]] = []
    with tempfile.TemporaryDirectory(prefix="urdf2dh-bench-") as tmp:
        work = Path(tmp)
        elapsed, fk = ours(nominal, m, args.repeats, Options(keep_scale=True))
        rows.append(
            (
                "urdf2dh, --keep-scale (robotkinecal's parameters)",
                elapsed,
                accuracy(fk(fresh), truth),
            )
        )
        elapsed, fk = ours(nominal, m, args.repeats, Options())
        rows.append(("urdf2dh, default (joint scales too)", elapsed, accuracy(fk(fresh), truth)))
        command = whole_command(m, work)
        for name, run in (
            ("robotkinecal", lambda: robotkinecal(nominal, m, work)),
            ("FIGAROH", lambda: figaroh(m, work)),
        ):
            best = math.inf
            try:
                for _ in range(args.repeats):
                    elapsed, fk = run()
                    best = min(best, elapsed)
            except Exception as e:  # report why a tool could not run, and go on
                print(f"{name}: could not run: {type(e).__name__}: {e}")
                continue
            rows.append((name, best, accuracy(fk(fresh), truth)))
    rows.append(("nominal (no calibration)", 0.0, accuracy(nominal.fk_batch(fresh), truth)))
    print(
        f"### Calibration: UR5 as built, {args.poses} poses, noise {NOISE * 1e3:g} mm and "
        f"{NOISE:g} rad; errors at 2000 new configurations\n"
    )
    print(
        f"| tool | time (best of {args.repeats}) | time / urdf2dh's | RMS position | "
        "max position | RMS rotation | max rotation |"
    )
    print("|---|---|---|---|---|---|---|")
    base = rows[0][1]
    for name, elapsed, acc in rows:
        ratio = f"{elapsed / base:.1f}x" if elapsed else "-"
        print(
            f"| {name} | {elapsed:.3f} s | {ratio} | {acc['rms_pos'] * 1e6:.3f} um | "
            f"{acc['max_pos'] * 1e6:.3f} um | {acc['rms_rot'] * 1e6:.3f} urad | "
            f"{acc['max_rot'] * 1e6:.3f} urad |"
        )
    print(f"\nwhole `urdf2dh calibrate` command (new process, files written): {command:.2f} s")
    if args.datasets > 1:
        more_datasets(nominal, args.poses, args.datasets)
    return 0


def more_datasets(nominal: PoeModel, poses: int, count: int) -> None:
    """RMS position (um) and rotation (urad) of urdf2dh and robotkinecal on more data sets."""
    print(f"\n### Accuracy on {count} more data sets (RMS position um / rotation urad)\n")
    print("| data set | urdf2dh --keep-scale | urdf2dh default | robotkinecal |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory(prefix="urdf2dh-bench-") as tmp:
        for seed in range(count):
            actual = perturb(nominal, seed=seed, angle=0.002, length=0.001)
            m = synthesize(actual, poses, NOISE, NOISE, seed=50 + seed)
            fresh = sample_configurations(actual, 2000, 99)
            truth = actual.fk_batch(fresh)
            cells = []
            for fk in (
                ours(nominal, m, 1, Options(keep_scale=True))[1],
                ours(nominal, m, 1, Options())[1],
                robotkinecal(nominal, m, Path(tmp))[1],
            ):
                acc = accuracy(fk(fresh), truth)
                cells.append(f"{acc['rms_pos'] * 1e6:.3f} / {acc['rms_rot'] * 1e6:.3f}")
            print(f"| {seed} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    sys.exit(main())
