"""Outliers: measurements the fit cannot explain, found with a stated threshold.

A measurement (one pose, or one marker's position) is *suspect* when its weighted residual at
the chosen level's fit, standardised by its leverage (``sum r^2 / (1 - h / rows)``, ``r`` the
residuals over the noise levels and ``h`` their leverage), would be exceeded with a chance below
:data:`~urdf2dh.tolerances.OUTLIER_CHANCE` by a chi-square variable of as many degrees of
freedom as it has residuals (3 or 6): a Gaussian measurement error that large almost never
happens.

A large residual is not always a wrong measurement: at a configuration unlike the others it may
be the model's error there, and the measurement the only one that shows it (on the Franka data
set, rejecting its two suspects makes the held-out error 13% worse: a held-out configuration
next to one of them is measured just as far off); or it is a wrong measurement that drags every
parameter (on a TALOS data set, a first row 79 mm off makes every level's held-out error 6 to 7
mm instead of 0.8). So suspects are listed, with their residuals and chances, and by default
rejected when that helps predict the others (:func:`rejecting_helps`): the levels are judged
again without them, and the other configurations, each left out in turn, are predicted by the
choice made without the suspects and by the one made with them; the suspects are rejected when
the former's error is smaller by more than :data:`~urdf2dh.tolerances.OUTLIER_GAIN` standard
errors of the paired per-configuration differences (a three-sigma test: measurements are not
thrown away on weak evidence). The levels without them are predicted to first order first
(:func:`.select.predicted_without`: each level's fit moved by one Gauss-Newton step, its noise
levels and prior kept); they are fitted again only when that predicts a gain, and the suspects
are rejected only when the refit confirms it. Asked, they are always rejected or kept.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..tolerances import OUTLIER_CHANCE, OUTLIER_GAIN, OUTLIER_SHARE
from .chart import count
from .fit import Fit, with_statistics
from .measurements import Measurements
from .select import Pass, Selection, judge_levels, per_configuration, predicted_without, within
from .start import to_data

if TYPE_CHECKING:
    from .problem import Options
    from .userunits import UserUnits

__all__ = ["Outliers", "Suspect", "rejecting_helps", "settle", "suspects"]

Mat = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Suspect:
    """A measurement the fit cannot explain.

    Attributes
    ----------
    row
        Its row among the fitted measurements (from 0).
    configuration
        Its configuration (:meth:`.measurements.Measurements.configurations`).
    position, rotation
        Its residual: distance (length unit) and angle (rad; ``None`` for positions).
    chance
        The chance of a residual this large from the noise alone.
    """

    row: int
    configuration: int
    position: float
    rotation: float | None
    chance: float


def suspects(fit: Measurements, result: Fit, pose: bool, ids: list[int]) -> list[Suspect]:
    """The measurements of ``fit`` whose residuals at ``result`` (a fit to ``fit``: the residuals
    its linearisation holds) are beyond the threshold."""
    from scipy.special import chdtrc  # the chi-square distribution's survival function

    data = to_data(fit, pose, ids)
    sigmas = np.array([result.sigma_pos] * 3 + [result.sigma_rot] * 3)[: data.rows]
    # the weighted residuals at the solution: its linearisation's, over the noise levels
    rows = result.solution.lin.residuals.reshape(len(data), data.rows) / sigmas
    m = len(data) * data.rows
    leverage = result.statistics.leverage[:m].reshape(len(data), data.rows).sum(axis=1)
    standardised = np.sum(rows**2, axis=1) / np.maximum(1.0 - leverage / data.rows, 1e-3)
    chance = chdtrc(data.rows, standardised)
    beyond = np.flatnonzero(chance < OUTLIER_CHANCE)
    if not len(beyond):
        return []
    index, _ = fit.configurations()
    out = []
    for k in beyond:
        position = float(np.linalg.norm(rows[k, :3])) * result.sigma_pos
        rotation = float(np.linalg.norm(rows[k, 3:])) * result.sigma_rot if pose else None
        out.append(Suspect(int(k), int(index[k]), position, rotation, float(chance[k])))
    return out


def rejecting_helps(
    kept: NDArray[np.int64],
    index: NDArray[np.int64],
    with_them: tuple[Selection, str],
    without: tuple[Selection, str],
) -> tuple[bool, float, float]:
    """Whether the level identified without the suspects predicts the other configurations
    better than the one identified with them (module docstring), and the left-out RMS position
    error of each over them: with the suspects, then without. ``kept`` are the rows kept (of
    the fit with the suspects), ``index`` their configurations in the fit without them; each
    selection comes with the level it led to."""
    (first_sel, first_level), (second_sel, second_level) = with_them, without
    if first_level not in first_sel.left_out or second_level not in second_sel.left_out:
        return False, float("nan"), float("nan")
    count = int(index.max(initial=-1)) + 1
    first = per_configuration(first_sel.left_out[first_level][kept], index, count)
    second = per_configuration(second_sel.left_out[second_level], index, count)
    weights = second_sel.weights
    helps = not within(first @ weights, second @ weights, OUTLIER_GAIN)
    return helps, float(np.sqrt(np.mean(first[:, 0]))), float(np.sqrt(np.mean(second[:, 0])))


@dataclass(frozen=True, slots=True)
class Outliers:
    """What became of the outlier suspects.

    Attributes
    ----------
    suspects
        The suspects, their rows numbered in the whole file (from 0).
    rejected
        Whether they were rejected.
    note
        Why they were rejected or kept, in a clause.
    """

    suspects: tuple[Suspect, ...] = ()
    rejected: bool = False
    note: str = ""


def _rejectable(found: list[Suspect], fit: Measurements, level_fit: Fit, pose: bool) -> bool:
    """Whether the suspects may be rejected: not more than
    :data:`~urdf2dh.tolerances.OUTLIER_SHARE` of the measurements (then the noise or the model
    is wrong, not they), and leaving as many equations as the level has parameters."""
    if len(found) > OUTLIER_SHARE * len(fit):
        return False
    rows = 6 if pose else 3
    left = (len(fit) - len(found)) * rows
    return left >= count(level_fit.solution.estimate) and len(fit) - len(found) >= 2


def settle(first: Pass, level: str, options: Options) -> tuple[Pass, Outliers]:
    """The suspects of ``first``'s ``level`` (module docstring), and the pass the calibration
    goes on with: ``first``, or the levels judged again without the suspects when they are
    rejected. The level's fit in ``first`` gets its statistics."""
    problem, opts = first.problem, first.options
    fit, ids, rows = problem.fit, problem.markers, problem.fit_rows
    first.fits[level] = with_statistics(first.fits[level], to_data(fit, opts.pose, ids))
    among = suspects(fit, first.fits[level], opts.pose, ids)  # rows among those fitted
    found = [replace(s, row=int(rows[s.row])) for s in among]
    reject = options.reject
    units = problem.units
    if not found:
        return first, Outliers()
    if reject is False:
        return first, Outliers(
            tuple(found),
            False,
            "kept as asked; a wrong measurement, or the model's error at an unusual configuration",
        )
    if not _rejectable(found, fit, first.fits[level], opts.pose):
        return first, Outliers(
            tuple(found),
            False,
            f"kept: {len(found)} of {len(fit)} are too many to be outliers (the noise or the "
            "model is wrong)"
            if len(found) > OUTLIER_SHARE * len(fit)
            else "kept: without them too few measurements would be left to identify the level",
        )
    kept = np.delete(np.arange(len(rows)), [s.row for s in among])
    rest = problem.refitted(rows[kept])
    index = rest.fit.configurations()[0]
    predicted = None if reject else predicted_without(first, kept, rest.fit, options.choice)
    if predicted is not None and predicted.chosen in predicted.left_out:
        # predicted first: the levels are fitted again only for a gain
        helps, with_rms, without_rms = rejecting_helps(
            kept, index, (first.selection, level), (predicted, predicted.chosen)
        )
        if not helps:
            return first, _kept(found, _figures(with_rms, without_rms, units), "to first order")
    second = judge_levels(rest, options, first=False)
    helps, with_rms, without_rms = rejecting_helps(
        kept, index, (first.selection, level), (second.selection, second.level or "")
    )
    figures = _figures(with_rms, without_rms, units)
    if reject is None and not helps:
        return first, _kept(found, figures, "fitted again")
    if not second.usable:
        return first, Outliers(tuple(found), False, "")
    why = (
        "as asked"
        if reject
        else f"without them the other configurations are predicted better ({figures})"
    )
    return second, Outliers(tuple(found), True, why)


def _figures(with_rms: float, without_rms: float, units: UserUnits) -> str:
    return (
        f"left-out RMS position {units.shown(without_rms):.3g} against "
        f"{units.shown(with_rms):.3g} {units.length}"
    )


def _kept(found: list[Suspect], figures: str, how: str) -> Outliers:
    """The suspects kept: without them (the levels ``how``) the other configurations are
    predicted no better."""
    return Outliers(
        tuple(found),
        False,
        f"kept: the other configurations are predicted no better without them ({figures}, "
        f"the levels {how}); a wrong measurement, or the model's error at an unusual "
        "configuration",
    )
