"""The Python API with wrong arguments: every public function and method refuses them at the
boundary (urdf2dh.checks), with the documented error and a message naming the argument.

A wrong type is a ``TypeError``, a wrong value a ``ValueError`` (an unknown convention, style or
format a :class:`~urdf2dh.errors.UsageError`, which is a ``ValueError`` too), a SOURCE that names
nothing a :class:`~urdf2dh.errors.SourceError`; never an ``AttributeError``, an ``OSError`` or a
NaN returned. Joint values must be finite numbers.
"""

from __future__ import annotations

import math
from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import urdf2dh
from urdf2dh import Joint, PoeModel
from urdf2dh.conventions.dh import DhLink
from urdf2dh.conventions.table import Check, Row
from urdf2dh.errors import SourceError, UsageError

MODEL = urdf2dh.load("ur5")
TABLE = urdf2dh.to_table(MODEL, "dh")
URDF = Path(__file__).parent / "data" / "genser6.urdf"
EXAMPLES = settings(derandomize=True, max_examples=200, deadline=None)


def refuses(call, error, *words):
    """``call()`` raises ``error`` with a one-line message holding each of ``words``."""
    with pytest.raises(error) as e:
        call()
    message = str(e.value)
    assert "\n" not in message and len(message) < 600, message
    for w in words:
        assert w in message, (w, message)
    return message


# --------------------------------------------------------------------------- load


@pytest.mark.parametrize("source", [None, 5, b"ur5", ["ur5"], 1.5])
def test_load_takes_text_or_a_path(source):
    got = "None" if source is None else type(source).__name__
    refuses(lambda: urdf2dh.load(source), TypeError, "load: source", got)


def test_load_reads_a_path_object():
    assert [j.name for j in urdf2dh.load(URDF).joints] == [f"joint{i}" for i in range(1, 7)]


@pytest.mark.parametrize(
    "source, words",
    [
        ("", ["SOURCE is empty", "ur5"]),
        ("x" * 100_000, ["(100000 characters)", "neither a file nor a bundled robot"]),
        ("d/" * 60_000, ["(120000 characters)", "no such file"]),
        ("ur\x005", ["'ur\\x005'", "neither a file nor a bundled robot"]),
    ],
)
def test_load_refuses_a_source_naming_nothing(source, words):
    refuses(lambda: urdf2dh.load(source), SourceError, *words)


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"base": 1}, ["load: base", "string or None", "int 1"]),
        ({"tip": ["tool0"]}, ["load: tip", "list"]),
        ({"ignore_mimic": "yes"}, ["load: ignore_mimic", "True or False", "str 'yes'"]),
        ({"ignore_mimic": None}, ["load: ignore_mimic", "None"]),
    ],
)
def test_load_checks_its_options(kwargs, words):
    refuses(lambda: urdf2dh.load("ur5", **kwargs), TypeError, *words)


# --------------------------------------------------------------------------- to_table, render


@pytest.mark.parametrize(
    "args, kwargs, error, words",
    [
        (("ur5", "dh"), {}, TypeError, ["to_table: model", "str 'ur5'", "urdf2dh.load('ur5')"]),
        ((None,), {}, TypeError, ["to_table: model must be a PoeModel, not None"]),
        ((TABLE,), {}, TypeError, ["to_table: model", "Table"]),
        ((MODEL, 1), {}, TypeError, ["to_table: convention", "int 1"]),
        ((MODEL, "DH"), {}, UsageError, ["unknown convention 'DH'", "dh, hayati, mdh"]),
        ((MODEL,), {"style": "fast"}, UsageError, ["unknown style 'fast'"]),
        ((MODEL,), {"tol": 1e-6}, TypeError, ["to_table: tol", "Tolerances", "float 1e-06"]),
        ((MODEL,), {"samples": 0}, ValueError, ["to_table: samples", "from 1", "not 0"]),
        ((MODEL,), {"samples": -5}, ValueError, ["to_table: samples", "not -5"]),
        ((MODEL,), {"samples": 10**9}, ValueError, ["to_table: samples", "1,000,000"]),
        ((MODEL,), {"samples": 2.0}, TypeError, ["to_table: samples", "integer", "float 2.0"]),
        ((MODEL,), {"samples": True}, TypeError, ["to_table: samples", "bool True"]),
        ((MODEL,), {"seed": -1}, ValueError, ["to_table: seed", "not -1"]),
        ((MODEL,), {"seed": "0"}, TypeError, ["to_table: seed", "str '0'"]),
    ],
)
def test_to_table_checks_its_arguments(args, kwargs, error, words):
    refuses(lambda: urdf2dh.to_table(*args, **kwargs), error, *words)


def test_usage_errors_are_value_errors_and_a_table_is_checked_at_one_configuration_or_more():
    with pytest.raises(ValueError):
        urdf2dh.to_table(MODEL, "DH")
    table = urdf2dh.to_table(MODEL, "mdh", samples=1, seed=3)
    assert table.check is not None and table.check.samples == 1
    refuses(lambda: Check(0, 0.0, 0.0), ValueError, "Check: samples", "not 0")


@pytest.mark.parametrize(
    "args, error, words",
    [
        ((MODEL, "json"), TypeError, ["render: table", "PoeModel", "urdf2dh.to_table(model"]),
        ((None, "json"), TypeError, ["render: table must be a Table, not None"]),
        ((TABLE, None), TypeError, ["render: fmt", "None"]),
        ((TABLE, "xlsx"), UsageError, ["unknown format 'xlsx'", "csv"]),
    ],
)
def test_render_checks_its_arguments(args, error, words):
    refuses(lambda: urdf2dh.render(*args), error, *words)


@pytest.mark.parametrize(
    "args, error, words",
    [
        ((MODEL, "png"), TypeError, ["plot: table", "PoeModel", "urdf2dh.to_table(model"]),
        ((None, "html"), TypeError, ["plot: table must be a Table, not None"]),
        ((TABLE, None), TypeError, ["plot: fmt", "None"]),
        ((TABLE, "gif"), UsageError, ["unknown plot format 'gif'", "png"]),
    ],
)
def test_plot_checks_its_arguments(args, error, words):
    refuses(lambda: urdf2dh.plot(*args), error, *words)


# --------------------------------------------------------------------------- fk and friends

METHODS = [(owner, name) for owner in (MODEL, TABLE) for name in ("fk", "fk_batch", "positions")]
IDS = [f"{type(o).__name__}.{n}" for o, n in METHODS]


@pytest.mark.parametrize("owner, method", METHODS, ids=IDS)
@pytest.mark.parametrize(
    "q, error, words",
    [
        ([math.nan] * 6, ValueError, ["q must be finite", "entry (0,) is nan"]),
        ([0.1, 0.2, math.inf, 0, 0, 0], ValueError, ["entry (2,) is inf"]),
        ([[0.0] * 6, [0.0] * 5 + [-math.inf]], ValueError, ["entry (1, 5) is -inf"]),
        (
            np.array([None] * 6, dtype=object),
            TypeError,
            ["of numbers, not of objects such as None"],
        ),
        (["0.1"] * 6, TypeError, ["not of strings"]),
        ([True] * 6, TypeError, ["not of booleans"]),
        (np.zeros(6, complex), TypeError, ["not of complex numbers"]),
        ([0.0] * 5, ValueError, ["shape", "(5,)"]),
        (np.zeros((2, 7)), ValueError, ["(2, 7)"]),
        ([[0.0] * 6, [0.0] * 5], ValueError, ["q must be"]),  # ragged
        (None, TypeError, ["q must be"]),
        (3.0, ValueError, ["shape", "()"]),
    ],
)
def test_joint_values_are_finite_numbers_of_the_right_shape(owner, method, q, error, words):
    where = f"{type(owner).__name__}.{method}: q"
    refuses(lambda: getattr(owner, method)(q), error, where, *words)


@pytest.mark.parametrize("owner", [MODEL, TABLE], ids=["PoeModel", "Table"])
def test_batches_are_batches(owner):
    refuses(lambda: owner.fk_batch(np.zeros((2, 3, 6))), ValueError, "(N, 6)", "(2, 3, 6)")
    assert owner.fk(np.zeros((2, 3, 6))).shape == (2, 3, 4, 4)  # fk takes stacks


@pytest.mark.parametrize("owner", [MODEL, TABLE], ids=["PoeModel", "Table"])
def test_any_real_numbers_are_joint_values(owner):
    q = [0, 1, -2, 2, 3, 1]  # exact as int32 and float32 too
    want = owner.fk(np.array(q, dtype=float))
    for same in (q, tuple(q), np.array(q, np.int32), np.array(q, np.float32),
                 np.array([Fraction(x) for x in q], dtype=object)):  # fmt: skip
        assert np.array_equal(owner.fk(same), want)
        assert np.array_equal(owner.fk_batch([same])[0], want)


@EXAMPLES
@given(
    st.integers(1, 40),
    st.lists(
        st.tuples(st.integers(0, 10**6), st.sampled_from([math.nan, math.inf, -math.inf])),
        min_size=1,
        max_size=4,
    ),
)
def test_a_non_finite_value_anywhere_in_a_batch_is_refused(n, bad):
    q = np.random.default_rng(n).uniform(-3, 3, (n, 6))
    for where, value in bad:
        q.flat[where % q.size] = value
    first = tuple(int(i) for i in np.argwhere(~np.isfinite(q))[0])
    for owner in (MODEL, TABLE):
        refuses(lambda o=owner: o.fk_batch(q), ValueError, f"entry {first} is")
        refuses(lambda o=owner: o.fk(q), ValueError, f"entry {first} is")


def test_scaled_checks_factor_and_unit():
    refuses(lambda: MODEL.scaled(0.0, "mm"), ValueError, "factor must be positive")
    refuses(lambda: MODEL.scaled(math.nan, "mm"), ValueError, "factor must be finite")
    refuses(lambda: MODEL.scaled("1000", "mm"), TypeError, "factor must be a number")
    refuses(lambda: MODEL.scaled(1000.0, None), TypeError, "unit must be a str")


# --------------------------------------------------------------------------- value types

Z = np.array([0.0, 0.0, 1.0])


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"name": 5}, TypeError, ["Joint: name must be a str, not int 5"]),
        ({"kind": "ball"}, ValueError, ["joint 'j': kind must be one of", "'ball'"]),
        ({"axis": [0, 0, 2]}, ValueError, ["joint 'j': axis must be a unit vector", "2.0"]),
        ({"axis": [0, 0]}, ValueError, ["joint 'j': axis must have shape (3,)"]),
        ({"axis": [0, math.nan, 1]}, ValueError, ["joint 'j': axis must be finite"]),
        ({"point": ["a", 0, 0]}, TypeError, ["joint 'j': point", "strings"]),
        ({"point": None}, ValueError, ["a revolute joint needs a point"]),
        ({"pitch": math.inf}, ValueError, ["joint 'j': pitch must be finite"]),
        ({"scale": 0.0}, ValueError, ["joint 'j': scale must not be 0"]),
        ({"lower": "-1"}, TypeError, ["joint 'j': lower must be a number"]),
        ({"mimic": "j0"}, TypeError, ["joint 'j': mimic must be a Mimic"]),
    ],
)
def test_a_joint_is_checked_when_made(kwargs, error, words):
    fields = {"name": "j", "kind": "revolute", "axis": Z, "point": np.zeros(3)} | kwargs
    refuses(lambda: Joint(**fields), error, *words)


def test_a_poe_model_is_checked_when_made():
    joint = MODEL.joints[0]
    bent = np.eye(4)
    bent[0, 1] = 1e-3
    for kwargs, error, words in (
        ({"joints": ("j",)}, TypeError, ["PoeModel: joints[0] must be a Joint, not str 'j'"]),
        ({"home": np.full((4, 4), math.nan)}, ValueError, ["PoeModel: home must be finite"]),
        ({"home": np.eye(3)}, ValueError, ["PoeModel: home must have shape (4, 4)"]),
        ({"home": bent}, ValueError, ["PoeModel: home must be a rigid transform"]),
        ({"home": 2 * np.eye(4)}, ValueError, ["rigid transform"]),
        ({"name": None}, TypeError, ["PoeModel: name must be a str, not None"]),
    ):
        fields = {"joints": (joint,), "home": np.eye(4)} | kwargs
        refuses(lambda f=fields: PoeModel(**f), error, *words)


def test_a_table_is_checked_when_made():
    row = TABLE.rows[0]
    other = urdf2dh.to_table(MODEL, "cpc")
    for change, error, words in (
        ({"rows": ("r",)}, TypeError, ["Table: rows[0] must be a Row, not str 'r'"]),
        ({"rows": other.rows}, TypeError, ["Table: row 'shoulder_pan_joint' (dh row): params"]),
        ({"base": other.base}, TypeError, ["Table: base (dh base record) must be a"]),
        ({"size": 0.0}, ValueError, ["Table: size must be positive"]),
        ({"size": math.nan}, ValueError, ["Table: size must be finite"]),
        ({"convention": "dhx"}, UsageError, ["unknown convention 'dhx'"]),
        ({"robot": None}, TypeError, ["Table: robot must be a str, not None"]),
        ({"check": "ok"}, TypeError, ["Table: check must be a Check"]),
    ):
        refuses(lambda c=change: replace(TABLE, **c), error, *words)
    refuses(lambda: replace(row, params=None), TypeError, "row 'shoulder_pan_joint': params")
    refuses(lambda: replace(row, scale=math.nan), ValueError, "row 'shoulder_pan_joint': scale")
    assert isinstance(row.params, DhLink)


def test_tolerances_are_numbers():
    refuses(lambda: urdf2dh.Tolerances(parallel_angle="1e-4"), TypeError, "parallel_angle")
    refuses(lambda: urdf2dh.Tolerances(noise=math.nan), ValueError, "noise")
    refuses(lambda: urdf2dh.Tolerances(report=True), TypeError, "report")


def test_every_public_callable_is_tried_here():
    tried = {"load", "to_table", "render", "plot", "export", "Joint", "PoeModel", "Row", "Table",
             "Check", "Tolerances", "ExportOptions"}  # fmt: skip
    # the other jobs' and results' wrong arguments: tests/test_public_api.py
    tried |= {"verify", "diff", "info", "measure", "plan", "calibrate", "Measurements"}
    # results the jobs make (their fields are the jobs' checked output)
    tried |= {"VerifyReport", "ModelCheck", "Diff", "Info", "Calibration", "Plan"}
    tried |= {"XacroOptions"}  # tests/test_xacro*.py
    tried |= {"match", "Match"}  # below; Match's fields are match's checked output
    public = {n for n in urdf2dh.__all__ if callable(getattr(urdf2dh, n))}
    assert public - {"Urdf2DhError"} <= tried, public - tried
    assert Row is urdf2dh.Row


def test_match_checks_its_arguments():
    refuses(lambda: urdf2dh.match(None, "ur5"), TypeError, "match: table")
    refuses(lambda: urdf2dh.match("ur5-dh", "ur5", convention="cpc"), UsageError,
            "unknown convention 'cpc'")  # fmt: skip
    refuses(lambda: urdf2dh.match("ur5-dh", "ur5", angle_unit="grad"), UsageError, "angle_unit")
    refuses(lambda: urdf2dh.match("ur5-dh", "ur5", length_unit="furlong"), UsageError,
            "length_unit")  # fmt: skip
    refuses(lambda: urdf2dh.match("ur5-dh", "ur5", samples=0), ValueError, "match: samples")
    refuses(lambda: urdf2dh.match("ur5-dh", "ur5", tol=1e-9), TypeError, "match: tol")


def test_export_checks_its_arguments():
    from urdf2dh.emit.export import export

    refuses(lambda: export("ur5", "rtb"), TypeError, "export: model", "str 'ur5'")
    refuses(lambda: export(MODEL, None), TypeError, "export: target must be a str, not None")
    refuses(lambda: export(MODEL, "vrml"), UsageError, "unknown export target 'vrml'")
    opw = urdf2dh.load("fanuc-m20ia")
    refuses(lambda: export(opw, "opw", samples=0), ValueError, "export: samples", "not 0")
    refuses(
        lambda: export(MODEL, "rtb", opts="mm"), TypeError, "export: opts must be an ExportOptions"
    )
