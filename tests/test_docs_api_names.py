"""The code examples of docs/python-api.md and docs/names.md run as written (each asserts what
the page says)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
PAGES = ["python-api.md", "names.md"]


def _blocks(page: str) -> list[str]:
    return re.findall(r"```python\n(.*?)```", (DOCS / page).read_text(encoding="utf-8"), re.S)


@pytest.mark.parametrize("page", PAGES)
def test_the_examples_run(page):
    blocks = _blocks(page)
    assert blocks, f"{page} has no Python example"
    for block in blocks:
        exec(compile(block, f"{page} example", "exec"), {"__name__": "docs_example"})
