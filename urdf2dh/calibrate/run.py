"""One calibration from start to finish: checks, held-out split, identification, the output
model in any convention or as a POE file, the report and its text summary.

The output model goes through the same writers as ``convert`` (:func:`urdf2dh.convert.to_table`,
self-check included, then :func:`urdf2dh.formats.render`), or, for ``poe``, through
:func:`urdf2dh.poefile.poe_to_dict`; either file is a valid SOURCE for ``export``, ``convert``
and ``diff``. Nothing is returned (so nothing is written) unless the fit converged and every
table passed its self-check.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError, Urdf2DhError, UsageError
from ..screws import PoeModel
from ..tolerances import DIFF_ANGLE_DEG, Tolerances
from .identify import Identified, identify
from .measurements import Measurements
from .report import holdout_split, report_tree, residuals_of, summary
from .start import Options, placement, start_estimate

__all__ = ["NotConverged", "Outcome", "Request", "run"]

Mat = NDArray[np.float64]

POE_FORMATS = ("yaml", "poe", "text", "json")


class NotConverged(Urdf2DhError):
    """The identification did not converge (exit 1; nothing is written)."""

    exit_code = 1


@dataclass(frozen=True)
class Request:
    """Everything ``urdf2dh calibrate`` was asked (see its options)."""

    nominal: PoeModel
    measurements: Measurements
    pose: bool
    convention: str = "dh"
    fmt: str = "text"
    style: str = "wu"
    tol: Tolerances | None = None
    check_samples: int | None = None
    holdout: float = 0.0
    seed: int = 0
    noise_pos: float | None = None
    noise_rot: float | None = None
    helical: tuple[str, ...] = ()
    keep_scale: bool = False
    keep_tool_axis: bool = False
    frame: str = "device"
    layout: dict[int, Mat] | None = None
    max_iterations: int = 100


@dataclass(frozen=True)
class Outcome:
    """The model's text, the report's JSON text and the summary; the result behind them."""

    text: str
    report: str
    summary: str
    result: Identified
    tree: dict[str, Any]


def _check_markers(req: Request) -> None:
    m = req.measurements
    ids = m.marker_ids()
    if req.pose or req.layout is None:
        if not req.pose and len(ids) > 1:
            raise InputError(
                f"{m.source}: {len(ids)} markers; give their positions on the tool "
                "(--marker-layout FILE, marker,x,y,z) to define the tool frame"
            )
        return
    missing = [k for k in ids if k not in req.layout]
    if missing:
        raise InputError(
            f"{m.source}: marker {missing[0]} is not in the marker layout "
            f"(markers there: {sorted(req.layout)})"
        )


def _render(model: PoeModel, req: Request, tol: Tolerances) -> tuple[str, Any]:
    """The output text, and the table (``None`` for ``poe``)."""
    from ..convert import to_table
    from ..formats import render

    if req.convention == "poe":
        from ..poefile import poe_to_dict

        tree = poe_to_dict(model)
        if req.fmt == "json":
            return json.dumps(tree, indent=2) + "\n", None
        import yaml

        return yaml.safe_dump(tree, sort_keys=False, default_flow_style=None), None
    table = to_table(model, req.convention, tol, samples=req.check_samples, style=req.style)
    return render(table, req.fmt), table


def _diff(req: Request, model: PoeModel, table: Any, tol: Tolerances) -> dict[str, Any]:
    """The ``diff`` of the nominal and the identified model as a tree (``urdf2dh diff``'s)."""
    from ..convert import to_table
    from ..diff import compare, default_length_threshold, ill_conditioned, render_diff

    convention = req.convention if table is not None else "dh"
    style = req.style if table is not None else "wu"
    ours = table if table is not None else to_table(model, convention, tol, style=style)
    theirs = to_table(req.nominal, convention, tol, style=style)
    try:
        length = default_length_threshold(model.length_unit)
    except UsageError:
        length = math.inf  # unknown unit: nothing is marked
    angle = math.radians(DIFF_ANGLE_DEG)  # as `urdf2dh diff` marks by default
    info = {
        "convention": convention,
        "nominal": req.nominal.name,
        "actual": model.name,
        "units": {"length": model.length_unit, "angle": "rad"},
        "thresholds": {"angle": angle, "length": length},
        "warnings": [w for t in (theirs, ours) for w in t.warnings],
    }
    changes = compare(theirs, ours, angle, length)
    pairs = ill_conditioned(req.nominal, model, math.radians(5.0))
    tree: dict[str, Any] = json.loads(render_diff(info, changes, pairs, "json"))
    return tree


def run(req: Request) -> Outcome:
    """Calibrate as ``req`` asks (module docstring).

    Raises
    ------
    InputError
        Inconsistent measurements, or fewer equations than parameters (exit 2).
    NotConverged
        The fit did not converge (exit 1).
    ConversionError
        A table failed its self-check (exit 1).
    """
    from ..tolerances import DEFAULT

    tol = req.tol or DEFAULT
    if req.convention == "poe" and req.fmt not in POE_FORMATS:
        raise UsageError(
            f"--convention poe writes a POE model file: --format yaml or json, not {req.fmt}"
        )
    _check_markers(req)
    m = req.measurements
    ids = m.marker_ids()
    fit_rows, held_rows = holdout_split(len(m), req.holdout, req.seed)
    fit, held = m.subset(fit_rows), m.subset(held_rows)
    opts = Options(
        pose=req.pose,
        helical=req.helical,
        keep_scale=req.keep_scale,
        keep_tool_axis=req.keep_tool_axis,
        frame=req.frame,
        noise_pos=req.noise_pos,
        noise_rot=req.noise_rot,
        layout=req.layout,
        max_iterations=req.max_iterations,
        tol=tol,
    )
    result = identify(req.nominal, fit, opts, ids)
    after = {
        "fit": residuals_of(result.estimate, fit, req.pose, ids),
        "held_out": residuals_of(result.estimate, held, req.pose, ids),
    }
    if not result.solution.converged:
        fitted = after["fit"]
        assert fitted is not None
        reached = f"RMS position residual {fitted.rms_position:.3g} {req.nominal.length_unit}"
        if fitted.rms_rotation is not None:
            reached += f", RMS rotation residual {fitted.rms_rotation:.3g} rad"
        raise NotConverged(
            f"{m.source}: the identification did not converge in "
            f"{result.solution.iterations} iterations ({reached}); nothing written"
        )
    start = start_estimate(req.nominal, placement(req.nominal, fit, opts, ids), opts, ids)
    before = {
        "fit": residuals_of(start, fit, req.pose, ids),
        "held_out": residuals_of(start, held, req.pose, ids),
    }
    text, table = _render(result.model, req, tol)
    from ..poefile import poe_to_dict

    warnings = [*result.notes, *(table.warnings if table is not None else ())]
    if result.stats.rank < len(result.names):
        lost = [
            n for n, s in zip(result.names, result.stats.std, strict=True) if not math.isfinite(s)
        ]
        warnings.append(
            f"the measurements determine {result.stats.rank} of the "
            f"{len(result.names)} parameters; not identified: {', '.join(lost)} "
            "(kept as in the nominal's start; measure more varied configurations)"
        )
    tree = report_tree(
        result,
        fit,
        held,
        req.pose,
        before,
        after,
        poe_to_dict(result.model),
        _diff(req, result.model, table, tol),
        warnings,
        req.frame,
    )
    return Outcome(text, json.dumps(tree, indent=2) + "\n", summary(tree), result, tree)
