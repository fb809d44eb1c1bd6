"""Calibrate a UR5: nominal URDF -> measurements -> calibrate -> UR's default_kinematics.yaml
and a calibrated URDF, with urdf2dh's commands.

    python examples/calibrate_ur5.py [OUT_DIR]

The "real" robot is simulated: the nominal UR5 as built with small errors (every joint axis
tilted by ~2 mrad and shifted by ~1 mm, the flange on its last axis), seen by a measuring device
(a laser tracker, say) standing 2 m away and turned; the device measures the flange pose at 200
configurations with 10 um and 10 urad of noise. Then, as one would type them:

    urdf2dh measure as-built.yaml --configs 200 --noise-pos 1e-5 --noise-rot 1e-5 -o poses.csv
    urdf2dh calibrate ur5 poses.csv --keep-scale --keep-tool-axis --frame nominal \\
        --holdout 0.2 --format json -o calibrated.json --report report.json
    urdf2dh export calibrated.json --to ur -o default_kinematics.yaml
    urdf2dh convert calibrated.json --format urdf -o calibrated.urdf

``--keep-scale`` and ``--keep-tool-axis`` identify what UR's model has (no joint scales; the
flange on D-H frame 6), ``--frame nominal`` expresses the result in the robot's base frame
(joint 1's axis where the nominal has it). The script checks that UR's description, built from
the yaml as ``ur_macro.xacro`` builds it, and the calibrated URDF move exactly as the identified
model, and how close that model comes to the robot as built, next to the nominal. Files go to
OUT_DIR if given, else to a temporary directory that is removed at the end.
"""

from __future__ import annotations

import json
import math
import sys
import tempfile
from pathlib import Path

import numpy as np
import yaml

import urdf2dh
from urdf2dh.calibration.identify import moved
from urdf2dh.calibration.measure import perturb
from urdf2dh.cli import main as urdf2dh_main
from urdf2dh.geometry.se3 import from_rpy, rot_z, twist_exp
from urdf2dh.io.poefile import poe_to_dict
from urdf2dh.model.poe import PoeModel


def command(*argv: str) -> None:
    print("$ urdf2dh " + " ".join(argv))
    code = urdf2dh_main(list(argv))
    if code != 0:
        raise SystemExit(f"urdf2dh {argv[0]} failed with exit code {code}")


def ur_description_fk(kinematics: dict, q: np.ndarray) -> np.ndarray:
    """tool0 in base_link as ur_macro.xacro builds it: base_link -> Rz(pi) -> each joint's origin
    (x y z, fixed-axis roll pitch yaw) and its rotation about z; tool0 is wrist_3_link."""
    out = rot_z(math.pi)
    for key, angle in zip(
        ("shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3"), q, strict=True
    ):
        k = kinematics[key]
        out = out @ from_rpy((k["x"], k["y"], k["z"]), (k["roll"], k["pitch"], k["yaw"]))
        out = out @ rot_z(angle)
    return out


def errors(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    """RMS position and rotation error between two (N, 4, 4) stacks."""
    pos = np.linalg.norm(a[:, :3, 3] - b[:, :3, 3], axis=1)
    cos = (np.einsum("nij,nij->n", a[:, :3, :3], b[:, :3, :3]) - 1.0) / 2.0
    rot = np.arccos(np.clip(cos, -1.0, 1.0))
    return float(np.sqrt(np.mean(pos**2))), float(np.sqrt(np.mean(rot**2)))


def walk(work: Path) -> bool:
    nominal = urdf2dh.load("ur5")
    built = perturb(nominal, seed=3, angle=0.002, length=0.001, tool_on_axis=True)
    device = twist_exp(np.array([0.1, -0.2, 0.7, 1.5, -0.8, 0.3]))  # base in the device frame
    seen = PoeModel(moved(built.joints, device), device @ built.home, "ur5-as-built")
    (work / "as-built.yaml").write_text(yaml.safe_dump(poe_to_dict(seen), sort_keys=False))

    poses, report = work / "poses.csv", work / "report.json"
    calibrated, kin, urdf = (
        work / n for n in ("calibrated.json", "default_kinematics.yaml", "calibrated.urdf")
    )
    command(
        "measure",
        str(work / "as-built.yaml"),
        "--configs",
        "200",
        "--noise-pos",
        "1e-5",
        "--noise-rot",
        "1e-5",
        "-o",
        str(poses),
    )
    command(
        "calibrate",
        "ur5",
        str(poses),
        "--keep-scale",
        "--keep-tool-axis",
        "--frame",
        "nominal",
        "--holdout",
        "0.2",
        "--format",
        "json",
        "-o",
        str(calibrated),
        "--report",
        str(report),
    )
    command("export", str(calibrated), "--to", "ur", "-o", str(kin))
    command("convert", str(calibrated), "--format", "urdf", "-o", str(urdf))
    print(f"wrote {', '.join(p.name for p in (poses, calibrated, report, kin, urdf))} in {work}")

    model = urdf2dh.load(str(calibrated))
    q = nominal.sample(1000, 21)
    ours = model.fk_batch(q)
    kinematics = yaml.safe_load(kin.read_text())["kinematics"]
    ur = np.array([ur_description_fk(kinematics, qk) for qk in q])
    from_urdf = urdf2dh.load(str(urdf), "base_link", "tool0").fk_batch(q)
    ur_error, urdf_error = float(np.abs(ur - ours).max()), float(np.abs(from_urdf - ours).max())
    print(f"UR description from the yaml vs the calibrated model: max |dT| = {ur_error:.2g}")
    print(f"calibrated URDF vs the calibrated model:              max |dT| = {urdf_error:.2g}")

    tree = json.loads(report.read_text())
    base = np.array(tree["nominal_base_in_device"])  # where the device saw the robot's base
    truth = seen.fk_batch(q)
    after = errors(base @ ours, truth)
    before = errors(base @ nominal.fk_batch(q), truth)
    print(
        f"against the robot as built, 1000 new configurations (RMS): nominal "
        f"{before[0] * 1e3:.3f} mm, {before[1] * 1e3:.3f} mrad; calibrated "
        f"{after[0] * 1e3:.4f} mm, {after[1] * 1e3:.4f} mrad (noise 0.01 mm, 0.01 mrad)"
    )
    held = tree["residuals"]["after"]["held_out"]
    print(
        f"held-out poses: RMS {held['rms_position'] * 1e3:.4f} mm, "
        f"{held['rms_rotation'] * 1e3:.4f} mrad; noise floor "
        f"{tree['noise']['floor']['position'] * 1e3:.4f} mm, "
        f"{tree['noise']['floor']['rotation'] * 1e3:.4f} mrad"
    )
    ok = (
        ur_error < 1e-9
        and urdf_error < 1e-9
        and after[0] < 0.01 * before[0]
        and after[1] < 0.01 * before[1]
    )
    print("calibration walk complete" if ok else "calibration walk FAILED")
    return ok


def main() -> int:
    if len(sys.argv) > 1:
        out = Path(sys.argv[1])
        out.mkdir(parents=True, exist_ok=True)
        return 0 if walk(out) else 1
    with tempfile.TemporaryDirectory(prefix="urdf2dh-calibrate-") as work:
        return 0 if walk(Path(work)) else 1


if __name__ == "__main__":
    sys.exit(main())
