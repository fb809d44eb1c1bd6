"""What ``calibrate`` leaves to the reading of its result, and what the conversions check: the
figures only the presentation reads (the parameters' values and changes, the ``diff``) are
made when first read, once, with the values a reading in ``calibrate`` gave; ``choose``
checks the table it returns and no other."""

from __future__ import annotations

import pickle
from pathlib import Path

import pytest
from chains import TILTED_ARM

import urdf2dh
from urdf2dh.calibration import figures
from urdf2dh.calibration.result import Later
from urdf2dh.conventions import convert
from urdf2dh.conventions.choice import choose
from urdf2dh.tolerances import DEFAULT

TILT = TILTED_ARM  # joint 2's axis 0.01 rad from joint 1's: D-H puts its row 29.8 m away


def test_later_makes_its_figure_once_and_keeps_it():
    made = []

    def make() -> list[int]:
        made.append(1)
        return [len(made)]

    later = Later(make)
    assert made == [] and later.get() == [1] and later.get() == [1] and made == [1]
    assert later == Later(lambda: [1]) and later != Later(lambda: [2])

    def fails() -> int:
        raise ValueError("not made")

    broken = Later(fails)
    for _ in range(2):  # a failure is not kept: every reading raises it
        with pytest.raises(ValueError, match="not made"):
            broken.get()


# figures' makers of the presentation, counted when called (module level: a result holding them
# pickles)
MADE: list[str] = []
REAL = {"_diff": figures._diff, "_parameters": figures._parameters}


def _diff(*args, **kwargs):  # type: ignore[no-untyped-def]
    MADE.append("_diff")
    return REAL["_diff"](*args, **kwargs)


def _parameters(*args, **kwargs):  # type: ignore[no-untyped-def]
    MADE.append("_parameters")
    return REAL["_parameters"](*args, **kwargs)


def test_calibrate_leaves_the_presentation_to_the_reading(monkeypatch):
    """Nothing of the diff or the parameters' table is made in calibrate; each is made once when
    read (the diff: urdf2dh diff's of the two models), and a result pickles read or not."""
    monkeypatch.setattr(figures, "_diff", _diff)
    monkeypatch.setattr(figures, "_parameters", _parameters)
    MADE.clear()
    made = MADE
    nominal = urdf2dh.load("puma560-nominal")
    m = urdf2dh.measure(urdf2dh.load("puma560-actual"), 30, 1e-5, 1e-5, seed=4)
    cal = urdf2dh.calibrate(nominal, m, level="geometry", helical=("all",), convention="poe")
    assert made == []
    unread = pickle.loads(pickle.dumps(cal))  # what makes them travels with it
    first = (cal.diff, cal.parameters)
    assert (cal.diff, cal.parameters) == first and sorted(made) == ["_diff", "_parameters"]
    assert pickle.loads(pickle.dumps(cal)).diff == cal.diff  # and what was made
    assert (unread.diff, unread.parameters) == first
    assert len(cal.parameters) == cal.counts.parameters
    # the figures are those of the calibration: the diff is urdf2dh diff's of the two models
    assert cal.diff.to_dict() == urdf2dh.diff(nominal, cal.model, cal.diff.convention).to_dict()


def test_choose_checks_the_table_it_returns_and_no_other(monkeypatch, tmp_path):
    checked: list[str] = []
    real = convert.self_check

    def counted(model, table, *args, **kwargs):  # type: ignore[no-untyped-def]
        checked.append(table.convention)
        return real(model, table, *args, **kwargs)

    monkeypatch.setattr(convert, "self_check", counted)
    for angle, fallback, expected in (
        (0.01, "hayati", "hayati"),  # D-H set aside: only hayati checked
        (0.01, None, "dh"),  # a reader of D-H only: the D-H table, checked
        (1e-5, "hayati", "dh"),  # no objection: the D-H table
    ):
        path = Path(tmp_path / f"tilt-{angle:g}.urdf")
        path.write_text(TILT.format(angle=angle))
        model = urdf2dh.load(str(path))
        checked.clear()
        chosen = choose(model, "dh", DEFAULT, fallback=fallback)
        assert checked == [expected] and chosen.table.convention == expected
        # the check and the warnings are to_table's (the reason first where there is one)
        alone = urdf2dh.to_table(model, expected)
        assert chosen.table.check == alone.check
        reason = () if chosen.reason is None else (chosen.reason,)
        assert chosen.table.warnings == (*reason, *alone.warnings)
