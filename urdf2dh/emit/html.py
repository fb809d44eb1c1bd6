"""One plotly figure as a self-contained HTML page that fetches nothing when opened.

plotly.js is written into the page (``plotly.io.to_html`` with ``include_plotlyjs=True``, no
MathJax), and the page's Content-Security-Policy lets it load nothing from anywhere: no script,
style, image, font or connection from outside the file, so even a plotly feature that would
reach for the network (a map's tiles, MathJax) cannot. The page's only data is the figure
(JSON, as plotly writes it); the caller writes every text from a file into the figure with
:func:`urdf2dh.escape.html_text`, since plotly reads its text as HTML. The output is
the same bytes for the same figure (a fixed element id). plotly is an optional dependency
(``pip install 'urdf2dh[plot]'``).
"""

from __future__ import annotations

from typing import Any

from ..errors import missing
from ..escape import html_text

__all__ = ["CSP", "DIV_ID", "offline_page", "plotly_objects"]

DIV_ID = "urdf2dh-figure"
CSP = (
    "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; "
    "img-src data: blob:; font-src data:; connect-src 'none'; form-action 'none'; "
    "base-uri 'none'"
)
CONFIG = {"displaylogo": False, "responsive": True, "scrollZoom": True}

PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="{csp}">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="urdf2dh">
<title>{title}</title>
<style>html, body {{height: 100%; margin: 0; font-family: sans-serif;}}</style>
</head>
<body>
{figure}
</body>
</html>
"""


def plotly_objects(what: str) -> Any:
    """``plotly.graph_objects``, or an :class:`InputError` saying how to install plotly
    (``what``: the feature that needs it)."""
    try:
        import plotly.graph_objects as go
    except ImportError as e:
        raise missing(what, "plotly", "plot") from e
    return go


def offline_page(figure: Any, title: str) -> str:
    """``figure`` (a plotly figure) as a whole HTML page titled ``title`` (any text: it is
    escaped) that draws it in any browser without the network."""
    div = figure.to_html(
        full_html=False,
        include_plotlyjs=True,
        include_mathjax=False,
        div_id=DIV_ID,
        config=CONFIG,
        default_height="100%",
        default_width="100%",
    )
    return PAGE.format(csp=CSP, title=html_text(title), figure=div)
