"""The measurement file of the tutorial "Calibrate your own robot" (docs/calibrate-your-robot.md),
written as a lab writes one.

    PYTHONPATH=. python scripts/lab_example.py            # (re)writes examples/lab/
    PYTHONPATH=. python scripts/lab_example.py --check    # exit 1 if examples/lab/ differs

A UR5 as built (every joint axis tilted by about 2 mrad and moved by about 1 mm, the flange on
its last axis: :func:`urdf2dh.calibration.measure.perturb`, seed 3) is measured by a laser
tracker with a six-degree-of-freedom probe on the flange, standing 2.6 m from the robot and
turned, at the 40 configurations ``urdf2dh plan ur5 --configs 40 --noise-pos 3e-5 --noise-rot
5e-5`` chooses, with 0.03 mm and 0.05 mrad of noise. The file is as the lab's software writes
it: a time column, the joints under the controller's names (``base``, ``shoulder``, ...) in
degrees to 4 decimals, the probe's position ``X, Y, Z`` in millimetres to 4 decimals, its
orientation as a scalar-first quaternion ``QW, QX, QY, QZ`` to 9 decimals. The robot as built
goes beside it (``ur5-as-built.yaml``, a POE model file in its base frame), to judge the
calibration against.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import urdf2dh  # noqa: E402
from urdf2dh.calibration.measure import perturb, synthesize  # noqa: E402
from urdf2dh.calibration.plan import plan  # noqa: E402
from urdf2dh.geometry.lie import quaternion_of, rotation_of  # noqa: E402
from urdf2dh.geometry.se3 import twist_exp  # noqa: E402
from urdf2dh.io.poefile import poe_to_dict  # noqa: E402

OUT = ROOT / "examples" / "lab"
CONFIGS = 40
NOISE = (3e-5, 5e-5)  # m, rad
NAMES = ("base", "shoulder", "elbow", "wrist1", "wrist2", "wrist3")
TRACKER = np.array([0.05, -0.02, 2.3, 1.9, -1.6, 0.4])  # the robot's base in the tracker frame


def files() -> dict[str, str]:
    """The files of examples/lab/, by name."""
    ur5 = urdf2dh.load("ur5")
    built = perturb(ur5, seed=3, angle=0.002, length=0.001, tool_on_axis=True)
    q = plan(ur5, CONFIGS, noise_pos=NOISE[0], noise_rot=NOISE[1]).configurations
    m = synthesize(built, len(q), NOISE[0], NOISE[1], seed=5, configurations=q)
    assert m.quaternions is not None
    g = twist_exp(TRACKER)
    points = (m.points @ g[:3, :3].T + g[:3, 3]) * 1000.0
    quats = quaternion_of(g[:3, :3] @ rotation_of(m.quaternions))  # x, y, z, w
    lines = ["time," + ",".join(NAMES) + ",X,Y,Z,QW,QX,QY,QZ"]
    for k in range(len(m)):
        cells = [f"{12.5 * k:.1f}"]
        cells += [f"{v:.4f}" for v in np.degrees(m.q[k])]
        cells += [f"{v:.4f}" for v in points[k]]
        cells += [f"{v:.9f}" for v in quats[k, [3, 0, 1, 2]]]
        lines.append(",".join(cells))
    tree = poe_to_dict(built)
    return {
        "ur5_tracker.csv": "\n".join(lines) + "\n",
        "ur5-as-built.yaml": yaml.safe_dump(tree, sort_keys=False),
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare, do not write")
    args = parser.parse_args()
    differ = []
    for name, text in files().items():
        path = OUT / name
        if args.check:
            if not path.exists() or path.read_text() != text:
                differ.append(name)
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
    if differ:
        print(f"examples/lab/ differs from what the script writes: {', '.join(differ)}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
