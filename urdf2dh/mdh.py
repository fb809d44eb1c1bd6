"""POE -> modified (Craig) Denavit-Hartenberg.

Forward kinematics of an ``mdh`` table (SPEC §2)::

    T(q) = Rz(theta_B) Tz(d_B) . prod_i [ Rx(alpha_i) Tx(a_i) . Q_i(s_i) . Rz(theta_i) Tz(d_i) ]
           . Rx(alpha_T) Tx(a_T) Rz(theta_T) Tz(d_T)

Row ``i`` holds Craig's ``alpha_{i-1}, a_{i-1}`` (the common normal from the previous axis to
joint ``i``'s) and ``theta_i, d_i`` (along joint ``i``'s axis). These are the same common normals
that the standard convention uses (Wu 2019 §III), grouped around ``Q_i`` the other way: the
standard link ``Rz Tz Rx Tx`` of row ``i`` splits into ``Rz Tz`` (ending Craig's row ``i``) and
``Rx Tx`` (starting Craig's row ``i + 1``). So the modified table is the standard one regrouped,
exact by construction, with the same tolerance choices.
"""

from __future__ import annotations

import math
from typing import Any

from .lines import dh_frame
from .se3 import Frame, compose

__all__ = ["BASE_PARAMS", "PARAMS", "TOOL_PARAMS", "base_frame", "row_frames", "tool_frame"]

PARAMS = ("alpha", "a", "theta", "d")
BASE_PARAMS = ("theta", "d")
TOOL_PARAMS = ("alpha", "a", "theta", "d")


def _rx_tx(alpha: float, a: float) -> Frame:
    c, s = math.cos(alpha), math.sin(alpha)
    return ((1.0, 0.0, 0.0, a), (0.0, c, -s, 0.0), (0.0, s, c, 0.0))


def base_frame(p: dict[str, Any]) -> Frame:
    """``B = Rz(theta) Tz(d)``."""
    return dh_frame(p["theta"], p["d"], 0.0, 0.0)


def row_frames(p: dict[str, Any]) -> tuple[Frame | None, Frame]:
    """(before ``Q_i``, after ``Q_i``): ``Rx Tx`` and ``Rz Tz``."""
    return _rx_tx(p["alpha"], p["a"]), dh_frame(p["theta"], p["d"], 0.0, 0.0)


def tool_frame(p: dict[str, Any]) -> Frame:
    """``T = Rx(alpha) Tx(a) Rz(theta) Tz(d)``."""
    return compose(_rx_tx(p["alpha"], p["a"]), dh_frame(p["theta"], p["d"], 0.0, 0.0))
