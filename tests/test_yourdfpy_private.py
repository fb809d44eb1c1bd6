"""urdf2dh reads URDF elements with yourdfpy's own parsers without running trimesh's package
(urdf2dh/io/urdf/_yourdfpy.py): the parsers give what the real yourdfpy gives, bit for bit, on
every bundled robot, and a process that uses urdf2dh and then (or before) trimesh and yourdfpy
gets the real packages."""

from __future__ import annotations

import dataclasses
import subprocess
import sys

import numpy as np
import pytest
import yourdfpy
from lxml import etree

from urdf2dh.io.catalog import ROBOTS, robot_path
from urdf2dh.io.urdf import _yourdfpy


def same(ours: object, theirs: object, where: str = "") -> None:
    """Equal field by field (the classes are yourdfpy's, once from each module instance)."""
    if dataclasses.is_dataclass(theirs):
        assert type(ours).__name__ == type(theirs).__name__, where
        for f in dataclasses.fields(theirs):
            same(getattr(ours, f.name), getattr(theirs, f.name), f"{where}.{f.name}")
    elif isinstance(theirs, np.ndarray):
        assert isinstance(ours, np.ndarray) and np.array_equal(ours, theirs), where
        assert ours.dtype == theirs.dtype, where
    elif isinstance(theirs, list):
        assert isinstance(ours, list) and len(ours) == len(theirs), where
        for k, (a, b) in enumerate(zip(ours, theirs, strict=True)):
            same(a, b, f"{where}[{k}]")
    else:
        assert type(ours) is type(theirs) and ours == theirs, (where, ours, theirs)


def test_the_private_instance_serves():
    assert _yourdfpy.urdf.__name__ == "urdf2dh.io.urdf._yourdfpy.urdf"
    assert _yourdfpy.urdf.URDF is not yourdfpy.URDF


URDF_FILES = {robot_path(r).name: robot_path(r) for r in ROBOTS.values()}  # MJCF, POE: no yourdfpy
URDF_FILES = {n: p for n, p in URDF_FILES.items() if p.suffix == ".urdf"}


@pytest.mark.parametrize("name", sorted(URDF_FILES))
def test_element_parsers_give_what_yourdfpy_gives(name):
    path = URDF_FILES[name]
    root = etree.parse(str(path)).getroot()
    for kind in ("link", "joint"):
        parse_ours = getattr(_yourdfpy.urdf.URDF, f"_parse_{kind}")
        parse_theirs = getattr(yourdfpy.URDF, f"_parse_{kind}")
        elements = list(root.iterchildren(kind))
        assert elements
        for el in elements:
            same(parse_ours(el), parse_theirs(el), f"{name}: {kind} {el.get('name')}")


def test_mesh_names_refuse_use():
    placeholder = _yourdfpy.urdf.trimesh.Trimesh
    assert isinstance(placeholder, _yourdfpy.NotLoaded)
    with pytest.raises(RuntimeError, match=r"trimesh\.Trimesh is not loaded"):
        placeholder()


# A library user's process: urdf2dh first, then trimesh and yourdfpy (and the other order).
USER = """
import sys
{before}
import urdf2dh
model = urdf2dh.load("ur5")
table = urdf2dh.to_table(model, "dh")
private = sorted(m for m in sys.modules if "trimesh" in m and not m.startswith("urdf2dh."))
{after}
import trimesh, trimesh.creation, yourdfpy
box = trimesh.creation.box(extents=(1, 2, 3))
assert abs(box.volume - 6) < 1e-12 and box.is_watertight
assert yourdfpy.urdf.trimesh is trimesh and yourdfpy.urdf.tra is trimesh.transformations
assert trimesh.Trimesh.__module__ == "trimesh.base"
robot = yourdfpy.URDF.load({path!r}, build_scene_graph=False, load_meshes=False)
assert [j.name for j in robot.robot.joints][:2] == ["shoulder_pan_joint", "shoulder_lift_joint"]
again = urdf2dh.to_table(urdf2dh.load("ur5"), "dh")
assert urdf2dh.render(again, "json") == urdf2dh.render(table, "json")
print("OK", private)
"""


@pytest.mark.parametrize("first", ["urdf2dh", "trimesh"])
def test_a_library_user_gets_the_real_trimesh_and_yourdfpy(first):
    path = str(robot_path(ROBOTS["ur5"]))
    before = "import trimesh, yourdfpy" if first == "trimesh" else ""
    code = USER.format(before=before, after="", path=path)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout.strip().splitlines()[-1]
    if first == "urdf2dh":
        assert out == "OK []"  # urdf2dh itself put no trimesh module in sys.modules
    else:
        assert out.startswith("OK ['trimesh'")


# A conversion imports neither logging nor six, which yourdfpy's module imports; yourdfpy's logger
# (module level: `_logger = logging.getLogger(__name__)`) logs through the real one when used.
DEFERRED = """
import sys
from urdf2dh.cli import main
assert main(["convert", "ur5"]) == 0
loaded = ("logging", "six", "zipfile", "numpy.random")
print("LOADED", sorted(m for m in loaded if m in sys.modules))
from urdf2dh.io.urdf._yourdfpy import urdf
assert urdf.six.string_types == (str,)
urdf._logger.warning("yourdfpy says %s", 42)
import logging
assert urdf._logger.getEffectiveLevel() == logging.getLogger(urdf.__name__).getEffectiveLevel()
print("NAME", urdf._logger.name)
"""


def test_logging_and_six_are_imported_when_yourdfpy_uses_them():
    proc = subprocess.run([sys.executable, "-c", DEFERRED], capture_output=True, text=True,
                          timeout=120)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert "LOADED []" in lines
    assert "NAME urdf2dh.io.urdf._yourdfpy.urdf" in lines
    assert proc.stderr.strip() == "yourdfpy says 42"  # logging's last-resort handler


def test_placeholder_modules_answer_tools_that_walk_sys_modules():
    # pytest's and hypothesis's plugins read every module's __file__ (a str or absent)
    private = [m for name, m in list(sys.modules.items()) if name.startswith(_yourdfpy.__name__)]
    assert {m.__name__.rsplit(".", 1)[1] for m in private} >= {"trimesh", *_yourdfpy.STUBBED}
    for module in private:
        for dunder in ("__file__", "__path__", "__wrapped__", "__all__"):
            value = getattr(module, dunder, None)
            assert not isinstance(value, _yourdfpy.NotLoaded), (module.__name__, dunder)
    assert isinstance(_yourdfpy.urdf.tra.diagonal_dot, _yourdfpy.NotLoaded)
