"""The linuxcnc export in LinuxCNC itself: Debian's ``linuxcnc-uspace`` runs each file with
``halcmd`` in a realtime-less session, its joint-zero ``scale`` components convert the drives'
positions, and the real genserkins turns them into the Cartesian pose LinuxCNC reports
(tests/linuxcnc_sim.py). Where LinuxCNC is not installed these tests are skipped and
test_exports.py's reading of the file (hal_reader.py, consumers.py) is what checks it;
scripts/check-consumers installs LinuxCNC and runs them."""

from __future__ import annotations

import numpy as np
import pytest
from consumers import genserkins_hal, real_linuxcnc, report, run_linuxcnc
from oracle import assert_fk_matches, pin_reference
from test_exports import AGREE, genser_cases

from urdf2dh import ExportOptions, export, units

pytestmark = pytest.mark.skipif(
    not real_linuxcnc(),
    reason="Debian's linuxcnc-uspace is not installed (scripts/check-consumers)",
)

CASES = list(genser_cases())


@pytest.fixture(scope="module")
def linuxcnc():
    """Every case's file and drive positions, run in one LinuxCNC session."""
    files, inputs = [], []
    for name, source, model in CASES:
        for unit in ("mm", "inch"):
            text = export(model, "linuxcnc", opts=ExportOptions(units=unit))
            q, reference = pin_reference(source, model, samples=50, seed=3)
            q_deg = np.degrees(np.pad(q, ((0, 0), (0, 6 - model.n))))
            files.append((text, q_deg))
            inputs.append((name, unit, model, q, q_deg, reference, text))
    version, answers = run_linuxcnc(files)
    return version, list(zip(inputs, answers, strict=True))


def test_real_genserkins_moves_like_pinocchio(linuxcnc):
    """The pose LinuxCNC reports, with the world and tool frames the file states, is the
    source's (Pinocchio's) on every bundled arm genserkins takes and on random 6R chains, in mm
    and in inches; the scale components turn the drives' positions into the angles the file
    says, and motion's command back into the drives' positions."""
    version, results = linuxcnc
    worst = (0.0, 0.0)
    for (name, unit, model, q, q_deg, reference, text), got in results:
        hal = genserkins_hal(text)
        np.testing.assert_allclose(got["joints"], hal.angles(q_deg), rtol=0, atol=1e-11)
        np.testing.assert_allclose(got["commands"], q_deg, rtol=0, atol=1e-11)
        poses = hal.tip_poses(got["poses"], units.factor(unit, model.length_unit))
        errors = assert_fk_matches(
            f"LinuxCNC {version} genserkins, {name} ({unit})",
            poses, reference, model.size(), q, rel=AGREE, rot=AGREE,
        )  # fmt: skip
        report("linuxcnc", f"LinuxCNC {version} genserkins (halcmd)", errors, model.size())
        worst = max(worst[0], errors[0] / model.size()), max(worst[1], errors[1])
    # within what the export may drop (a tool tilted by a URDF's rounded pi/2: check_rotation)
    assert worst[0] < 1e-10 and worst[1] < 1e-10, worst


def test_real_halcmd_refuses_a_line_it_cannot_read():
    """The session fails on a line halcmd refuses: a pin genserkins does not have."""
    text = export(CASES[0][2], "linuxcnc") + "setp genserkins.A-6 1.0\n"
    with pytest.raises(AssertionError, match=r"genserkins\.A-6"):
        run_linuxcnc([(text, np.zeros((1, 6)))])
