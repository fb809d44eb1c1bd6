"""str() of every value a job returns is what a person reads (what the command prints); repr()
stays one short line, also for names that hold line breaks."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import urdf2dh
from urdf2dh.calibration.report import summary
from urdf2dh.cli import main


@pytest.fixture(scope="module")
def values():
    model = urdf2dh.load("ur5")
    actual = urdf2dh.load("puma560-actual")
    measurements = urdf2dh.measure(actual, 30, seed=1)
    return {
        "model": model,
        "table": urdf2dh.to_table(model, "mdh"),
        "verify": urdf2dh.verify("ur5", samples=20),
        "diff": urdf2dh.diff("puma560-nominal", "puma560-actual", "cpc"),
        "info": urdf2dh.info("ur5"),
        "measurements": measurements,
        "plan": urdf2dh.plan(model, 8),
        "calibration": urdf2dh.calibrate(  # the actual PUMA's joints are helical
            urdf2dh.load("puma560-nominal"), measurements, level="full", helical=("all",)
        ),
    }


def printed(argv, capsys) -> str:
    assert main(argv) in (0, 1)
    return capsys.readouterr().out


def test_str_is_what_the_command_prints(values, capsys):
    assert str(values["table"]) == printed(["convert", "ur5", "--convention", "mdh"], capsys)
    assert str(values["diff"]) == printed(
        ["diff", "puma560-nominal", "puma560-actual", "--convention", "cpc"], capsys
    )
    assert str(values["info"]) == printed(["info", "ur5"], capsys)
    out = printed(["verify", "ur5", "--samples", "20"], capsys)
    assert out.startswith(str(values["verify"]))  # then the verdict line
    assert str(values["table"]) == urdf2dh.render(values["table"], "text")
    assert str(values["plan"]) == values["plan"].summary()
    assert str(values["calibration"]) == summary(values["calibration"])


def test_str_of_a_model_and_of_measurements_reads_as_a_table(values):
    text = str(values["model"]).splitlines()
    assert text[0] == "ur5 base_link -> tool0: POE model, 6 joints"
    assert text[2].split()[:3] == ["joint", "type", "axis"] and set(text[3]) <= {"-", " "}
    assert len(text) >= 4 + 6 and text[-1].startswith("tip at home: origin (0.817250")
    lines = str(values["measurements"]).splitlines()
    assert lines[0] == "30 measured poses at 30 configurations from puma560-actual"
    assert lines[2].split() == ["j1", "j2", "j3", "j4", "j5", "j6", "x", "y", "z",
                                "qx", "qy", "qz", "qw"]  # fmt: skip
    first = np.array(lines[4].split(), dtype=float)
    m = values["measurements"]
    assert np.allclose(first, np.concatenate([m.q[0], m.points[0], m.quaternions[0]]), rtol=1e-5)


@pytest.mark.parametrize(
    "name", ["model", "table", "verify", "diff", "info", "measurements", "plan", "calibration"]
)
def test_repr_is_one_short_line(values, name):
    value = values[name]
    text = repr(value)
    assert "\n" not in text and len(text) <= 120, text
    assert text.startswith(f"<{type(value).__name__}") and text != str(value)


def test_repr_stays_one_line_for_names_with_line_breaks(values):
    model = dataclasses.replace(values["model"], name="two\nlines", tip_link="a\u2028b")
    table = dataclasses.replace(values["table"], robot="x\ny", base_link="\x1b[31m")
    for value in (model, table):
        text = repr(value)
        assert text.isprintable() and "\\n" in text, text


def test_tolerances_show_what_differs_from_the_defaults():
    assert repr(urdf2dh.DEFAULT) == "Tolerances()"
    assert repr(urdf2dh.EXACT) == (
        "Tolerances(parallel_angle=0.0, intersect_distance=0.0, sane_factor=0.0, solver_snap=0.0)"
    )
    tol = urdf2dh.Tolerances(parallel_angle=1e-6)
    assert eval(repr(tol), {"Tolerances": urdf2dh.Tolerances}) == tol
