"""Whether the measurements contradict a calibration: a judgement of the identified model against
the data and the noise, before anything is written.

A calibration is *implausible* when the measurements say the model or the file's reading is
wrong (:func:`judge`; the thresholds are :mod:`urdf2dh.tolerances`'s, each several times beyond
what the ten real data sets of ``benchmarks/calibration.py`` show):

* ``gross-position``, ``gross-rotation``: residuals no measuring device leaves (a tenth of the
  robot's size, 0.2 rad): a unit, an order or a sequence read wrong, or another robot;
* ``scale``: measured points that spread several times as far (or as near) as the
  nominal's tool points at the same configurations, where the nominal joints with base and tool
  fitted leave gross residuals (a length unit read wrong: the geometry level would otherwise
  fit a robot a thousand times smaller), or a joint scale ten times the nominal's or a tenth of
  it (joint values in another unit), or negative (a joint counted the other way round);
* ``noise-under-stated``, ``noise-over-stated``: a residual level (RMS per coordinate) ten times
  the noise given (an optimistic noise figure, or a model that misses something), or, over the
  fit's redundancy, a third of it (a noise in another unit: it weighs the nominal's geometry
  over the measurements, and the residuals grow toward it);
  ``noise-balance``: the two levels given weigh positions against rotations five times
  otherwise than the residuals (the model then trusts the wrong kind);
* ``position-rotation``: estimated noise levels of poses whose positions are ten times coarser
  than their rotations at the robot's size, which a device measuring orientations from points
  hardly does: the positions carry the model's error where helical joints explain them (a
  warning where they do not: the device's position noise, maybe);
* ``marker-layout``: markers whose identified places on the tool miss the layout given by a
  tenth of its spread (markers numbered otherwise, a layout in another unit);
* ``outliers-everywhere``: more than a fifth of the measurements are outlier suspects: the noise
  levels are wrong, not the measurements;
* ``worse-than-before``: the calibrated model predicts configurations it was not fitted to worse
  than the nominal joints with base and tool fitted, beyond the scatter of the configurations.

:func:`judged` then has :mod:`.diagnosis` look for the cause (another reading of the file,
helical joints) and refuses the result (:class:`~urdf2dh.errors.Implausible`, naming the cause
and the option that fixes it: :func:`refusal`) unless it is accepted on purpose.
:func:`beyond_limits` names joint values far beyond the joints' limits (a warning: the
judgement decides whether they are degrees).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..errors import Implausible, NotConverged, Remedy, visible
from ..model.poe import PoeModel
from ..tolerances import (
    BEYOND_LIMITS,
    GROSS_POSITION,
    GROSS_ROTATION,
    LAYOUT_MISFIT,
    NOISE_BALANCE,
    NOISE_MISMATCH,
    NOISE_OVER,
    OUTLIER_SHARE,
    POSITION_ROTATION,
    SCALE_FACTOR,
    SPREAD,
    WORSE_CONFIGURATIONS,
    WORSE_RATIO,
    WORSE_THAN_BEFORE,
)
from .chart import Estimate, absorbed
from .diagnosis import HELICAL_GAIN, explained, helical, misread, spread_ratio
from .identify import Identified
from .levels import BASE_TOOL, HIGHER, LOWER, OFFSETS
from .measurements import Measurements
from .residuals import errors
from .residuals import rms as root_mean_square
from .rigid import misfit, spread
from .select import per_configuration, within
from .solver import Solution
from .start import FitOptions, to_data
from .userunits import UserUnits

if TYPE_CHECKING:
    from .problem import CalibrationProblem
    from .result import Calibration, Comparison

__all__ = [
    "ACCEPT",
    "KINDS",
    "Finding",
    "beyond_limits",
    "judge",
    "judged",
    "refusal",
    "unconverged",
]

Mat = NDArray[np.float64]

#: What the judgement and the diagnosis (:mod:`.diagnosis`) can find, and what it means.
KINDS = {
    "not-converged": "the fit did not converge",
    "gross-position": "position residuals no measuring device leaves",
    "gross-rotation": "rotation residuals no measuring device leaves",
    "scale": "measurements or joint values at another scale than the nominal's",
    "noise-under-stated": "residuals far beyond the noise given",
    "noise-over-stated": "residuals far below the noise given",
    "noise-balance": "positions weighed against rotations otherwise than the residuals say",
    "position-rotation": "positions far coarser than the rotations show the noise to be",
    "outliers-everywhere": "most measurements beyond what the noise explains",
    "marker-layout": "markers that do not sit where the layout puts them",
    "worse-than-before": "new configurations predicted worse than by the nominal",
    "length-unit": "lengths in another unit",
    "joint-degrees": "joint values in degrees (or radians) read as the other",
    "joint-column-degrees": "one joint's values in degrees (or radians) among the other unit",
    "angle-degrees": "orientation angles in degrees (or radians) read as the other",
    "quaternion-order": "quaternion components in another order",
    "orientation-inverted": "orientations inverted",
    "euler-sequence": "angles of another rotation sequence",
    "joint-columns": "joint columns swapped",
    "joint-sign": "a joint counted the other way round",
    "position-columns": "position columns swapped",
    "position-sign": "a position axis counted the other way round",
    "helical": "joints that advance along their axis as they turn (helical)",
}

ACCEPT = Remedy("accept", "; nothing written ({} writes it all the same)")


def _less(level: str) -> Remedy:
    """Choose the level below ``level``, or measure more."""
    return Remedy(
        "level",
        "; choose a lower level ({}), or measure more configurations, spread over every joint's "
        "range",
        LOWER.get(level, BASE_TOOL.name),
    )


@dataclass(frozen=True, slots=True)
class Finding:
    """What the measurements say is wrong.

    Attributes
    ----------
    kind
        One of :data:`KINDS`.
    text
        What the data show and the likely cause, one clause with its figures.
    remedy
        The argument that fixes it, or ``None`` (the file itself must change).
    about
        ``position`` or ``rotation`` where it concerns one kind of residual.
    """

    kind: str
    text: str
    remedy: Remedy | None = None
    about: str = ""


def _rms_per_coordinate(rms: float) -> float:
    return rms / math.sqrt(3.0)


def _same(weighted: float | None, stated: float) -> bool:
    """Whether a noise level given weighed the fit as it was given (not raised to a floor)."""
    return weighted is not None and abs(weighted - stated) <= 1e-9 * stated


def _gross(cal: Calibration, size: float) -> list[Finding]:
    fit = cal.comparisons[0].after
    unit = cal.units.length
    out = []
    higher = HIGHER.get(cal.level) if cal.level in (BASE_TOOL.name, OFFSETS.name) else None
    if not fit.rms_position <= GROSS_POSITION * size:  # NaN counts as gross
        out.append(
            Finding(
                "gross-position",
                f"the position residuals are {fit.rms_position:.3g} {unit} RMS, "
                f"{fit.rms_position / size:.3g} times the robot's size ({size:.3g} {unit}): "
                "the file is read in the wrong unit, order or columns, or it measured another "
                "robot"
                + (", or the robot differs from the nominal more than this level corrects"
                   if higher else ""),
                Remedy("level", "; identify more ({})", higher) if higher else None,
            )
        )  # fmt: skip
    if fit.rms_rotation is not None and not fit.rms_rotation <= GROSS_ROTATION:
        out.append(
            Finding(
                "gross-rotation",
                f"the rotation residuals are {fit.rms_rotation:.3g} rad RMS: the orientations "
                "are read wrong (a quaternion in another order, angles of another sequence or "
                "unit)",
            )
        )
    return out


def _scale(
    cal: Calibration,
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    before: Estimate,
    after: Estimate,
) -> list[Finding]:
    """``scale``: the measurements at another scale than the nominal (where the nominal joints
    with base and tool fitted leave gross residuals), or joint scales far from the nominal's."""
    out = []
    size = cal.units.shown(nominal.size())
    first = cal.comparisons[0].before.rms_position
    # the spread is measured only where the residuals are gross (NaN counts as gross)
    ratio = spread_ratio(nominal, fit, opts, ids) if not first <= GROSS_POSITION * size else 1.0
    if not 1.0 / SPREAD <= ratio <= SPREAD:
        out.append(
            Finding(
                "scale",
                f"the measured points spread {ratio:.3g} times as far as the nominal's tool "
                f"points at the same configurations, and the nominal joints with base and tool "
                f"fitted leave {first:.3g} {cal.units.length} RMS: the lengths are in another "
                "unit, or the measurements are of another robot",
            )
        )
    names = before.chain.names
    scales = after.chain.scale / before.chain.scale
    if len(scales):
        k = int(np.argmax(np.abs(np.log(np.abs(scales) + 1e-300)) + (scales < 0.0) * 1e3))
        said = None
        if scales[k] < 0.0:
            said = "it is counted the other way round in the file (negate its column)"
        elif not 1.0 / SCALE_FACTOR <= scales[k] <= SCALE_FACTOR:
            said = "its values are in another unit (degrees read as radians, or the reverse?)"
        if said is not None:
            out.append(
                Finding(
                    "scale",
                    f"joint {visible(names[k])} is identified with a scale of {scales[k]:.4g}: "
                    f"{said}, or the level asks more than the measurements support",
                    _less(cal.level),
                )
            )
    return out


def _noise(cal: Calibration, given: tuple[float | None, float | None]) -> list[Finding]:
    """``noise-under-stated``, ``noise-over-stated`` and ``position-rotation``."""
    fit = cal.comparisons[0].after
    unit, size = cal.units.length, cal.units.shown(cal.nominal.size())
    given_pos, given_rot = given
    out = []
    if cal.noise.given and given_pos is not None:
        ratios: list[tuple[str, float, float, float | None, str]] = [
            ("position", _rms_per_coordinate(fit.rms_position), given_pos, cal.noise.position, unit)
        ]
        if fit.rms_rotation is not None and given_rot is not None:
            ratios.append(
                ("rotation", _rms_per_coordinate(fit.rms_rotation), given_rot,
                 cal.noise.rotation, "rad")
            )  # fmt: skip
        # RMS residuals fall short of the noise by sqrt((m - p) / m): what the fit absorbed
        m, p = cal.counts.equations, cal.counts.parameters
        redundancy = math.sqrt(m / (m - p)) if m > 1.1 * p else math.inf
        for what, level, stated, weighted, u in ratios:
            ratio = level / stated
            if ratio > NOISE_MISMATCH:
                out.append(
                    Finding(
                        "noise-under-stated",
                        f"the {what} residuals are {ratio:.3g} times the noise given ({level:.3g} "
                        f"against {stated:.3g} {u} per coordinate): the noise is under-stated, or "
                        "the model misses something (helical joints? the tool? a marker?)",
                        Remedy(
                            "noise_pos, noise_rot",
                            "; state the noise the residuals show, or leave out {} to have it "
                            "estimated",
                        ),
                        what,
                    )
                )
            elif ratio * redundancy < 1.0 / NOISE_OVER and _same(weighted, stated):
                out.append(
                    Finding(
                        "noise-over-stated",
                        f"the {what} residuals are {ratio:.3g} times the noise given ({level:.3g} "
                        f"against {stated:.3g} {u} per coordinate): the noise is over-stated "
                        f"(given in another unit? {what} noise is in {u}), and so weighed the "
                        "nominal's geometry over the measurements",
                        Remedy(
                            "noise_pos, noise_rot",
                            "; state it in the file's units, or leave out {} to have it estimated",
                        ),
                    )
                )
        if len(ratios) == 2 and not out:
            (_, pos, pos_given, _, _), (_, rot, rot_given, weighted, _) = ratios
            balance = (pos / pos_given) / (rot / rot_given)
            if _same(weighted, rot_given) and not 1 / NOISE_BALANCE <= balance <= NOISE_BALANCE:
                out.append(
                    Finding(
                        "noise-balance",
                        f"the noise given weighs positions against rotations {balance:.3g} times "
                        f"otherwise than the residuals do ({pos:.3g} {unit} and {rot:.3g} rad "
                        f"per coordinate, against {pos_given:.3g} {unit} and {rot_given:.3g} rad "
                        "given): one of the two is stated wrong",
                        Remedy(
                            "noise_pos, noise_rot",
                            "; state the noise the residuals show, or leave out {} to have it "
                            "estimated",
                        ),
                    )
                )
    elif fit.rms_rotation is not None:
        comp = cal.comparisons[0]
        assert comp.after_rotation is not None
        position = float(np.median(comp.after_position))
        rotation = float(np.median(comp.after_rotation))
        ratio = position / (rotation * size) if rotation > 0.0 else math.inf
        if ratio > POSITION_ROTATION:
            out.append(
                Finding(
                    "position-rotation",
                    f"the rotation residuals ({rotation:.3g} rad, the median) are "
                    f"{rotation * size:.3g} {unit} at the robot's size, and the position "
                    f"residuals {ratio:.3g} times more ({position:.3g} {unit}): no device "
                    "measures so; the positions carry the model's error (helical joints? a tool "
                    "point other than the one measured?)",
                )
            )
    return out


def _layout(cal: Calibration, opts: FitOptions) -> list[Finding]:
    """``marker-layout``: the markers' identified positions on the tool against the layout
    given, after the best rigid fit (their relative places the measurements fix)."""
    if opts.layout is None or len(cal.markers_on_tool) < 2:
        return []
    ids = sorted(cal.markers_on_tool)
    given = cal.units.shown_array(np.array([opts.layout[k] for k in ids]))
    found = np.array([cal.markers_on_tool[k] for k in ids])
    layout_misfit = misfit(given, found)
    reach = spread(given)
    if layout_misfit <= LAYOUT_MISFIT * reach:
        return []
    unit = cal.units.length
    return [
        Finding(
            "marker-layout",
            f"the markers' identified positions on the tool miss the layout given by "
            f"{layout_misfit:.3g} {unit} RMS (the layout spreads {reach:.3g} {unit}): markers "
            f"numbered otherwise, or a layout in another unit (it is read in {unit})",
        )
    ]


def _outliers(cal: Calibration) -> list[Finding]:
    share = len(cal.suspects) / max(cal.counts.fit, 1)
    if share <= OUTLIER_SHARE or cal.rejected:
        return []
    given = "given" if cal.noise.given else "estimated"
    level = _rms_per_coordinate(cal.comparisons[0].after.rms_position)
    return [
        Finding(
            "outliers-everywhere",
            f"{len(cal.suspects)} of the {cal.counts.fit} fitted measurements lie beyond what the "
            f"noise {given} explains (a chance below 1e-6 each): they are not outliers; the "
            f"noise is under-stated (the residuals show {level:.3g} {cal.units.length} per "
            "coordinate), or the model misses something",
            Remedy(
                "noise_pos, noise_rot",
                "; state the noise the residuals show, or leave out {} to have it estimated",
            )
            if cal.noise.given
            else None,
        )
    ]


def worse(after: Mat, before: Mat) -> bool:
    """Whether per-configuration squared errors ``after`` are worse than ``before``'s beyond
    their scatter (:data:`~urdf2dh.tolerances.WORSE_THAN_BEFORE` standard errors of the paired
    differences), or their RMS :data:`~urdf2dh.tolerances.WORSE_RATIO` times or more over
    enough configurations (one or two far off leave the paired test weak)."""
    if len(after) < 2:
        return False
    if not within(after, before, WORSE_THAN_BEFORE):
        return True
    ratio = math.sqrt(float(np.mean(after)) / max(float(np.mean(before)), 1e-300))
    return len(after) >= WORSE_CONFIGURATIONS and ratio >= WORSE_RATIO


def _worse(comp: Comparison, what: str, unit: str, level: str) -> Finding | None:
    before = np.square(np.array(comp.before_position))
    after = np.square(np.array(comp.after_position))
    if not worse(after, before):
        return None
    return Finding(
        "worse-than-before",
        f"the {level} model predicts the {what} configurations worse than the nominal joints "
        f"with base and tool fitted ({comp.after.rms_position:.3g} against "
        f"{comp.before.rms_position:.3g} {unit} RMS): it follows the fitted measurements' noise, "
        "or the other configurations are unlike the fitted ones",
        _less(level),
    )


def _worse_than_before(cal: Calibration, index: NDArray[np.int64]) -> list[Finding]:
    unit = cal.units.length
    out = []
    for comp in cal.comparisons[1:]:
        found = _worse(
            comp, "held-out" if comp.name == "held_out" else "validation", unit, cal.level
        )
        if found is not None:
            out.append(found)
    sel = cal.selection
    if (
        sel is not None
        and cal.level != BASE_TOOL.name
        and cal.level in sel.left_out
        and BASE_TOOL.name in sel.left_out
        and sel.configurations >= 2
    ):
        count = int(index.max(initial=-1)) + 1
        mine = per_configuration(sel.left_out[cal.level], index, count) @ sel.weights
        base = per_configuration(sel.left_out[BASE_TOOL.name], index, count) @ sel.weights
        if worse(mine, base):
            score, first = sel.score(cal.level), sel.score(BASE_TOOL.name)
            out.append(
                Finding(
                    "worse-than-before",
                    f"the {cal.level} model predicts each configuration left out of the fit "
                    f"worse than the nominal joints with base and tool fitted "
                    f"({score.rms_position:.3g} against {first.rms_position:.3g} {unit} RMS): "
                    "its parameters follow the measurements' noise",
                    _less(cal.level),
                )
            )
    return out


def judge(
    cal: Calibration,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    before: Estimate,
    after: Estimate,
    given: tuple[float | None, float | None],
) -> tuple[Finding, ...]:
    """What the measurements contradict in ``cal`` (module docstring): ``()`` when nothing.

    ``fit`` are the fitted measurements, ``opts`` and ``ids`` how they were fitted; ``before``
    and ``after`` the base-tool level's and the identified estimates; ``given`` the noise levels
    given (the user's unit and rad; ``None``: estimated)."""
    size = cal.units.shown(cal.nominal.size())
    index = fit.configurations()[0]
    found = _gross(cal, size)
    found += _scale(cal, cal.nominal, fit, opts, ids, before, after)
    found += _noise(cal, given)
    found += _layout(cal, opts)
    found += _outliers(cal)
    found += _worse_than_before(cal, index)
    return tuple(found)


def beyond_limits(nominal: PoeModel, q: Mat) -> tuple[tuple[str, float, float, float], ...]:
    """The revolute and helical joints whose values ``q`` ``(N, n)`` lie beyond their limits by
    more than :data:`~urdf2dh.tolerances.BEYOND_LIMITS` rad: ``(name, worst value, lower,
    upper)`` each."""
    out = []
    for k, j in enumerate(nominal.joints):
        if j.kind == "prismatic" or j.lower is None or j.upper is None or not len(q):
            continue
        values = q[:, k]
        excess = np.maximum(values - j.upper, j.lower - values)
        worst = int(np.argmax(excess))
        if excess[worst] > BEYOND_LIMITS:
            out.append((j.name, float(values[worst]), float(j.lower), float(j.upper)))
    return tuple(out)


# ----------------------------------------------------------------------------- the verdict


def judged(
    cal: Calibration,
    problem: CalibrationProblem,
    opts: FitOptions,
    result: Identified,
    accept: bool,
) -> Calibration:
    """``cal`` judged against the measurements: returned when nothing contradicts it (with the
    joints beyond their limits named among its warnings), or with ``accept`` (the findings
    among them too); else :class:`~urdf2dh.errors.Implausible`, naming the likely cause
    (:func:`refusal`). ``problem`` holds the fitted measurements and the noise levels given,
    ``opts`` (at the level identified) how they were fitted, ``result`` the identification."""
    nominal, fit, ids = problem.nominal, problem.fit, problem.markers
    given = (problem.noise_pos, problem.noise_rot)
    findings = judge(cal, fit, opts, ids, result.before, result.estimate, given)
    notes = [
        f"joint {visible(name)}'s values reach {value:.4g}, beyond its limits [{lower:.4g}, "
        f"{upper:.4g}] rad; the fit explains them as radians"
        for name, value, lower, upper in beyond_limits(nominal, fit.q)
    ]
    joints = None
    if any(f.kind == "position-rotation" or _positions_beyond(f) for f in findings):
        rms = cal.comparisons[0].after.rms_position / cal.units.per_model
        joints = helical(nominal, fit, opts, ids, rms)
        if joints is None:  # the device's own, maybe: said, not refused
            notes += [
                f"{f.text}; with every joint's pitch free they fit no better, so this may be the "
                "device's position noise"
                for f in findings
                if f.kind == "position-rotation"
            ]
            findings = tuple(f for f in findings if f.kind != "position-rotation")
    if findings and not accept:
        raise refusal(cal.measurements, findings, nominal, fit, opts, ids, cal, joints)
    accepted = [f"accepted all the same: {f.text}" for f in findings]
    if not (notes or accepted):
        return cal
    return replace(cal, warnings=(*accepted, *cal.warnings, *notes))


def _positions_beyond(f: Finding) -> bool:
    return f.kind == "noise-under-stated" and f.about == "position"


def refusal(
    source: str,
    findings: tuple[Finding, ...],
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    cal: Calibration | None,
    joints: tuple[str, ...] | None = None,
) -> Implausible:
    """The refusal of a fit the measurements contradict, naming the likely cause and the
    argument that fixes it: another reading of the file that explains the measurements
    (:func:`.diagnosis.misread`, where the residuals are gross), helical joints that explain the
    positions (``joints``, :func:`.diagnosis.helical`), or the first finding's."""
    kinds = tuple(dict.fromkeys(f.kind for f in findings))
    first = findings[0]
    if joints is None:
        reads, _, _ = misread(nominal, fit, opts, ids, None if cal is None else cal.device_model)
        if reads:
            cause, remedies = explained(reads, fit)
            return Implausible(
                f"{source}: {cause} ({first.text})",
                causes=(*(r.kind for r in reads), *kinds),
                result=cal,
                remedy=remedies[0] if remedies else None,
                also=(*remedies[1:], ACCEPT),
            )
    positions = [f for f in findings if f.kind == "position-rotation" or _positions_beyond(f)]
    if positions and joints is not None:
        revolute = sum(j.kind == "revolute" for j in nominal.joints)
        return Implausible(
            f"{source}: {positions[0].text}; with the pitch of joints "
            f"{', '.join(map(visible, joints))} free (helical joints) the positions fit "
            f"{HELICAL_GAIN:g} times better or more",
            causes=("helical", *kinds),
            result=cal,
            remedy=Remedy(
                "helical", "; identify it with {}",
                "all" if len(joints) == revolute else ",".join(joints),
            ),
            also=(ACCEPT,),
        )  # fmt: skip
    more = "" if len(kinds) == 1 else f" (also: {', '.join(KINDS[k] for k in kinds[1:])})"
    return Implausible(
        f"{source}: {first.text}{more}",
        causes=kinds,
        result=cal,
        remedy=first.remedy,
        also=(ACCEPT,),
    )


def unconverged(
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    what: str,
    solution: Solution,
) -> Implausible | NotConverged:
    """A fit that did not converge: the other reading of the file that explains the
    measurements, where there is one (:func:`.diagnosis.misread`), else
    :class:`~urdf2dh.errors.NotConverged` (exit 1)."""
    reads, _, _ = misread(nominal, fit, opts, ids)
    user = UserUnits.of(nominal.length_unit, fit)
    each = errors(absorbed(solution.estimate), to_data(fit, opts.pose, ids))
    rms = user.shown(root_mean_square(each[:, 0]))
    if reads:
        cause, remedies = explained(reads, fit)
        return Implausible(
            f"{fit.source}: {cause} ({what} did not converge: RMS position residual "
            f"{rms:.3g} {user.length})",
            causes=(*(r.kind for r in reads), "not-converged"),
            remedy=remedies[0] if remedies else None,
            also=tuple(remedies[1:]),
        )
    return NotConverged(
        f"{fit.source}: {what} did not converge in {solution.iterations} iterations (RMS "
        f"position residual {rms:.3g} {user.length}); nothing written"
    )
