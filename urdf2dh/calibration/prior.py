"""An optional prior: the joints' parameters pulled toward the nominal's, with stated deviations.

With ``--prior LENGTH,ANGLE`` each joint parameter adds a residual ``(value - nominal) / sigma``
to the fit, ``sigma`` being LENGTH for lengths (a line's shifts, a sliding joint's offset, a
pitch per radian) and ANGLE for angles (a line's turns, a turning joint's offset) and for
scales (a relative error of the motion): maximum a posteriori for a Gaussian prior centred on
the nominal, what regularised calibration (Tikhonov) does. The base, the tool and the markers
have no prior: they are unknown by nature. "Nominal" is the nominal joints as the base-and-tool
fit placed them in the device frame (the fair "before"): the coordinates of the identified
model's chart that lead from there to it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from .chart import Estimate, all_names, local_coordinates, retract

__all__ = ["Prior", "prior_rows"]

Mat = NDArray[np.float64]

_STEP = 1e-7  # central differences of the line chart's coordinates (smooth: 1e-14 accurate)


@dataclass(frozen=True, slots=True)
class Prior:
    """Standard deviations of the joints' parameters about the nominal.

    Attributes
    ----------
    length
        Of lengths, in the nominal's length unit (> 0).
    angle
        Of angles, in radians, and of scales (> 0).
    """

    length: float
    angle: float

    def __post_init__(self) -> None:
        for what, value in (("length", self.length), ("angle", self.angle)):
            if not (math.isfinite(value) and value > 0.0):
                raise InputError(f"the prior's {what} deviation must be a number > 0, not {value}")


def _sigmas(est: Estimate, prior: Prior) -> Mat:
    """Each free coordinate's deviation (``inf``: no prior on it)."""
    kinds = dict(zip(est.chain.names, est.chain.kinds, strict=True))
    out = []
    for name in all_names(est):
        owner, leaf = name.rsplit(".", 1)
        if owner not in kinds:  # base, tool, markers
            out.append(math.inf)
        elif leaf.startswith("turn") or leaf == "scale":
            out.append(prior.angle)
        elif leaf == "offset":
            out.append(prior.length if kinds[owner] == "prismatic" else prior.angle)
        else:  # shifts and pitches
            out.append(prior.length)
    sig = np.array(out)
    return sig if est.free is None else sig[est.free]


def prior_rows(
    est: Estimate, reference: Estimate, prior: Prior, jacobian: bool = True
) -> tuple[Mat, Mat | None]:
    """The prior's residuals ``(k,)`` and their Jacobian ``(k, p)`` with respect to ``est``'s
    free coordinates (``k``: the coordinates that have a prior).

    The coordinates of ``est`` seen from ``reference`` are the chart's (:func:`.chart.
    local_coordinates`); their derivatives are 1 for offsets, scales and pitches and, for a
    line's turns and shifts, taken by central differences (each line's four depend on that line
    alone).
    """
    sig = _sigmas(est, prior)
    keep = np.isfinite(sig)
    here = local_coordinates(reference, est)
    r = (here / sig)[keep]
    if not jacobian:
        return r, None
    p = len(sig)
    jac = np.zeros((p, p))
    names = [n for n, f in zip(all_names(est), _free(est), strict=True) if f]
    for k, name in enumerate(names):
        if not keep[k]:
            continue
        leaf = name.rsplit(".", 1)[1]
        if leaf.startswith(("turn", "shift")):
            step = np.zeros(p)
            step[k] = _STEP
            plus = local_coordinates(reference, retract(est, step))
            minus = local_coordinates(reference, retract(est, -step))
            jac[:, k] = (plus - minus) / (2.0 * _STEP)
        else:
            jac[k, k] = 1.0
    return r, (jac / sig[:, None])[keep]


def _free(est: Estimate) -> NDArray[np.bool_]:
    return np.ones(len(all_names(est)), dtype=bool) if est.free is None else est.free
