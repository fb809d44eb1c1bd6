"""A seeded corpus of hostile and malformed MJCF files: includes reaching out of the SOURCE's
directory (``../``, absolute paths, symbolic links), included twice or missing, document type
declarations and entity bombs, nesting and counts beyond the bounds, numbers MuJoCo's grammar or
urdf2dh's refuses, and elements that contradict MJCF (unknown classes, several orientations,
zero quaternions and axes, joints of the world, generated bodies, global coordinates, couplings of
unknown joints).

    PYTHONPATH=. python scripts/hostile_mjcf.py                 # 160 cases, seed 0
    PYTHONPATH=. python scripts/hostile_mjcf.py --count 40 --seed 5

Each case runs through ``urdf2dh convert -o FILE``, ``verify --oracle both`` and ``info``
(in-process) and must keep the invariants of scripts/hostile_files.py: exit 0, 1 or 2, no
traceback, no internal error, bounded in time; a refusal is one line naming the file, holding
the case's phrase (which names the element and attribute at fault), and leaves no output file.
The test suite runs a seeded sample (tests/test_hostile_mjcf.py).
"""

from __future__ import annotations

import os
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from hostile_files import Case, Outcome, corpus_main, run_case

from urdf2dh.tolerances import JOINTS

Rng = np.random.Generator
COMMANDS = ("convert", "verify", "info")

ARM = """<mujoco model="arm">
  {head}
  <worldbody>
    <body name="base">
      <body name="l1" {l1}>
        <joint name="j1" {j1}/>
        <body name="l2" pos="0.25 0 0">
          <joint name="j2" axis="0 1 0"/>
          <site name="tool" pos="0 0 0.1"/>
        </body>
      </body>
    </body>
  </worldbody>
  {tail}
</mujoco>
"""


def arm(head: str = "", l1: str = 'pos="0 0 0.3"', j1: str = 'axis="0 0 1"', tail: str = "") -> str:
    return ARM.format(head=head, l1=l1, j1=j1, tail=tail)


def _write(path: Path, text: str) -> str:
    path.write_text(text, encoding="utf-8")
    return str(path)


ESCAPES = ("parent", "absolute", "symlink", "etc")
WRONG_INCLUDES = ("missing", "itself", "twice", "empty name")


def include_escape(rng: Rng, tmp: Path, i: int, what: str | None = None) -> Case:
    """An include of a file outside the SOURCE's directory: ``../``, absolute, a link out."""
    home = tmp / f"case{i}"
    home.mkdir()
    outside = _write(tmp / f"secret{i}.xml", "<mujoco><default/></mujoco>")
    what = what or str(rng.choice(ESCAPES))
    name = {"parent": f"../secret{i}.xml", "absolute": outside, "etc": "/etc/passwd"}.get(
        what, "link.xml"
    )
    if what == "symlink":
        os.symlink(outside, home / "link.xml")
    path = _write(home / "arm.xml", arm(head=f'<include file="{name}"/>'))
    return Case("include escape", what, path, "is outside the SOURCE's directory", COMMANDS)


def include_wrong(rng: Rng, tmp: Path, i: int, what: str | None = None) -> Case:
    """An include of a missing file, of itself, of a file twice, or with no name."""
    home = tmp / f"case{i}"
    home.mkdir()
    what = what or str(rng.choice(WRONG_INCLUDES))
    _write(home / "part.xml", "<mujoco><default/></mujoco>")
    head = {
        "missing": '<include file="nowhere.xml"/>',
        "itself": '<include file="arm.xml"/>',
        "twice": '<include file="part.xml"/><include file="part.xml"/>',
        "empty name": '<include file=""/>',
    }[what]
    refusal = {
        "missing": "no such file",
        "itself": "included twice",
        "twice": "included twice",
        "empty name": "no file named",
    }[what]
    return Case("include wrong", what, _write(home / "arm.xml", arm(head=head)), refusal, COMMANDS)


def declaration(rng: Rng, tmp: Path, i: int) -> Case:
    """A document type declaration: a harmless entity, an entity bomb, an external entity."""
    what = str(rng.choice(["entity", "bomb", "external"]))
    if what == "bomb":
        entities = '<!ENTITY e0 "lol">' + "".join(
            f'<!ENTITY e{k} "{f"&e{k - 1};" * 10}">' for k in range(1, 10)
        )
        text = f'<?xml version="1.0"?><!DOCTYPE mujoco [{entities}]><mujoco model="&e9;"/>'
        refusal = "beyond the XML parser's limits"
    elif what == "external":
        text = '<!DOCTYPE mujoco [<!ENTITY x SYSTEM "file:///etc/passwd">]>' + arm(l1='pos="&x;"')
        refusal = "references external entity 'x'"
    else:
        text = '<!DOCTYPE mujoco [<!ENTITY x "0.3">]>' + arm(l1='euler="&x; 0 0"')
        refusal = "document type declaration"
    return Case("declaration", what, _write(tmp / f"case{i}.xml", text), refusal, COMMANDS)


def beyond_bounds(rng: Rng, tmp: Path, i: int) -> Case:
    """Bodies nested beyond the XML bound (in one file, or spliced from includes), more bodies
    or joints than urdf2dh reads, an attribute over libxml2's 10 MB."""
    what = str(rng.choice(["deep", "deep includes", "bodies", "sites", "joints", "attribute"]))
    path = tmp / f"case{i}.xml"
    if what == "deep":
        text = "<mujoco><worldbody>" + "<body>" * 300 + "</body>" * 300 + "</worldbody></mujoco>"
        refusal = "beyond the XML parser's limits"
    elif what == "deep includes":
        home = tmp / f"case{i}"
        home.mkdir()
        path = home / "arm.xml"
        for k in range(4):  # 300 bodies deep, no file deeper than 101 elements
            nested = "<body>" * 100 + f'<include file="p{k + 1}.xml"/>' + "</body>" * 100
            _write(home / f"p{k}.xml", f"<mujoco>{nested if k < 3 else '<body/>'}</mujoco>")
        text = '<mujoco><worldbody><include file="p0.xml"/></worldbody></mujoco>'
        refusal = "with the includes spliced in; at most 256"
    elif what == "bodies":
        text = "<mujoco><worldbody>" + "<body/>" * (JOINTS + 2) + "</worldbody></mujoco>"
        refusal = f"more than {JOINTS + 1:,} bodies"
    elif what == "sites":
        sites = "".join(f'<site name="s{k}"/>' for k in range(JOINTS + 2))
        text = f"<mujoco><worldbody><body>{sites}</body></worldbody></mujoco>"
        refusal = f"more than {JOINTS + 1:,} bodies and sites"
    elif what == "joints":
        text = (
            "<mujoco><worldbody><body>" + "<joint/>" * (JOINTS + 1) + "</body></worldbody></mujoco>"
        )
        refusal = f"more than {JOINTS:,} joints"
    else:
        text = arm(l1='pos="' + "1 " * 5_500_000 + '"')
        refusal = "beyond the XML parser's limits"
    return Case("beyond bounds", what, _write(path, text), refusal, COMMANDS)


# (attribute text of l1 or j1, the phrase the refusal holds)
NUMBERS = (
    ("l1", 'pos="nan 0 0.3"', "body 'l1': pos 'nan 0 0.3' is not finite"),
    ("l1", 'pos="1e999 0 0"', "body 'l1': pos '1e999 0 0' is not finite"),
    ("l1", 'pos="0x10 0 0"', "body 'l1': pos '0x10 0 0' is not 3 numbers"),
    ("l1", 'pos="1,5 0 0"', "body 'l1': pos '1,5 0 0' is not 3 numbers"),
    ("l1", 'pos="0 0"', "body 'l1': pos '0 0' is not 3 numbers (it holds 2)"),
    ("l1", 'quat="1 0 0 0 0"', "body 'l1': quat '1 0 0 0 0' is not 4 numbers"),
    ("l1", 'euler="1e60 0 0"', "body 'l1': euler '1e60 0 0' is out of range"),
    ("j1", 'axis="0 0 1" range="-1 inf"', "joint 'j1': range '-1 inf' is not finite"),
    ("j1", 'axis="0 0 1" ref="1 2"', "joint 'j1': ref '1 2' is not a number"),
    ("j1", 'axis="0 0 1" range="-1e6 1e6"', "joint 'j1': range '-1e6 1e6' is beyond ±10000 rad"),
)


def bad_number(rng: Rng, tmp: Path, i: int) -> Case:
    """A number MuJoCo's grammar refuses, or one beyond urdf2dh's bounds."""
    where, attribute, refusal = NUMBERS[int(rng.integers(len(NUMBERS)))]
    text = arm(l1=attribute) if where == "l1" else arm(j1=attribute)
    return Case("bad number", attribute, _write(tmp / f"case{i}.xml", text), refusal, COMMANDS)


# (arm() keyword arguments, the phrase the refusal holds)
CONTRADICTIONS = (
    ({"j1": 'class="nope"'}, "joint 'j1': class 'nope' is no default class"),
    ({"l1": 'childclass="nope"'}, "body 'l1': childclass 'nope' is no default class"),
    ({"l1": 'quat="1 0 0 0" euler="0 0 1"'}, "body 'l1': several orientations (quat, euler)"),
    ({"l1": 'quat="0 0 0 0"'}, "body 'l1': quat '0 0 0 0' has no direction"),
    ({"l1": 'xyaxes="1 0 0 2 0 0"'}, "body 'l1': xyaxes y axis (made perpendicular to x) has"),
    ({"j1": 'axis="0 0 0"'}, "joint 'j1': axis '0 0 0' has no direction"),
    ({"j1": 'type="screw"'}, "joint 'j1': unknown type 'screw'"),
    ({"j1": 'axis="0 0 1" limited="yes"'}, "joint 'j1': limited 'yes' is not true, false or auto"),
    ({"j1": 'axis="0 0 1" limited="true"'}, "joint 'j1' is limited but has no range"),
    ({"head": '<compiler coordinate="global"/>'}, 'coordinate="global" is not read'),
    ({"head": '<compiler angle="grad"/>'}, "<compiler>: angle 'grad' is not one of"),
    ({"head": '<compiler eulerseq="xyw"/>'}, "<compiler>: eulerseq 'xyw' is not three of"),
    ({"head": '<compiler autolimits="false"/>', "j1": 'axis="0 0 1" range="-1 1"'},
     "joint 'j1' has a range but no limited attribute"),
    ({"head": '<default><default class="a"/></default><default><default class="a"/></default>'},
     "<default class='a'> is defined twice"),
    ({"head": '<default><default><joint/></default></default>'},
     "a nested <default> has no class attribute"),
    ({"tail": '<equality><joint joint1="j2" joint2="nope"/></equality>'},
     "<equality><joint>: joint2 'nope' is no joint"),
    ({"tail": '<equality><joint joint2="j1"/></equality>'}, "<equality><joint> has no joint1"),
    ({"tail": '<equality><joint joint1="j2" polycoef="1 2 3 4 5 6"/></equality>'},
     "polycoef '1 2 3 4 5 6' is not 1 to 5 numbers"),
    ({"rename": ('name="l1"', 'name="l2"')}, "body 'l2' is declared twice"),
    ({"rename": ('name="j1"', 'name="j2"')}, "joint 'j2' is declared twice"),
)  # fmt: skip


def contradiction(rng: Rng, tmp: Path, i: int) -> Case:
    """An element MJCF does not allow, or one that contradicts another."""
    slots, refusal = CONTRADICTIONS[int(rng.integers(len(CONTRADICTIONS)))]
    if "rename" in slots:
        text = arm().replace(*slots["rename"])
    else:
        text = arm(**slots)  # type: ignore[arg-type]
    return Case("contradiction", str(slots), _write(tmp / f"case{i}.xml", text), refusal, COMMANDS)


def not_built(rng: Rng, tmp: Path, i: int) -> Case:
    """Elements that make bodies urdf2dh does not build, and joints of the world."""
    what = str(rng.choice(["composite", "flexcomp", "replicate", "attach", "world joint"]))
    if what == "world joint":
        text = '<mujoco><worldbody><joint name="w"/></worldbody></mujoco>'
        refusal = "joint 'w': the world body cannot have joints"
    else:
        text = arm().replace('<site name="tool"', f'<{what} count="2"/><site name="tool"')
        refusal = f"<{what}> in body 'l2' is not read"
    return Case("not built", what, _write(tmp / f"case{i}.xml", text), refusal, COMMANDS)


def long_name(rng: Rng, tmp: Path, i: int) -> Case:
    """A name of megabytes where a message names it."""
    size = int(rng.choice([300_000, 1_000_000]))
    name = str(rng.choice(["x", "\u00e9", "'"])) * size
    what = str(rng.choice(["class", "equality"]))
    from lxml import etree

    root = etree.fromstring(arm().encode())
    if what == "class":
        root.find(".//joint").set("class", name)
        refusal = "is no default class"
    else:
        eq = etree.SubElement(etree.SubElement(root, "equality"), "joint", joint1=name)
        eq.set("joint2", "j1")
        refusal = "is no joint"
    path = tmp / f"case{i}.xml"
    path.write_bytes(etree.tostring(root, encoding="utf-8"))
    return Case("long name", f"{what} of {size:,}", str(path), refusal, COMMANDS)


CLASSES: dict[str, Callable[[Rng, Path, int], Case]] = {
    "include escape": include_escape,
    "include wrong": include_wrong,
    "declaration": declaration,
    "beyond bounds": beyond_bounds,
    "bad number": bad_number,
    "contradiction": contradiction,
    "not built": not_built,
    "long name": long_name,
}


def cases(count: int, seed: int, tmp: Path) -> list[Case]:
    rng = np.random.default_rng(seed)
    kinds = tuple(CLASSES)
    return [CLASSES[kinds[i % len(kinds)]](rng, tmp, i) for i in range(count)]


def run_corpus(count: int, seed: int) -> list[Outcome]:
    with tempfile.TemporaryDirectory(prefix="urdf2dh-hostile-mjcf-") as directory:
        tmp = Path(directory)
        return [run_case(c, tmp, i) for i, c in enumerate(cases(count, seed, tmp))]


def main(argv: list[str] | None = None) -> int:
    return corpus_main(argv, __doc__.splitlines()[0], run_corpus, CLASSES, 160)


if __name__ == "__main__":
    sys.exit(main())
