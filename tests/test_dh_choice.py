"""One rule for when a D-H table is not the one to write (urdf2dh/conventions/choice.py), used
by convert, every export and calibrate where no convention is asked for; the documentation shows
what the program prints."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import numpy as np
import pytest
from chains import TILTED_ARM
from test_doc_blocks import _workspace

import urdf2dh
from urdf2dh.calibration.figures import output_table
from urdf2dh.cli import main
from urdf2dh.conventions.choice import choose, objection
from urdf2dh.emit.export import TARGETS
from urdf2dh.io.catalog import ROBOTS
from urdf2dh.tolerances import DEFAULT

ROOT = Path(__file__).resolve().parents[1]

ARM = TILTED_ARM

# angle -> why D-H is not the table to write (None: it is)
CASES = {
    0.01: r"dh would put row 'j1' 29\.8 m away \(d\), 51 times the robot's size",
    2e-4: r"dh would treat 'j1' and 'j2', 0\.0002 rad from parallel \(beyond --parallel-angle "
    r"0\.0001\), as parallel: a deviation of up to",
    1e-5: None,  # within --parallel-angle: the deviation asked for, declared
}


def arm(tmp_path: Path, angle: float) -> str:
    path = tmp_path / f"tilt-{angle:g}.urdf"
    path.write_text(ARM.format(angle=angle))
    return str(path)


@pytest.mark.parametrize("angle", sorted(CASES))
def test_convert_writes_hayati_where_dh_is_not_the_table_to_write(angle, tmp_path, capsys):
    source = arm(tmp_path, angle)
    assert main(["convert", source, "--format", "json"]) == 0
    written = __import__("json").loads(capsys.readouterr().out)
    said = CASES[angle]
    if said is None:
        assert written["convention"] == "dh"
        assert not any("written in" in w for w in written["warnings"])
        return
    assert written["convention"] == "hayati"
    reason = written["warnings"][0]
    assert reason.startswith("written in hayati, not dh: ") and re.search(said, reason), reason
    assert reason.endswith("(--convention dh writes dh all the same)")
    assert main(["convert", source, "--convention", "dh", "--format", "json"]) == 0
    assert __import__("json").loads(capsys.readouterr().out)["convention"] == "dh"


@pytest.mark.parametrize("target", sorted(t for t in TARGETS if not TARGETS[t].reads_model))
def test_every_export_applies_the_rule(target, tmp_path, capsys):
    """rtb writes its Hayati robot; a target of D-H tables only writes the far rows (exact) with
    the reason in its header, and refuses the table that deviates beyond what was asked."""
    convention = TARGETS[target].conventions[0]
    out = tmp_path / f"x{TARGETS[target].suffix}"
    code = main(["export", arm(tmp_path, 0.01), "--to", target, "-o", str(out)])
    err = capsys.readouterr().err
    if "hayati" in TARGETS[target].conventions:  # rtb: its Hayati robot
        assert code == 0 and "Hayati" in out.read_text()
        return
    six = {"ur": "a UR arm has 6 joints", "eaik": "not 6R", "ikdh": "not 6R"}
    if target in six:  # six joints or none: refused for that before anything else
        assert code == 2 and six[target] in err and "3" in err, err
        return
    assert code == 0, err
    assert (
        f"{convention} would put row 'j1' 29.8 m away (d), 51 times the robot's size; written in "
        f"{convention} all the same: the reader takes D-H tables only, and this one is exact"
    ) in out.read_text()
    out.unlink()
    assert main(["export", arm(tmp_path, 2e-4), "--to", target, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"{convention} would treat 'j1' and 'j2', 0.0002 rad from parallel" in err
    assert err.rstrip().endswith(f"--convention {convention} writes it all the same"), err
    assert not out.exists()
    assert main(["export", arm(tmp_path, 2e-4), "--to", target, "--convention", convention]) == 0
    capsys.readouterr()


def test_calibrate_chooses_by_the_same_rule(tmp_path):
    model = urdf2dh.load(arm(tmp_path, 0.01))
    convention, table, reason = output_table(model, None, "wu", DEFAULT, None)
    assert convention == "hayati" and table is not None
    assert reason == choose(model, "dh", DEFAULT).reason and table.warnings[0] == reason
    q = model.sample(50, 1)
    assert np.allclose(table.fk_batch(q), model.fk_batch(q), atol=1e-14 * model.size())
    assert output_table(model, "dh", "wu", DEFAULT, None)[0] == "dh"  # asked for: as asked
    near = urdf2dh.load(arm(tmp_path, 1e-5))
    assert output_table(near, None, "wu", DEFAULT, None)[:3:2] == ("dh", None)


@pytest.mark.parametrize("robot", sorted(ROBOTS))
def test_every_bundled_robot_keeps_its_d_h_tables(robot):
    model = urdf2dh.load(robot)
    for convention in ("dh", "mdh"):
        table = urdf2dh.to_table(model, convention)
        assert objection(model, table, DEFAULT) is None, robot


def test_the_page_shows_what_the_program_prints(tmp_path):
    """docs/parallel-axes.md's block under "When D-H is not the table to write": each line of
    its output block is a line the commands above it print."""
    page = (ROOT / "docs" / "parallel-axes.md").read_text()
    section = page.split("## When D-H is not the table to write", 1)[1].split("\n## ", 1)[0]
    commands = re.search(r"```bash\n(.*?)```", section, re.S)[1]
    shown = re.search(r"```text\n(.*?)```", section, re.S)[1].splitlines()
    proc = subprocess.run(
        ["bash", "-euo", "pipefail", "-c", commands],
        cwd=tmp_path,
        env=_workspace(tmp_path),
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr
    printed = (proc.stdout + proc.stderr).splitlines()
    assert shown and all(line in printed for line in shown), (shown, printed)
