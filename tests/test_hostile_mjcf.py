"""A fast seeded sample of the corpus of hostile and malformed MJCF files (scripts/hostile_mjcf.py
runs all of it): every class refused in one line naming the file and the element or bound, no
traceback, no internal error, no output file from a failed run, every run bounded in time."""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))

import hostile_mjcf
from hostile_files import report


def test_a_seeded_sample_of_every_class_keeps_every_invariant():
    outcomes = hostile_mjcf.run_corpus(count=2 * len(hostile_mjcf.CLASSES), seed=3)
    broken = [o for o in outcomes if o.problems]
    assert not broken, report(broken, hostile_mjcf.CLASSES)
    assert {o.case.kind for o in outcomes} == set(hostile_mjcf.CLASSES)
    codes = Counter(r.code for o in outcomes for r in o.runs)
    assert codes == {2: 3 * len(outcomes)}, codes  # every case refused by every command


def test_every_number_and_contradiction_names_its_element(tmp_path):
    """Each listed fault, once: the one-line refusal names the element and attribute."""
    cases = [
        hostile_mjcf.Case("bad number", a, hostile_mjcf._write(tmp_path / f"n{i}.xml",
                          hostile_mjcf.arm(**{"l1" if w == "l1" else "j1": a})), r, ("convert",))
        for i, (w, a, r) in enumerate(hostile_mjcf.NUMBERS)
    ]  # fmt: skip
    for i, (slots, refusal) in enumerate(hostile_mjcf.CONTRADICTIONS):
        text = (hostile_mjcf.arm().replace(*slots["rename"]) if "rename" in slots
                else hostile_mjcf.arm(**slots))  # fmt: skip
        path = hostile_mjcf._write(tmp_path / f"c{i}.xml", text)
        cases.append(hostile_mjcf.Case("contradiction", str(slots), path, refusal, ("convert",)))
    outcomes = [hostile_mjcf.run_case(c, tmp_path, i) for i, c in enumerate(cases)]
    assert not [o for o in outcomes if o.problems], report(outcomes)
