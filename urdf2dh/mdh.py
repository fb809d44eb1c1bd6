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

import numpy as np
from numpy.typing import NDArray

from .lines import dh_matrix

__all__ = ["BASE_PARAMS", "PARAMS", "TOOL_PARAMS", "base_matrix", "row_matrices", "tool_matrix"]

PARAMS = ("alpha", "a", "theta", "d")
BASE_PARAMS = ("theta", "d")
TOOL_PARAMS = ("alpha", "a", "theta", "d")

Mat = NDArray[np.float64]


def _rx_tx(alpha: float, a: float) -> Mat:
    c, s = math.cos(alpha), math.sin(alpha)
    return np.array([[1.0, 0, 0, a], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def base_matrix(p: dict[str, Any]) -> Mat:
    """``B = Rz(theta) Tz(d)``."""
    return dh_matrix(p["theta"], p["d"], 0.0, 0.0)


def row_matrices(p: dict[str, Any]) -> tuple[Mat | None, Mat]:
    """(before ``Q_i``, after ``Q_i``): ``Rx Tx`` and ``Rz Tz``."""
    return _rx_tx(p["alpha"], p["a"]), dh_matrix(p["theta"], p["d"], 0.0, 0.0)


def tool_matrix(p: dict[str, Any]) -> Mat:
    """``T = Rx(alpha) Tx(a) Rz(theta) Tz(d)``."""
    return _rx_tx(p["alpha"], p["a"]) @ dh_matrix(p["theta"], p["d"], 0.0, 0.0)
