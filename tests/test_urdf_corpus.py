"""A fast seeded sample of the corpus of mutated real URDFs (scripts/fuzz_urdf.py runs it all):
no traceback, no internal error, exit codes 0/1/2, one-line errors naming the file, no warning,
and every table that converts agrees with Pinocchio whenever Pinocchio loads the file."""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))

import fuzz_urdf


def test_a_seeded_sample_of_the_corpus_keeps_every_invariant():
    outcomes = fuzz_urdf.run_corpus(count=150, seed=12)
    broken = [o for o in outcomes if o.problems]
    assert not broken, fuzz_urdf.report(broken)
    labels = Counter(o.label for o in outcomes)
    # the sample reaches both sides: tables that convert and agree, and refused input
    assert labels["convert: converted; verify: Pinocchio agrees"] >= 30, labels
    assert labels["convert: input error; verify: input error"] >= 30, labels
    assert len({k for o in outcomes for k in o.kinds}) == len(fuzz_urdf.MUTATIONS)


def test_the_invariants_are_checked():
    path = Path("/tmp/x.urdf")
    ok = fuzz_urdf.Run(0, "table", "", ())
    bad = [
        fuzz_urdf.Run(2, "", "urdf2dh: internal error: KeyError: 'x'\n", ()),
        fuzz_urdf.Run(2, "", "urdf2dh: error: /tmp/x.urdf: two\nlines\n", ()),
        fuzz_urdf.Run(2, "", "urdf2dh: error: elsewhere.urdf: bad\n", ()),
        fuzz_urdf.Run(0, "", "", ("RuntimeWarning: overflow encountered in multiply",)),
        fuzz_urdf.Run(3, "", "urdf2dh: error: /tmp/x.urdf: bad\n", ()),
        fuzz_urdf.Run(1, "Traceback (most recent call last):", "verify: FAILED for dh\n", ()),
    ]
    assert fuzz_urdf._problems(path, ok, ok) == []
    for run in bad:
        assert fuzz_urdf._problems(path, run, run), run
    refused = fuzz_urdf.Run(2, "", f"urdf2dh: error: {path}: Pinocchio cannot load it (x)\n", ())
    assert fuzz_urdf._problems(path, ok, refused) == []
    disagrees = fuzz_urdf.Run(1, "", "verify: FAILED for dh (allowed 1e-10 m)\n", ())
    assert fuzz_urdf._problems(path, ok, disagrees) == [
        "converted, yet verify exits 1: verify: FAILED for dh (allowed 1e-10 m)"
    ]
