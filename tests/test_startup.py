"""Start-up hygiene: `urdf2dh --help` imports neither yourdfpy nor Pinocchio (nor numpy), and
`convert` imports neither Pinocchio nor trimesh's package and what it pulls in (scipy, networkx,
PIL, ...): yourdfpy's element parsers are run without it (urdf2dh/io/urdf/_yourdfpy.py). Each
command runs in a new interpreter, which then lists the heavy packages it ended up importing."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

HEAVY = ("numpy", "yourdfpy", "trimesh", "scipy", "pinocchio", "lxml", "mujoco")
# what a conversion needs none of: Pinocchio, MuJoCo, and trimesh's package with what it imports
NOT_FOR_CONVERT = (
    "pinocchio", "mujoco", "yourdfpy", "trimesh", "scipy", "networkx", "PIL", "shapely", "rtree",
    "matplotlib", "plotly", "pandas",
)  # fmt: skip

PROBE = """
import json, sys
from urdf2dh.cli import main
try:
    code = main({argv!r})
except SystemExit as e:
    code = e.code
heavy = sorted({{m.split(".")[0] for m in sys.modules}} & set({heavy!r}))
print("\\nIMPORTED " + json.dumps([code, heavy]))
"""


def imported(*argv: str) -> tuple[int, list[str]]:
    proc = subprocess.run(
        [sys.executable, "-c", PROBE.format(argv=list(argv), heavy=HEAVY + NOT_FOR_CONVERT)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    line = proc.stdout.rsplit("IMPORTED ", 1)[-1]
    assert proc.returncode == 0 and line != proc.stdout, proc.stdout + proc.stderr
    code, heavy = json.loads(line)
    return code, heavy


@pytest.mark.parametrize("argv", [["--help"], ["convert", "--help"], ["--version"], []])
def test_help_imports_no_heavy_package(argv):
    code, heavy = imported(*argv)
    assert code in (0, 2)
    assert heavy == [], f"urdf2dh {' '.join(argv)} imported {heavy}"


@pytest.mark.parametrize(
    "argv",
    [
        ["convert", "ur5"],
        ["convert", "panda", "--convention", "cpc", "--format", "json"],
        ["convert", "puma560-actual", "--convention", "mdh", "--format", "yaml"],
        ["convert", "fr3-mjcf"],
    ],
)
def test_convert_imports_neither_pinocchio_nor_trimesh(argv):
    code, heavy = imported(*argv)
    assert code == 0
    assert set(heavy).isdisjoint(NOT_FOR_CONVERT), heavy
    assert "numpy" in heavy  # the probe sees what a conversion does import


def test_verify_does_import_pinocchio():
    code, heavy = imported("verify", "ur5", "--samples", "10")
    assert code == 0 and "pinocchio" in heavy
    assert set(heavy).isdisjoint(set(NOT_FOR_CONVERT) - {"pinocchio"}), heavy


def test_the_program_collects_cycles_rarely_and_main_leaves_the_collector_alone():
    code = (
        "import atexit, gc, sys\nfrom urdf2dh.cli.run import console, main\n"
        "default = gc.get_threshold()\n"
        "assert main(['robots']) == 0 and gc.get_threshold() == default and gc.isenabled()\n"
        "runs = []\ngc.callbacks.append(lambda phase, info: runs.append(phase))\n"
        "atexit.register(lambda: print('COLLECTOR', gc.isenabled(), gc.get_threshold()[0], "
        "runs.count('start')))\n"
        "sys.argv = ['urdf2dh', 'convert', 'ur5']\nconsole()"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines()[-1] == "COLLECTOR True 100000 0"  # on, and no scan in convert
