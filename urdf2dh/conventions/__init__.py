"""The parameter conventions, one module each, and the registry everything else reads.

==========  =====================================================  =========================
name        forward kinematics                                     module
==========  =====================================================  =========================
``dh``      ``B . prod [Q_i Rz Tz Rx Tx] . Rz Tz``                  :mod:`.dh` (Wu 2019)
``mdh``     ``Rz Tz . prod [Rx Tx Q_i Rz Tz] . Rx Tx Rz Tz``        :mod:`.mdh` (Craig)
``cpc``     ``V_0 . prod [Q_i V(b, l, beta)]``                     :mod:`.cpc` (Sumenkov)
``hayati``  ``B . prod [Q_i H_i] . Rz Tz``, ``H`` D-H or Hayati's  :mod:`.hayati`
==========  =====================================================  =========================

A convention is an object satisfying :class:`~.base.Convention`; adding one is its module
and a line in :data:`REGISTRY`. The command line lists :data:`NAMES` without importing numpy.
"""

from __future__ import annotations

from ..errors import UsageError, choices, near
from .base import Column, Convention, Conversion, Params, columns
from .cpc import CPC
from .dh import DH
from .hayati import HAYATI
from .mdh import MDH

__all__ = [
    "NAMES",
    "REGISTRY",
    "STYLES",
    "Column",
    "Convention",
    "Conversion",
    "Params",
    "columns",
    "get",
]

REGISTRY: dict[str, Convention] = {c.name: c for c in (DH, MDH, CPC, HAYATI)}

NAMES: tuple[str, ...] = tuple(REGISTRY)
STYLES: tuple[str, ...] = tuple(dict.fromkeys(s for c in REGISTRY.values() for s in c.styles))


def get(name: str) -> Convention:
    """The convention called ``name``; a :class:`~urdf2dh.errors.UsageError` listing the valid
    names otherwise (a ``TypeError`` for a name that is not a string)."""
    if not isinstance(name, str):
        raise TypeError(f"a convention is named by a string such as 'dh', not {name!r}")
    try:
        return REGISTRY[name]
    except KeyError:
        raise UsageError(
            f"unknown convention '{name}'{near(name, NAMES)}; valid: {choices(NAMES)}"
        ) from None
