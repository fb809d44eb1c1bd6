"""A fast seeded sample of the corpus of hostile and huge inputs (scripts/hostile_files.py runs
it all): every attack class refused in one line naming the file and the bound or field, no
traceback, no internal error, no output file from a failed run, every run bounded in time."""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))

import hostile_files


def test_a_seeded_sample_of_every_class_keeps_every_invariant():
    outcomes = hostile_files.run_corpus(count=2 * len(hostile_files.CLASSES), seed=4)
    broken = [o for o in outcomes if o.problems]
    assert not broken, hostile_files.report(broken)
    assert {o.case.kind for o in outcomes} == set(hostile_files.CLASSES)
    codes = Counter(r.code for o in outcomes for r in o.runs)
    assert codes[2] >= 30 and codes[0] >= 1, codes


def test_the_invariants_are_checked():
    case = hostile_files.Case("huge file", "x", "/tmp/big.urdf", "larger than")
    good = hostile_files.Run(("convert",), 2, "", "urdf2dh: error: /tmp/big.urdf: larger than "
                             "16 MiB, the most urdf2dh reads\n", 0.1)  # fmt: skip
    assert hostile_files.judge(case, good) == []
    bad = [
        hostile_files.Run(("convert",), 0, "{}", "", 0.1),  # not refused
        hostile_files.Run(("convert",), 2, "", "urdf2dh: internal error: KeyError\n", 0.1),
        hostile_files.Run(("convert",), 2, "", "urdf2dh: error: /tmp/big.urdf: other\n", 0.1),
        hostile_files.Run(("convert",), 2, "", "urdf2dh: error: elsewhere: larger than\n", 0.1),
        hostile_files.Run(
            ("convert",),
            2,
            "",
            "urdf2dh: error: /tmp/big.urdf: larger than" + "x" * 5000 + "\n",
            0.1,
        ),
        hostile_files.Run(("convert",), 2, "", "urdf2dh: error: /tmp/big.urdf: larger than\n", 99),
        hostile_files.Run(("convert",), 3, "", "urdf2dh: error: /tmp/big.urdf: larger than\n", 0.1),
    ]
    for run in bad:
        assert hostile_files.judge(case, run), run
