"""``python -m urdf2dh.cli``: the ``urdf2dh`` command."""

from __future__ import annotations

from .run import console

__all__: list[str] = []

console()
