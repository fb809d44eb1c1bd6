"""A calibration presented: the text ``calibrate`` prints (:func:`summary`), its notebook view
(:func:`markdown`) and its JSON report (:func:`to_dict`, ``--report``,
docs/formats/calibration-report.md). Each reads a :class:`~.result.Calibration` and nothing
else; what it holds is made by :mod:`.figures` and judged by :mod:`.plausible`.
"""

from __future__ import annotations

import math
from dataclasses import asdict
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import visible
from ..escape import markdown_table, markdown_text
from .prior import Deviations

if TYPE_CHECKING:
    from .result import Calibration, Residuals

__all__ = ["markdown", "summary", "to_dict"]


def _floats(a: Any) -> Any:
    return [[float(x) for x in row] for row in np.asarray(a)]


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def to_dict(cal: Calibration) -> dict[str, Any]:
    """The ``--report`` JSON tree (docs/formats/calibration-report.md)."""
    from ..io.poefile import poe_to_dict

    sel = cal.selection
    return {
        "schema": cal.schema,
        "nominal": cal.nominal.name,
        "measurements": cal.measurements,
        "measure": cal.measure,
        "frame": cal.frame,
        "units": {"length": cal.units.length, "angle": "rad"},
        "level": cal.level,
        "chosen_by": cal.chosen_by,
        "selection": None
        if sel is None
        else {
            "method": "leave-one-configuration-out" if sel.seed is None else "folds",
            "folds": sel.folds,
            "seed": sel.seed,
            "configurations": sel.configurations,
            "best": sel.best,
            "chosen": sel.chosen,
            "reason": sel.reason,
            "levels": [
                {
                    "level": s.level,
                    "parameters": s.parameters,
                    "fit_rms_position": _finite(s.fit_rms_position),
                    "rms_position": _finite(s.rms_position),
                    "uncertainty": _finite(s.uncertainty),
                    "rms_rotation": None if s.rms_rotation is None else _finite(s.rms_rotation),
                    "iterations": s.iterations,
                    "prior": None
                    if s.prior is None
                    else {
                        "links": list(s.prior.links),
                        "offsets": s.prior.offsets,
                        "scales": s.prior.scales,
                        "length_per_angle": s.prior.length_per_angle,
                    },
                    "failure": s.failure,
                }
                for s in sel.scores
            ],
        },
        "counts": {**asdict(cal.counts), "formula": cal.formula, "in_words": cal.in_words},
        "condition_number": _finite(cal.condition_number),
        "convergence": {"iterations": cal.iterations, "converged": cal.converged},
        "noise": {
            "position": cal.noise.position,
            "rotation": cal.noise.rotation,
            "given": cal.noise.given,
            "variance_factor": _finite(cal.noise.variance_factor),
            "floor": {"position": cal.noise.floor_position, "rotation": cal.noise.floor_rotation},
        },
        "residuals": {
            when: {c.name: asdict(getattr(c, when)) for c in cal.comparisons}
            for when in ("before", "after")
        },
        "configurations": {
            c.name: {
                "configuration": list(c.configurations),
                "before_position": list(c.before_position),
                "after_position": list(c.after_position),
                "before_rotation": None if c.before_rotation is None else list(c.before_rotation),
                "after_rotation": None if c.after_rotation is None else list(c.after_rotation),
            }
            for c in cal.comparisons
        },
        "parameters": [asdict(p) for p in cal.parameters],
        "held": [asdict(h) for h in cal.held],
        "barely_moved": [{"joint": n, "span": s} for n, s in cal.barely_moved],
        "outliers": {
            "rejected": cal.rejected,
            "suspects": [asdict(s) | {"row": s.row + 1} for s in cal.suspects],
        },
        "nominal_base_in_device": _floats(cal.base_in_device),
        "markers_on_tool": {str(k): [float(x) for x in v] for k, v in cal.markers_on_tool.items()},
        "convention": cal.convention,
        "convention_reason": cal.convention_reason,
        "model": poe_to_dict(cal.model),
        "diff": cal.diff.to_dict(),
        "warnings": list(cal.warnings),
    }


def _res_line(label: str, r: Residuals | None, unit: str) -> str:
    if r is None:
        return f"  {label:<18} (none)"
    text = f"  {label:<18} {r.rms_position:>11.3g} {r.max_position:>11.3g} {unit:<3}"
    if r.rms_rotation is not None and r.max_rotation is not None:
        text += f" {r.rms_rotation:>11.3g} {r.max_rotation:>11.3g} rad"
    return text


def _deviations(dev: Deviations) -> str:
    """The prior's deviations in brief: the links' range, the offsets' (rad)."""
    links = f"links {min(dev.links):.1e}..{max(dev.links):.1e}" if dev.links else "no links"
    return f"{links}, offsets {dev.offsets:.1e} rad"


def summary(cal: Calibration) -> str:
    """The brief text that ``urdf2dh calibrate`` prints (the report's main figures)."""
    c, noise, unit = cal.counts, cal.noise, cal.units.length
    kind = "poses" if cal.measure == "pose" else "positions"
    held = f", {c.held_out} held out" if c.held_out else ""
    valid = f", {c.validation} to validate" if c.validation else ""
    out = [
        f"calibrate {visible(cal.nominal.name)} from {visible(cal.measurements)}: "
        f"{c.measurements} {kind} at {c.configurations} configurations ({c.fit} fitted{held}"
        f"{valid})"
    ]
    sel = cal.selection
    if sel is not None and cal.chosen_by == "cross-validation":
        how = (
            "each configuration left out in turn"
            if sel.seed is None
            else f"{sel.folds} folds of configurations left out in turn"
        )
        out.append(f"levels, judged on configurations left out of the fit ({how}):")
        for s in sel.scores:
            mark = " <- chosen" if s.level == cal.level else ""
            if s.failure is not None:
                out.append(
                    f"  {s.level:<10} {s.parameters:>3} parameters: not judged: {s.failure}{mark}"
                )
                continue
            rot = "" if s.rms_rotation is None else f", {s.rms_rotation:.3g} rad"
            prior = "" if s.prior is None else f"; prior {_deviations(s.prior)}"
            out.append(
                f"  {s.level:<10} {s.parameters:>3} parameters: fit {s.fit_rms_position:.3g}, "
                f"left out {s.rms_position:.3g} +- {s.uncertainty:.2g} {unit}{rot}{prior}{mark}"
            )
        out.append(f"chosen: {sel.reason}")
    else:
        out.append(f"level: {cal.level} (as asked)")
    kept = f"; {len(cal.held)} more held at the nominal's" if cal.held else ""
    out.append(
        f"identified {c.parameters} parameters ({cal.in_words}{kept}); the measurements "
        f"determine {c.rank} of them (numerical rank), condition number "
        f"{cal.condition_number:.3g}"
    )
    levels = f"position {noise.position:.3g} {unit}"
    if noise.rotation is not None:
        levels += f", rotation {noise.rotation:.3g} rad"
    out.append(
        f"converged in {cal.iterations} iterations; noise {levels} "
        f"({'given' if noise.given else 'estimated'}); variance factor {noise.variance_factor:.3g}"
    )
    head = f"  {'residuals':<18} {'RMS pos':>11} {'max pos':>11}"
    if noise.rotation is not None:
        head += f"     {'RMS rot':>11} {'max rot':>11}"
    out.append(head)
    labels = {"fit": "fitted", "held_out": "held out", "validation": "validation"}
    for when in ("before", "after"):
        for comp in cal.comparisons:
            out.append(_res_line(f"{when}, {labels[comp.name]}", getattr(comp, when), unit))
    text = f"  noise floor        {noise.floor_position:>11.3g} {'':>11} {unit:<3}"
    if noise.floor_rotation is not None:
        text += f" {noise.floor_rotation:>11.3g}"
    out.append(text)
    out.append("  (before: the nominal joints with base and tool fitted)")
    worst = sorted(cal.parameters, key=lambda p: -(p.std if p.std is not None else math.inf))[:3]
    if worst:
        out.append(
            "largest standard deviations: "
            + ", ".join(
                f"{p.name} {p.std:.3g} {p.unit}"
                if p.std is not None
                else f"{p.name} (not determined)"
                for p in worst
            )
        )
    forms = len(cal.diff.forms)
    out.append(
        f"output: {cal.convention}; diff against the nominal ({cal.diff.convention}): "
        f"{cal.diff.marked} parameters changed beyond the thresholds"
        + (f", {forms} row{'s' if forms > 1 else ''} changed form" if forms else "")
    )
    out += [f"warning: {w}" for w in cal.warnings]
    return "\n".join(out) + "\n"


def markdown(cal: Calibration) -> str:
    """A notebook's view of ``cal``: the residuals before and after on each set, and the
    identified parameters, as tables (names escaped)."""
    t, unit = markdown_text, markdown_text(cal.units.length)
    c = cal.counts
    out = [
        f"**{t(cal.nominal.name)}** calibrated at level {cal.level} ({cal.chosen_by}) "
        f"from {t(cal.measurements)}: {c.measurements} {cal.measure} measurements at "
        f"{c.configurations} configurations, {c.parameters} parameters (rank {c.rank}), "
        f"{'converged' if cal.converged else 'NOT converged'} in {cal.iterations} "
        f"iterations",
        "",
    ]

    def rms(r: Residuals) -> list[str]:
        rot = "" if r.rms_rotation is None else f"{r.rms_rotation:.3g}"
        return [f"{r.rms_position:.3g}", f"{r.max_position:.3g}", rot]

    rows = [[k.name, str(k.before.count), *rms(k.before), *rms(k.after)]
            for k in cal.comparisons]  # fmt: skip
    out += markdown_table(
        ["set", "measurements", f"RMS before [{unit}]", f"max before [{unit}]",
         "RMS rot. before [rad]", f"RMS after [{unit}]", f"max after [{unit}]",
         "RMS rot. after [rad]"], rows)  # fmt: skip
    out.append("")
    rows = [[t(q.name), f"{q.change:.3g}", "" if q.std is None else f"{q.std:.3g}",
             t(q.unit), t(q.flag or "")] for q in cal.parameters]  # fmt: skip
    out += markdown_table(["parameter", "change", "std", "unit", "note"], rows)
    out += [f"- {t(w)}" for w in cal.warnings]
    return "\n".join(out) + "\n"
