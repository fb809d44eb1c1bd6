"""Seeded mutations of a URDF for ``fuzz_urdf.py``: numbers perturbed or replaced by odd values,
elements removed or duplicated, attributes dropped, names changed, types swapped, axes zeroed,
tiny or huge, limits and origins at the edges of float64, mimic relations added, links
re-parented, and the bytes re-encoded or damaged.

Tree mutations edit an lxml element tree; at most one byte mutation then acts on its text.
Two thirds of the targets are joints on the chain that is converted, so that most mutations
reach the numbers that matter.
"""

from __future__ import annotations

import codecs
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from lxml import etree

__all__ = ["MUTATIONS", "Original", "mutate"]

Rng = np.random.Generator


@dataclass(frozen=True, slots=True)
class Original:
    """A URDF to mutate: its text, the chain converted (base, tip, the joints on it)."""

    name: str
    text: str
    base: str | None
    tip: str | None
    chain: tuple[str, ...]


# odd values for a number: the grammar's edges, float64's, and things that are not numbers
ODD_NUMBERS = (
    *"nan -inf inf 1e308 -1e308 1e999 1e-300 5e-324 0 -0 1_0 0x10 1e .5 5. +1 1e50".split(),
    *"-1e51 1e16 1,5 1e-320 3.4e38 -2.5 1e154".split(),
    *("", " ", "1 2", "\u0661", "\t1", "1\t"),
)
ODD_NAMES = ("", " ", "a\nb", 'x"y', "x'y", "\u2028", "\u00fc", "j" * 300, "<&>", "a b", "#;%")
ODD_AXES = (
    *"0 0 0,1e-300 0 0,5e-324 0 0,1e308 1e308 0,1e200 0 0,1e-160 1e-160 0,0 5 0".split(","),
    *"-1 0 0,1 1 1,1e-150 0 0,1e150 1e150 0,0 0 -1e-5".split(","),
    None,  # <axis/>
)
EDGE_VALUES = (
    *"1e4 -1e5 1e6 1e16 -1e16 1e40 1e50 -1e50 1e51 1e154 1e308 -1e308 1e-300 0".split(),
    "3.141592653589793",
)
# element -> its numeric attributes (joints' and links')
NUMERIC = {
    tag: tuple(attrs.split())
    for tag, attrs in (
        item.split(":")
        for item in (
            "origin:xyz rpy|axis:xyz|limit:lower upper effort velocity|mimic:multiplier offset|"
            "mass:value|inertia:ixx iyy izz ixy|box:size|cylinder:radius length|sphere:radius|"
            "mesh:scale|color:rgba|dynamics:damping friction|"
            "safety_controller:soft_lower_limit k_velocity"
        ).split("|")
    )
}
JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar", "ball", "")


def _pick(rng: Rng, items: list[Any] | tuple[Any, ...]) -> Any:
    return items[int(rng.integers(len(items)))]


def _joints(root: Any, original: Original, rng: Rng) -> list[Any]:
    """Joints to target: those on the converted chain two times in three."""
    joints = list(root.iterchildren("joint"))
    on_chain = [j for j in joints if j.get("name") in original.chain]
    return on_chain if on_chain and rng.random() < 2 / 3 else joints


def _joint(root: Any, original: Original, rng: Rng) -> Any:
    joints = _joints(root, original, rng)
    return _pick(rng, joints) if joints else root


def number(root: Any, original: Original, rng: Rng) -> str:
    """A numeric attribute perturbed, replaced by an odd value, or given a number more or less."""
    scope = _joint(root, original, rng) if rng.random() < 2 / 3 else root
    slots = [(el, a) for el in scope.iter(*NUMERIC) for a in NUMERIC[el.tag] if el.get(a)]
    if not slots:
        return "no number found"
    el, attr = _pick(rng, slots)
    pieces = el.get(attr).split()
    k = int(rng.integers(len(pieces))) if pieces else 0
    mode = _pick(rng, ("perturb", "perturb", "odd", "odd", "count"))
    if mode == "perturb" and pieces:
        try:
            pieces[k] = repr(float(pieces[k]) * (1 + rng.normal() * 1e-3) + rng.normal() * 1e-6)
        except ValueError:
            pieces[k] = "0"
    elif mode == "count":
        pieces = pieces[:-1] if pieces and rng.random() < 0.5 else [*pieces, "4"]
    else:
        pieces[k : k + 1] = [_pick(rng, ODD_NUMBERS)]
    el.set(attr, " ".join(pieces))
    return f"{el.tag} {attr}={el.get(attr)!r}"


def axis(root: Any, original: Original, rng: Rng) -> str:
    """A joint's axis zero, tiny, huge, not unit, ``<axis/>``, or gone."""
    joint = _joint(root, original, rng)
    value = _pick(rng, ODD_AXES)
    el = joint.find("axis")
    if el is None:
        el = etree.SubElement(joint, "axis")
    if value is None:
        el.attrib.pop("xyz", None)
        return f"joint {joint.get('name')!r}: <axis/>"
    el.set("xyz", value)
    return f"joint {joint.get('name')!r}: axis {value!r}"


def edges(root: Any, original: Original, rng: Rng) -> str:
    """A joint's origin or limits at the edges of float64."""
    joint = _joint(root, original, rng)
    tag, attrs = _pick(rng, (("origin", ("xyz", "rpy")), ("limit", ("lower", "upper"))))
    el = joint.find(tag)
    if el is None:
        el = etree.SubElement(joint, tag)
    attr = _pick(rng, attrs)
    if tag == "origin":
        values = ["0", "0", "0"]
        values[int(rng.integers(3))] = _pick(rng, EDGE_VALUES)
        el.set(attr, " ".join(values))
    else:
        value = _pick(rng, EDGE_VALUES)
        el.set(attr, value)
        if rng.random() < 0.5:  # symmetric, or swapped
            other = "upper" if attr == "lower" else "lower"
            el.set(other, value[1:] if value.startswith("-") else "-" + value)
    return f"joint {joint.get('name')!r}: {tag} {attr}={el.get(attr)!r}"


def wide_limits(root: Any, original: Original, rng: Rng) -> str:
    """Every joint on the chain given the limits +-v (v from the edges of float64)."""
    value = _pick(rng, EDGE_VALUES).lstrip("-")
    for joint in root.iterchildren("joint"):
        if joint.get("name") in original.chain and joint.get("type") != "fixed":
            el = joint.find("limit")
            if el is None:
                el = etree.SubElement(joint, "limit", effort="1", velocity="1")
            el.set("lower", f"-{value}")
            el.set("upper", value)
    return f"limits +-{value} on the chain"


def remove_element(root: Any, original: Original, rng: Rng) -> str:
    """An element removed: a joint's origin, axis, limit, parent, child, or a joint or link."""
    joint = _joint(root, original, rng)
    candidates = [*joint, joint, *list(root.iterchildren("link"))[:3]]
    el = _pick(rng, candidates)
    if el.getparent() is None:
        return "nothing removed"
    el.getparent().remove(el)
    return f"removed <{el.tag} {el.get('name') or ''}>"


def duplicate_element(root: Any, original: Original, rng: Rng) -> str:
    """An element duplicated (a joint, a link, or a joint's child), the copy's numbers changed."""
    joint = _joint(root, original, rng)
    el = _pick(rng, [*joint, joint, *list(root.iterchildren("link"))[:2]])
    copy = etree.fromstring(etree.tostring(el))
    for sub in copy.iter("origin"):
        sub.set("xyz", "0.5 0.5 0.5")
    el.addnext(copy)
    return f"duplicated <{el.tag} {el.get('name') or ''}>"


def drop_attribute(root: Any, original: Original, rng: Rng) -> str:
    """An attribute dropped (a name, a type, a link reference, a number)."""
    scope = _pick(rng, (_joint(root, original, rng), root))
    slots = [(el, a) for el in scope.iter() if isinstance(el.tag, str) for a in el.attrib]
    if not slots:
        return "no attribute"
    el, attr = _pick(rng, slots)
    del el.attrib[attr]
    return f"dropped {el.tag} {attr}"


def rename(root: Any, original: Original, rng: Rng) -> str:
    """A link, joint or the robot renamed to an odd name, its references following or not."""
    kind = _pick(rng, ("link", "joint", "robot"))
    el = root if kind == "robot" else _pick(rng, list(root.iterchildren(kind)) or [root])
    old, new = el.get("name"), _pick(rng, ODD_NAMES)
    if rng.random() < 0.2:  # the name of another element of its kind
        others = [e.get("name") for e in root.iterchildren(el.tag) if e is not el]
        new = _pick(rng, others) if others else new
    el.set("name", new)
    follow = rng.random() < 0.5
    if follow:
        for ref in root.iter("parent", "child", "mimic"):
            for attr in ("link", "joint"):
                if ref.get(attr) == old:
                    ref.set(attr, new)
    return f"{el.tag} {old!r} renamed {new!r}{' everywhere' if follow else ''}"


def swap_type(root: Any, original: Original, rng: Rng) -> str:
    """A joint's type swapped."""
    joint = _joint(root, original, rng)
    joint.set("type", _pick(rng, JOINT_TYPES))
    return f"joint {joint.get('name')!r} type {joint.get('type')!r}"


def add_mimic(root: Any, original: Original, rng: Rng) -> str:
    """A mimic relation added to a joint, of a neighbour or of no joint, with an odd factor."""
    joint = _joint(root, original, rng)
    names = [j.get("name") for j in root.iterchildren("joint")]
    target = _pick(rng, [*names, "nowhere"])
    el = etree.SubElement(joint, "mimic", joint=target or "")
    el.set("multiplier", _pick(rng, ("1", "-1", "0", "1e308", "nan", "1e40", "0.01", "1e50")))
    if rng.random() < 0.3:
        el.set("offset", _pick(rng, ("0", "0.1", "1e999")))
    return f"joint {joint.get('name')!r} mimics {target!r} ({dict(el.attrib)})"


def reparent(root: Any, original: Original, rng: Rng) -> str:
    """A joint's parent or child link changed to another link."""
    joint = _joint(root, original, rng)
    role = _pick(rng, ("parent", "child"))
    el, links = joint.find(role), [link.get("name") for link in root.iterchildren("link")]
    if el is None or not links:
        return "nothing re-parented"
    el.set("link", _pick(rng, links))
    return f"joint {joint.get('name')!r} {role} {el.get('link')!r}"


LATIN1 = b'<?xml version="1.0" encoding="ISO-8859-1"?>\n'


def encode(text: str, rng: Rng) -> tuple[str, bytes]:
    """The text in another encoding, or with an XML declaration lxml refuses."""
    body = text.replace('<robot name="', '<robot name="\u00e9', 1)  # a character beyond ASCII
    choices: list[tuple[str, Callable[[], bytes]]] = [
        ("UTF-16-LE with BOM", lambda: codecs.BOM_UTF16_LE + body.encode("utf-16-le")),
        ("UTF-16-BE with BOM", lambda: codecs.BOM_UTF16_BE + body.encode("utf-16-be")),
        ("UTF-8 with BOM", lambda: codecs.BOM_UTF8 + body.encode()),
        ("UTF-32 with BOM", lambda: codecs.BOM_UTF32_LE + body.encode("utf-32-le")),
        ("version 0.0", lambda: b'<?xml version="0.0"?>\n' + body.encode()),
        ("version 2.0", lambda: b'<?xml version="2.0" encoding="utf-8"?>' + body.encode()),
        ("Latin-1, declared", lambda: LATIN1 + body.encode("latin-1", errors="replace")),
        ("Latin-1, undeclared", lambda: body.encode("latin-1", errors="replace")),
        ("CRLF line ends", lambda: body.replace("\n", "\r\n").encode()),
    ]
    name, make = _pick(rng, choices)
    return name, make()


def damage(text: str, rng: Rng) -> tuple[str, bytes]:
    """The bytes truncated, or a NUL, a stray byte or a missing character put in."""
    data = text.encode()
    at = int(rng.integers(1, len(data)))
    mode = _pick(rng, ("truncated", "NUL", "stray byte", "character removed"))
    if mode == "truncated":
        return f"truncated at byte {at}", data[:at]
    if mode == "NUL":
        return f"NUL at byte {at}", data[:at] + b"\x00" + data[at:]
    if mode == "stray byte":
        return f"byte 0xff at {at}", data[:at] + b"\xff" + data[at:]
    return f"byte {at} removed", data[:at] + data[at + 1 :]


_EDITS = (number, axis, edges, wide_limits, remove_element, duplicate_element, drop_attribute)
_EDITS += (rename, swap_type, add_mimic, reparent)
TREE: dict[str, Callable[[Any, Original, Rng], str]] = {
    f.__name__.replace("_", " "): f for f in _EDITS
}
BYTES: dict[str, Callable[[str, Rng], tuple[str, bytes]]] = {"encoding": encode, "damage": damage}
MUTATIONS = (*TREE, *BYTES)
WEIGHTS = {"number": 6, "axis": 3, "edges": 3, "encoding": 2, "damage": 1}  # others: 1


def mutate(original: Original, rng: Rng) -> tuple[tuple[str, ...], str, bytes]:
    """One to three mutations of ``original``: their kinds, a description and the bytes."""
    weights = np.array([WEIGHTS.get(k, 1) for k in MUTATIONS], dtype=float)
    count = int(_pick(rng, (1, 1, 1, 2, 3)))
    kinds = [str(k) for k in rng.choice(MUTATIONS, size=count, p=weights / weights.sum())]
    byte_kinds = [k for k in kinds if k in BYTES][:1]
    kinds = [k for k in kinds if k in TREE] + byte_kinds
    root = etree.fromstring(
        original.text.encode(), etree.XMLParser(remove_comments=True, resolve_entities=False)
    )
    said = [TREE[k](root, original, rng) for k in kinds if k in TREE]
    text = etree.tostring(root, encoding="unicode")
    data = text.encode()
    for k in byte_kinds:
        what, data = BYTES[k](text, rng)
        said.append(what)
    return tuple(kinds), f"{original.name}: " + "; ".join(said), data
