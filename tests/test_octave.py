"""The MATLAB targets run in GNU Octave (Debian's ``octave``), where they are checked against
Pinocchio: the scripts are read and executed by Octave's own interpreter, and the classes they
call are ours, written from the published definitions (tests/octave/), because neither toolbox
is on a package registry:

* ``corke-matlab``: Peter Corke's Robotics Toolbox for MATLAB is not packaged by PyPI, npm,
  Debian or Octave Forge; ``Link`` and ``SerialLink`` (tests/octave/corke/) evaluate ``fkine``
  with the formulas of his documentation and book, no code of the toolbox.
* ``matlab``: ``rigidBodyTree`` belongs to MATLAB's Robotics System Toolbox, which Octave does
  not have; ``rigidBodyTree``, ``rigidBody`` and ``rigidBodyJoint`` (tests/octave/rst/) follow
  MathWorks' documented semantics (handle objects, ``setFixedTransform`` with ``"dh"``/``"mdh"``
  ignoring theta of revolute joints, ``getTransform``).

So Octave checks the scripts' syntax and statements as an interpreter runs them; what MATLAB's
own classes do is checked against their documentation. Octave reads ``"..."`` with backslash
escapes, MATLAB without, so names holding backslashes are left to tests/test_hostile_names.py.
Skipped where Octave is not installed; scripts/check-consumers installs it.
"""

from __future__ import annotations

import numpy as np
import pytest
from consumers import octave_version, report, run_octave
from oracle import assert_fk_matches, pin_reference
from test_exports import AGREE, _cases, _source

from urdf2dh.emit.export import export

VERSION = octave_version()
pytestmark = pytest.mark.skipif(VERSION is None, reason="GNU Octave is not installed")

CASES = list(_cases())


@pytest.fixture(scope="module")
def octave_runs():
    """Every case in both conventions for both targets, run in one Octave session."""
    jobs, inputs = [], []
    for case in CASES:
        source, model = _source(case.values[0])
        q, reference = pin_reference(source, model, samples=30, seed=5)
        for convention in ("dh", "mdh"):
            for target, kind in (("corke-matlab", "corke"), ("matlab", "rst")):
                script = export(model, target, convention)
                jobs.append((kind, script, model.tip_link or "tool", q))
                inputs.append((case.id, convention, target, model, q, reference))
    return list(zip(inputs, run_octave(jobs), strict=True))


@pytest.mark.parametrize("target", ["corke-matlab", "matlab"])
def test_matlab_scripts_move_like_pinocchio_in_octave(octave_runs, target):
    consumer = {
        "corke-matlab": f"Octave {VERSION}, Link/SerialLink from Corke's published formulas",
        "matlab": f"Octave {VERSION}, rigidBodyTree from MathWorks' documentation",
    }[target]
    runs = [(inp, poses) for inp, poses in octave_runs if inp[2] == target]
    assert len(runs) == 2 * len(CASES)
    for (case, convention, _, model, q, reference), poses in runs:
        errors = assert_fk_matches(
            f"{target} in Octave, {case} {convention}", poses, reference, model.size(), q,
            rel=AGREE, rot=AGREE,
        )  # fmt: skip
        report(target, consumer, errors, model.size())


def test_octave_refuses_a_statement_it_cannot_run():
    """The session fails on a script Octave cannot execute (a call of an unknown option)."""
    script = "L(1) = Link('revolute', 'twist', 1.0, 'standard');\nrobot = SerialLink(L);\n"
    with pytest.raises(AssertionError, match="option twist not understood"):
        run_octave([("corke", script, "", np.zeros((1, 1)))])
