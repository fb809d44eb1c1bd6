"""Kinematic calibration side by side: urdf2dh, FIGAROH and robotkinecal, one run, the same data.

    python benchmarks/calibration.py [--repeats 3]                  # the real data sets
    python benchmarks/calibration.py --synthetic [--poses 1000] [--datasets 1]

**Real data** (the default): the three sets of ``../shared/calibration-data`` (a UR10e with a
camera, 23 poses; a TIAGo with motion capture, 34 positions of one marker; a Franka with an
eye-in-hand camera, 114 poses), each split as its README says (30% of the configurations held
out, seed 0: ``*_fit.csv`` and ``*_test.csv``). Every tool fits the fit file and is judged by its
RMS position error on the test file:

* urdf2dh's default, ``calibrate(nominal, measurements)``: the level chosen by cross-validation
  over configurations, and every level asked for in turn;
* FIGAROH 1.0.2 (PyPI ``figaroh``): its ``full_params`` and ``joint_offset`` calibration levels,
  base and tool frames unknown, its default solve (Levenberg-Marquardt with outlier rounds); the
  measurements written in its CSV layout (``x1, y1, z1[, phix1, phiy1, phiz1]``, joints by name);
* robotkinecal 0.1.0 (PyPI, installed with ``pip install --no-deps robotkinecal``): pose sets
  only (it takes poses), the measurements brought into the nominal's base frame by the rigid fit
  of the nominal's tool points (urdf2dh's own first step) since it starts from the nominal there.

Times are wall clock of the identification alone, best of ``--repeats`` (data in memory and the
model built: urdf2dh's ``calibrate``, FIGAROH's ``initialize`` + ``solve``, robotkinecal's
``set_observations`` + ``solve``) on a shared two-core machine; the ratios divide by urdf2dh's
default.

**Synthetic** (``--synthetic``): a UR5 as built (every joint axis tilted by ~2 mrad and shifted
by ~1 mm about the nominal, the tool turned and moved likewise; joint scales exact, as
robotkinecal's model has none), its flange poses measured in its base frame at ``--poses``
seeded configurations with 0.01 mm and 1e-5 rad of Gaussian noise per coordinate. Each tool
starts from the nominal UR5 and is judged by its model's forward kinematics against the robot as
built at 2000 fresh configurations. urdf2dh runs its geometry level (robotkinecal's parameters:
4 per joint and the tool's 6) and its full level (joint scales too); with ``--datasets K`` the
accuracies of urdf2dh and robotkinecal are also compared on K further data sets.
"""

from __future__ import annotations

import argparse
import math
import subprocess
import sys
import tempfile
import time
import warnings
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import urdf2dh  # noqa: E402
from urdf2dh import (  # noqa: E402
    calibrate,
    render,
    to_table,
)
from urdf2dh.calibration.identify import identify  # noqa: E402
from urdf2dh.calibration.measure import perturb, synthesize  # noqa: E402
from urdf2dh.calibration.measurements import (  # noqa: E402
    Measurements,
    read_measurements,
    write_measurements,
)
from urdf2dh.calibration.start import FitOptions, placement  # noqa: E402
from urdf2dh.geometry.lie import log_so3, rotation_of  # noqa: E402
from urdf2dh.io.catalog import ROBOTS, robot_path  # noqa: E402
from urdf2dh.model.poe import PoeModel, joint_from_twist  # noqa: E402

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


def ours(nominal: PoeModel, m: Measurements, repeats: int, opts: FitOptions) -> tuple[float, Any]:
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
    """FIGAROH's full_params on the synthetic UR5 poses: (time, its forward kinematics)."""
    import pinocchio as pin
    from figaroh.calibration.calibration_tools import calc_updated_fkm

    ur5 = str(robot_path(ROBOTS["ur5"]))
    elapsed, cal, robot = run_figaroh(ur5, "base_link", "tool0", m, "full_params", work, 1)

    def fk(q: np.ndarray) -> np.ndarray:
        config = dict(cal.calib_config, NbSample=len(q))
        flat = calc_updated_fkm(robot.model, robot.data, cal.LM_result.x, q, config)
        flat = flat.reshape(6, len(q))
        out = np.zeros((len(q), 4, 4))
        out[:, 3, 3] = 1.0
        out[:, :3, 3] = flat[:3].T
        out[:, :3, :3] = [pin.rpy.rpyToMatrix(*angles) for angles in flat[3:].T]
        return out

    return elapsed, fk


def run_figaroh(
    urdf: str, base: str, tool: str, fit: Measurements, level: str, work: Path, repeats: int
) -> tuple[float, Any, Any]:
    """FIGAROH at ``level`` (``full_params``, ``joint_offset``) on ``fit``, base and tool frames
    unknown, its default solve; the measurements in its CSV layout (x1, y1, z1 and, for poses,
    phix1, phiy1, phiz1; joints by name). Returns the best time of ``repeats``, the calibration
    and the robot. Its printed report goes nowhere."""
    import contextlib
    import io

    import pandas as pd
    import pinocchio as pin
    import yaml
    from figaroh.calibration.base_calibration import BaseCalibration
    from pinocchio.robot_wrapper import RobotWrapper

    robot = RobotWrapper(pin.buildModelFromUrdf(urdf))
    pose = fit.quaternions is not None
    columns = {f"{k}1": v for k, v in zip("xyz", fit.points.T, strict=True)}
    if pose:
        rpy = np.array([pin.rpy.matrixToRpy(r) for r in rotation_of(fit.quaternions)])
        columns |= {f"{k}1": v for k, v in zip(("phix", "phiy", "phiz"), rpy.T, strict=True)}
    columns |= {n: fit.q[:, i] for i, n in enumerate(fit.joints)}
    pd.DataFrame(columns).to_csv(work / "figaroh.csv", index=False)
    config = {
        "schema_version": "2.0",
        "robot": {"name": "robot"},
        "tasks": {
            "calibration": {
                "type": "kinematic_calibration",
                "kinematics": {"base_frame": base, "tool_frame": tool},
                "measurements": {"markers": [{"measurable_dof": [True] * 3 + [pose] * 3}]},
                "parameters": {"calibration_level": level},
                "data": {"source_file": str(work / "figaroh.csv"), "number_of_samples": len(fit)},
            }
        },
    }
    (work / "figaroh.yaml").write_text(yaml.safe_dump(config))

    class Calibration(BaseCalibration):
        pass

    def run() -> Any:
        cal = Calibration(robot, str(work / "figaroh.yaml"))
        cal.calib_config["known_baseframe"] = False  # the device frame and the tool are unknown
        cal.calib_config["known_tipframe"] = False
        with contextlib.redirect_stdout(io.StringIO()):
            cal.initialize()
            cal.solve(enable_logging=False)
        return cal

    elapsed, cal = best_time(run, repeats)
    return elapsed, cal, robot


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--synthetic", action="store_true", help="the synthetic UR5 comparison")
    parser.add_argument("--poses", type=int, default=1000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--datasets", type=int, default=1)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    if not args.synthetic:
        return real_sets(args.repeats)
    nominal = urdf2dh.load("ur5")
    actual = perturb(nominal, seed=3, angle=0.002, length=0.001)
    m = synthesize(actual, args.poses, NOISE, NOISE, seed=5)
    fresh = actual.sample(2000, 99)
    truth = actual.fk_batch(fresh)
    rows: list[tuple[str, float, dict[str, float]]] = []
    with tempfile.TemporaryDirectory(prefix="urdf2dh-bench-") as tmp:
        work = Path(tmp)
        elapsed, fk = ours(nominal, m, args.repeats, FitOptions(level="geometry"))
        rows.append(
            (
                "urdf2dh, --identify geometry (robotkinecal's parameters)",
                elapsed,
                accuracy(fk(fresh), truth),
            )
        )
        elapsed, fk = ours(nominal, m, args.repeats, FitOptions())
        rows.append(
            ("urdf2dh, --identify full (joint scales too)", elapsed, accuracy(fk(fresh), truth))
        )
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
    print("| data set | urdf2dh geometry | urdf2dh full | robotkinecal |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory(prefix="urdf2dh-bench-") as tmp:
        for seed in range(count):
            actual = perturb(nominal, seed=seed, angle=0.002, length=0.001)
            m = synthesize(actual, poses, NOISE, NOISE, seed=50 + seed)
            fresh = actual.sample(2000, 99)
            truth = actual.fk_batch(fresh)
            cells = []
            for fk in (
                ours(nominal, m, 1, FitOptions(level="geometry"))[1],
                ours(nominal, m, 1, FitOptions())[1],
                robotkinecal(nominal, m, Path(tmp))[1],
            ):
                acc = accuracy(fk(fresh), truth)
                cells.append(f"{acc['rms_pos'] * 1e6:.3f} / {acc['rms_rot'] * 1e6:.3f}")
            print(f"| {seed} | " + " | ".join(cells) + " |")


# ----------------------------------------------------------------------------- real data

DATA = Path(__file__).resolve().parents[2] / "shared" / "calibration-data"
if not DATA.is_dir():
    DATA = Path("/work/shared/calibration-data")

# name: (nominal for urdf2dh, URDF file for FIGAROH, its base and tool frames, stem of the files,
#        the best anchor's held-out RMS position from the data's README, m)
REAL = {
    "ur10": ("ur10", "wrist_3_link", "ur10/ur10_pose", 3.61e-3),
    "tiago": ("tiago", "wrist_ft_tool_link", "tiago/tiago_m1", 4.33e-3),
    "panda": ("panda", "panda_link8", "panda/panda_cam", 1.39e-3),
}


def _urdf(name: str) -> str:
    if name == "ur10":
        return str(DATA / "ur10" / "ur10_robot.urdf")
    if name == "tiago":
        return str(DATA / "tiago" / "tiago_48_schunk.urdf")
    return str(robot_path(ROBOTS["panda"]))


def held_out_rms(points: np.ndarray, measured: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum((points - measured) ** 2, axis=1))))


def best_time(run: Any, repeats: int) -> tuple[float, Any]:
    best, out = math.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        out = run()
        best = min(best, time.perf_counter() - start)
    return best, out


def _tool_points(model: PoeModel, m: Measurements) -> np.ndarray:
    poses = model.fk_batch(m.q)
    return poses[:, :3, 3]


def figaroh_real(
    urdf: str,
    tool: str,
    fit: Measurements,
    test: Measurements,
    level: str,
    work: Path,
    repeats: int = 1,
) -> tuple[float, float]:
    """FIGAROH at ``level`` on ``fit``, judged on ``test``: (time, held-out RMS position)."""
    from figaroh.calibration.calibration_tools import calc_updated_fkm

    elapsed, cal, robot = run_figaroh(urdf, "universe", tool, fit, level, work, repeats)
    q = np.zeros((len(test), robot.model.nq))
    for i, n in enumerate(test.joints):
        q[:, robot.model.joints[robot.model.getJointId(n)].idx_q] = test.q[:, i]
    flat = calc_updated_fkm(
        robot.model, robot.data, cal.LM_result.x, q, dict(cal.calib_config, NbSample=len(q))
    )
    flat = flat.reshape(6 if fit.quaternions is not None else 3, len(q))
    return elapsed, held_out_rms(flat[:3].T, test.points)


def robotkinecal_real(
    nominal: PoeModel, fit: Measurements, test: Measurements, work: Path, repeats: int = 1
) -> tuple[float, float]:
    """robotkinecal on ``fit`` brought into the nominal's base frame (module docstring)."""
    import roboticstoolbox as rtb
    from robotkinecal import SerialRobotKineCal
    from spatialmath import SE3

    g = np.linalg.inv(placement(nominal, fit, FitOptions(), [0]))  # device -> nominal base
    path = work / "nominal-dh.urdf"
    path.write_text(render(to_table(nominal, "dh"), "urdf"))
    robot = rtb.Robot.URDF(str(path))
    rotations = g[:3, :3] @ rotation_of(fit.quaternions)
    points = fit.points @ g[:3, :3].T + g[:3, 3]
    observations = [SE3.Rt(r, t, check=False) for r, t in zip(rotations, points, strict=True)]

    def run() -> Any:
        np.random.seed(0)  # noqa: NPY002 -- its joint bases come from numpy's global generator
        cal = SerialRobotKineCal(robot, ee_name=robot.links[-1].name, verbose=False)
        cal.set_observations(list(fit.q), observations)
        return cal.solve()

    elapsed, result = best_time(run, repeats)
    screws = result.get_screw_axes()  # [v, w] (spatialmath's order)
    joints = tuple(
        joint_from_twist(j.name, np.r_[s[3:], s[:3]], 1e-12)
        for j, s in zip(nominal.joints, screws, strict=True)
    )
    model = PoeModel(joints, np.array(result.get_zero_conf_EE_pose().A), "robotkinecal")
    predicted = _tool_points(model, test) @ np.linalg.inv(g)[:3, :3].T + np.linalg.inv(g)[:3, 3]
    return elapsed, held_out_rms(predicted, test.points)


def real_sets(repeats: int) -> int:
    """The side-by-side table on the real data sets (module docstring)."""
    print("### Calibration on real measurements: held-out RMS position, 30% of the configurations")
    print(
        "held out (the data's README split), and identification time (best of "
        f"{repeats}, wall clock)\n"
    )
    print("| set | tool | held-out RMS | vs best anchor | time | time / urdf2dh's |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory(prefix="urdf2dh-bench-") as tmp:
        for name in REAL:
            for label, rms, elapsed, base in one_set(name, repeats, Path(tmp)):
                print(
                    f"| {name} | {label} | {rms * 1e3:.2f} mm | {rms / REAL[name][3]:.3f}x | "
                    f"{elapsed:.3f} s | {elapsed / base:.2f}x |"
                )
    return 0


def one_set(name: str, repeats: int, work: Path) -> list[tuple[str, float, float, float]]:
    """Every tool on one real set: (label, held-out RMS, time, urdf2dh's default time)."""
    robot, tool, stem, _ = REAL[name]
    urdf = _urdf(name)
    nominal = urdf2dh.load(robot) if name == "panda" else urdf2dh.load(urdf, tip=tool)
    joints = tuple(j.name for j in nominal.joints)
    fit = read_measurements(DATA / f"{stem}_fit.csv", joints)
    test = read_measurements(DATA / f"{stem}_test.csv", joints)
    rows: list[tuple[str, float, float]] = []
    base, cal = best_time(partial(calibrate, nominal, fit, convention="poe"), repeats)
    label = f"urdf2dh default (chose {cal.level}, {cal.iterations} iterations)"
    rows.append((label, _held_out(cal.device_model, cal, test), base))
    for level in ("base-tool", "offsets", "geometry", "full"):
        run = partial(calibrate, nominal, fit, identify_level=level, convention="poe")
        elapsed, other = best_time(run, repeats)
        rows.append(
            (f"urdf2dh --identify {level}", _held_out(other.device_model, other, test), elapsed)
        )
    for level in ("full_params", "joint_offset"):
        try:
            elapsed, rms = figaroh_real(urdf, tool, fit, test, level, work, repeats)
        except Exception as e:  # report why a tool could not run, and go on
            print(f"FIGAROH {level} on {name}: could not run: {type(e).__name__}: {e}")
            continue
        rows.append((f"FIGAROH {level}", rms, elapsed))
    if fit.quaternions is not None:
        try:
            elapsed, rms = robotkinecal_real(nominal, fit, test, work, repeats)
            rows.append(("robotkinecal", rms, elapsed))
        except Exception as e:  # report why a tool could not run, and go on
            print(f"robotkinecal on {name}: could not run: {type(e).__name__}: {e}")
    return [(label, rms, elapsed, base) for label, rms, elapsed in rows]


def _held_out(device_model: PoeModel, cal: Any, test: Measurements) -> float:
    """The held-out RMS position of a calibration's model, its marker where it has one."""
    poses = device_model.fk_batch(test.q)
    if cal.measure == "position" and cal.markers_on_tool:
        marker = next(iter(cal.markers_on_tool.values()))
        points = np.einsum("nij,j->ni", poses[:, :3, :3], marker) + poses[:, :3, 3]
    else:
        points = poses[:, :3, 3]
    return held_out_rms(points, test.points)


if __name__ == "__main__":
    sys.exit(main())
