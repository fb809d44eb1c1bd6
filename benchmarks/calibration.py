"""Kinematic calibration side by side: urdf2dh, FIGAROH and robotkinecal, one run, the same data.

    python benchmarks/calibration.py [--repeats 3]                  # the real data sets
    python benchmarks/calibration.py --synthetic [--poses 1000] [--datasets 1]

**Real data** (the default): the three sets of ``examples/calibration-data`` (a UR10e with a
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
default, and the last column by urdf2dh's time for the level its default chose when that level
is asked for (``level=...``: the same model, no levels judged). A last table compares level for
level: FIGAROH's ``joint_offset`` over urdf2dh's ``offsets`` and its ``full_params`` over
urdf2dh's ``full``, each asked for.

**Scaling** (``--scaling``): the UR5 as built below measured at 1,000, 10,000 and 100,000 seeded
configurations, each count in a new process: the CSV written, read back (``read_measurements``)
and calibrated by the default command (``calibrate``, best of 3 in that process), the times and
the process's peak memory.

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
from dataclasses import dataclass, field, replace
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
from urdf2dh.calibration.levels import NAMES  # noqa: E402
from urdf2dh.calibration.measure import perturb, synthesize  # noqa: E402
from urdf2dh.calibration.measurements import (  # noqa: E402
    Measurements,
    Reading,
    read_measurements,
    write_measurements,
)
from urdf2dh.calibration.problem import holdout_split  # noqa: E402
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
    parser.add_argument("--scaling", action="store_true", help="1,000 to 100,000 UR5 poses")
    parser.add_argument("--scaling-child", type=int, help=argparse.SUPPRESS)
    parser.add_argument(
        "--unseen",
        metavar="DIR",
        type=Path,
        help="the data sets the project did not build on, their files in DIR (unseen_sets)",
    )
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    if args.scaling_child is not None:
        return scaling_child(args.scaling_child)
    if args.scaling:
        return scaling()
    if args.unseen is not None:
        return real_sets(unseen_sets(args.unseen), args.repeats)
    if not args.synthetic:
        return real_sets(shared_sets(), args.repeats)
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


SCALING = (1_000, 10_000, 100_000)
SCALING_REPEATS = 3  # each count's calibration: the best of these (one process)


def scaling_child(poses: int) -> int:
    """One row of the scaling table (module docstring), printed as ``poses bytes read fit
    peak-bytes level``."""
    import resource

    nominal = urdf2dh.load("ur5")
    actual = perturb(nominal, seed=3, angle=0.002, length=0.001)
    m = synthesize(actual, poses, NOISE, NOISE, seed=5)
    calibrate(nominal, synthesize(actual, 50, NOISE, NOISE, seed=6))  # the first call's imports
    with tempfile.TemporaryDirectory(prefix="urdf2dh-bench-") as tmp:
        path = Path(tmp) / "poses.csv"
        path.write_text(write_measurements(m))
        size = path.stat().st_size
        start = time.perf_counter()
        read = read_measurements(path, tuple(j.name for j in nominal.joints))
        reading = time.perf_counter() - start
    fitting, cal = best_time(partial(calibrate, nominal, read), SCALING_REPEATS)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    print(poses, size, reading, fitting, peak, cal.level)
    return 0


def scaling() -> int:
    """The scaling table (module docstring)."""
    print("### Scaling: UR5 poses, the default `calibrate`, each count in a new process\n")
    print("| poses | CSV | read | calibrate | / 1,000 poses' | peak memory (process) | level |")
    print("|---|---|---|---|---|---|---|")
    base = math.nan
    for poses in SCALING:
        done = subprocess.run(
            [sys.executable, __file__, "--scaling-child", str(poses)],
            check=True,
            capture_output=True,
            text=True,
        )
        _, size, reading, fitting, peak, level = done.stdout.split()
        base = float(fitting) if poses == SCALING[0] else base
        print(
            f"| {poses:,} | {int(size) / 2**20:.1f} MiB | {float(reading):.2f} s | "
            f"{float(fitting):.2f} s | {float(fitting) / base:.1f}x | "
            f"{int(peak) / 2**30:.2f} GiB | {level} |"
        )
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

DATA = Path(__file__).resolve().parents[1] / "examples" / "calibration-data"
FIGAROH_LEVELS = ("full_params", "joint_offset")
LEVEL_NAMES = NAMES


@dataclass(frozen=True)
class RealSet:
    """One real data set: what urdf2dh loads, what FIGAROH loads, the measurements.

    Attributes
    ----------
    name, source
        Its name and provenance (repository @ commit : path).
    robot, tip
        urdf2dh's SOURCE and ``--tip`` (``None``: the source's own).
    urdf, tool
        The URDF file FIGAROH loads and its tool frame (its base frame is the URDF's root).
    files
        The fit and test files (the data's README split), or one file split as the README says
        (30% of the configurations held out, seed 0).
    reading
        How the file is read (:class:`urdf2dh.calibration.measurements.Reading`).
    anchor
        The best anchor's held-out RMS position (the data's README, m), where there is one.
    shifted
        Rows of the file recorded with a controller's joint offsets in its joint readings, taken
        off before the split (:class:`Shifted`); ``None``: every row as it is.
    """

    name: str
    source: str
    robot: str
    tip: str | None
    urdf: str
    tool: str
    files: tuple[Path, ...]
    reading: Reading = field(default_factory=Reading)
    anchor: float | None = None
    shifted: Shifted | None = None


@dataclass(frozen=True)
class Shifted:
    """Joint readings a controller's own calibration shifted: ``offsets`` (joint name -> rad)
    are subtracted from the readings of the file's data rows ``rows`` (0-based)."""

    rows: range
    offsets: dict[str, float]
    why: str

    def take_off(self, m: Measurements) -> Measurements:
        q = m.q.copy()
        for name, offset in self.offsets.items():
            q[list(self.rows), m.joints.index(name)] -= offset
        return replace(m, q=q)


def shared_sets() -> list[RealSet]:
    """The three sets of ``examples/calibration-data`` (its README)."""
    ur10 = str(DATA / "ur10" / "ur10_robot.urdf")
    tiago = str(DATA / "tiago" / "tiago_48_schunk.urdf")
    panda = str(robot_path(ROBOTS["panda"]))
    return [
        RealSet("ur10", "calibration-data/ur10", ur10, "wrist_3_link", ur10, "wrist_3_link",
                (DATA / "ur10" / "ur10_pose_fit.csv", DATA / "ur10" / "ur10_pose_test.csv"),
                anchor=3.61e-3),
        RealSet("tiago", "calibration-data/tiago", tiago, "wrist_ft_tool_link", tiago,
                "wrist_ft_tool_link",
                (DATA / "tiago" / "tiago_m1_fit.csv", DATA / "tiago" / "tiago_m1_test.csv"),
                anchor=4.33e-3),
        RealSet("panda", "calibration-data/panda", "panda", None, panda, "panda_link8",
                (DATA / "panda" / "panda_cam_fit.csv", DATA / "panda" / "panda_cam_test.csv"),
                anchor=1.39e-3),
    ]  # fmt: skip


def _talos(side: str) -> tuple[tuple[str, str], ...]:
    short = "L" if side == "left" else "R"
    return (
        ("torso1", "torso_1_joint"),
        ("torso2", "torso_2_joint"),
        *((f"arm{short}{k}", f"arm_{side}_{k}_joint") for k in range(1, 8)),
    )


PAL_OFFSETS = Shifted(
    range(8, 16),
    {
        "arm_1_joint": 0.02,
        "arm_2_joint": -0.000704814,
        "arm_3_joint": -0.0054179,
        "arm_4_joint": 0.0105299,
        "arm_5_joint": -0.02,
        "arm_6_joint": 0.0197129,
        "arm_7_joint": -0.02,
    },
    "cross_valid.csv is three blocks of 8 rows reaching the same 8 points: without joint "
    "offsets, with PAL's, with FIGAROH's motion-capture calibration (thanhndv212/figaroh @ "
    "742cd41 : scripts/tiago_cross_valid.py, which gives PAL's 7 arm offsets and applies them "
    "to the second block's joint values). Those rows agree with the others only with PAL's "
    "offsets taken off their readings (scripts/session_offsets.py)",
)


def unseen_sets(directory: Path) -> list[RealSet]:
    """Data sets the project did not build on, their files in ``directory`` as their
    repositories name them (fetch them from there; they are not part of urdf2dh):

    * thanhndv212/figaroh @ 742cd41 : ``data/talos/talos_feb_arm_02_10_contact.csv``,
      ``talos_feb_arm_02_07_crane.csv``, ``talos_mars_right_arm_04_03_crane.csv`` (TALOS arm
      positions, motion capture) and ``data/tiago/cross_valid.csv`` (a TIAGo session: as it
      is, and with PAL's joint offsets taken off the rows recorded under them, :data:`PAL_OFFSETS`);
    * thanhndv212/figaroh-plus @ c3b5172 : ``examples/talos/data/talos_full_v2.urdf``,
      ``examples/mate/urdf/mate.urdf`` and ``examples/mate/data/transformed_poses.csv`` (MATE,
      three joints, poses in degrees);
    * clementPene/figaroh_tiagoPro @ eb4d7d6 : ``tiago_pro.urdf`` and
      ``data/calibration_samples_20260701_0913.csv`` (a TIAGo Pro's right arm).
    """
    d = directory
    talos, tiago_pro = str(d / "talos_full_v2.urdf"), str(d / "tiago_pro.urdf")
    tiago = str(DATA / "tiago" / "tiago_48_schunk.urdf")
    tiago_joints = (("torso", "torso_lift_joint"), ("atm6", "arm_6_joint"),
                    *((f"arm{k}", f"arm_{k}_joint") for k in (1, 2, 3, 4, 5, 7)))  # fmt: skip
    left = Reading(ignore=("t",), rename=_talos("left"))
    right = Reading(rename=_talos("right"))
    figaroh = "thanhndv212/figaroh @ 742cd41 : data/"
    pro = "clementPene/figaroh_tiagoPro @ eb4d7d6 : data/"
    mate = "thanhndv212/figaroh-plus @ c3b5172 : examples/mate/data/"
    hand, other_hand = "gripper_left_base_link", "gripper_right_base_link"
    contact, crane = "talos_feb_arm_02_10_contact.csv", "talos_feb_arm_02_07_crane.csv"
    right_crane, samples = (
        "talos_mars_right_arm_04_03_crane.csv",
        "calibration_samples_20260701_0913.csv",
    )
    return [
        RealSet("TALOS left arm, contact", figaroh + "talos/" + contact, talos, hand, talos,
                hand, (d / contact,), left),
        RealSet("TALOS left arm, crane", figaroh + "talos/" + crane, talos, hand, talos, hand,
                (d / crane,), left),
        RealSet("TALOS right arm, crane", figaroh + "talos/" + right_crane, talos, other_hand,
                talos, other_hand, (d / right_crane,), right),
        RealSet("TIAGo, another session, as it is", figaroh + "tiago/cross_valid.csv", tiago,
                "wrist_ft_tool_link", tiago, "wrist_ft_tool_link", (d / "cross_valid.csv",),
                Reading(rename=tiago_joints)),
        RealSet("TIAGo, another session, PAL's offsets off rows 9-16",
                figaroh + "tiago/cross_valid.csv", tiago, "wrist_ft_tool_link", tiago,
                "wrist_ft_tool_link", (d / "cross_valid.csv",), Reading(rename=tiago_joints),
                shifted=PAL_OFFSETS),
        RealSet("TIAGo Pro, right arm", pro + samples, tiago_pro, "gripper_right_tool_holder",
                tiago_pro, "gripper_right_tool_holder", (d / samples,)),
        RealSet("MATE, 3 joints, poses in degrees", mate + "transformed_poses.csv",
                str(d / "mate.urdf"), "end_effector", str(d / "mate.urdf"), "end_effector",
                (d / "transformed_poses.csv",), Reading(degrees=True)),
    ]  # fmt: skip


def read_set(real: RealSet) -> tuple[PoeModel, tuple[Measurements, ...]]:
    """The nominal and each file of a set as read (no offsets taken off, no split)."""
    nominal = urdf2dh.load(real.robot, tip=real.tip)
    joints = tuple(j.name for j in nominal.joints)
    sliding = tuple(j.name for j in nominal.joints if j.kind == "prismatic")
    files = tuple(
        read_measurements(
            path, joints, reading=real.reading, sliding=sliding, length_unit=nominal.length_unit
        )
        for path in real.files
    )
    return nominal, files


def load_set(real: RealSet) -> tuple[PoeModel, Measurements, Measurements]:
    """The nominal, the fit and the test measurements of a set."""
    nominal, files = read_set(real)
    if len(files) == 2:
        return nominal, files[0], files[1]
    m = files[0] if real.shifted is None else real.shifted.take_off(files[0])
    fit_rows, held_rows = holdout_split(m, 0.3, 0)
    return nominal, m.subset(fit_rows), m.subset(held_rows)


def held_out_rms(points: np.ndarray, measured: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum((points - measured) ** 2, axis=1))))


def best_time(run: Any, repeats: int) -> tuple[float, Any]:
    best, out = math.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        out = run()
        best = min(best, time.perf_counter() - start)
    return best, out


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
    predicted = model.fk_batch(test.q)[:, :3, 3] @ np.linalg.inv(g)[:3, :3].T
    return elapsed, held_out_rms(predicted + np.linalg.inv(g)[:3, 3], test.points)


@dataclass(frozen=True)
class Row:
    """One set's figures: held-out RMS position per tool (m, ``nan``: could not run) and the
    times (s)."""

    real: RealSet
    configurations: tuple[int, int]
    measure: str
    chosen: str
    held: dict[str, float]
    times: dict[str, float]


def one_set(real: RealSet, repeats: int, work: Path) -> Row:
    """Every tool on one real set, fitted to its fit measurements and judged on its test ones.
    Keys: ``default``, the four levels, ``FIGAROH full_params``, ``FIGAROH joint_offset``,
    ``robotkinecal`` (pose sets)."""
    nominal, fit, test = load_set(real)
    held: dict[str, float] = {}
    times: dict[str, float] = {}
    times["default"], cal = best_time(partial(calibrate, nominal, fit, convention="poe"), repeats)
    held["default"] = _held_out(cal.device_model, cal, test)
    for level in LEVEL_NAMES:
        # accepted where the measurements contradict it (base-tool alone on MATE): a figure to
        # compare, not a model written
        run = partial(calibrate, nominal, fit, level=level, convention="poe", accept=True)
        times[level], other = best_time(run, repeats)
        held[level] = _held_out(other.device_model, other, test)
    tools: list[tuple[str, Any]] = [
        (f"FIGAROH {level}", partial(figaroh_real, real.urdf, real.tool, fit, test, level, work,
                                     repeats))
        for level in FIGAROH_LEVELS
    ]  # fmt: skip
    if fit.quaternions is not None:
        tools.append(
            ("robotkinecal", partial(robotkinecal_real, nominal, fit, test, work, repeats))
        )
    for label, run in tools:
        try:
            times[label], held[label] = run()
        except Exception as e:  # report why a tool could not run, and go on
            print(f"{label} on {real.name}: could not run: {type(e).__name__}: {e}")
            times[label], held[label] = math.nan, math.nan
    counts = (fit.configurations()[1], test.configurations()[1])
    measure = "poses" if fit.quaternions is not None else "positions"
    return Row(real, counts, measure, cal.level, held, times)


def real_sets(sets: list[RealSet], repeats: int) -> int:
    """The side-by-side tables of ``sets`` (module docstring)."""
    rows = []
    with tempfile.TemporaryDirectory(prefix="urdf2dh-bench-") as tmp:
        for real in sets:
            rows.append(one_set(real, repeats, Path(tmp)))
    tools = ("FIGAROH full_params", "FIGAROH joint_offset", "robotkinecal")
    print("### Held-out RMS position (mm): 30% of the configurations held out, seed 0\n")
    print(
        "| set | configurations (fit + held out) | urdf2dh default (its choice) | "
        + " | ".join(LEVEL_NAMES)
        + " | "
        + " | ".join(tools)
        + " | best anchor (README) |"
    )
    print("|---|---|---|" + "---|" * (len(LEVEL_NAMES) + len(tools) + 1))
    for row in rows:
        cells = [f"{row.held['default'] * 1e3:.2f} ({row.chosen})"]
        cells += [_mm(row.held[level]) for level in LEVEL_NAMES]
        cells += [_mm(row.held.get(tool, math.nan)) for tool in tools]
        cells.append(_mm(row.real.anchor if row.real.anchor is not None else math.nan))
        fit_n, held_n = row.configurations
        print(f"| {row.real.name} | {fit_n} + {held_n} {row.measure} | " + " | ".join(cells) + " |")
    print(
        f"\n### Identification time (best of {repeats}, wall clock): ratios to urdf2dh's default\n"
    )
    print(
        "| set | urdf2dh default | "
        + " | ".join(tools)
        + " | fastest FIGAROH / urdf2dh | urdf2dh's choice asked for | fastest FIGAROH / it |"
    )
    print("|---|---|" + "---|" * (len(tools) + 3))
    for row in rows:
        base = row.times["default"]
        ratios = [_ratio(row.times.get(tool, math.nan), base) for tool in tools]
        fastest = min(row.times.get(tool, math.inf) for tool in tools[:2])
        alone = row.times[row.chosen]  # the chosen level asked for: no choice made
        print(
            f"| {row.real.name} | {base:.3f} s | "
            + " | ".join(ratios)
            + f" | {fastest / base:.2f} | {alone:.3f} s ({row.chosen}) | {fastest / alone:.2f} |"
        )
    print("\n### Level for level: each of FIGAROH's levels over urdf2dh's nearest, asked for\n")
    pairs = (("FIGAROH joint_offset", "offsets"), ("FIGAROH full_params", "full"))
    print("| set | " + " | ".join(f"{tool} / urdf2dh {level}" for tool, level in pairs) + " |")
    print("|---|" + "---|" * len(pairs))
    for row in rows:
        cells = [_ratio(row.times.get(tool, math.nan), row.times[level]) for tool, level in pairs]
        print(f"| {row.real.name} | " + " | ".join(cells) + " |")
    return 0


def _mm(value: float) -> str:
    return "-" if not math.isfinite(value) else f"{value * 1e3:.2f}"


def _ratio(value: float, base: float) -> str:
    return "-" if not math.isfinite(value) else f"{value / base:.2f}x"


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
