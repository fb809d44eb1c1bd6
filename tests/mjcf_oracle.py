"""Checking a hand-written MJCF model against both oracles (test_mjcf_features.py and
test_mjcf_models.py): every table within 1e-14 x size (and rad) of MuJoCo, and of Pinocchio within
that plus the two oracles' own distance; or Pinocchio not judging, for the reason expected."""

from __future__ import annotations

import math
import sys
import tempfile
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin

from urdf2dh.check.verify import compare_with_oracles
from urdf2dh.geometry.se3 import pose_errors
from urdf2dh.io.sources import Source, open_source
from urdf2dh.model.poe import PoeModel

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))

from mjcf_oracles import PROMISE, oracles_apart


def write(directory: Path, text: str, name: str = "model.xml") -> Path:
    path = directory / name
    path.write_text(text, encoding="utf-8")
    return path


def agrees(
    source: Source,
    model: PoeModel,
    pinocchio: str | None = None,
    samples: int = 40,
) -> dict[str, float]:
    """Assert that ``model`` and its tables agree with MuJoCo and with Pinocchio (or that
    Pinocchio does not judge, its reason holding ``pinocchio``); the worst errors by oracle."""
    checks, abstentions = compare_with_oracles(source, model, samples, 3, oracle="both")
    judged = {c.oracle for c in checks}
    assert "mujoco" in judged, abstentions
    if pinocchio is None:
        assert judged == {"pinocchio", "mujoco"}, abstentions
    else:
        assert [a.oracle for a in abstentions] == ["pinocchio"], abstentions
        assert pinocchio in abstentions[0].reason, abstentions[0].reason
    size = model.size()
    apart = oracles_apart(source, model, samples, 3)
    worst: dict[str, float] = {}
    for c in checks:
        check = c.table.check if c.table is not None else None
        declared = (0.0, 0.0) if check is None else (check.declared_position,
                                                     check.declared_rotation)  # fmt: skip
        extra = apart if c.oracle == "pinocchio" else (0.0, 0.0)
        assert c.position <= (PROMISE + extra[0]) * size + declared[0], (c.oracle, c.label, c)
        assert c.rotation <= PROMISE + extra[1] + declared[1], (c.oracle, c.label, c)
        worst[c.oracle] = max(worst.get(c.oracle, 0.0), c.position / size, c.rotation)
    return worst


def mujoco_site(text: str, site: str, qpos: np.ndarray) -> np.ndarray:
    """MuJoCo's pose (4, 4) of ``site`` at ``qpos`` (the text has no files to read)."""
    model = mujoco.MjModel.from_xml_string(text)
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.mj_kinematics(model, data)
    out = np.eye(4)
    out[:3, :3] = data.site(site).xmat.reshape(3, 3)
    out[:3, 3] = data.site(site).xpos
    return out


def pinocchio_model(text: str) -> pin.Model:
    """Pinocchio's model of MJCF ``text`` (its parser reads a file)."""
    with tempfile.TemporaryDirectory() as directory:
        return pin.buildModelFromMJCF(str(write(Path(directory), text)))


def pinocchio_site(text: str, site: str, q: np.ndarray) -> np.ndarray:
    """Pinocchio's pose (4, 4) of ``site`` at ``q``, its MJCF parser reading ``text``."""
    model = pinocchio_model(text)
    data = model.createData()
    pin.forwardKinematics(model, data, q)
    frame = model.getFrameId(site)
    assert frame < model.nframes, f"Pinocchio has no frame {site}"
    return pin.updateFramePlacement(model, data, frame).homogeneous


def oracles_differ(text: str, site: str, nq: int) -> float:
    """How far Pinocchio's pose of ``site`` is from MuJoCo's, at a few configurations
    (infinite where Pinocchio's model does not even have MuJoCo's joints)."""
    if pinocchio_model(text).nq != nq:
        return math.inf
    rng = np.random.default_rng(5)
    worst = 0.0
    for q in rng.uniform(-1.0, 1.0, (4, nq)):
        pos, rot = pose_errors(
            mujoco_site(text, site, q)[None], pinocchio_site(text, site, q)[None]
        )
        worst = max(worst, pos, rot)
    return worst


def opened(directory: Path, text: str) -> Source:
    return open_source(str(write(directory, text)))
