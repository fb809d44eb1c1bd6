"""`urdf2dh plot -o FILE.html`: the interactive view, read back from the page as plotly.js
reads it (tests/view_reader.py).

Every frame is there at its pose, every label at its anchor (just beyond the tip of the arrow it
names, which starts at its frame's origin), with the frames computed from the table's forward
kinematics (tests/frames_oracle.py); hovering a frame shows its record's parameters; the page
needs nothing from the network and is the same bytes each time. The browser's side is
tests/test_view_browser.py.
"""

from __future__ import annotations

import html
import math
import re
import sys
import time

import numpy as np
import pytest
from chains import random_chain_urdf
from frames_oracle import anchor, fk_frames, named, span
from view_reader import read_page

from urdf2dh import load, to_table
from urdf2dh.cli import main
from urdf2dh.emit.scene import ARROW, MAX_JOINTS, NAME_CHARS, TOOL_ARROW

CASES = (
    [("panda", c, "wu") for c in ("dh", "mdh", "cpc", "hayati")]
    + [("ur5", "dh", s) for s in ("wu", "ur", "zero")]
    + [("kinova", "mdh", "zero"), ("scara", "dh", "wu"), ("stanford", "cpc", "wu")]
    + [("puma560-actual", "hayati", "wu"), ("tiago-arm", "mdh", "wu")]
)


def _view(tmp_path, robot: str, convention: str = "dh", style: str = "wu"):
    out = tmp_path / f"{robot}-{convention}-{style}.html"
    argv = ["plot", robot, "--convention", convention, "--style", style, "-o", str(out)]
    assert main(argv) == 0
    table = to_table(load(robot), convention, style=style)
    return read_page(out.read_text(encoding="utf-8")), table


def _segments(points: np.ndarray) -> np.ndarray:
    """``(k, 2, 3)`` segments of a line trace drawn as pairs with gaps."""
    return points.reshape(-1, 3, 3)[:, :2]


@pytest.mark.parametrize(("robot", "convention", "style"), CASES)
def test_every_label_is_at_its_frame(tmp_path, robot, convention, style):
    page, table = _view(tmp_path, robot, convention, style)
    frames = fk_frames(table)
    size = span(frames) or table.size
    arrow, tol = ARROW * size, 1e-12 * size

    origins = page.points("frames")
    assert page.trace("frames")["text"] == list(frames)
    np.testing.assert_allclose(origins, [f[:3, 3] for f in frames.values()], atol=tol)

    for axis in "xz":  # each arrow from its frame's origin along its axis
        c = "xyz".index(axis)
        want = [(f[:3, 3], f[:3, 3] + (TOOL_ARROW if k == "tool" else 1.0) * arrow * f[:3, c])
                for k, f in frames.items()]  # fmt: skip
        np.testing.assert_allclose(_segments(page.points(f"{axis} axes")), want, atol=tol)

    labels = page.trace("labels")
    seen = set()
    for text, at in zip(labels["text"], page.points("labels"), strict=True):
        for what, which in named(html.unescape(text)):
            seen.add((what, which))
            start, direction, distance = anchor(table, frames, what, which)
            want = start + distance * direction
            np.testing.assert_allclose(at, want, atol=tol, err_msg=f"{text} {what}{which}")
    names = [str(k) for k in range(table.n + 1)] + ["tool"]
    everything = {(a, k) for a in "xz" for k in names} | {
        ("J", str(i)) for i in range(1, table.n + 1)
    }
    assert seen == everything


def _hover_values(hover: str) -> dict[str, tuple[float, ...]]:
    """``name [unit] = value`` lines of a hover text -> name -> the number(s)."""
    out = {}
    for line in hover.split("<br>"):
        m = re.fullmatch(r"(\w+)(?: \[[^\]]*\])? = \(?([-0-9., ]+?)\)?", html.unescape(line))
        if m:
            out[m[1]] = tuple(float(v) for v in m[2].split(", "))
    return out


HOVER_CASES = [("panda", "dh"), ("panda", "mdh"), ("puma560-actual", "cpc"), ("ur5", "hayati")]


@pytest.mark.parametrize(("robot", "convention"), HOVER_CASES)
def test_hovering_a_frame_shows_its_record(tmp_path, robot, convention):
    page, table = _view(tmp_path, robot, convention)
    hovers = page.trace("frames")["hovertext"]
    records = [table.base, *(r.params for r in table.rows), table.tool]
    assert len(hovers) == len(records)
    for k, (hover, record) in enumerate(zip(hovers, records, strict=True)):
        if 0 < k <= table.n:
            row = table.rows[k - 1]
            assert f"row {k}, joint {html.escape(row.name)} ({row.kind})" in hover
        got = _hover_values(hover)
        for name, quantity in record.quantities().items():
            value = getattr(record, name)
            values = value if isinstance(value, tuple) else (value,)
            if quantity == "angle":  # degrees, 4 decimals
                want, within = tuple(math.degrees(v) for v in values), 0.6e-4
            else:  # lengths in the unit's decimals (mm: 4), directions 6
                want, within = values, 0.6e-4 if table.length_unit == "mm" else 0.6e-6
            np.testing.assert_allclose(got[name], want, atol=within, err_msg=f"frame {k} {name}")
        origin = fk_frames(table)[list(fk_frames(table))[k]][:3, 3]
        np.testing.assert_allclose(got["origin"], origin, rtol=1e-5, atol=1e-6 * table.size)


def test_the_page_needs_no_network_and_is_reproducible(tmp_path):
    page, _ = _view(tmp_path, "panda")
    first = (tmp_path / "panda-dh-wu.html").read_bytes()
    assert main(["plot", "panda", "-o", str(tmp_path / "again.html")]) == 0
    assert (tmp_path / "again.html").read_bytes() == first
    attributes = [(tag, k, v or "") for tag, attrs in page.tags for k, v in attrs]
    assert not [a for a in attributes if a[1] in ("src", "href", "srcset", "action", "data")]
    assert not [t for t, _ in page.tags if t in ("link", "iframe", "object", "embed", "img")]
    csp = [v for t, k, v in attributes if t == "meta" and k == "content" and "default-src" in v]
    assert len(csp) == 1 and csp[0].startswith("default-src 'none';")
    assert "connect-src 'none'" in csp[0] and "http" not in csp[0]
    plotly_js = max(page.scripts, key=len)
    assert len(plotly_js) > 1_000_000 and "plotly.js v" in plotly_js[:1000]
    assert page.config["displaylogo"] is False
    assert len(page.scripts) == 3  # plotly's settings, plotly.js, the figure


def test_the_view_needs_plotly(tmp_path, capsys, monkeypatch):
    for name in [m for m in sys.modules if m.split(".")[0] == "plotly"]:
        monkeypatch.setitem(sys.modules, name, None)  # as if plotly were not installed
    monkeypatch.setitem(sys.modules, "plotly", None)
    assert main(["plot", "ur5", "-o", str(tmp_path / "x.html")]) == 2
    err = capsys.readouterr().err
    assert "pip install plotly" in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- bounds


def test_a_chain_too_long_to_draw_is_refused_at_once(tmp_path, capsys):
    """10^4 joints (the most a URDF holds, urdf2dh.tolerances.JOINTS, its tool's fixed joint
    counted): refused on one line naming the limit, before any conversion, no file."""
    source = tmp_path / "long.urdf"
    source.write_text(random_chain_urdf(7, 9_999)[0])
    for suffix in ("png", "html"):
        started = time.perf_counter()
        assert main(["plot", str(source), "-o", str(tmp_path / f"long.{suffix}")]) == 2
        seconds = time.perf_counter() - started
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and f"at most {MAX_JOINTS}" in err and "9999 joints" in err
        assert seconds < 60, seconds
    assert sorted(p.name for p in tmp_path.iterdir()) == ["long.urdf"]


def test_the_longest_chain_drawn(tmp_path):
    """:data:`MAX_JOINTS` joints: drawn, every frame labelled."""
    source = tmp_path / "limit.urdf"
    source.write_text(random_chain_urdf(8, MAX_JOINTS, tool=False)[0])
    out = tmp_path / "limit.html"
    assert main(["plot", str(source), "-o", str(out)]) == 0
    texts = {n for t in read_page(out.read_text()).trace("labels")["text"] for n in named(t)}
    assert {("x", str(MAX_JOINTS)), ("J", str(MAX_JOINTS)), ("z", "0")} <= texts


def test_a_huge_name_is_shortened(tmp_path):
    """A 3 MB joint name: drawn in seconds, shown cut to :data:`NAME_CHARS` characters."""
    name = "j<b>" + "é" * 1_500_000
    source = tmp_path / "huge.urdf"
    source.write_text(
        f'<robot name="{"r" * 100}"><link name="base"/><link name="l1"/><link name="l2"/>'
        f'<joint name="{html.escape(name)}" type="revolute"><parent link="base"/>'
        '<child link="l1"/><axis xyz="0 0 1"/><origin xyz="0 0 0.1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        '<joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/>'
        '<axis xyz="0 1 0"/><origin xyz="0 0 0.3"/></joint></robot>',
        encoding="utf-8",
    )
    assert source.stat().st_size > 3_000_000
    for suffix in ("html", "png"):
        started = time.perf_counter()
        assert main(["plot", str(source), "-o", str(tmp_path / f"huge.{suffix}")]) == 0
        assert time.perf_counter() - started < 60
    page = read_page((tmp_path / "huge.html").read_text(encoding="utf-8"))
    hover = html.unescape(page.trace("frames")["hovertext"][1])
    assert f"joint {name[: NAME_CHARS - 1]}… (revolute)" in hover
    assert (tmp_path / "huge.html").stat().st_size < 6_000_000
    assert page.texts == [f"{'r' * (NAME_CHARS - 1)}…: standard D-H frames at home (base -> l2)"]
