"""Golden files for every export target's text (tests/golden/).

The generated text must match token for token; numbers may differ by 1e-12 relative (so a
platform's last-digit round-off does not fail the test, while any real change does). After an
intended change, refresh them with ``python -m pytest tests/test_golden.py --update-golden`` and
review the diff.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from urdf2dh import load, to_table
from urdf2dh.emit.export import TARGETS, ExportOptions, export, export_table, table_choices

ROOT = Path(__file__).resolve().parents[1]
GOLDEN = ROOT / "tests" / "golden"
NUMBER = re.compile(r"([-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?)")
# The table's self-check is round-off measured on this machine: compared as text up to there.
CHECK = re.compile(r"(check: FK against the source at \d+ configurations:)[^\n]*")

# (golden file, source, target, convention, options)
CASES = [
    ("ur-ur10.yaml", "ur10", "ur", None, ExportOptions()),
    ("linuxcnc-genser6.hal", "tests/data/genser6.urdf", "linuxcnc", None, ExportOptions()),
    (
        "linuxcnc-genser6-inch.hal",
        "tests/data/genser6.urdf",
        "linuxcnc",
        None,
        ExportOptions(units="inch"),
    ),
    ("linuxcnc-kuka-kr6-r700-sixx.hal", "kuka-kr6-r700-sixx", "linuxcnc", None, ExportOptions()),
    ("linuxcnc-so100.hal", "so100", "linuxcnc", None, ExportOptions()),
    ("rtb-ur5.py", "ur5", "rtb", None, ExportOptions()),
    ("rtb-stanford-mdh.py", "stanford", "rtb", "mdh", ExportOptions()),
    ("matlab-ur5.m", "ur5", "matlab", None, ExportOptions()),
    ("matlab-stanford-mdh.m", "stanford", "matlab", "mdh", ExportOptions()),
    ("kdl-panda.py", "panda", "kdl", None, ExportOptions()),
    ("kdl-panda-mdh.py", "panda", "kdl", "mdh", ExportOptions()),
    ("corke-matlab-scara.m", "scara", "corke-matlab", None, ExportOptions()),
    ("corke-matlab-puma560-mdh.m", "puma560-nominal", "corke-matlab", "mdh", ExportOptions()),
    ("opw-fanuc-m20ia.yaml", "fanuc-m20ia", "opw", None, ExportOptions()),
    ("eaik-kinova.py", "kinova", "eaik", None, ExportOptions()),
    ("ikdh-ur5.yaml", "ur5", "ikdh", None, ExportOptions()),
]


def _tokens(text: str) -> list[str]:
    return [t for t in NUMBER.split(CHECK.sub(r"\1 ...", text)) if t]


def _same(got: str, want: str) -> str | None:
    """None if the texts match (numbers to 1e-12 relative), else where they differ."""
    a, b = _tokens(got), _tokens(want)
    for i, (x, y) in enumerate(zip(a, b, strict=False)):
        if x == y:
            continue
        if NUMBER.fullmatch(x) and NUMBER.fullmatch(y):
            fx, fy = float(x), float(y)
            if abs(fx - fy) <= 1e-12 * max(1.0, abs(fx), abs(fy)):
                continue
        context = "".join(a[max(0, i - 6) : i + 6])
        return f"token {i}: got {x!r}, golden {y!r}, near: {context!r}"
    if len(a) != len(b):
        return f"lengths differ: {len(a)} tokens, golden {len(b)}"
    return None


@pytest.mark.parametrize(
    ("name", "source", "target", "convention", "opts"), CASES, ids=[c[0] for c in CASES]
)
def test_golden(name, source, target, convention, opts, request, monkeypatch):
    monkeypatch.chdir(ROOT)  # sources named relative to the repository, as in the files
    model = load(source)
    if TARGETS[target].reads_model:  # written from the POE model, not from a table
        text = export(model, target, opts=opts, samples=None)
    else:
        convention, style = table_choices(target, convention, None)
        text = export_table(to_table(model, convention, style=style), target, opts)
    path = GOLDEN / name
    if request.config.getoption("--update-golden"):
        path.parent.mkdir(exist_ok=True)
        path.write_text(text)
        pytest.skip(f"updated {path.relative_to(ROOT)}")
    assert path.exists(), f"no golden file {path}; run pytest --update-golden"
    problem = _same(text, path.read_text())
    assert problem is None, f"{name} differs from its golden file: {problem}"


def test_the_comparison_catches_real_changes():
    assert _same("a 0.1 b", "a 0.1000000000000001 b") is None
    assert _same("a 0.1 b", "a 0.1000001 b") is not None
    assert _same("setp x.D-5 100.0", "setp x.D-4 100.0") is not None
    assert _same("a 1.0", "a 1.0 b") is not None
    assert (
        _same(
            "# checked against the source at 9 configurations: 1e-16 m",
            "# checked against the source at 9 configurations: 3e-16 m",
        )
        is None
    )
