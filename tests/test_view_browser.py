"""The interactive view in a real browser: Debian's headless Chromium opens
``urdf2dh plot panda -o panda.html`` from disk (driven through the DevTools protocol,
tests/cdp.py) and

* draws it: plotly's DOM is built (its plot container, the WebGL canvas of the 3-D scene) and a
  screenshot of the plot area holds the red x and blue z arrows;
* reads the figure as written: plotly.js's own data in the page puts every frame at its pose
  and each label where the table's forward kinematics says (tests/frames_oracle.py);
* fetches nothing: the tab's recorded requests are the file itself and nothing else (a control
  page with one remote image shows that a fetch is recorded), and the network is blocked
  anyway: every request Chromium makes goes to a proxy on the loopback that refuses it.

Runs where Chromium is installed (``apt-get install chromium``); scripts/check-consumers
installs it and sets ``URDF2DH_BROWSER_TEST=required``, which turns a missing browser into a
failure instead of a skip.
"""

from __future__ import annotations

import io
import os
import shutil
import socketserver
import threading

import numpy as np
import pytest
from cdp import Browser
from frames_oracle import anchor, fk_frames, named, span

from urdf2dh import load, to_table
from urdf2dh.cli import main
from urdf2dh.emit.picture import COLOURS

FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--enable-unsafe-swiftshader",  # WebGL in software: the 3-D scene draws without a GPU
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--hide-scrollbars",
]
TRACES = """Array.from(document.getElementById("urdf2dh-figure")._fullData)
  .filter(t => t.name === "labels" || t.name === "frames")
  .map(t => ({name: t.name, text: Array.from(t.text), x: Array.from(t.x), y: Array.from(t.y),
              z: Array.from(t.z)}))"""
DRAWN = """(() => {
  const gd = document.getElementById("urdf2dh-figure");
  return Boolean(gd && gd._fullLayout && gd._fullLayout.scene && gd._fullLayout.scene._scene
                 && document.querySelector(".gl-container canvas"));
})()"""
FRAMES = "new Promise(done => requestAnimationFrame(() => requestAnimationFrame(done)))"


def _browser() -> str:
    found = next(
        (shutil.which(n) for n in ("chromium", "chromium-browser") if shutil.which(n)), None
    )
    if found:
        return found
    reason = "Debian's Chromium is not installed (apt-get install chromium)"
    if os.environ.get("URDF2DH_BROWSER_TEST") == "required":
        pytest.fail(reason + ", and URDF2DH_BROWSER_TEST=required")
    pytest.skip(reason + "; scripts/check-consumers installs it and runs this test")


class _Recorder(socketserver.ThreadingTCPServer):
    """A proxy on the loopback that answers every request 403 and remembers its first line."""

    daemon_threads = True
    allow_reuse_address = True

    def __init__(self) -> None:
        self.requests: list[str] = []
        super().__init__(("127.0.0.1", 0), _Handler)


class _Handler(socketserver.StreamRequestHandler):
    def handle(self) -> None:
        line = self.rfile.readline(4096).decode("latin-1").strip()
        self.server.requests.append(line)  # type: ignore[attr-defined]
        self.wfile.write(
            b"HTTP/1.1 403 Forbidden\r\nContent-Length: 0\r\nConnection: close\r\n\r\n"
        )


@pytest.fixture
def recorder():
    server = _Recorder()
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield server
    server.shutdown()
    server.server_close()


@pytest.fixture
def browser(tmp_path, recorder):
    port = recorder.server_address[1]
    proxy = [f"--proxy-server=http://127.0.0.1:{port}", "--proxy-bypass-list=<-loopback>"]
    b = Browser(_browser(), FLAGS + proxy, tmp_path / "profile")
    yield b
    b.close()


def _rgb(hex_colour: str) -> np.ndarray:
    return np.array([int(hex_colour[i : i + 2], 16) for i in (1, 3, 5)]) / 255.0


def test_chromium_draws_the_view_offline(tmp_path, browser):
    from matplotlib.image import imread

    page = tmp_path / "panda.html"
    assert main(["plot", "panda", "--convention", "mdh", "-o", str(page)]) == 0
    table = to_table(load("panda"), "mdh")
    tab = browser.open(page.as_uri())
    browser.wait(tab, DRAWN)
    browser.evaluate(tab, FRAMES)

    image = imread(io.BytesIO(browser.screenshot(tab)), format="png")[:, :, :3]
    assert image.shape[:2] == (900, 1200)
    plot = image[80:, :950].reshape(-1, 3)  # below the title, left of the legend
    assert (np.abs(plot - 1.0).max(axis=1) > 0.1).sum() > 20_000  # a scene, not a blank page
    for axis in ("x", "z"):
        near = np.abs(plot - _rgb(COLOURS[axis])).max(axis=1) < 0.12
        assert near.sum() > 300, f"no {axis} arrows drawn ({near.sum()} pixels)"
    for selector in (".plot-container", ".main-svg", ".gl-container canvas", ".modebar"):
        assert browser.evaluate(tab, f"document.querySelector({selector!r}) !== null"), selector

    traces = {t["name"]: t for t in browser.evaluate(tab, TRACES)}
    frames = fk_frames(table)
    size = span(frames)
    shown = traces["frames"]
    assert shown["text"] == list(frames)
    origins = np.array([shown["x"], shown["y"], shown["z"]]).T
    np.testing.assert_allclose(origins, [f[:3, 3] for f in frames.values()], atol=1e-12 * size)
    labels = traces["labels"]
    seen = set()
    for text, *at in zip(labels["text"], labels["x"], labels["y"], labels["z"], strict=True):
        for what, which in named(text):
            seen.add(what + which)
            start, direction, distance = anchor(table, frames, what, which)
            want = start + distance * direction
            np.testing.assert_allclose(at, want, atol=1e-12 * size, err_msg=text)
    assert {f"{a}{k}" for a in "xz" for k in frames} <= seen

    assert browser.requests(tab) == [page.as_uri()]


def test_a_fetch_would_be_seen(tmp_path, browser, recorder):
    """The control: a page that fetches something is recorded doing it, and the network is
    not reached (the proxy refuses it)."""
    page = tmp_path / "fetches.html"
    page.write_text('<!DOCTYPE html><img src="http://urdf2dh.invalid/probe.png">')
    tab = browser.open(page.as_uri())
    browser.wait(tab, "document.images[0].complete")
    assert browser.requests(tab) == [page.as_uri(), "http://urdf2dh.invalid/probe.png"]
    assert any("urdf2dh.invalid/probe.png" in r for r in recorder.requests), recorder.requests
