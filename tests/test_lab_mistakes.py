"""The corpus of lab mistakes (scripts/lab_mistakes.py), all of it: on each mistaken file or
command, ``calibrate`` writes the model the right file gives, or stops naming the cause; no
internal error, no silently wrong model, no right file refused."""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))

import lab_mistakes


def test_every_lab_mistake_gives_the_same_model_or_a_refusal_naming_its_cause():
    outcomes = lab_mistakes.run_corpus()
    failed = [o for o in outcomes if o.verdict in lab_mistakes.FAILURES]
    assert not failed, lab_mistakes.report(outcomes)
    counts = Counter(o.verdict for o in outcomes)
    assert counts["internal error"] == counts["silent wrong model"] == 0
    # every class is there, with its right files and its refusals
    assert {o.mistake.kind for o in outcomes} == set(lab_mistakes.CLASSES)
    assert counts["same model"] >= 10 and counts["refused, cause named"] >= 25, counts
    right = [o for o in outcomes if o.mistake.name == "the right file"]
    assert len(right) == len(lab_mistakes.scenarios()) and all(o.accuracy for o in right)
    # a refusal is exit 3 (the data contradict the fit) or 2 (a file that cannot be read)
    assert {o.code for o in outcomes if o.verdict.startswith("refused")} <= {2, 3}


def test_the_verdicts_are_checked(tmp_path):
    """The judge catches a model written from a mistaken file: the wrong unit accepted on
    purpose gives a model far from the robot as built, which the corpus calls silent."""
    mistake = lab_mistakes.Mistake(
        "units",
        "millimetres accepted on purpose",
        "tracker",
        lambda lab, a: (lab, (*lab_mistakes._drop(a, "--length-unit"), "--accept-implausible")),
        ("--length-unit mm",),
    )
    right = lab_mistakes.Mistake("right", "the right file", "tracker", lab_mistakes._as_is)
    accuracy: dict[str, float] = {}
    assert lab_mistakes.run_one(right, tmp_path, accuracy).verdict == "same model"
    outcome = lab_mistakes.run_one(mistake, tmp_path, accuracy)
    assert outcome.code == 0 and outcome.verdict == "silent wrong model", outcome


def test_the_tutorials_lab_files_are_what_the_script_writes():
    """examples/lab/ (docs/calibrate-your-robot.md) is reproducible: scripts/lab_example.py
    writes it byte for byte, at the configurations plan chooses."""
    import lab_example

    for name, text in lab_example.files().items():
        assert (lab_example.OUT / name).read_text() == text, (
            f"examples/lab/{name} differs from what scripts/lab_example.py writes; run it"
        )
