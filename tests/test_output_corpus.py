"""A seeded sample of the output-path corpus (scripts/output_corpus.py runs it all): links, hard
links, modes, owners, read-only files and directories, /dev/full, a closed stdout and two
writers at once; 0 internal errors, 0 owners changed, every refusal naming the output or its
directory, nothing else touched."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))

import output_corpus


def test_a_seeded_sample_of_every_class_keeps_every_invariant():
    classes = [k for k in output_corpus.CLASSES if output_corpus.ROOTED or k != "owner"]
    light = (output_corpus.COMMANDS[2],)  # a file of tests/data: the quickest to run
    outcomes = output_corpus.run_corpus(count=len(classes), seed=5, commands=light)
    broken = [o for o in outcomes if o.problems]
    assert not broken, output_corpus.report(broken)
    assert {o.case.kind for o in outcomes} == set(classes)
    assert sum(o.owners_changed for o in outcomes) == 0


def test_the_invariants_are_checked(tmp_path):
    case = output_corpus.Case("dangling link", "x", ("convert", "ur5"), lambda d: "out.txt",
                              "refused")  # fmt: skip
    snap = {"out.txt": (0o120000, 0o777, 0, 0, "/nowhere")}
    good = [(2, "urdf2dh: error: out.txt: is a dangling symbolic link; refusing to write\n")]
    assert output_corpus.judge(case, "out.txt", (2,), good, snap, snap, tmp_path) == []
    for results, after in [
        ([(0, "")], snap),  # written, not refused
        ([(2, "urdf2dh: internal error: KeyError\n")], snap),
        ([(2, "urdf2dh: error: elsewhere: refused\n")], snap),
        (good, {**snap, ".out.txt.abc": (0o100000, 0o600, 0, 0, "x")}),  # a temporary file
        (good, {"out.txt": (0o120000, 0o777, 65534, 0, "/nowhere")}),  # an owner changed
    ]:
        codes = tuple(code for code, _ in results)
        assert output_corpus.judge(case, "out.txt", codes, results, snap, after, tmp_path)
