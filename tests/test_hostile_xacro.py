"""A seeded sample of the hostile xacro corpus (tests/xacro_corpus.py; scripts/hostile_xacro.py
runs all of it): each attack is refused with one line, nothing it would run runs, nothing it
would start is left, and urdf2dh stays small."""

from __future__ import annotations

import time

import pytest
from xacro_corpus import LATE, cases, failed, judge, markers, run_case, sample, survivors

SAMPLE = sample(6, seed=18)


def test_the_corpus_holds_every_attack_in_every_place():
    got = cases()
    assert len({(c.attack, c.place) for c in got}) == len(got) > 90
    assert {c.benign for c in got} == {True, False}


@pytest.mark.parametrize("case", SAMPLE, ids=lambda c: f"{c.attack} in {c.place}")
def test_a_sample_of_the_corpus(tmp_path, case):
    proc, token, started = run_case(case, tmp_path)
    verdict = judge(case, tmp_path, proc, started)
    assert not failed(verdict), verdict
    assert verdict.result == ("expanded" if case.benign else "refused")
    if not case.benign:
        time.sleep(LATE + 0.5)  # a background process that got through would write now
    assert markers(tmp_path) == [] and survivors(token) == []
