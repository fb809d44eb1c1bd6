"""Reading an HTML view (``urdf2dh plot -o FILE.html``) back as a browser and plotly.js do.

The page is read by Python's ``html.parser``, which, like a browser, takes a ``<script>``'s
text to the first ``</script`` and decodes character references in text and attributes; the
figure is the JSON of the page's one ``Plotly.newPlot(id, data, layout, config)`` call, read
with ``json`` (so it is data: JSON holds no code).
"""

from __future__ import annotations

import base64
import json
from dataclasses import dataclass
from html.parser import HTMLParser
from typing import Any

import numpy as np

CALL = "Plotly.newPlot("


@dataclass(frozen=True)
class Page:
    """A page as read: its start tags with their attributes, its text nodes (outside scripts
    and styles, but for those of white space only), its scripts, and the figure: the plot
    call's arguments and the script's text around them."""

    tags: list[tuple[str, list[tuple[str, str | None]]]]
    texts: list[str]
    scripts: list[str]
    div: str
    data: list[dict[str, Any]]
    layout: dict[str, Any]
    config: dict[str, Any]
    around: tuple[str, str]  # the figure script before the first and after the last argument

    def trace(self, name: str) -> dict[str, Any]:
        """The one scatter trace named ``name``."""
        found = [t for t in self.data if t.get("name") == name and t["type"] == "scatter3d"]
        assert len(found) == 1, f"{len(found)} scatter3d traces named {name!r}"
        return found[0]

    def points(self, name: str) -> np.ndarray:
        """The ``(k, 3)`` points of trace ``name`` (``None`` gaps as NaN rows)."""
        t = self.trace(name)
        return np.array([array(t[c]) for c in "xyz"], dtype=float).T


def array(value: Any) -> np.ndarray:
    """A figure's array as plotly.js reads it: a JSON list, or a typed array written as
    ``{"dtype": ..., "bdata": base64, "shape": ...}`` (plotly.py's encoding of numpy arrays)."""
    if isinstance(value, dict):
        data = np.frombuffer(base64.b64decode(value["bdata"]), dtype=np.dtype(value["dtype"]))
        shape = value.get("shape")
        return data.reshape([int(n) for n in str(shape).split(",")] if shape else -1)
    return np.array([np.nan if v is None else v for v in value], dtype=float)


class _Reader(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.tags: list[tuple[str, list[tuple[str, str | None]]]] = []
        self.texts: list[str] = []
        self.scripts: list[str] = []
        self._in: str | None = None

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.tags.append((tag, attrs))
        if tag in ("script", "style"):
            self._in = tag
            if tag == "script":
                self.scripts.append("")

    def handle_endtag(self, tag: str) -> None:
        if tag == self._in:
            self._in = None

    def handle_data(self, data: str) -> None:
        if self._in == "script":
            self.scripts[-1] += data
        elif self._in is None and data.strip():
            self.texts.append(data)


def _arguments(script: str) -> tuple[str, list[Any], tuple[str, str]]:
    """The plot call's arguments (JSON values) and the script's text before and after them."""
    decoder = json.JSONDecoder()
    start = script.index(CALL) + len(CALL)
    at, values = start, []
    while True:
        while script[at] in " \t\r\n,":
            at += 1
        if script[at] == ")":
            break
        value, at = decoder.raw_decode(script, at)
        values.append(value)
    return values[0], values[1:], (script[:start], script[at:])


def read_page(text: str) -> Page:
    """Read a view page; the one script that calls plotly must exist."""
    reader = _Reader()
    reader.feed(text)
    reader.close()
    plots = [s for s in reader.scripts if CALL in s]
    assert len(plots) == 1, f"{len(plots)} scripts call {CALL}"
    div, (data, layout, config), around = _arguments(plots[0])
    return Page(reader.tags, reader.texts, reader.scripts, div, data, layout, config, around)
