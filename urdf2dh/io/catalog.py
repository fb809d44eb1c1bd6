"""Bundled robots: the serial arms that example-robot-data ships, plus the models in ``robots/``
(three of them MuJoCo Menagerie's MJCF arms, their licences in ``robots/LICENSES/``), and the
vendors' published tables in ``robots/references/`` (each file names its source).

example-robot-data 6 installs data only (no Python module): its URDFs live under
``<site-packages>/cmeel.prefix/share/example-robot-data/robots/``. Each entry names its file and a
sensible base and tip link (the arm's own base, and its flange or end-effector frame).
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError

__all__ = [
    "REFERENCES",
    "ROBOTS",
    "Bundled",
    "example_robot_data_dir",
    "lookup",
    "our_robots_dir",
    "robot_path",
]

ERD = "erd:"  # file under example-robot-data's robots/
OURS = "ours:"  # file under this project's robots/


@dataclass(frozen=True, slots=True)
class Bundled:
    """A bundled robot: short name, file, default base and tip links, one-line description."""

    name: str
    file: str
    base: str | None
    tip: str | None
    description: str


ROBOTS: dict[str, Bundled] = {
    b.name: b
    for b in [
        Bundled(
            "ur3",
            ERD + "ur_description/urdf/ur3_robot.urdf",
            "base_link",
            "tool0",
            "Universal Robots UR3, 6R",
        ),
        Bundled(
            "ur5",
            ERD + "ur_description/urdf/ur5_robot.urdf",
            "base_link",
            "tool0",
            "Universal Robots UR5, 6R",
        ),
        Bundled(
            "ur10",
            ERD + "ur_description/urdf/ur10_robot.urdf",
            "base_link",
            "tool0",
            "Universal Robots UR10, 6R",
        ),
        Bundled(
            "panda",
            ERD + "panda_description/urdf/panda.urdf",
            "panda_link0",
            "panda_link8",
            "Franka Emika Panda, 7R, to the flange",
        ),
        Bundled(
            "kinova",
            ERD + "kinova_description/robots/kinova.urdf",
            "j2s6s200_link_base",
            "j2s6s200_end_effector",
            "Kinova Jaco2 j2s6s200, 6R",
        ),
        Bundled(
            "xarm7",
            ERD + "xarm_description/urdf/xarm7.urdf",
            "link_base",
            "link_eef",
            "UFACTORY xArm7, 7R",
        ),
        Bundled(
            "z1",
            ERD + "z1_description/urdf/z1.urdf",
            "link00",
            "link06",
            "Unitree Z1, 6R, to the flange",
        ),
        Bundled(
            "so100",
            ERD + "so_arm_description/urdf/so100.urdf",
            "base",
            "gripper",
            "SO-ARM100, 5R, to the gripper body",
        ),
        Bundled(
            "so101",
            ERD + "so_arm_description/urdf/so101.urdf",
            "base_link",
            "gripper_frame_link",
            "SO-ARM101, 5R, to the gripper frame",
        ),
        Bundled(
            "talos-left-arm",
            ERD + "talos_data/robots/talos_left_arm.urdf",
            "arm_left_1_link",
            "wrist_left_ft_tool_link",
            "PAL TALOS left arm, 6R",
        ),
        Bundled(
            "baxter-left",
            ERD + "baxter_description/urdf/baxter.urdf",
            "left_arm_mount",
            "left_gripper",
            "Rethink Baxter left arm, 7R",
        ),
        Bundled(
            "baxter-right",
            ERD + "baxter_description/urdf/baxter.urdf",
            "right_arm_mount",
            "right_gripper",
            "Rethink Baxter right arm, 7R",
        ),
        Bundled(
            "tiago-arm",
            ERD + "tiago_description/robots/tiago_no_hand.urdf",
            "base_footprint",
            "arm_tool_link",
            "PAL TIAGo torso lift and arm, P + 7R",
        ),
        Bundled(
            "finger-edu",
            ERD + "finger_edu_description/robots/finger_edu.urdf",
            "base_link",
            "finger_tip_link",
            "Open Dynamic Robot Initiative finger, 3R",
        ),
        Bundled(
            "hextilt-arm",
            ERD + "hextilt_description/urdf/hextilt_flying_arm_5.urdf",
            "flying_arm_5__base_link",
            "flying_arm_5__gripper",
            "flying arm, 5R",
        ),
        Bundled(
            "borinot-arm",
            ERD + "borinot_description/urdf/borinot_flying_arm_2.urdf",
            "borinot__base_link",
            "flying_arm_2__ee",
            "flying arm, 2R",
        ),
        Bundled(
            "twodof",
            ERD + "asr_twodof_description/urdf/TwoDofs.urdf",
            "world",
            "Tip",
            "planar 2R arm",
        ),
        Bundled(
            "double-pendulum",
            ERD + "double_pendulum_description/urdf/double_pendulum.urdf",
            "base_link",
            "link2",
            "planar double pendulum, 2R",
        ),
        Bundled(
            "scara",
            OURS + "scara.urdf",
            "base_link",
            "flange",
            "SCARA (RRPR), parallel vertical axes, tool pointing down",
        ),
        Bundled(
            "stanford",
            OURS + "stanford.urdf",
            "base_link",
            "flange",
            "Stanford arm (RRPRRR), prismatic third joint",
        ),
        Bundled(
            "kuka-kr6-r700-sixx",
            OURS + "kuka-kr6-r700-sixx.urdf",
            "base_link",
            "tool0",
            "KUKA KR 6 R700 sixx from published dimensions, 6R OPW arm",
        ),
        Bundled(
            "fanuc-m20ia",
            OURS + "fanuc-m20ia.urdf",
            "base_link",
            "tool0",
            "FANUC M-20iA from published dimensions, 6R OPW arm, z-on-axis link frames",
        ),
        Bundled(
            "ur5e-mjcf",
            OURS + "ur5e.xml",
            "base",
            "wrist_3_link",
            "Universal Robots UR5e, 6R, MJCF (MuJoCo Menagerie, BSD-3-Clause)",
        ),
        Bundled(
            "fr3-mjcf",
            OURS + "fr3.xml",
            "base",
            "attachment_site",
            "Franka FR3, 7R, to the attachment site, MJCF (MuJoCo Menagerie, Apache-2.0)",
        ),
        Bundled(
            "xarm7-mjcf",
            OURS + "xarm7_nohand.xml",
            "link_base",
            "attachment_site",
            "UFACTORY xArm7, 7R, to the attachment site, MJCF (MuJoCo Menagerie, BSD-3-Clause)",
        ),
        Bundled(
            "puma560-nominal",
            OURS + "puma560-nominal.yaml",
            None,
            None,
            "PUMA 560 nominal POE model (Wu 2019 Table I, after Okamura & Park 1996)",
        ),
        Bundled(
            "puma560-actual",
            OURS + "puma560-actual.yaml",
            None,
            None,
            "PUMA 560 calibrated POE model (Wu 2019 Table I), helical joints",
        ),
    ]
}


#: Vendors' published tables (``robots/references/``, each file naming its source): TABLEs for
#: ``urdf2dh match`` and, as they state their convention and units, SOURCEs like the robots.
REFERENCES: dict[str, Bundled] = {
    b.name: b
    for b in [
        *(
            Bundled(
                f"{model}-dh",
                OURS + f"references/{model}-dh.yaml",
                None,
                None,
                f"{title}: Universal Robots' published D-H table (reference)",
            )
            for model, title in [
                ("ur3", "UR3"),
                ("ur5", "UR5"),
                ("ur10", "UR10"),
                ("ur3e", "UR3e"),
                ("ur5e", "UR5e"),
                ("ur10e", "UR10e"),
                ("ur16e", "UR16e"),
                ("ur20", "UR20"),
                ("ur30", "UR30"),
            ]
        ),
        Bundled(
            "panda-mdh",
            OURS + "references/panda-mdh.yaml",
            None,
            None,
            "Franka Emika Panda: Franka's published modified D-H table (reference)",
        ),
        Bundled(
            "kuka-kr6-r700-sixx-opw",
            OURS + "references/kuka-kr6-r700-sixx-opw.yaml",
            None,
            None,
            "KUKA KR 6 R700 sixx: OPW parameters as opw_kinematics publishes them (reference)",
        ),
        Bundled(
            "fanuc-m20ia-opw",
            OURS + "references/fanuc-m20ia-opw.yaml",
            None,
            None,
            "FANUC M-20iA: ROS-Industrial's OPW parameters (reference)",
        ),
        Bundled(
            "puma560-wu2019-dh",
            OURS + "references/puma560-wu2019-dh.yaml",
            None,
            None,
            "PUMA 560 nominal: Wu 2019 Table II's D-H table (reference)",
        ),
    ]
}


def lookup(name: str) -> Bundled | None:
    """The bundled robot or reference table called ``name``, if there is one."""
    return ROBOTS.get(name) or REFERENCES.get(name)


def example_robot_data_dir() -> Path:
    """The ``robots/`` directory that example-robot-data installs."""
    rel = Path("cmeel.prefix", "share", "example-robot-data", "robots")
    candidates = [Path(p) / rel for p in sys.path if p]
    candidates.append(Path(sys.prefix, "share", "example-robot-data", "robots"))
    env = os.environ.get("EXAMPLE_ROBOT_DATA_DIR")
    if env:
        candidates.insert(0, Path(env))
    for c in candidates:
        if c.is_dir():
            return c
    raise InputError(
        "example-robot-data is not installed (no cmeel.prefix/share/example-robot-data/robots on "
        "sys.path); install it with: pip install example-robot-data"
    )


def our_robots_dir() -> Path:
    """This project's ``robots/``: installed as ``urdf2dh/robots``, or beside the package in a
    source checkout (where ``python -m pytest`` imports the package from)."""
    here = Path(__file__).resolve().parents[1]  # the urdf2dh package
    for candidate in (here / "robots", here.parent / "robots"):
        if (candidate / "puma560-nominal.yaml").is_file():
            return candidate
    raise InputError(f"urdf2dh's robots/ directory is missing (looked beside {here})")


def robot_path(robot: Bundled) -> Path:
    """The file of a bundled robot."""
    if robot.file.startswith(ERD):
        return example_robot_data_dir() / robot.file[len(ERD) :]
    return our_robots_dir() / robot.file[len(OURS) :]
