"""The arms the analytic IK exports are proven on: every bundled 6-axis arm, the real URDFs of
tests/data/vendor, and the real D-H tables ikdh ships (``ikdh/robots/*.yaml``: 1,178 industrial
arms from RoboDK's library), each made a URDF here.

A D-H table becomes a URDF joint by joint, from ikdh's own reading of its file
(``ikdh.load_robot``): revolute joint ``i`` turns about the z axis of frame ``i - 1``, and a fixed
joint then carries ``Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``, whose URDF origin is exactly
``xyz = (a cos theta, a sin theta, d)``, ``rpy = (alpha, 0, theta)`` (URDF's ``R = Rz(yaw)
Ry(pitch) Rx(roll)``). So the URDF moves as ikdh's table does, and Pinocchio is the oracle.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from urdf2dh import load
from urdf2dh.io.catalog import ROBOTS

DATA = Path(__file__).parent / "data"
VENDOR = sorted(
    str(p)
    for p in (DATA / "vendor").rglob("*.urdf")
    if load(str(p)).n == 6  # every one is a 6R arm; the filter keeps it so
)


def six_axis_robots() -> list[str]:
    """The bundled robots whose chain has six joints (any kind: the exports refuse or take)."""
    return [name for name in ROBOTS if load(name).n == 6]


def ikdh_robots() -> list[Path]:
    """ikdh's bundled robot files, sorted."""
    import ikdh

    return sorted(Path(ikdh.robots_dir()).glob("*.yaml"))


def sample(paths: list[Path], count: int, seed: int) -> list[Path]:
    """``count`` of ``paths``, drawn without replacement (seeded)."""
    rng = np.random.default_rng(seed)
    picked = rng.choice(len(paths), size=min(count, len(paths)), replace=False)
    return [paths[int(i)] for i in sorted(picked)]


def _f(x: float) -> str:
    return repr(float(x))


def dh_urdf(path: Path) -> str:
    """The URDF of ikdh's robot file ``path`` (module doc): ``base`` -> ``tool``, limits from the
    file (degrees there)."""
    import ikdh

    robot = ikdh.load_robot(str(path))
    dh, lim = robot.dh, robot.limits
    name = path.stem
    parts = [f'<robot name="{name}">', '<link name="base"/>']
    parent = "base"
    for i in range(6):
        lo, hi = math.radians(lim.lo[i]), math.radians(lim.hi[i])
        parts.append(f'<link name="link{i + 1}"/><link name="frame{i + 1}"/>')
        parts.append(
            f'<joint name="j{i + 1}" type="revolute"><parent link="{parent}"/>'
            f'<child link="link{i + 1}"/><axis xyz="0 0 1"/>'
            f'<limit lower="{_f(lo)}" upper="{_f(hi)}" effort="1" velocity="1"/></joint>'
        )
        a, d, alpha, theta = dh.a[i], dh.d[i], dh.alpha[i], dh.theta[i]
        xyz = f"{_f(a * math.cos(theta))} {_f(a * math.sin(theta))} {_f(d)}"
        parts.append(
            f'<joint name="dh{i + 1}" type="fixed"><parent link="link{i + 1}"/>'
            f'<child link="frame{i + 1}"/><origin xyz="{xyz}" '
            f'rpy="{_f(alpha)} 0 {_f(theta)}"/></joint>'
        )
        parent = f"frame{i + 1}"
    parts.append('<link name="tool"/>')
    parts.append(
        f'<joint name="flange" type="fixed"><parent link="{parent}"/><child link="tool"/></joint>'
    )
    return "\n".join([*parts, "</robot>"])
