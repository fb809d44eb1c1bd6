"""The evidence behind calibration's choice of level, set by set.

    python scripts/selection_evidence.py [--unseen DIR] [--refit] [--only NAME]

For each real data set of ``benchmarks/calibration.py`` (the three shared sets, and with
``--unseen DIR`` the six the project did not build on, split as there: 30% of the
configurations held out, seed 0), the default ``calibrate`` is run on the fit part and, per
level, this prints:

* ``LOO``: the left-out RMS position (mm) of each configuration left out in turn, as the
  selection computes it (linearised: the grouped deleted residuals);
* ``d``, ``se``, ``z``: the mean over the fit part's configurations of the paired difference of
  the selection's score (squared errors over the noise, position and rotation) between the
  level and base-tool, its standard error, and their ratio (negative: the level predicts
  better than base-tool);
* with ``--refit``: the same paired difference when each configuration is left out by fitting
  every level again without it (the base and tool, the joints, and the prior's deviations all
  estimated again), ``d*``, ``se*``, ``z*``, and the refitted left-out RMS position ``LOO*``;
* ``held``: the RMS position (mm) on the held-out part of the level fitted to the fit part.

Then what candidate rules choose, and the held-out RMS position of that choice: ``one-SE`` (the
selection's: the simplest level within one paired standard error of the best); ``2 SE``,
``3 SE``, ``t(n-1)``: that choice only if it beats base-tool by that many paired standard
errors (``t(n-1)``: Student's two-sided 95% quantile for the configurations' count), else
base-tool; with ``--refit``, ``one-SE, refitted``: the one-SE rule on the refitted scores
(levels whose refit failed for some configuration left out).

The held-out figures judge the choice; nothing here feeds them back into it.
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy import stats

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import calibration as bench  # noqa: E402

from urdf2dh import calibrate  # noqa: E402
from urdf2dh.calibration.fit import fit_before  # noqa: E402
from urdf2dh.calibration.levels import LEVELS  # noqa: E402
from urdf2dh.calibration.measurements import Measurements  # noqa: E402
from urdf2dh.calibration.prior import AUTO  # noqa: E402
from urdf2dh.calibration.select import (  # noqa: E402
    _squared_errors,
    level_fits,
    per_configuration,
    within,
)
from urdf2dh.calibration.start import FitOptions  # noqa: E402
from urdf2dh.model.poe import PoeModel  # noqa: E402


def paired(values: np.ndarray) -> tuple[float, float]:
    """Mean and standard error of paired differences."""
    return float(np.mean(values)), float(np.std(values, ddof=1) / math.sqrt(len(values)))


def simplest(scores: dict[str, np.ndarray]) -> str:
    """The selection's rule: the simplest level within one paired standard error of the best."""
    best = min(scores, key=lambda lv: float(np.mean(scores[lv])))
    return next(lv for lv in scores if within(scores[lv], scores[best]))


def choices(scores: dict[str, np.ndarray], count: int) -> dict[str, str]:
    """What each candidate rule chooses from per-configuration scores (module docstring)."""
    out = {"one-SE": simplest(scores)}
    base = scores["base-tool"]
    for label, margin in (
        ("2 SE", 2.0),
        ("3 SE", 3.0),
        ("t(n-1)", float(stats.t.ppf(0.975, count - 1))),
    ):
        d, se = paired(scores[out["one-SE"]] - base)
        out[label] = out["one-SE"] if se == 0.0 or d <= -margin * se else "base-tool"
    return out


def refit_left_out(
    nominal: PoeModel, used: Measurements, pose: bool, ids: list[int]
) -> dict[str, np.ndarray]:
    """``(configurations, 1 or 2)`` per level: each configuration's mean squared position (and
    rotation) error when every level is fitted again without it."""
    index, count = used.configurations()
    opts = FitOptions(pose=pose, level="base-tool", prior=AUTO)
    out: dict[str, np.ndarray] = {}
    for c in range(count):
        rest, alone = (
            used.subset(np.flatnonzero(index != c)),
            used.subset(np.flatnonzero(index == c)),
        )
        _, before = fit_before(nominal, rest, opts, ids)
        fits, failures = level_fits(nominal, rest, opts, ids, before, tuple(LEVELS))
        for level, f in fits.items():
            if level in failures:
                continue
            sq = _squared_errors(f.solution.estimate, alone, pose, ids).mean(axis=0)
            out.setdefault(level, np.full((count, sq.shape[0]), np.nan))[c] = sq
    return out


def one(real: bench.RealSet, refit: bool) -> None:
    nominal, fit, test = bench.load_set(real)
    cal = calibrate(nominal, fit, convention="poe")
    s = cal.selection
    used = fit.subset(np.array(cal.rows) - 1)
    index, count = used.configurations()
    pose = cal.measure == "pose"
    ids = sorted(set(fit.marker_ids()))
    per = {lv: per_configuration(sq, index, count) for lv, sq in s.left_out.items()}
    combined = {lv: v @ s.weights for lv, v in per.items()}
    again = refit_left_out(nominal, used, pose, ids) if refit else {}
    print(
        f"\n## {real.name}: {count} + {test.configurations()[1]} configurations, "
        f"chosen {cal.level} ({'outliers rejected' if cal.rejected else 'none rejected'}), "
        f"held out {bench._held_out(cal.device_model, cal, test) * 1e3:.2f} mm"
    )
    head = "| level | p | LOO mm | d | se | z |"
    if refit:
        head += " LOO* mm | d* | se* | z* |"
    print(head + " held mm |")
    print("|---" * (head.count("|") - 0) + "|")
    held_of: dict[str, float] = {}
    for score in s.scores:
        lv = score.level
        other = calibrate(nominal, fit, level=lv, convention="poe")
        held = held_of[lv] = bench._held_out(other.device_model, other, test) * 1e3
        cells = [lv, str(score.parameters), f"{score.rms_position * 1e3:.2f}"]
        if lv in combined and "base-tool" in combined:
            d, se = paired(combined[lv] - combined["base-tool"])
            cells += [f"{d:.3g}", f"{se:.3g}", f"{d / se:.2f}" if se > 0 else "-"]
        else:
            cells += ["-", "-", "-"]
        if refit:
            if lv in again and not np.isnan(again[lv]).any():
                w = s.weights[: again[lv].shape[1]]
                d, se = paired(again[lv] @ w - again["base-tool"] @ w)
                loo = math.sqrt(float(np.mean(again[lv][:, 0]))) * 1e3
                cells += [f"{loo:.2f}", f"{d:.3g}", f"{se:.3g}", f"{d / se:.2f}" if se else "-"]
            else:
                cells += ["-", "-", "-", "-"]
        print("| " + " | ".join([*cells, f"{held:.2f}"]) + " |")
    rules = choices(combined, count)
    if refit:
        rules["one-SE, refitted"] = simplest(
            {lv: v @ s.weights[: v.shape[1]] for lv, v in again.items() if not np.isnan(v).any()}
        )
    print("\nrules: " + "; ".join(f"{k} -> {v} ({held_of[v]:.2f} mm)" for k, v in rules.items()))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--unseen", type=Path, help="the unseen sets' files (benchmark's)")
    parser.add_argument("--refit", action="store_true", help="also leave out by refitting")
    parser.add_argument("--only", help="only the set whose name starts with this")
    args = parser.parse_args()
    sets = bench.shared_sets() + (bench.unseen_sets(args.unseen) if args.unseen else [])
    if args.only:
        sets = [r for r in sets if r.name.startswith(args.only)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for real in sets:
            one(real, args.refit)
    return 0


if __name__ == "__main__":
    sys.exit(main())
