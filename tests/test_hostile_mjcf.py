"""A fast seeded sample of the corpus of hostile and malformed MJCF files (scripts/hostile_mjcf.py
runs all of it): every class refused in one line naming the file and the element or bound, no
traceback, no internal error, no output file from a failed run, every run bounded in time."""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))

import hostile_mjcf
import numpy as np
from hostile_files import report

from urdf2dh.cli import main


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


def test_every_include_escape_and_wrong_include_is_refused(tmp_path):
    rng = np.random.default_rng(0)
    cases = [hostile_mjcf.include_escape(rng, tmp_path, i, what)
             for i, what in enumerate(hostile_mjcf.ESCAPES)]  # fmt: skip
    cases += [hostile_mjcf.include_wrong(rng, tmp_path, 10 + i, what)
              for i, what in enumerate(hostile_mjcf.WRONG_INCLUDES)]  # fmt: skip
    outcomes = [hostile_mjcf.run_case(c, tmp_path, i) for i, c in enumerate(cases)]
    assert not [o for o in outcomes if o.problems], report(outcomes, hostile_mjcf.CLASSES)


def test_a_source_directly_in_the_home_directory_includes_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("HOME", str(tmp_path))
    (tmp_path / "part.xml").write_text("<mujoco><default/></mujoco>")
    model = tmp_path / "arm.xml"
    model.write_text(hostile_mjcf.arm(head='<include file="part.xml"/>'))
    assert main(["info", str(model)]) == 2
    err = capsys.readouterr().err
    assert f"the SOURCE lies directly in {tmp_path}" in err and err.count("\n") == 1
    (tmp_path / "robot").mkdir()  # in a directory of its own, it reads its tree
    (tmp_path / "robot" / "part.xml").write_text("<mujoco><default/></mujoco>")
    (tmp_path / "robot" / "arm.xml").write_text(model.read_text())
    assert main(["info", str(tmp_path / "robot" / "arm.xml")]) == 0
