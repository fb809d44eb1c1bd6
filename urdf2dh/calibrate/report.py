"""What a calibration reports: residuals before and after, counts, rank, deviations, the diff.

Residual statistics of a model on a measurement set: the position error is the distance between
the modelled and the measured tool point, the rotation error the angle of ``R R_meas^T``; RMS is
the root of their mean square, max the largest. "Before" is the nominal placed in the device
frame by the start fit (:func:`.start.placement`), "after" the identified model. The noise
floor is what a perfect model would leave: ``sqrt(3) sigma`` for isotropic noise of ``sigma``
per coordinate.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .chart import Estimate
from .identify import Identified
from .measurements import Measurements
from .residuals import evaluate
from .start import to_data

__all__ = [
    "SCHEMA",
    "Residuals",
    "formula",
    "holdout_split",
    "report_tree",
    "residuals_of",
    "summary",
]

SCHEMA = "urdf2dh-calibration/1"

Mat = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Residuals:
    """Residual statistics of one model on one set (rotation ``None`` for positions)."""

    count: int
    rms_position: float
    max_position: float
    rms_rotation: float | None = None
    max_rotation: float | None = None


def holdout_split(
    count: int, fraction: float, seed: int
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Rows to fit and rows held out: ``round(fraction x count)`` rows drawn with
    ``numpy.random.default_rng((seed, 3))``, both in ascending order."""
    held = round(fraction * count)
    order = np.random.default_rng((seed, 3)).permutation(count)
    return np.sort(order[held:]), np.sort(order[:held])


def residuals_of(est: Estimate, m: Measurements, pose: bool, ids: list[int]) -> Residuals | None:
    """The statistics of ``est`` on ``m`` (``None`` for an empty set)."""
    if len(m) == 0:
        return None
    data = to_data(m, pose, ids)
    r, _ = evaluate(est, data, 1.0, 1.0, jacobian=False)
    rows = r.reshape(len(data), data.rows)
    pos = np.linalg.norm(rows[:, :3], axis=1)
    out = Residuals(len(m), float(np.sqrt(np.mean(pos * pos))), float(pos.max()))
    if pose:
        rot = np.linalg.norm(rows[:, 3:], axis=1)
        out = Residuals(
            out.count,
            out.rms_position,
            out.max_position,
            float(np.sqrt(np.mean(rot * rot))),
            float(rot.max()),
        )
    return out


def formula(est: Estimate) -> str:
    """The identifiable-parameter count as a formula with its numbers, e.g.
    ``5h + 4r + 2t + n + 6 = 5*4 + 4*2 + 2*0 + 6 + 6 = 40`` (Wu 2019 eq. 23 for poses)."""
    kinds = Counter(j.kind for j in est.joints)
    terms = [
        ("5h", 5, kinds["helical"]),
        ("4r", 4, kinds["revolute"]),
        ("2t", 2, kinds["prismatic"]),
    ]
    names = [t[0] for t in terms]
    values = [f"{k}*{c}" for _, k, c in terms]
    total = sum(k * c for _, k, c in terms)
    if est.scales:
        names.append("n")
        values.append(str(est.n))
        total += est.n
    if est.home is not None:
        tool = 2 if est.keep_tool_axis else 6
        names.append(str(tool))
        values.append(str(tool))
        total += tool
    else:
        assert est.markers is not None
        names.append("3K")
        values.append(f"3*{len(est.markers)}")
        total += 3 * len(est.markers)
    return f"{' + '.join(names)} = {' + '.join(values)} = {total}"


def _floats(a: Any) -> Any:
    return [[float(x) for x in row] for row in np.asarray(a)]


def _std(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def report_tree(
    result: Identified,
    fit: Measurements,
    held: Measurements,
    pose: bool,
    before: dict[str, Residuals | None],
    after: dict[str, Residuals | None],
    model_tree: dict[str, Any],
    diff: dict[str, Any],
    warnings: list[str],
    frame: str = "device",
) -> dict[str, Any]:
    """The ``--report`` JSON tree (module docstring; README "Calibration")."""
    stats, est = result.stats, result.estimate
    unit = result.model.length_unit
    units = []
    for name in result.names:
        leaf = name.rsplit(".", 1)[1]
        units.append(
            "1"
            if leaf == "scale"
            else f"{unit}/rad"
            if leaf == "pitch"
            else "rad"
            if leaf.startswith(("turn", "r"))
            else unit
        )
    # scales and pitches are values in themselves; the other coordinates are zero at the
    # estimate by construction (a chart centred on it), and only their deviations mean something
    values = {f"{j.name}.scale": float(j.scale) for j in est.joints}
    values |= {f"{j.name}.pitch": float(j.pitch) for j in est.joints if j.kind == "helical"}
    floor = {"position": math.sqrt(3.0) * result.sigma_pos}
    if pose:
        floor["rotation"] = math.sqrt(3.0) * result.sigma_rot
    return {
        "schema": SCHEMA,
        "nominal": result.model.name.removesuffix("-calibrated"),
        "measurements": fit.source,
        "measure": "pose" if pose else "position",
        "frame": frame,
        "units": {"length": unit, "angle": "rad"},
        "counts": {
            "measurements": len(fit) + len(held),
            "fit": len(fit),
            "held_out": len(held),
            "equations": len(fit) * (6 if pose else 3),
            "parameters": len(result.names),
            "formula": formula(est),
            "rank": stats.rank,
            "markers": 0 if est.markers is None else len(est.markers),
        },
        "condition_number": _std(stats.condition),
        "convergence": {
            "iterations": result.solution.iterations,
            "converged": result.solution.converged,
        },
        "noise": {
            "position": result.sigma_pos,
            "rotation": result.sigma_rot if pose else None,
            "given": result.noise_given,
            "variance_factor": stats.variance_factor,
            "floor": floor,
        },
        "residuals": {
            "before": {k: None if v is None else asdict(v) for k, v in before.items()},
            "after": {k: None if v is None else asdict(v) for k, v in after.items()},
        },
        "parameters": [
            {"name": n, "unit": u, "value": values.get(n), "std": _std(s)}
            for n, u, s in zip(result.names, units, stats.std, strict=True)
        ],
        "nominal_base_in_device": _floats(result.base_in_device),
        "markers_on_tool": {
            str(k): [float(x) for x in v] for k, v in result.markers_on_tool.items()
        },
        "model": model_tree,
        "diff": diff,
        "warnings": warnings,
    }


def _res_line(label: str, r: Residuals | None, unit: str) -> str:
    if r is None:
        return f"  {label:<16} (none)"
    text = f"  {label:<16} {r.rms_position:>11.3g} {r.max_position:>11.3g} {unit:<3}"
    if r.rms_rotation is not None and r.max_rotation is not None:
        text += f" {r.rms_rotation:>11.3g} {r.max_rotation:>11.3g} rad"
    return text


def summary(tree: dict[str, Any]) -> str:
    """The brief text that ``urdf2dh calibrate`` prints (the report's main figures)."""
    c, noise, unit = tree["counts"], tree["noise"], tree["units"]["length"]
    kind = "poses" if tree["measure"] == "pose" else "positions"
    out = [
        f"calibrate {tree['nominal']} from {tree['measurements']}: {c['measurements']} {kind} "
        f"({c['fit']} fitted, {c['held_out']} held out)",
        f"identified {c['parameters']} parameters ({c['formula']}); numerical rank "
        f"{c['rank']}; condition number {tree['condition_number'] or math.inf:.3g}",
    ]
    levels = f"position {noise['position']:.3g} {unit}"
    if noise["rotation"] is not None:
        levels += f", rotation {noise['rotation']:.3g} rad"
    out.append(
        f"converged in {tree['convergence']['iterations']} iterations; noise "
        f"{levels} ({'given' if noise['given'] else 'estimated'}); variance factor "
        f"{noise['variance_factor']:.3g}"
    )
    head = f"  {'residuals':<16} {'RMS pos':>11} {'max pos':>11}"
    if noise["rotation"] is not None:
        head += f"     {'RMS rot':>11} {'max rot':>11}"
    out.append(head)
    for when in ("before", "after"):
        for which, label in (("fit", "fitted"), ("held_out", "held out")):
            raw = tree["residuals"][when][which]
            res = None if raw is None else Residuals(**raw)
            out.append(_res_line(f"{when}, {label}", res, unit))
    floor = tree["noise"]["floor"]
    text = f"  noise floor      {floor['position']:>11.3g} {'':>11} {unit:<3}"
    if "rotation" in floor:
        text += f" {floor['rotation']:>11.3g}"
    out.append(text)
    worst = sorted((p for p in tree["parameters"]), key=lambda p: -(p["std"] or math.inf))[:3]
    out.append(
        "largest standard deviations: "
        + ", ".join(
            f"{p['name']} {p['std']:.3g} {p['unit']}"
            if p["std"] is not None
            else f"{p['name']} (not identified)"
            for p in worst
        )
    )
    marked = [p for p in tree["diff"].get("parameters", []) if p["marked"]]
    out.append(
        f"diff against the nominal ({tree['diff'].get('convention', '-')}): "
        f"{len(marked)} parameters changed beyond the thresholds"
    )
    out += [f"warning: {w}" for w in tree["warnings"]]
    return "\n".join(out) + "\n"
