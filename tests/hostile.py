"""Robots with hostile names, and the command line run on them (test_hostile_names.py and
scripts/hostile_names.py).

A hostile robot is a real chain (genser6 from tests/data, or the bundled UR5) whose robot,
link and joint names (and file name) are drawn, seeded, from the characters and snippets that
end strings, comments and lines in the languages we write: every quote kind, backslash, LF,
CR, U+2028, ``%``, ``#``, ``;``, ``--``, ``]]>``, ``${}``, and payloads such as a HAL
``loadusr`` line. Its clean twin is the same chain with plain placeholder names. The robot is
written as a URDF and as MJCF (lxml escapes the names: the attack is the names' values, not
broken XML) and as POE files (JSON in metres, YAML in millimetres; those can also carry control
characters XML cannot).

:func:`run` runs ``urdf2dh export``/``convert`` in-process, for every target and format, on the
hostile robot and its twin; :mod:`safety` judges the output.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np
import yaml
from lxml import etree

from urdf2dh import cli, load
from urdf2dh.emit.export import TARGETS
from urdf2dh.emit.formats import FORMATS
from urdf2dh.io.catalog import ROBOTS, robot_path

HERE = Path(__file__).parent
GEOMETRIES = {  # URDF file, base link, tip link
    "genser6": (HERE / "data" / "genser6.urdf", "floor", "tool"),
    "ur5": (robot_path(ROBOTS["ur5"]), "base_link", "tool0"),
}
KINDS = ("urdf", "mjcf", "poe-json", "poe-yaml")
XML_KINDS = ("urdf", "mjcf")  # sources with link names (--base/--tip), whose names XML carries
RUNS = [("export", t) for t in TARGETS] + [("convert", f) for f in FORMATS] + [("plot", "html")]

FRAGMENTS = (
    "'",
    '"',
    '"""',
    "'''",
    "\\",
    "\\n",
    "\n",
    "\r",
    "\r\n",
    "\u2028",
    "\u2029",
    "\x85",
    "%",
    "#",
    ";",
    "--",
    "---",
    "]]>",
    "${x}",
    "${9**9}",
    "$(env HOME)",
    "$HOME",
    "[EMC]X",
    "%{",
    "%}",
    "...",
    "*/",
    "/*",
    "<!--",
    "-->",
    "<![CDATA[",
    "&amp;",
    "&",
    "<",
    ">",
    "\t",
    "|",
    "`",
    "*",
    "_",
    "~",
    "!",
    "[a](javascript:x)",
    "<script>",
    "=cmd|' /C calc'!A0",
    "@SUM(1)",
    "+1",
    "-1",
    "\x7f",
    "\x9b",
    "\u202e",
    "\ufeff",
    # invisible: zero-width space and joiner, bidi isolates and marks, soft hyphen, tag
    # characters, Mongolian vowel separator; and the full-width formula starts
    "\u200b",
    "\u200d",
    "\u2066",
    "\u2069",
    "\u200e",
    "\u061c",
    "\u00ad",
    "\U000e0041",
    "\U000e0001",
    "\u180e",
    "\uff1d",
    "\uff1dcmd|' /C calc'!A0",
    "\uff0b1",
    "\t=1",
    "é",
    "名",
    "\U0001f600",
    " ",
    "  ",
    ": ",
    "- ",
    "? ",
    "{",
    "}",
    "[",
    "]",
    ",",
    "&a",
    "*a",
    "!!str",
    "\\x00",
    "\\u2028",
    "setp genserkins.A-0 9",
)
PAYLOADS = (
    '"""\nimport os; os.system("touch PWNED")\n"""',
    "'''\nimport os; os.system('touch PWNED')\n'''",
    "\nloadusr -w sh -c 'touch PWNED'\n",
    "\rloadusr -w sh -c 'touch PWNED'",
    "\n!touch PWNED\n",
    "');system('touch PWNED');%",
    '");system("touch PWNED");%',
    '" + system("touch PWNED") + "',
    "x: 1\nevil: [2]",
    "\n---\nevil: 1\n",
    "\u2028evil: [2]",
    "\x85evil: [2]",
    "--><evil/><!--",
    '"/><evil a="',
    "\n| a | b |\n",
    "\n%}\nsystem('touch PWNED')\n%{\n",
    "x" * 1030 + "loadusr -w sh -c 'touch PWNED'",
)
WORDS = (
    *("joint", "link", "arm", "base", "tool0", "j", "A", "wrist_1", "x"),
    # names the writers make up, and their parts
    *("body2", "dh_base", "tool_fixed", "_fixed", "_link", "_lead", "_joint", "_offset", "_2"),
)
# characters XML 1.0 cannot carry (so only POE files hold them): C0 controls, terminal escape
# sequences, a lone surrogate, a non-character
CONTROLS = (
    "\x00",
    "\x01",
    "\x08",
    "\x0b",
    "\x0c",
    "\x1f",
    "\x1b[31m",
    "\x1b]52;c;eA==\x07",
    "\ud800",
    "\ufffe",
)
NAME = "QZ"  # placeholders: QZR robot, QZB base, QZT tip, QZP file, QZJ01.. joints


@dataclass(frozen=True)
class Names:
    """A robot's names: robot, base and tip links, movable joints, the other links and fixed
    joints of the chain, and the source file's stem."""

    robot: str
    base: str
    tip: str
    joints: tuple[str, ...]
    links: tuple[str, ...]
    fixed: tuple[str, ...]
    stem: str

    def shown(self, kind: str) -> dict[str, str]:
        """Placeholder -> name for the names that reach the output (POE files have no link
        names: their chain runs base -> tool)."""
        out = {f"{NAME}R": self.robot, f"{NAME}P": self.stem}
        if kind in XML_KINDS:
            out |= {f"{NAME}B": self.base, f"{NAME}T": self.tip}
        out |= {f"{NAME}J{i:02d}": j for i, j in enumerate(self.joints, 1)}
        return out


@dataclass(frozen=True)
class Chain:
    """A chain's joints from base to tip: (type, origin xyz, origin rpy, axis, limit attrs)."""

    joints: tuple[tuple[str, str, str, str | None, tuple[tuple[str, str], ...]], ...]

    @property
    def movable(self) -> int:
        return sum(j[0] != "fixed" for j in self.joints)


@cache
def chain(geometry: str) -> Chain:
    path, base, tip = GEOMETRIES[geometry]
    root = etree.parse(str(path)).getroot()
    by_child = {j.find("child").get("link"): j for j in root.findall("joint")}
    joints = []
    link = tip
    while link != base:
        j = by_child[link]
        origin, axis, limit = j.find("origin"), j.find("axis"), j.find("limit")
        joints.append(
            (
                j.get("type"),
                origin.get("xyz", "0 0 0") if origin is not None else "0 0 0",
                origin.get("rpy", "0 0 0") if origin is not None else "0 0 0",
                axis.get("xyz") if axis is not None else None,
                tuple(limit.attrib.items()) if limit is not None else (),
            )
        )
        link = j.find("parent").get("link")
    return Chain(tuple(reversed(joints)))


def clean_names(geometry: str) -> Names:
    c = chain(geometry)
    return Names(
        f"{NAME}R",
        f"{NAME}B",
        f"{NAME}T",
        tuple(f"{NAME}J{i:02d}" for i in range(1, c.movable + 1)),
        tuple(f"l{i}" for i in range(len(c.joints) - 1)),
        tuple(f"f{i}" for i in range(len(c.joints) - c.movable)),
        f"{NAME}P",
    )


def _name(rng: np.random.Generator, controls: bool, taken: set[str]) -> str:
    while True:
        parts = []
        for _ in range(int(rng.integers(1, 5))):
            r = rng.random()
            pool = FRAGMENTS if r < 0.6 else WORDS if r < 0.85 else PAYLOADS
            parts.append(pool[int(rng.integers(len(pool)))])
        if controls and rng.random() < 0.25:
            control = CONTROLS[int(rng.integers(len(CONTROLS)))]
            parts.insert(int(rng.integers(len(parts) + 1)), control)
        name = "".join(parts)
        if name not in taken and NAME not in name:
            taken.add(name)
            return name


def _stem(rng: np.random.Generator) -> str:
    """A file name stem: hostile too, but one a file system takes (no '/', no NUL)."""
    while True:
        stem = "".join(
            FRAGMENTS[int(rng.integers(len(FRAGMENTS)))] for _ in range(int(rng.integers(1, 4)))
        )
        if "/" not in stem and "\x00" not in stem and len(stem.encode()) < 100:
            return stem


CLASSIC = Names(  # the issue's own examples
    "x: 1\nevil: [2]",
    'base"""\nimport os; os.system("touch PWNED")\n"""',
    "tip\nloadusr -w sh -c 'touch PWNED'",
    (
        'j1"\nsystem("touch PWNED")%',
        "j2'''\n'''",
        "j3\\",
        "j4\r\nsetp genserkins.A-0 9",
        "j5\u2028x",
        'j6" + system("touch PWNED") + "',
    ),
    ("l0", "l1", "l2", "l3", "l4", "l5", "l6"),  # genser6: floor, 7 links, tool
    ("f0", "f1"),
    'x"""\nimport os\n',
)


def _colliding(base: str, tip: str, joints: tuple[str, ...], robot: str = "r") -> Names:
    """genser6 with these base, tip and joint names (plain names elsewhere)."""
    return Names(robot, base, tip, joints, tuple(f"l{i}" for i in range(7)), ("f0", "f1"), "c")


# robots named as the writers name what they make up (:mod:`urdf2dh.emit.names`): MATLAB's
# bodies and joints (dh_base, body<i>, body<i>_offset, <body>_fixed; genser6's fifth row has a
# theta offset), KDL's segments and fixed joints, the URDF writer's links and joints
# (<joint>_link, <tip>_joint), roboticstoolbox's link names (link<i>), and the suffixes the
# writers add (_2)
COLLIDING = (
    _colliding("body1", "body2", ("joint1", "joint2", "joint3", "joint4", "joint5", "joint6")),
    _colliding(
        "floor",
        "tool",
        (
            "dh_base_fixed",
            "tool_fixed",
            "body5_offset_fixed",
            "body1_offset_fixed",
            "tool_joint",
            "j6",
        ),
    ),
    _colliding(
        "dh_base",
        "body5_offset",
        (
            "body5_offset_fixed",
            "dh_base_fixed",
            "dh_base_2_fixed",
            "body5_offset_2_fixed",
            "body5",
            "j6",
        ),
    ),
    _colliding("joint1", "joint6", ("joint1", "joint2", "joint3", "joint4", "joint5", "joint6")),
    _colliding(
        "joint1_link",
        "joint2_link",
        ("joint1", "joint2", "joint3", "joint4", "joint5", "joint2_link_joint"),
    ),
    _colliding(
        "body1",
        "body1_2",
        ("dh_base_fixed", "dh_base_fixed_2", "body1", "body1_2", "body1_2_fixed", "body2_fixed"),
    ),
    _colliding(
        "base",
        "tool",
        ("link1", "link0", "link-0", "base_link", "tool", "tool_joint"),
        robot="link1",
    ),
    _colliding(
        "body6",
        "body3",
        ("body6_fixed", "body3_fixed", "body6", "body3", "dh_base", "body3_fixed_2"),
    ),
)


def hostile_names(seed: int, geometry: str, controls: bool = False) -> Names:
    """The hostile names of robot ``seed`` (seed 0: :data:`CLASSIC`, for genser6); ``controls``
    adds characters XML cannot carry (for POE files)."""
    c = chain(geometry)
    if seed == 0 and geometry == "genser6":
        return CLASSIC
    rng = np.random.default_rng(seed)
    joints: set[str] = set()
    links: set[str] = set()
    return Names(
        _name(rng, controls, set()),
        _name(rng, controls, links),
        _name(rng, controls, links),
        tuple(_name(rng, controls, joints) for _ in range(c.movable)),
        tuple(_name(rng, controls, links) for _ in range(len(c.joints) - 1)),
        tuple(_name(rng, controls, joints) for _ in range(len(c.joints) - c.movable)),
        _stem(rng),
    )


# --------------------------------------------------------------------------- source files


def urdf_text(geometry: str, names: Names) -> str:
    """The chain as URDF, every name an attribute value set through lxml."""
    c = chain(geometry)
    robot = etree.Element("robot", name=names.robot)
    links = [names.base, *names.links, names.tip]
    for link in links:
        etree.SubElement(robot, "link", name=link)
    moving, fixed = iter(names.joints), iter(names.fixed)
    for k, (kind, xyz, rpy, axis, limit) in enumerate(c.joints):
        name = next(fixed) if kind == "fixed" else next(moving)
        j = etree.SubElement(robot, "joint", name=name, type=kind)
        etree.SubElement(j, "parent", link=links[k])
        etree.SubElement(j, "child", link=links[k + 1])
        etree.SubElement(j, "origin", xyz=xyz, rpy=rpy)
        if axis is not None:
            etree.SubElement(j, "axis", xyz=axis)
        if limit:
            etree.SubElement(j, "limit", dict(limit))
    return etree.tostring(robot, xml_declaration=True, encoding="utf-8").decode()


def mjcf_text(geometry: str, names: Names) -> str:
    """The chain as MJCF: a body per link (the URDF joint's origin as ``pos`` and ``euler``, rpy
    being intrinsic z-y-x), a hinge or slide per moving joint; every name an attribute value set
    through lxml."""
    c = chain(geometry)
    root = etree.Element("mujoco", model=names.robot)
    etree.SubElement(root, "compiler", angle="radian", eulerseq="zyx")
    body = etree.SubElement(etree.SubElement(root, "worldbody"), "body", name=names.base)
    links = [names.base, *names.links, names.tip]
    moving = iter(names.joints)
    for k, (kind, xyz, rpy, axis, limit) in enumerate(c.joints):
        r, p, y = rpy.split()
        body = etree.SubElement(body, "body", name=links[k + 1], pos=xyz, euler=f"{y} {p} {r}")
        if kind == "fixed":
            continue
        joint = etree.SubElement(body, "joint", name=next(moving), axis=axis or "1 0 0",
                                 type="slide" if kind == "prismatic" else "hinge")  # fmt: skip
        limits = dict(limit)
        if kind != "continuous" and "lower" in limits and "upper" in limits:
            joint.set("range", f"{limits['lower']} {limits['upper']}")
    return etree.tostring(root, xml_declaration=True, encoding="utf-8").decode()


@cache
def _poe_geometry(geometry: str) -> tuple[list[list[float]], list[list[float]], list]:
    path, base, tip = GEOMETRIES[geometry]
    model = load(str(path), base, tip)
    twists = [[float(x) for x in t] for t in model.twists()]
    limits = [
        [float(j.lower), float(j.upper)] if j.lower is not None else None for j in model.joints
    ]
    return twists, [[float(x) for x in row] for row in model.home], limits


def poe_text(geometry: str, names: Names, fmt: str, unit: str | None = None) -> str:
    """The chain as a POE model file (``fmt`` json, in metres, or yaml, in millimetres), joint
    names and ``name:`` hostile; written by json / PyYAML, which escape every character."""
    twists, home, limits = _poe_geometry(geometry)
    k = 1000.0 if fmt == "yaml" else 1.0  # revolute joints: only v and the position scale
    twists = [t[:3] + [k * x for x in t[3:]] for t in twists]
    home = [[*row[:3], k * row[3]] for row in home[:3]] + [home[3]]
    joints = []
    for name, twist, limit in zip(names.joints, twists, limits, strict=True):
        entry = {"name": name, "twist": twist}
        if limit is not None:
            entry["limits"] = limit
        joints.append(entry)
    tree = {
        "format": "poe",
        "name": names.robot,
        "length_unit": unit or ("mm" if k != 1 else "m"),
        "joints": joints,
        "tool": {"matrix": home},
    }
    if fmt == "json":
        return json.dumps(tree, indent=1)
    return yaml.safe_dump(tree, sort_keys=False)


def write_source(
    directory: Path, geometry: str, names: Names, kind: str, unit: str | None = None
) -> str:
    """Write the robot into ``directory``; the SOURCE argument naming it (``./<stem>.urdf``)."""
    if kind == "urdf":
        text, suffix = urdf_text(geometry, names), ".urdf"
    elif kind == "mjcf":
        text, suffix = mjcf_text(geometry, names), ".xml"
    else:
        fmt = kind.split("-")[1]
        text, suffix = poe_text(geometry, names, fmt, unit), "." + fmt
    (directory / (names.stem + suffix)).write_text(text, encoding="utf-8")
    return "./" + names.stem + suffix


# --------------------------------------------------------------------------- running urdf2dh


@dataclass(frozen=True)
class Outcome:
    code: int
    stderr: str
    output: bytes | None  # the -o file, if one was written
    crashed: str | None  # an exception that escaped cli.main (a traceback for the user)


def run(
    directory: Path,
    source: str,
    command: str,
    what: str,
    names: Names,
    kind: str,
    extra: list[str] | None = None,
) -> Outcome:
    """``urdf2dh export SOURCE --to what``, ``convert SOURCE --format what`` or ``plot SOURCE
    -o out.what`` in-process, in ``directory``, with ``--base``/``--tip`` for URDF sources (and
    ``extra`` options), output to a file."""
    out = directory / f"out-{command}-{what}"
    out.unlink(missing_ok=True)
    argv = [command, source, "-o", str(out), *(extra or [])]
    if command == "plot":
        out = out.with_suffix("." + what)  # plot's format is the file's suffix
        argv[3] = str(out)
    else:
        argv += ["--to", what] if command == "export" else ["--format", what]
    if kind in XML_KINDS:
        argv += [f"--base={names.base}", f"--tip={names.tip}"]
    err = io.StringIO()
    crashed = None
    cwd = os.getcwd()
    os.chdir(directory)
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            code = cli.main(argv)
    except BaseException as e:
        code, crashed = -1, f"{type(e).__name__}: {e}"
    finally:
        os.chdir(cwd)
    data = out.read_bytes() if out.exists() else None
    leftovers = [p.name for p in directory.iterdir() if p.name.startswith(".out-")]
    if leftovers:
        crashed = f"temporary files left: {leftovers}"
    return Outcome(code, err.getvalue(), data, crashed)
