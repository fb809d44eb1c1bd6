"""The comment in which urdf2dh's controller and solver files name their chain, so that they
read back as the chain they were written from (:mod:`urdf2dh.io.opwfile`,
:mod:`urdf2dh.io.halfile`, :mod:`urdf2dh.io.ikdhfile`)::

    # urdf2dh chain: {"robot": "...", "base_link": "...", "tip_link": "...", ...}

One line of JSON in ASCII (``json.dumps``: every name whatever it holds, escaped), written in a
comment as :func:`~urdf2dh.escape.visible` shows text, which doubles its backslashes; the reader
halves them again. The formats' own keys beside those three (the joints' names, a length unit)
are the formats' readers' to check.
"""

from __future__ import annotations

import json
import re
from typing import Any

from ..errors import InputError

__all__ = ["PREFIX", "chain_links", "decoded", "encoded", "find_chain"]

PREFIX = "urdf2dh chain: "
_LINE = re.compile(r"^#\s*urdf2dh chain: (.*)$", re.MULTILINE)


def encoded(chain: dict[str, Any]) -> str:
    """The comment's text (without ``#``): :data:`PREFIX` and ``chain`` as one line of JSON."""
    return PREFIX + json.dumps(chain)


def decoded(text: str, where: str) -> Any:
    """A JSON value as a comment shows it (backslashes doubled).

    Raises
    ------
    InputError
        It is not JSON; the message names ``where``.
    """
    try:
        return json.loads(text.replace("\\\\", "\\"))
    except json.JSONDecodeError as e:
        raise InputError(f"{where}: the urdf2dh chain comment is malformed ({e.msg})") from None


def find_chain(text: str, display: str) -> dict[str, Any]:
    """The chain a file's first ``# urdf2dh chain:`` line names (``{}`` where it has none).

    Raises
    ------
    InputError
        The comment is not JSON, or not a mapping.
    """
    match = _LINE.search(text)
    if match is None:
        return {}
    chain = decoded(match.group(1), display)
    if not isinstance(chain, dict):
        raise InputError(f"{display}: the urdf2dh chain comment must hold a mapping")
    return chain


def chain_links(chain: dict[str, Any], display: str) -> tuple[str, str, str]:
    """The chain's robot, base link and tip link (``""`` where it does not name them).

    Raises
    ------
    InputError
        One of them is not a string.
    """
    fields = [chain.get(k, "") for k in ("robot", "base_link", "tip_link")]
    if not all(isinstance(v, str) for v in fields):
        raise InputError(f"{display}: the urdf2dh chain's robot, base_link and tip_link are names")
    robot, base, tip = fields
    return robot, base, tip
