"""mkdocs hook: the documentation's formulas as MathML, written into the pages at build time.

``pymdownx.arithmatex`` (generic mode) keeps each formula of the Markdown (``$$ ... $$``,
``$ ... $``) as its TeX inside ``<div class="arithmatex">\\[ ... \\]</div>`` or
``<span class="arithmatex">\\( ... \\)</span>``; this hook replaces each by the MathML that
``latex2mathml`` makes of it, which browsers draw themselves. The site thus shows its formulas
offline and loads no script from anywhere. A formula that does not convert fails the build,
naming the page.
"""

from __future__ import annotations

import html
import re
from typing import Any

from latex2mathml.converter import convert

FORMULA = re.compile(
    r'<(?P<tag>div|span) class="arithmatex">\s*\\(?P<open>[\[(])(?P<tex>.*?)\\[\])]\s*</(?P=tag)>',
    re.S,
)


def _mathml(match: re.Match[str], page: str) -> str:
    tex = html.unescape(match["tex"]).strip()
    display = "block" if match["open"] == "[" else "inline"
    try:
        return convert(tex, display=display)
    except Exception as e:  # any failure of the converter stops the build
        raise ValueError(f"{page}: the formula {tex!r} does not convert to MathML: {e}") from e


def on_page_content(html_text: str, page: Any, **_: Any) -> str:
    """Each arithmatex formula of the page as MathML."""
    return FORMULA.sub(lambda m: _mathml(m, page.file.src_path), html_text)
