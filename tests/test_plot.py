"""`urdf2dh plot`: the arm at home with its D-H frames, rendered headless (Agg)."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from urdf2dh.cli import main
from urdf2dh.convert import to_table
from urdf2dh.plot import COLOURS, dh_frames
from urdf2dh.sources import open_source


def _rgb(hex_colour: str) -> np.ndarray:
    return np.array([int(hex_colour[i : i + 2], 16) for i in (1, 3, 5)]) / 255.0


def test_png_is_a_real_picture(tmp_path, capsys):
    from matplotlib.image import imread

    out = tmp_path / "ur5.png"
    assert main(["plot", "ur5", "-o", str(out)]) == 0
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 30_000
    image = imread(out)[:, :, :3]
    assert image.shape[0] >= 600 and image.shape[1] >= 600
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
    for k in range(8):
        assert f"<!-- x{k} -->" in svg and f"<!-- z{k} -->" in svg
    assert "<!-- J7 panda_joint7 -->" in svg


def test_frames_follow_the_table():
    table = to_table(open_source("ur5").model(), "dh", style="ur")
    frames = dh_frames(table)
    assert len(frames) == table.n + 2
    np.testing.assert_allclose(frames[-1], table.fk(np.zeros(6)), atol=1e-15)
    # standard D-H: frame k-1's z is joint k's axis
    for f, g in zip(frames[:-2], table.frames()[:-1], strict=True):
        np.testing.assert_allclose(f, g, atol=1e-15)


def test_plot_errors(tmp_path, capsys, monkeypatch):
    assert main(["plot", "ur5", "-o", str(tmp_path / "x.gif")]) == 2
    assert "unknown image format 'gif'" in capsys.readouterr().err
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


@pytest.mark.parametrize("robot", ["ur5", "panda", "scara", "puma560-actual"])
def test_labels_do_not_overlap(robot):
    """Frames sharing an origin (UR5's last frame and its tool, its wrist) get their labels
    moved along their arrows until they are apart on the picture."""
    from urdf2dh.plot import apart, box, layout

    table = to_table(open_source(robot).model(), "dh", style="ur" if robot == "ur5" else "wu")
    _, placed = layout(table)
    texts = [label.text for label, _, _ in placed]
    assert "x6" in texts or "x4" in texts
    boxes = [(label.text, box(label, xy)) for label, _, xy in placed]
    for i, (a, box_a) in enumerate(boxes):
        for b, box_b in boxes[:i]:
            assert apart(box_a, box_b), (robot, a, b, box_a, box_b)
