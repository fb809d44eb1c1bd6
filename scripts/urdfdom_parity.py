"""A seeded corpus of URDF variants judged against the real urdfdom: urdf2dh must accept and
refuse what Pinocchio's URDF reader accepts and refuses, and read the same numbers.

    PYTHONPATH=. python scripts/urdfdom_parity.py                 # 600 variants, seed 0
    PYTHONPATH=. python scripts/urdfdom_parity.py --count 200 --seed 7

Each case is a random chain of three to five moving joints (seeded: its joints' types,
origins, axes, limits), with one to three mutations from the classes of :data:`CLASSES`: a
number written in another form (signs, digits that are not ASCII, grouping, other bases, words,
commas, exponents, white space before, between and after, tabs and line breaks as characters
and as references), a limit taken away or changed (no ``<limit>``, no effort or velocity, a
negative one, lower above upper), a joint's other elements (dynamics, safety controller,
calibration, mimic) with attributes missing or bad, a robot version, materials, and what a
link holds (visuals, inertials, collisions, broken or not). The text is then given to
``pinocchio.buildModelFromXML`` and to ``urdf2dh convert`` (in-process). Every case must hold:

- the same verdict: urdf2dh converts the file exactly when Pinocchio loads it, except where
  urdf2dh is documented to be the stricter (:data:`STRICTER`: bounds, axes it cannot
  normalise, malformed XML);
- the same numbers: where both read the file, each joint's placement and limits in Pinocchio's
  model are urdf2dh's (limits with lower above upper read as the range between, with a warning
  naming the joint);
- a refusal is one line, ``urdf2dh: error: <file>: ...``, naming the joint when the fault is in
  a joint, and never an internal error.

It prints the cases by class and verdict, then every broken case; it exits 1 if any broke an
invariant. tests/test_urdfdom_parity.py runs a seeded sample.
"""

from __future__ import annotations

import contextlib
import io
import sys
import tempfile
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from corpus_main import corpus_main

from urdf2dh.check.verify import native_stderr
from urdf2dh.cli import main as cli
from urdf2dh.errors import shown
from urdf2dh.io.urdf import load_tree

Rng = np.random.Generator

# What urdf2dh refuses and urdfdom reads (docs/limits.md): the message says which
STRICTER = (
    "is out of range",  # LARGEST_URDF_NUMBER, LARGEST_URDF_ANGLE
    "malformed XML",  # a character XML 1.0 forbids, which tinyxml2 reads
    "zero axis",
    "too short to normalise",
    "too long to normalise",
    "has no xyz attribute",
    "an empty joint name",  # urdfdom reads a mimic of joint ""
)
NUMBERS = {  # attribute -> how many numbers, on which element of a joint
    ("origin", "xyz"): 3,
    ("origin", "rpy"): 3,
    ("axis", "xyz"): 3,
    ("limit", "lower"): 1,
    ("limit", "upper"): 1,
    ("limit", "effort"): 1,
    ("limit", "velocity"): 1,
}


@dataclass
class Joint:
    """One joint of a case, as elements: tag -> attribute -> text (``None``: the element is
    left out), and extra elements written as they are."""

    name: str
    type: str
    elements: dict[str, dict[str, str] | None]
    extra: list[str] = field(default_factory=list)


@dataclass
class Robot:
    """A case's robot, written by :meth:`text`."""

    joints: list[Joint]
    version: str | None = None
    materials: list[str] = field(default_factory=list)
    link_inside: dict[int, str] = field(default_factory=dict)

    def text(self) -> str:
        head = '<robot name="r"' + ("" if self.version is None else f' version="{self.version}"')
        parts = [head + ">", *self.materials]
        for k in range(len(self.joints) + 1):
            parts.append(f'<link name="l{k}">{self.link_inside.get(k, "")}</link>')
        for k, j in enumerate(self.joints):
            inner = [f'<parent link="l{k}"/><child link="l{k + 1}"/>']
            for tag, attributes in j.elements.items():
                if attributes is not None:
                    shown_attributes = "".join(f' {a}="{v}"' for a, v in attributes.items())
                    inner.append(f"<{tag}{shown_attributes}/>")
            inner += j.extra
            parts.append(f'<joint name="{j.name}" type="{j.type}">{"".join(inner)}</joint>')
        return "\n".join([*parts, "</robot>"])


@dataclass(frozen=True, slots=True)
class Case:
    kinds: tuple[str, ...]
    description: str
    text: str
    joint: str | None  # the joint a fault is in, if it is in one


@dataclass(frozen=True, slots=True)
class Outcome:
    case: Case
    pinocchio: bool  # Pinocchio loads it
    code: int  # urdf2dh convert's exit code
    err: str
    problems: tuple[str, ...]

    @property
    def verdict(self) -> str:
        ours = "converts" if self.code == 0 else f"exit {self.code}"
        return f"Pinocchio {'loads' if self.pinocchio else 'refuses'}, urdf2dh {ours}"


def _plain(rng: Rng, low: float, high: float) -> str:
    return f"{rng.uniform(low, high):.{int(rng.integers(1, 7))}g}"


def robot(rng: Rng) -> Robot:
    """A random valid chain of 3 to 5 moving joints."""
    joints = []
    for k in range(int(rng.integers(3, 6))):
        jtype = str(rng.choice(["revolute", "revolute", "prismatic", "continuous"]))
        axis = [0.0, 0.0, 0.0]
        axis[int(rng.integers(3))] = float(rng.choice([-1.0, 1.0]))
        elements: dict[str, dict[str, str] | None] = {
            "origin": {
                "xyz": " ".join(_plain(rng, -0.5, 0.5) for _ in range(3)),
                "rpy": " ".join(_plain(rng, -3, 3) for _ in range(3)),
            },
            "axis": {"xyz": " ".join(f"{a:g}" for a in axis)},
            "limit": None,
        }
        if jtype != "continuous":
            low = float(rng.uniform(-3, -0.1))
            elements["limit"] = {
                "lower": f"{low:.4g}",
                "upper": f"{rng.uniform(0.1, 3):.4g}",
                "effort": _plain(rng, 0, 100),
                "velocity": _plain(rng, 0, 5),
            }
        joints.append(Joint(f"j{k + 1}", jtype, elements))
    return Robot(joints)


# ----------------------------------------------------------------------------- number forms

_DIGITS = "0123456789"
_FULL_WIDTH = "０１２３４５６７８９"
_ARABIC = "٠١٢٣٤٥٦٧٨٩"
_SPACES = (" ", "\t", "\n", "\r", "\r\n", "&#9;", "&#10;", "&#13;", "&#32;", "\u00a0", "  ")
_WORDS = ("nan", "NaN", "inf", "-inf", "Infinity", ".inf", "0x1F", "0X10", "0o17", "0b101",
          "1,5", "1d0", "0.1f", "1e", "1e+", "--1", "+-1", ".", "-.", "1.2.3", "e5", "1e999",
          "-1e400", "1e-400", "4.9e-324", "1.8e308", "2:50", "١", "1 000", "½")  # fmt: skip


def _digits(rng: Rng, n: int) -> str:
    pool = _DIGITS if rng.random() < 0.85 else str(rng.choice([_FULL_WIDTH, _ARABIC]))
    text = "".join(pool[int(rng.integers(10))] for _ in range(n))
    if rng.random() < 0.08 and n > 1:
        cut = int(rng.integers(1, n))
        text = text[:cut] + "_" + text[cut:]
    return text


def number(rng: Rng) -> str:
    """A number in a random form: mostly of the grammar, often just outside it."""
    if rng.random() < 0.15:
        return str(rng.choice(_WORDS))
    sign = str(
        rng.choice(["", "", "", "-", "+", "--", "+-"], p=[0.3, 0.2, 0.1, 0.2, 0.1, 0.05, 0.05])
    )
    whole = _digits(rng, int(rng.integers(0, 4)))
    point = str(rng.choice(["", ".", ","], p=[0.4, 0.55, 0.05]))
    fraction = _digits(rng, int(rng.integers(0, 5)))
    exponent = ""
    if rng.random() < 0.25:
        exponent = (str(rng.choice(["e", "E"])) + str(rng.choice(["", "+", "-"]))
                    + _digits(rng, int(rng.integers(0, 4))))  # fmt: skip
    text = sign + whole + point + fraction + exponent
    return text or "0"


def numbers_text(rng: Rng, count: int) -> str:
    """``count`` numbers (or one more or fewer), with random white space before, between and
    after them."""
    n = count + int(rng.choice([0, 0, 0, 0, 0, 1, -1]))
    pieces = [number(rng) if rng.random() < 0.35 else _plain(rng, -2, 2) for _ in range(max(n, 0))]
    out = (
        str(rng.choice(["", "", "", " ", "  ", "\t", "&#9;", "\n", " \n"]))
        if rng.random() < 0.3
        else ""
    )
    for i, piece in enumerate(pieces):
        if i:
            out += " " if rng.random() < 0.75 else str(rng.choice(_SPACES))
        out += piece
    if rng.random() < 0.15:
        out += str(rng.choice(_SPACES))
    return out


# ----------------------------------------------------------------------------- mutations


def _moving(rng: Rng, r: Robot) -> Joint:
    return r.joints[int(rng.integers(len(r.joints)))]


def mutate_number(rng: Rng, r: Robot) -> tuple[str, str | None]:
    j = _moving(rng, r)
    choices = [key for key in NUMBERS if j.elements.get(key[0]) is not None]
    tag, attribute = choices[int(rng.integers(len(choices)))]
    text = numbers_text(rng, NUMBERS[tag, attribute])
    element = j.elements[tag]
    assert element is not None
    element[attribute] = text
    return f"{j.name} {tag} {attribute} = {text!r}", j.name


def mutate_limit(rng: Rng, r: Robot) -> tuple[str, str | None]:
    j = _moving(rng, r)
    what = str(rng.choice(["none", "drop", "negative", "inverted", "on continuous", "bare"]))
    limit = j.elements.get("limit")
    if what == "on continuous" or limit is None:
        j.type = str(rng.choice(["continuous", "fixed"]))
        j.elements["limit"] = {"lower": "1", "upper": "-1", "effort": "1", "velocity": "1"}
        for attribute in rng.choice(
            ["lower", "upper", "effort", "velocity"], int(rng.integers(3)), replace=False
        ):
            del j.elements["limit"][str(attribute)]
        return f"{j.name} {j.type} with {j.elements['limit']}", j.name
    if what == "none":
        j.elements["limit"] = None
    elif what == "drop":
        for attribute in rng.choice(
            ["lower", "upper", "effort", "velocity"], int(rng.integers(1, 3)), replace=False
        ):
            limit.pop(str(attribute), None)
    elif what == "negative":
        limit[str(rng.choice(["effort", "velocity"]))] = str(
            rng.choice(["-1", "-0", "-1e-400", "-0.5"])
        )
    elif what == "inverted":
        limit["lower"], limit["upper"] = limit.get("upper", "0"), limit.get("lower", "0")
    else:
        j.elements["limit"] = {}
    return f"{j.name} {j.type} limit {what}: {j.elements['limit']}", j.name


def mutate_parts(rng: Rng, r: Robot) -> tuple[str, str | None]:
    j = _moving(rng, r)
    tag = str(rng.choice(["dynamics", "safety_controller", "calibration", "mimic"]))
    attributes = {
        "dynamics": ["damping", "friction"],
        "safety_controller": ["soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"],
        "calibration": ["rising", "falling"],
        "mimic": ["multiplier", "offset"],
    }[tag]
    chosen = [a for a in attributes if rng.random() < 0.5]
    values = {a: (number(rng) if rng.random() < 0.4 else _plain(rng, 0, 2)) for a in chosen}
    if tag == "mimic":
        others = [o.name for o in r.joints if o is not j and o.type == j.type]
        if rng.random() < 0.8 and others:
            values["joint"] = str(rng.choice(others))
        elif rng.random() < 0.5:
            values["joint"] = ""
    shown_values = "".join(f' {a}="{v}"' for a, v in values.items())
    j.extra.append(f"<{tag}{shown_values}/>")
    return f"{j.name} <{tag}{shown_values}/>", j.name


def mutate_version(rng: Rng, r: Robot) -> tuple[str, str | None]:
    major = str(rng.choice(["1", "1", "0", "2", "01", "+1", " 1", "-1", "4294967297", "", "1.0"]))
    minor = str(rng.choice(["0", "1", "2", "3", "00", "-0", "+1", " 0", "0 ", "x", "", "10"]))
    r.version = str(
        rng.choice([f"{major}.{minor}", major, f"{major}.{minor}.0"], p=[0.8, 0.1, 0.1])
    )
    return f"version {r.version!r}", None


def mutate_materials(rng: Rng, r: Robot) -> tuple[str, str | None]:
    for _ in range(int(rng.integers(1, 4))):
        name = str(rng.choice(["", "red", "blue", None]))
        named = "" if name == "None" else f' name="{name}"'
        color = '<color rgba="1 0 0 1"/>' if rng.random() < 0.7 else '<color rgba="1 0"/>'
        r.materials.append(f"<material{named}>{color}</material>")
    return f"materials {r.materials}", None


def mutate_link(rng: Rng, r: Robot) -> tuple[str, str | None]:
    k = int(rng.integers(len(r.joints) + 1))
    inside = str(rng.choice([
        "<visual><geometry><box/></geometry></visual>",
        '<visual><origin xyz="a b"/><geometry><sphere radius="x"/></geometry></visual>',
        f'<inertial><origin rpy="{numbers_text(rng, 3)}"/><mass value="{number(rng)}"/></inertial>',
        "<inertial/>",
        "<collision><geometry/></collision>",
        '<visual><geometry><mesh filename="nowhere.stl" scale="1 1"/></geometry></visual>',
    ]))  # fmt: skip
    r.link_inside[k] = inside
    return f"link l{k}: {inside}", None


CLASSES: dict[str, Callable[[Rng, Robot], tuple[str, str | None]]] = {
    "number": mutate_number,
    "limit": mutate_limit,
    "joint parts": mutate_parts,
    "version": mutate_version,
    "materials": mutate_materials,
    "link contents": mutate_link,
}
WEIGHTS = {"number": 5, "limit": 3, "joint parts": 2, "version": 1, "materials": 1,
           "link contents": 1}  # fmt: skip


def cases(count: int, seed: int) -> list[Case]:
    """``count`` seeded cases, each with one to three mutations (the first of a class drawn in
    turn, so that a sample of a few dozen reaches every class)."""
    rng = np.random.default_rng(seed)
    names = list(CLASSES)
    p = np.array([WEIGHTS[n] for n in names], dtype=float)
    out = []
    for i in range(count):
        r = robot(rng)
        kinds = [names[i % len(names)]]
        kinds += [str(k) for k in rng.choice(names, int(rng.integers(0, 3)), p=p / p.sum())]
        said, joints = [], []
        for kind in kinds:
            description, joint = CLASSES[kind](rng, r)
            said.append(description)
            joints.append(joint)
        joint = joints[0] if len(kinds) == 1 else None
        out.append(Case(tuple(kinds), "; ".join(said), r.text(), joint))
    return out


# ----------------------------------------------------------------------------- judging


def pinocchio_model(text: str) -> object | None:
    """Pinocchio's model of the text, or ``None`` where it refuses it (urdfdom's lines to file
    descriptor 2 kept from the terminal)."""
    import pinocchio as pin

    with native_stderr():
        try:
            return pin.buildModelFromXML(text)
        except Exception:  # Pinocchio raises RuntimeError/ValueError with C++ text
            return None


def _same_numbers(model: object, path: Path) -> list[str]:
    """Each joint's placement and limits as Pinocchio has them against urdf2dh's tree."""
    tree = load_tree(path)
    problems: list[str] = []
    if any(j.type == "fixed" for j in tree.joints.values()):
        return problems  # Pinocchio merges a fixed joint's origin into the next joint's
    for k in range(1, model.njoints):  # type: ignore[attr-defined]
        name = model.names[k]  # type: ignore[attr-defined]
        ours = tree.joints[name]
        theirs = model.jointPlacements[k].homogeneous  # type: ignore[attr-defined]
        if np.abs(theirs - ours.origin).max() > 1e-12 * max(1.0, np.abs(ours.origin).max()):
            problems.append(f"joint {name}: placement differs from Pinocchio's")
        if ours.lower is not None and ours.type == "revolute":
            q = model.idx_qs[k]  # type: ignore[attr-defined]
            lo = model.lowerPositionLimit[q]  # type: ignore[attr-defined]
            hi = model.upperPositionLimit[q]  # type: ignore[attr-defined]
            if sorted((lo, hi)) != [ours.lower, ours.upper]:
                problems.append(
                    f"joint {name}: limits [{lo}, {hi}] read as [{ours.lower}, {ours.upper}]"
                )
    return problems


def run_case(case: Case, tmp: Path, index: int) -> Outcome:
    path = tmp / f"case{index}.urdf"
    path.write_text(case.text, encoding="utf-8")
    model = pinocchio_model(case.text)
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = cli(["convert", str(path)])
        except SystemExit as e:
            code = e.code if isinstance(e.code, int) else 2
    problems = judge(case, str(path), model is not None, code, err.getvalue())
    if model is not None and code == 0:
        problems += _same_numbers(model, path)
        inverted = [n for n, j in load_tree(path).joints.items() if j.swapped]
        for name in inverted:
            if f"warning: joint {shown(name)}: its <limit> has lower" not in out.getvalue():
                problems.append(f"joint {name}: lower above upper, and no warning names it")
    return Outcome(case, model is not None, code, err.getvalue(), tuple(problems))


def judge(case: Case, path: str, pinocchio: bool, code: int, err: str) -> list[str]:
    """The invariants of the module docstring that a run breaks."""
    problems = []
    if "internal error" in err or "Traceback" in err:
        problems.append(f"internal error: {err.strip()[:300]}")
    if code not in (0, 2):
        problems.append(f"exit code {code}")
    if code == 2:
        lines = err.splitlines()
        if len(lines) != 1 or not lines[0].startswith(f"urdf2dh: error: {path}: "):
            problems.append(f"refusal is not one line naming the file: {err[:300]!r}")
        elif case.joint is not None and pinocchio is False and f"joint '{case.joint}'" not in err:
            if "<robot" not in err and "material" not in err and "malformed XML" not in err:
                problems.append(f"refusal does not name joint {case.joint}: {lines[0][:300]}")
    if pinocchio and code == 2 and not any(reason in err for reason in STRICTER):
        problems.append(f"Pinocchio loads it, urdf2dh refuses it: {err.strip()[:300]}")
    if not pinocchio and code == 0:
        problems.append("Pinocchio refuses it, urdf2dh converts it")
    return problems


def run_corpus(count: int, seed: int) -> list[Outcome]:
    with tempfile.TemporaryDirectory(prefix="urdf2dh-parity-") as directory:
        return [run_case(c, Path(directory), i) for i, c in enumerate(cases(count, seed))]


def report(outcomes: list[Outcome]) -> str:
    lines = [f"{len(outcomes)} URDF variants judged against Pinocchio's urdfdom", ""]
    lines.append("By class (first mutation) and verdict:")
    by = Counter((o.case.kinds[0], o.verdict) for o in outcomes)
    for kind in CLASSES:
        shown_verdicts = ", ".join(f"{v}: {n}" for (k, v), n in sorted(by.items()) if k == kind)
        lines.append(f"  {kind:<14} {shown_verdicts}")
    totals = Counter(o.verdict for o in outcomes)
    lines += ["", "All: " + ", ".join(f"{v}: {n}" for v, n in sorted(totals.items()))]
    broken = [o for o in outcomes if o.problems]
    lines += ["", f"Cases that broke an invariant: {len(broken)}"]
    for o in broken:
        lines.append(
            f"  [{', '.join(o.case.kinds)}] {o.case.description[:160]!r}: " + "; ".join(o.problems)
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    return corpus_main(__doc__, run_corpus, report, 600, argv)


if __name__ == "__main__":
    sys.exit(main())
