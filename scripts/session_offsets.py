"""Whether the rows of a calibration file share one joint zero: the TIAGo's ``cross_valid.csv``.

    python scripts/session_offsets.py DIR [--draws 300]

``DIR`` holds the unseen sets' files (``benchmarks/calibration.py --unseen DIR``). FIGAROH's
script for that file (thanhndv212/figaroh @ 742cd41 : ``scripts/tiago_cross_valid.py``) reads
it as three blocks of 8 rows, the same 8 target points reached three times: with no joint
offsets, with PAL's factory offsets, and with FIGAROH's motion-capture calibration; it gives
PAL's 7 arm offsets and applies them to the second block's joint values. This prints:

* how far each block's measured points lie from the first block's (the same targets);
* the RMS position of base-and-tool fitted to all 24 rows (the nominal joints; nothing that
  could absorb a joint offset) with the readings as they are, with PAL's offsets taken off the
  second block, added to it, or taken off another block instead;
* the same for ``--draws`` seeded random rearrangements of PAL's offsets (the 7 values permuted
  over the joints, each sign drawn), taken off the second block: how many fit as well;
* the same comparison on the benchmark's fit part alone (its held-out rows left aside);
* the held-out RMS position of the default, base-tool and offsets, as it is and with PAL's
  offsets taken off, on the split's seeds 0 to ``--seeds`` - 1 (30% of the configurations held
  out; seed 0 is the benchmark's split).

A block whose readings carry offsets the others do not is a different joint zero: a calibration
of one robot state has to take them off first (``benchmarks/calibration.py``'s
:data:`PAL_OFFSETS`).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import calibration as bench  # noqa: E402

from urdf2dh import calibrate  # noqa: E402
from urdf2dh.calibration.measurements import Measurements  # noqa: E402
from urdf2dh.calibration.problem import holdout_split  # noqa: E402
from urdf2dh.model.poe import PoeModel  # noqa: E402

BLOCK = 8


def base_tool_rms(nominal: PoeModel, m: Measurements) -> float:
    """RMS position (mm) of base and tool fitted to ``m``, the nominal joints kept."""
    cal = calibrate(nominal, m, level="base-tool", convention="poe")
    fit = cal.comparison("fit")
    assert fit is not None
    return fit.after.rms_position * 1e3


def shifted(m: Measurements, rows: range, offsets: np.ndarray) -> Measurements:
    """``m`` with ``offsets`` (one per joint of PAL_OFFSETS, in its order) taken off ``rows``."""
    joints = dict(zip(bench.PAL_OFFSETS.offsets, offsets.tolist(), strict=True))
    return replace(bench.PAL_OFFSETS, rows=rows, offsets=joints).take_off(m)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("directory", type=Path, help="the unseen sets' files")
    parser.add_argument("--draws", type=int, default=300, help="random rearrangements")
    parser.add_argument("--seeds", type=int, default=10, help="held-out splits to judge on")
    args = parser.parse_args()
    real = next(r for r in bench.unseen_sets(args.directory) if r.shifted is not None)
    nominal, (m,) = bench.read_set(real)
    blocks = [range(k * BLOCK, (k + 1) * BLOCK) for k in range(len(m.q) // BLOCK)]
    pal = np.array(list(bench.PAL_OFFSETS.offsets.values()))
    print(f"{real.source}: {len(m.q)} rows, blocks of {BLOCK}")
    for k, rows in enumerate(blocks):
        gap = np.linalg.norm(m.points[list(rows)] - m.points[list(blocks[0])], axis=1)
        print(
            f"  block {k + 1} (rows {rows.start + 1}-{rows.stop}): its points "
            f"{gap.mean() * 1e3:.1f} mm (mean; max {gap.max() * 1e3:.1f}) from block 1's"
        )
    second = blocks[1]
    cases = [
        ("as it is", m),
        ("PAL's offsets taken off block 2", shifted(m, second, pal)),
        ("PAL's offsets added to block 2", shifted(m, second, -pal)),
        *((f"PAL's offsets taken off block {k + 1} instead", shifted(m, rows, pal))
          for k, rows in enumerate(blocks) if rows != second),
    ]  # fmt: skip
    print("\nbase and tool fitted to all rows, RMS position:")
    for name, case in cases:
        print(f"  {name}: {base_tool_rms(nominal, case):.2f} mm")
    rng = np.random.default_rng(0)
    best = base_tool_rms(nominal, cases[1][1])
    arrangements = [rng.permutation(pal) * rng.choice([-1, 1], len(pal)) for _ in range(args.draws)]
    draws = np.array([base_tool_rms(nominal, shifted(m, second, a)) for a in arrangements])
    same = int(np.sum(np.isclose(draws, best, rtol=1e-9)))
    print(
        f"\n{args.draws} random rearrangements of PAL's offsets taken off block 2 (seed 0): "
        f"median {np.median(draws):.2f} mm, 5th percentile {np.percentile(draws, 5):.2f}; "
        f"better than PAL's own: {int(np.sum(draws < best * (1 - 1e-9)))}, "
        f"as good (PAL's own drawn again): {same}"
    )
    fit_rows, _ = holdout_split(m, 0.3, 0)
    print(f"\nthe benchmark's fit part alone ({len(fit_rows)} rows):")
    for name, case in cases[:3]:
        print(f"  {name}: {base_tool_rms(nominal, case.subset(fit_rows)):.2f} mm")
    print(f"\nheld-out RMS position (mm) over the split's seeds 0-{args.seeds - 1}:")
    for name, case in cases[:2]:
        print(f"  {name}:")
        for seed in range(args.seeds):
            print(f"    seed {seed}: " + held_out(nominal, case, seed))


def held_out(nominal: PoeModel, m: Measurements, seed: int) -> str:
    """The default's held-out RMS position (and its level), base-tool's and offsets' alone, on
    the split of ``seed`` (30% of the configurations held out)."""
    fit_rows, held_rows = holdout_split(m, 0.3, seed)
    fit, held = m.subset(fit_rows), m.subset(held_rows)
    cells = []
    for level in ("auto", "base-tool", "offsets"):
        cal = calibrate(nominal, fit, level=level, validation=held, convention="poe")
        judged = cal.comparison("validation")
        assert judged is not None
        name = f"default ({cal.level})" if level == "auto" else level
        cells.append(f"{name} {judged.after.rms_position * 1e3:.2f}")
    return ", ".join(cells)


if __name__ == "__main__":
    main()
