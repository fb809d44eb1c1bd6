"""Every command that `urdf2dh --help` lists works after the README's one install command
(`pip install .`): a process runs each command's example, and the picture and interactive
outputs of plot and calibrate, and every package it then holds comes from a distribution that
urdf2dh's dependencies bring (pyproject.toml's `dependencies`, followed through their own
requirements; no extra)."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from importlib.metadata import PackageNotFoundError, packages_distributions, requires
from pathlib import Path

import pytest
from packaging.requirements import Requirement

from urdf2dh.cli.parser import commands

ROOT = Path(__file__).resolve().parents[1]
tomllib = pytest.importorskip("tomllib", reason="reads pyproject.toml with Python 3.11's tomllib")

RUN = """
import json, shlex, sys
from urdf2dh.cli import main
for line in json.loads(sys.argv[1]):
    code = main(shlex.split(line)[1:])
    assert code == 0, (line, code)
print("MODULES " + json.dumps(sorted({m.split(".")[0] for m in sys.modules})))
"""


def canonical(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def installed_by(requirements: list[str]) -> set[str]:
    """The distributions ``pip install`` of these requirements brings (base, no extras asked
    for by the user; extras a requirement names are followed)."""
    seen: set[str] = set()
    todo = [(Requirement(r), "") for r in requirements]
    while todo:
        req, extra = todo.pop()
        if req.marker is not None and not req.marker.evaluate({"extra": extra}):
            continue
        name = canonical(req.name)
        for wanted in [*req.extras, ""]:
            key = f"{name}[{wanted}]"
            if key in seen:
                continue
            seen.add(key)
            try:
                todo += [(Requirement(r), wanted) for r in requires(req.name) or []]
            except PackageNotFoundError:
                pass  # a marker-less requirement of a platform we are not on
    return {key.split("[")[0] for key in seen}


def test_every_command_runs_on_what_the_one_install_brings(tmp_path):
    dependencies = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    lines = [c.EXAMPLE for c in commands()]
    lines += [
        "urdf2dh plot panda -o panda.png",  # the README's picture
        "urdf2dh plot panda -o panda.html",
        "urdf2dh calibrate puma560-nominal m.csv --helical all -o id.yaml --plot cal.html",
        "urdf2dh calibrate puma560-nominal m.csv --helical all -o id.json --plot cal.png",
    ]
    proc = subprocess.run(
        [sys.executable, "-c", RUN, json.dumps(lines)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=600,
        env={**__import__("os").environ, "MPLBACKEND": "Agg"},
    )
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-3000:]
    modules = json.loads(proc.stdout.rsplit("MODULES ", 1)[1])
    brought = installed_by(dependencies) | {"urdf2dh"}
    by_module = packages_distributions()
    foreign = {}
    for module in modules:
        if module in sys.stdlib_module_names or module.startswith("_") or module == "urdf2dh":
            continue
        dists = {canonical(d) for d in by_module.get(module, [])}
        if dists and not dists & brought:
            foreign[module] = sorted(dists)
    assert foreign == {}, f"imported, but not brought by `pip install .`: {foreign}"
    for name in ("panda.png", "panda.html", "cal.html", "cal.png", "id.yaml", "id.json"):
        assert (tmp_path / name).stat().st_size > 0, name
    assert {"matplotlib", "plotly"} <= set(modules)  # the check above saw them
