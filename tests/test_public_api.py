"""Every job of the command, called from ``import urdf2dh`` on a bundled robot: each returns a
typed frozen value with real content, and shows itself as a Markdown table in a notebook."""

from __future__ import annotations

import dataclasses
import inspect
import json
import math
from dataclasses import replace

import numpy as np
import pytest
from markdown_it import MarkdownIt

import urdf2dh

MODEL = urdf2dh.load("ur5")
JOBS = ("load", "to_table", "render", "plot", "export", "verify", "diff", "info", "measure",
        "calibrate", "plan")  # fmt: skip
RESULTS = ("PoeModel", "Table", "VerifyReport", "Diff", "Info", "Measurements", "Calibration",
           "Plan")  # fmt: skip


def markdown_cells(markdown: str) -> list[list[str]]:
    """The cells of the first table of ``markdown``, as CommonMark + tables renders them."""
    tokens = MarkdownIt("commonmark").enable("table").parse(markdown)
    rows: list[list[str]] = []
    for t in tokens:
        if t.type == "tr_open":
            rows.append([])
        elif t.type == "inline" and rows and t.map is not None:
            rows[-1].append(t.content)
        elif t.type == "table_close":
            break
    assert rows, markdown
    return rows


def test_every_job_is_a_documented_function_of_the_package():
    for name in JOBS:
        f = getattr(urdf2dh, name)
        assert inspect.isfunction(f) and name in urdf2dh.__all__
        doc = inspect.getdoc(f) or ""
        assert "Parameters\n----------" in doc, name
        assert "Returns\n-------" in doc or "Raises\n------" in doc, name
        returned = str(inspect.signature(f).return_annotation)
        assert returned in ("str", "bytes", *RESULTS) and "dict" not in returned, (name, returned)


def test_every_result_is_a_frozen_dataclass_shown_as_a_table():
    for name in RESULTS:
        kind = getattr(urdf2dh, name)
        assert dataclasses.is_dataclass(kind) and kind.__dataclass_params__.frozen, name
        assert callable(getattr(kind, "_repr_markdown_", None)), name
        for f in dataclasses.fields(kind):
            assert "dict[str, Any]" not in str(f.type), (name, f.name)


def test_load_and_to_table_and_render():
    assert [j.kind for j in MODEL.joints] == ["revolute"] * 6
    table = urdf2dh.to_table(MODEL, "mdh")
    assert table.convention == "mdh" and len(table.rows) == 6
    q = MODEL.sample(5, 3)
    assert np.allclose(table.fk_batch(q), MODEL.fk_batch(q), atol=1e-14 * MODEL.size())
    tree = json.loads(urdf2dh.render(table, "json"))
    assert tree["convention"] == "mdh" and len(tree["joints"]) == 6
    cells = markdown_cells(table._repr_markdown_())
    assert cells[2][:3] == ["1", "shoulder_pan_joint", "revolute"] and cells[2][5] == "180.0000"
    assert markdown_cells(MODEL._repr_markdown_())[1][1] == "shoulder_pan_joint"


def test_plot_and_export():
    table = urdf2dh.to_table(MODEL, "dh", style="ur")
    assert urdf2dh.plot(table, "svg").startswith(b"<?xml")
    script = urdf2dh.export(MODEL, "rtb")
    assert "DHRobot" in script and "shoulder_pan_joint" in script


def test_verify_report():
    report = urdf2dh.verify("ur5", samples=50)
    assert isinstance(report, urdf2dh.VerifyReport) and report.ok
    labels = [c.label for c in report.checks]
    assert len(labels) >= 5 and all(c.position < 1e-12 for c in report.checks), labels
    cells = markdown_cells(report._repr_markdown_())
    assert cells[0][0] == "model" and [row[-1] for row in cells[1:]] == ["ok"] * len(labels)


def test_diff_of_a_model_and_its_moved_copy():
    moved = list(MODEL.joints)
    j = moved[2]
    moved[2] = replace(j, point=j.point + np.array([0.0, 0.0, 0.002]))
    actual = replace(MODEL, joints=tuple(moved), name="ur5-moved")
    d = urdf2dh.diff(MODEL, actual)
    assert isinstance(d, urdf2dh.Diff) and d.marked >= 1
    assert {c.row for c in d.changes if c.marked} <= {j.name, moved[1].name, moved[3].name}
    cells = markdown_cells(d._repr_markdown_())
    assert cells[0][:2] == ["row", "param"] and any("*" in row[-1] for row in cells[1:])
    assert json.loads(d.render("json"))["actual"] == "ur5-moved"


def test_info():
    i = urdf2dh.info("panda")
    assert isinstance(i, urdf2dh.Info) and i.chain is not None
    assert i.identifiable is not None and i.identifiable.maximum == 5 * 0 + 4 * 7 + 7 + 6
    assert "panda_joint1" in i._repr_markdown_() and "|---" in i._repr_markdown_()


def test_measure_and_calibrate_and_plan():
    joints = list(MODEL.joints)
    j = joints[2]  # the elbow (axis y) moved 2 mm along x
    joints[2] = replace(j, point=j.point + np.array([0.002, 0.0, 0.0]))
    built = replace(MODEL, joints=tuple(joints))
    m = urdf2dh.measure(built, 40, noise_pos=1e-6, noise_rot=1e-6, seed=4)
    assert isinstance(m, urdf2dh.Measurements) and len(m) == 40 and m.quaternions is not None
    assert markdown_cells(m._repr_markdown_())[0][0] == "shoulder_pan_joint"
    markers = urdf2dh.measure(built, 10, markers=3, seed=4)
    assert len(markers) == 30 and markers.layout is not None and sorted(markers.layout) == [0, 1, 2]

    cal = urdf2dh.calibrate(MODEL, m, level="geometry", convention="poe")
    assert isinstance(cal, urdf2dh.Calibration) and cal.converged
    fit = cal.comparison("fit")
    assert fit is not None and fit.after.rms_position < 1e-5 < fit.before.rms_position
    cells = markdown_cells(cal._repr_markdown_())
    assert cells[0][0] == "set" and cells[1][0] == "fit"
    assert "parameter" in cal._repr_markdown_()

    p = urdf2dh.plan(MODEL, 12, level="geometry", seed=1)
    assert isinstance(p, urdf2dh.Plan) and p.configurations.shape == (12, 6)
    finite = np.isfinite(p.std)
    assert finite.any() and math.exp(np.mean(np.log(p.std[finite] / p.random_std[finite]))) < 1
    cells = markdown_cells(p._repr_markdown_())
    assert cells[0] == ["parameter", "expected std", "random configurations"]
    assert len(cells) == 1 + len(p.parameters)


@pytest.mark.parametrize(
    "call, error, words",
    [
        (lambda: urdf2dh.verify(5), TypeError, "verify: source"),
        (lambda: urdf2dh.verify("ur5", samples="x"), TypeError, "verify: samples"),
        (lambda: urdf2dh.diff("ur5", 3), TypeError, "diff: actual"),
        (lambda: urdf2dh.info(None), TypeError, "info: source"),
        (lambda: urdf2dh.measure("ur5", 3), TypeError, "measure: model must be a PoeModel"),
        (lambda: urdf2dh.measure(MODEL, "3"), TypeError, "measure: configs"),
        (lambda: urdf2dh.measure(MODEL, 3, noise_pos=-1.0), ValueError, "measure: noise_pos"),
        (lambda: urdf2dh.measure(MODEL, 3, markers=0), ValueError, "measure: markers"),
        (lambda: urdf2dh.plan("ur5", 3), TypeError, "plan: model must be a PoeModel"),
        (lambda: urdf2dh.plan(MODEL, 3, level="most"), ValueError, "unknown level 'most'"),
        (lambda: urdf2dh.calibrate(MODEL, None), TypeError, "calibrate: measurements"),
        (lambda: urdf2dh.calibrate(MODEL, urdf2dh.measure(MODEL, 5), seed=-1), ValueError,
         "calibrate: seed"),
        (lambda: urdf2dh.Measurements(("j",), np.zeros((2, 2)), np.zeros((2, 3))), ValueError,
         "q must be (N, joints)"),
    ],
)  # fmt: skip
def test_the_jobs_refuse_wrong_arguments(call, error, words):
    with pytest.raises(error) as e:
        call()
    assert words in str(e.value) and "\n" not in str(e.value)


def test_library_messages_say_what_is_wrong_and_the_command_adds_the_option(capsys):
    from urdf2dh.cli import main

    with pytest.raises(urdf2dh.Urdf2DhError) as e:
        urdf2dh.export(MODEL, "linuxcnc", "dh")
    assert "--" not in str(e.value) and e.value.remedy is not None
    assert e.value.remedy.argument == "convention" and e.value.remedy.value == "mdh"
    assert main(["export", "ur5", "--to", "linuxcnc", "--convention", "dh"]) == 2
    err = capsys.readouterr().err
    assert err == f"urdf2dh: error: {e.value}; export with --convention mdh\n"
