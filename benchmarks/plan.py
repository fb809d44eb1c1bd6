"""``urdf2dh plan``'s time against the configurations asked for, beside the whole greedy choice.

    python benchmarks/plan.py [--configs 20 300 1000] [--repeats 3]

For each count, on the UR5 at the full level (36 parameters, poses): :func:`urdf2dh.plan` as
shipped (beyond :data:`~urdf2dh.calibration.plan.WHOLE` weighings, each step weighs a seeded
sample of the candidates left: stochastic greedy), and in the same run the whole greedy
choice (every candidate weighed at every step, as plan chose before) on the same candidates:
the time of each (best of ``--repeats``, wall clock, a shared two-core machine), their ratio,
the time per configuration (constant when the time grows linearly), and how much information
plan's choice reaches against the whole choice's (the difference of ``log det`` of the scaled
information matrices: 36 parameters' standard deviations grow by ``exp(-difference / 72)`` in
geometric mean). The whole choice is skipped beyond 300 configurations (its time grows with
their square: minutes).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import urdf2dh  # noqa: E402
import urdf2dh.calibration.plan as planning  # noqa: E402

WHOLE_UP_TO = 300


def _best(run, repeats: int) -> tuple[float, object]:
    best, out = float("inf"), None
    for _ in range(repeats):
        start = time.perf_counter()
        out = run()
        best = min(best, time.perf_counter() - start)
    return best, out


def _whole(model, configs: int) -> list[int]:
    """The whole greedy choice on plan's own candidates (every gain at every step)."""
    est = planning._estimate(model, "full", True, None, 0)
    count = min(max(planning.CANDIDATES_PER_CONFIGURATION * configs, 500), planning.MAX_CANDIDATES)
    candidates = model.sample(max(count, configs), (0, 7))
    rows = planning._rows(est, candidates, 1e-4, 1e-4)
    sampled = planning.SAMPLED
    planning.SAMPLED = 10**9
    try:
        return planning._greedy(rows, configs, 0)
    finally:
        planning.SAMPLED = sampled


def _logdet(model, q: np.ndarray) -> float:
    est = planning._estimate(model, "full", True, None, 0)
    rows = planning._rows(est, q, 1e-4, 1e-4).reshape(-1, 36)
    rows = rows / np.linalg.norm(rows, axis=0)
    return float(np.linalg.slogdet(rows.T @ rows)[1])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--configs", type=int, nargs="+", default=[20, 300, 1000])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    ur5 = urdf2dh.load("ur5")
    head = ["configurations", "plan", "per configuration", "whole greedy", "whole / plan"]
    print("| " + " | ".join([*head, "log det, plan - whole"]) + " |")
    print("|---|---|---|---|---|---|")
    for n in args.configs:
        seconds, result = _best(lambda n=n: urdf2dh.plan(ur5, n, noise_pos=1e-4, noise_rot=1e-4),
                                args.repeats)  # fmt: skip
        q = result.configurations  # type: ignore[attr-defined]
        cells = [f"{n}", f"{seconds:.2f} s", f"{1000 * seconds / n:.2f} ms"]
        if n <= WHOLE_UP_TO:
            whole_seconds, chosen = _best(lambda n=n: _whole(ur5, n), 1)
            count = min(
                max(planning.CANDIDATES_PER_CONFIGURATION * n, 500), planning.MAX_CANDIDATES
            )
            candidates = ur5.sample(max(count, n), (0, 7))
            gap = _logdet(ur5, q) - _logdet(ur5, candidates[chosen])  # type: ignore[index]
            cells += [f"{whole_seconds:.2f} s", f"{whole_seconds / seconds:.1f}", f"{gap:+.3f}"]
        else:
            cells += ["(skipped)", "", ""]
        print("| " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
