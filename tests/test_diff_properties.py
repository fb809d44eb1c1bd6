"""diff under small changes of a chain's axes, in every convention: it never fails, and it
reports the change (a parameter or a row's link beyond the thresholds). The chains are real URDF
text with parallel, anti-parallel, intersecting, coincident, skew and prismatic relations
(:mod:`chains`); the tilt makes nearly parallel pairs, where rows change form."""

from __future__ import annotations

import json
import tempfile
from pathlib import Path

import numpy as np
import yaml
from chains import random_chain_urdf
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import urdf2dh
from urdf2dh import CONVENTIONS, PoeModel
from urdf2dh.cli import main
from urdf2dh.geometry.se3 import rot_axis
from urdf2dh.io.poefile import poe_to_dict

SETTINGS = settings(
    derandomize=True, max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)


def _tilted(model: PoeModel, which: int, angle: float, axis: np.ndarray) -> PoeModel:
    j = model.joints[which]
    turn = rot_axis(axis / np.linalg.norm(axis), angle)
    moved = type(j)(j.name, j.kind, turn @ j.axis, j.point, j.pitch, j.scale, j.lower, j.upper)
    joints = (*model.joints[:which], moved, *model.joints[which + 1 :])
    return PoeModel(joints, model.home, "tilted", length_unit=model.length_unit)


def _file(path: Path, model: PoeModel) -> str:
    unit = "m" if model.length_unit == "km" else model.length_unit  # POE files know no km
    tree = poe_to_dict(PoeModel(model.joints, model.home, model.name, length_unit=unit))
    path.write_text(yaml.safe_dump(tree, sort_keys=False))
    return str(path)


@SETTINGS
@given(
    st.integers(0, 2**31),
    st.integers(1, 7),
    st.sampled_from([1e-3, 1.0, 1e3]),
    st.integers(0, 6),
    st.floats(1e-3, 2e-2),
    st.tuples(*(st.floats(-1.0, 1.0) for _ in range(3))),
)
def test_diff_reports_a_small_tilt_of_an_axis_in_every_convention(
    seed, n, scale, which, angle, axis
):
    text, _ = random_chain_urdf(seed, n, scale=scale)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "chain.urdf"
        path.write_text(text)
        model = urdf2dh.load(str(path))
    assume(model.n > 0)
    joint = model.joints[which % model.n]
    normal = np.cross(joint.axis, np.array(axis))  # tilt about a line normal to the axis
    if np.linalg.norm(normal) < 1e-3:
        normal = np.cross(joint.axis, [1.0, 0.0, 0.0] if abs(joint.axis[0]) < 0.9 else [0, 1.0, 0])
    actual = _tilted(model, which % model.n, angle, normal)
    with tempfile.TemporaryDirectory() as tmp:
        a, b = _file(Path(tmp) / "a.yaml", model), _file(Path(tmp) / "b.yaml", actual)
        for convention in CONVENTIONS:
            out = Path(tmp) / f"{convention}.json"
            code = main(
                [
                    "diff",
                    str(a),
                    str(b),
                    "--convention",
                    convention,
                    "--format",
                    "json",
                    "-o",
                    str(out),
                ]
            )
            assert code == 0, convention
            tree = json.loads(out.read_text())
            marked = [p for p in tree["parameters"] if p["marked"]]
            forms = [f for f in tree["changed_form"] if f["marked"]]
            assert marked or forms, (convention, angle)
