"""`urdf2dh plot -o FILE.png|svg|pdf`: the picture for papers, drawn headless (Agg).

Every label must be at what it names: its 3-D position (read from matplotlib's text objects)
on its own arrow's line, just beyond the arrow's tip, with the arrows computed from the table's
forward kinematics (tests/frames_oracle.py), and on every bundled robot no label's text may
cover another's.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest
from frames_oracle import anchor, fk_frames, named, on_ray, span

from urdf2dh import load, to_table
from urdf2dh.cli import main
from urdf2dh.emit.picture import COLOURS, draw
from urdf2dh.emit.scene import ARROW, SLIDE, frames_at_home, scene
from urdf2dh.io.catalog import ROBOTS

STYLE = {"ur3": "ur", "ur5": "ur", "ur10": "ur"}


def _table(robot: str, convention: str = "dh", style: str | None = None):
    return to_table(load(robot), convention, style=style or STYLE.get(robot, "wu"))


def _rgb(hex_colour: str) -> np.ndarray:
    return np.array([int(hex_colour[i : i + 2], 16) for i in (1, 3, 5)]) / 255.0


def test_png_is_a_real_picture(tmp_path):
    from matplotlib.image import imread

    out = tmp_path / "ur5.png"
    assert main(["plot", "ur5", "-o", str(out)]) == 0
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 30_000
    image = imread(out)[:, :, :3]
    assert image.shape[0] >= 1000 and image.shape[1] >= 700
    colours = np.unique((image * 255).astype(np.uint8).reshape(-1, 3), axis=0)
    assert len(colours) > 50  # lines, labels, grid, anti-aliasing: not a blank canvas
    pixels = image.reshape(-1, 3)
    for name in ("x", "z", "joint", "link"):  # every kind of line was drawn
        near = np.abs(pixels - _rgb(COLOURS[name])).max(axis=1) < 0.02
        assert near.sum() > 50, f"no {name} pixels"


def test_svg_labels_every_frame(tmp_path):
    out = tmp_path / "panda.svg"
    assert main(["plot", "panda", "--convention", "mdh", "-o", str(out)]) == 0
    svg = out.read_text()
    # matplotlib writes text as glyph paths, with the string in a comment
    shown = {n for text in svg.split("<!-- ")[1:] for n in named(text.split(" -->")[0])}
    want = {(a, str(k)) for a in "xz" for k in range(8)} | {("x", "tool"), ("z", "tool")}
    assert want | {("J", str(i)) for i in range(1, 8)} <= shown


def test_frames_follow_the_table():
    table = _table("ur5")
    frames = frames_at_home(table)
    assert len(frames) == table.n + 2
    for got, want in zip(frames, fk_frames(table).values(), strict=True):
        np.testing.assert_allclose(got, want, atol=1e-15)
    # standard D-H: frame k-1's z is joint k's axis
    for f, g in zip(frames[:-2], table.joint_frames()[:-1], strict=True):
        np.testing.assert_allclose(f, g, atol=1e-15)


def test_plot_errors(tmp_path, capsys, monkeypatch):
    assert main(["plot", "ur5", "-o", str(tmp_path / "x.gif")]) == 2
    err = capsys.readouterr().err
    assert "unknown format '.gif'" in err and "html" in err and err.count("\n") == 1
    for name in [m for m in sys.modules if m.split(".")[0] in ("matplotlib", "mpl_toolkits")]:
        monkeypatch.setitem(sys.modules, name, None)  # as if matplotlib were not installed
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    assert main(["plot", "ur5", "-o", str(tmp_path / "x.png")]) == 2
    assert "pip install matplotlib" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("robot", ["stanford", "puma560-nominal"])
def test_prismatic_and_mm_sources_plot(tmp_path, robot):
    out = tmp_path / f"{robot}.pdf"
    assert main(["plot", robot, "-o", str(out)]) == 0
    assert out.read_bytes()[:4] == b"%PDF"


def _check_labels_at_their_arrows(table, texts) -> set[tuple[str, str]]:
    """Each text naming axes or joints sits on each one's line, at its anchor or slid further
    along it by at most the slide; returns what the texts name."""
    frames = fk_frames(table)
    size = span(frames) or table.size
    tol = 1e-9 * size
    seen = set()
    for text in texts:
        position = np.asarray(text.get_position_3d(), float)
        for what, which in named(text.get_text()):
            seen.add((what, which))
            start, direction, distance = anchor(table, frames, what, which)
            along, off = on_ray(position, start, direction)
            slid = along - distance
            assert off <= tol and -tol <= slid <= SLIDE * ARROW * size + tol, (text, off, slid)
    return seen


def _everything(table) -> set[tuple[str, str]]:
    frames = [str(k) for k in range(table.n + 1)] + ["tool"]
    return {(a, f) for a in "xz" for f in frames} | {("J", str(i + 1)) for i in range(table.n)}


@pytest.mark.parametrize(
    ("robot", "convention", "style"),
    [("panda", c, "wu") for c in ("dh", "mdh", "cpc", "hayati")]
    + [("ur5", "dh", s) for s in ("wu", "ur", "zero")]
    + [("scara", "mdh", "wu"), ("stanford", "dh", "wu"), ("puma560-actual", "hayati", "wu")],
)
def test_every_label_is_at_its_arrow(robot, convention, style):
    table = _table(robot, convention, style)
    _, ax, placed = draw(scene(table))
    assert len(ax.texts) == len(placed)
    assert _check_labels_at_their_arrows(table, ax.texts) == _everything(table)


def _drawn_boxes(fig, ax) -> list[tuple[str, object]]:
    """Each label's text and the pixels it covers as drawn: a 3-D text is drawn at its
    position's projection, in its font and alignment."""
    from matplotlib.text import Text
    from mpl_toolkits.mplot3d import proj3d

    renderer = fig.canvas.get_renderer()
    fig.draw(renderer)
    out = []
    for t in ax.texts:
        x, y, _ = proj3d.proj_transform(*t.get_position_3d(), ax.get_proj())
        probe = Text(x, y, t.get_text(), fontproperties=t.get_fontproperties(),
                     ha=t.get_ha(), va=t.get_va(), transform=ax.transData, figure=fig)  # fmt: skip
        out.append((t.get_text(), probe.get_window_extent(renderer)))
    return out


@pytest.mark.parametrize("robot", sorted(ROBOTS))
def test_every_bundled_robot_reads(robot):
    """Every label at its arrow, inside the figure, and no label's text over another's."""
    table = _table(robot)
    fig, ax, _ = draw(scene(table))
    assert _check_labels_at_their_arrows(table, ax.texts) == _everything(table)
    boxes = _drawn_boxes(fig, ax)
    for i, (a, box_a) in enumerate(boxes):
        for b, box_b in boxes[:i]:
            assert not box_a.overlaps(box_b), (robot, a, b)
        assert fig.bbox.contains(box_a.x0, box_a.y0) and fig.bbox.contains(box_a.x1, box_a.y1)
