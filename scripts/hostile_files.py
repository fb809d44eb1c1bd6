"""A seeded corpus of hostile and huge inputs: wrong-number YAML, repeated keys, sources that are
not files, files and chains beyond the bounds, names of megabytes, XML and YAML bombs.

    PYTHONPATH=. python scripts/hostile_files.py                 # 240 cases, seed 0
    PYTHONPATH=. python scripts/hostile_files.py --count 40 --seed 5

Each case is one input of one attack class (:data:`CLASSES`), run in-process through
``urdf2dh convert -o FILE``, ``verify`` and ``info`` (``urdf2dh.cli.main``). Every run must hold:

- no traceback and no "internal error"; exit codes 0, 1 or 2 only; within :data:`SECONDS`;
- a failing command writes one line, ``urdf2dh: error: ...``, naming the file, at most
  ``errors.MESSAGE_LENGTH`` characters long (a name of megabytes is shortened);
- ``convert`` that fails leaves no output file;
- the class's own verdict: a YAML 1.1 number is refused naming the field (never read as YAML 1.1
  reads it), a repeated key is refused naming it, a source that is not a regular file or is
  beyond a bound is refused naming the bound, a bomb is refused, not expanded.

The script prints the runs by class and outcome, then every case that broke an invariant, and
exits 1 if one did. The test suite runs a seeded sample (tests/test_hostile_files.py).
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
import socket
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from chains import random_chain_urdf  # noqa: E402  (tests/chains.py)
from corpus_main import corpus_main as seeded_main  # noqa: E402  (beside this script)

from urdf2dh.check.verify import native_stderr  # noqa: E402
from urdf2dh.cli import main as cli  # noqa: E402
from urdf2dh.errors import MESSAGE_LENGTH  # noqa: E402
from urdf2dh.tolerances import FILE_BYTES, JOINTS, MAPPING_VALUES, VERIFY_JOINTS  # noqa: E402

SECONDS = 60.0  # a run taking longer breaks the "bounded" invariant
Rng = np.random.Generator

# (text where a number is expected, what YAML 1.1 reads it as): all refused by urdf2dh
YAML11 = (
    ("0100", "octal 64"),
    ("-0100", "octal -64"),
    ("0777", "octal 511"),
    ("2:50", "170"),
    ("1:30.5", "90.5"),
    ("-1:00", "-60"),
    ("1_000", "1000"),
    ("0.000_1", "0.0001"),
    ("0b101", "5"),
    ("0x_1F", "31"),
    ("yes", "true"),
    ("No", "false"),
    ("on", "true"),
    ("OFF", "false"),
)
# YAML 1.2 numbers of urdf2dh's one grammar: read as YAML 1.2 reads them (0x1F, 0o17, .inf and
# .nan, numbers to YAML 1.2 but not of the grammar, are the "number grammar" class's)
YAML12 = (("1e3", 1000.0), ("+.5", 0.5), ("2.", 2.0), ("-0", 0.0), ("1E-3", 0.001))

POE = """format: poe
name: arm
length_unit: mm
joints:
  - {{name: j1, twist: [0, 0, 1, 0, 0, 0], limits: [-1, {a}]}}
  - {{name: j2, twist: [0, 1, 0, {b}, 0, 0], mimic: {{joint: j1, multiplier: {c}}}}}
  - {{name: j3, twist: [1, 0, 0, 0, {d}, 0]}}
tool:
  twist: [0, 0, 0, {e}, 0, 0]
"""
POE_FIELDS = {  # placeholder -> the field a refusal names, and its plain value
    "a": ("joint 'j1' limits", "1"),
    "b": ("joint 'j2' twist", "-300"),
    "c": ("joint 'j2': mimic multiplier", "1"),
    "d": ("joint 'j3' twist", "200"),
    "e": ("tool twist", "100"),
}


@dataclass(frozen=True, slots=True)
class Run:
    """One command on one case: exit code, what it wrote, seconds taken."""

    argv: tuple[str, ...]
    code: int
    out: str
    err: str
    seconds: float


@dataclass(frozen=True, slots=True)
class Case:
    """An input and what must become of it: ``refusal`` the phrase (or one of the phrases)
    every failing command's
    message holds (``None``: the case may be read), ``exit_0`` whether convert must succeed."""

    kind: str
    description: str
    path: str
    refusal: str | tuple[str, ...] | None
    commands: tuple[str, ...] = ("convert", "verify", "info")
    exit_0: bool = False


@dataclass(frozen=True, slots=True)
class Outcome:
    case: Case
    runs: tuple[Run, ...]
    problems: tuple[str, ...]


# ----------------------------------------------------------------------------- the classes


def yaml11_number(rng: Rng, tmp: Path, i: int) -> Case:
    """A POE file with a YAML 1.1 number where a number is expected."""
    field = str(rng.choice(list(POE_FIELDS)))
    text, reading = YAML11[int(rng.integers(len(YAML11)))]
    values = {k: v for k, (_, v) in POE_FIELDS.items()} | {field: text}
    path = tmp / f"case{i}.yaml"
    path.write_text(POE.format(**values))
    where = POE_FIELDS[field][0]
    return Case("yaml 1.1 number", f"{where} = {text} (YAML 1.1: {reading})", str(path),
                f"{where} must be a number, not {text!r}")  # fmt: skip


def yaml12_number(rng: Rng, tmp: Path, i: int) -> Case:
    """A POE file with a YAML 1.2 number that YAML 1.1 reads otherwise (or not at all)."""
    text, value = YAML12[int(rng.integers(len(YAML12)))]
    values = {k: v for k, (_, v) in POE_FIELDS.items()} | {"a": text}
    path = tmp / f"case{i}.yaml"
    path.write_text(POE.format(**values))
    return Case("yaml 1.2 number", f"limits upper = {text} (= {value:g})", str(path), None,
                ("convert",), exit_0=True)  # fmt: skip


def number_grammar(rng: Rng, tmp: Path, i: int) -> Case:
    """A URDF attribute or a POE field holding a text outside the one number grammar
    (urdf2dh.numerals), made up from its parts: signs, digits that are not ASCII, digits grouped,
    other bases, words, commas, broken exponents."""
    text = _not_a_number(rng)
    if rng.random() < 0.5 and re.search(r"\w", text) and "," not in text:  # one YAML scalar
        field = str(rng.choice(list(POE_FIELDS)))
        values = {k: v for k, (_, v) in POE_FIELDS.items()} | {field: text}
        path = tmp / f"case{i}.yaml"
        path.write_text(POE.format(**values), encoding="utf-8")
        where = POE_FIELDS[field][0]
        return Case("number grammar", f"{where} = {text!r}", str(path),
                    (f"{where} must be a number, not", f"{where} must be finite"))  # fmt: skip
    urdf, _ = random_chain_urdf(int(rng.integers(1000)), 5)
    joint, (start, end) = _limited_joint(rng, urdf)
    attribute = str(rng.choice(["origin xyz", "limit upper"]))
    if attribute == "origin xyz":
        urdf = re.sub(f'(<joint name="{joint}".*?<origin xyz=")[^"]*"', rf'\g<1>0 {text} 0"',
                      urdf, count=1, flags=re.S)  # fmt: skip
    else:
        limit = re.sub(r'upper="[^"]*"', f'upper="{text}"', urdf[start:end])
        urdf = urdf[:start] + limit + urdf[end:]
    path = tmp / f"case{i}.urdf"
    path.write_text(urdf, encoding="utf-8")
    return Case("number grammar", f"{joint} {attribute} holds {text!r}", str(path),
                f"joint '{joint}': {attribute}")  # fmt: skip


def _limited_joint(rng: Rng, urdf: str) -> tuple[str, tuple[int, int]]:
    """A joint of ``urdf`` that has a <limit>, and where the limit's text is."""
    pattern = r'<joint name="([^"]*)"[^>]*>(?:(?!</joint>).)*?(<limit[^>]*/>)'
    limited = list(re.finditer(pattern, urdf))
    m = limited[int(rng.integers(len(limited)))]
    return m[1], m.span(2)


def _not_a_number(rng: Rng) -> str:
    """A seeded text that is not a number of the grammar (urdf2dh.numerals.decimal says so)."""
    from urdf2dh.numerals import decimal

    if rng.random() < 0.15:
        return str(rng.choice(["1e999", "-1e400", "nan", "0x1F", "0o17", ".nan", "1,5"]))
    parts = (
        ("", "-", "+", "--", "+-"),
        ("1", "12", "\uff11", "\u0661", "1_2", "", "0x1", "0o7", "0b1", "\u0663\u0663"),
        ("", ".", ".5", "._5"),
        ("", "e", "E+", "e-3", "e1_0", "e\uff13", "d0", "f"),
        ("", "", "", "nan", "inf", "Infinity", ".inf"),
    )
    while True:
        text = "".join(str(rng.choice(p)) for p in parts)
        if text and decimal(text) is None:
            return text


def urdf_limits(rng: Rng, tmp: Path, i: int) -> Case:
    """A URDF joint whose <limit> urdfdom refuses (none on a revolute joint, no effort or
    velocity, a negative one, lower above upper in a URDF of version 1.2), or whose lower is
    above its upper (read as the range between, with a warning)."""
    urdf, _ = random_chain_urdf(int(rng.integers(1000)), 5)
    joint, (start, end) = _limited_joint(rng, urdf)
    old = urdf[start:end]
    what = str(rng.choice(["none", "no effort", "no velocity", "negative", "1.2 inverted",
                           "inverted"]))  # fmt: skip
    new = {
        "none": "",
        "no effort": re.sub(r' effort="[^"]*"', "", old),
        "no velocity": re.sub(r' velocity="[^"]*"', "", old),
        "negative": re.sub(r' effort="[^"]*"', ' effort="-1"', old),
        "1.2 inverted": '<limit lower="1" upper="-1" effort="1" velocity="1"/>',
        "inverted": '<limit lower="1" upper="-1" effort="1" velocity="1"/>',
    }[what]
    urdf = urdf[:start] + new + urdf[end:]
    if what == "1.2 inverted":
        urdf = urdf.replace("<robot ", '<robot version="1.2" ', 1)
    path = tmp / f"case{i}.urdf"
    path.write_text(urdf, encoding="utf-8")
    if what == "inverted":
        return Case("urdf limits", f"{joint}: lower above upper", str(path), None, ("convert",),
                    exit_0=True)  # fmt: skip
    return Case("urdf limits", f"{joint}: limit {what}", str(path), f"joint '{joint}'")


def repeated_key(rng: Rng, tmp: Path, i: int) -> Case:
    """A POE file in YAML or JSON with a key given twice in one mapping."""
    as_json = bool(rng.integers(2))
    joint = {"name": "j1", "twist": [0, 0, 1, 0, 0, 0], "limits": [-1, 1]}
    tree = {"format": "poe", "name": "arm", "joints": [joint],
            "tool": {"twist": [0, 0, 0, 100, 0, 0]}}  # fmt: skip
    key = str(rng.choice(["name", "twist", "limits", "format", "tool"]))
    value = joint.get(key, tree.get(key))
    text = json.dumps(tree)
    at = text.index(f'"{key}": ')
    text = text[:at] + f'"{key}": {json.dumps(value)}, ' + text[at:]  # the key once more
    if not as_json:
        text = text.replace('"', "")  # the same tree as YAML (flow style, plain scalars)
    path = tmp / f"case{i}.{'json' if as_json else 'yaml'}"
    path.write_text(text)
    return Case("repeated key", f"{key} twice ({path.suffix})", str(path),
                f"key '{key}' appears twice in one mapping")  # fmt: skip


def not_a_file(rng: Rng, tmp: Path, i: int) -> Case:
    """A source that is a FIFO (no writer), a character device, a socket or a directory."""
    what = str(rng.choice(["fifo", "zero", "socket", "directory", "stdin"]))
    if what == "fifo":
        path = str(tmp / f"case{i}.urdf")
        os.mkfifo(path)
    elif what == "zero":
        path = "/dev/zero"
    elif what == "stdin":
        path = "/dev/stdin"
    elif what == "socket":
        path = str(tmp / f"case{i}.yaml")
        server = socket.socket(socket.AF_UNIX)
        server.bind(path)  # left bound until the directory goes: a socket file to read
        _SOCKETS.append(server)
    else:
        path = str(tmp / f"case{i}.urdf")
        os.mkdir(path)
    refusal = "is a directory" if what == "directory" else "not a regular file"
    return Case("not a file", what, path, refusal)


_SOCKETS: list[socket.socket] = []


def huge_file(rng: Rng, tmp: Path, i: int) -> Case:
    """A regular file beyond FILE_BYTES (sparse: written in no time), URDF or YAML."""
    suffix = str(rng.choice([".urdf", ".yaml", ".json"]))
    path = tmp / f"case{i}{suffix}"
    with open(path, "wb") as f:
        f.write(b"<robot name='r'>" if suffix == ".urdf" else b"format: poe\n")
        f.truncate(FILE_BYTES + 1 + int(rng.integers(1000)))
    return Case("huge file", f"{path.stat().st_size:,} bytes", str(path), "larger than")


def long_chain(rng: Rng, tmp: Path, i: int) -> Case:
    """A chain beyond a bound: a URDF of JOINTS + 1 joints (convert refuses), one of
    VERIFY_JOINTS + 1 (verify refuses, convert reads it), a POE file of JOINTS + 1, or a comb
    (a leaf on every link of a chain) whose chains have more than JOINTS joints in all."""
    what = str(rng.choice(["urdf", "verify", "poe", "comb"]))
    if what == "comb":
        n = int(rng.integers(150, 3000))
        links, joints = ['<link name="c0"/>'], []
        for k in range(1, n + 1):
            links += [f'<link name="c{k}"/>', f'<link name="t{k}"/>']
            joints += [
                f'<joint name="j{k}" type="revolute"><parent link="c{k - 1}"/>'
                f'<child link="c{k}"/><origin xyz="0.1 0 0" rpy="0.3 0 0"/><axis xyz="0 0 1"/>'
                '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>',
                f'<joint name="f{k}" type="fixed"><parent link="c{k}"/><child link="t{k}"/>'
                "</joint>",
            ]
        path = tmp / f"case{i}.urdf"
        path.write_text('<robot name="comb">' + "".join(links + joints) + "</robot>")
        return Case("long chain", f"comb of {n:,} links, --all-tips", str(path),
                    (f"joints in all; one run converts at most {JOINTS:,}",
                     f"verify checks at most {VERIFY_JOINTS:,}"),
                    ("convert --all-tips", "verify --all-tips"))  # fmt: skip
    if what == "poe":
        path = tmp / f"case{i}.yaml"
        rows = "".join(f"  - {{name: j{k}, twist: [0, 0, 1, {k % 7}, 0, 0]}}\n"
                       for k in range(JOINTS + 1))  # fmt: skip
        path.write_text(f"format: poe\njoints:\n{rows}tool: {{twist: [0, 0, 0, 1, 0, 0]}}\n")
        return Case("long chain", f"POE of {JOINTS + 1:,} joints", str(path),
                    f"{JOINTS + 1:,} joints; urdf2dh reads chains of at most")  # fmt: skip
    joints = JOINTS + 1 if what == "urdf" else VERIFY_JOINTS
    path = tmp / f"case{i}.urdf"
    path.write_text(random_chain_urdf(int(rng.integers(1000)), joints)[0])  # + the tool joint
    if what == "urdf":
        bound = f"urdf2dh reads URDFs of at most {JOINTS:,} joints"
        return Case("long chain", f"URDF of {joints:,} joints", str(path), bound)
    return Case("long chain", f"URDF of {joints + 1:,} joints, verified", str(path),
                f"verify checks at most {VERIFY_JOINTS:,}", ("verify",))  # fmt: skip


def long_name(rng: Rng, tmp: Path, i: int) -> Case:
    """A name of megabytes where a message names it: a joint's undeclared child link, a
    duplicated link, a POE joint with a bad twist, an unknown --tip."""
    character = str(rng.choice(["x", "\u00e9", "\n", "'"]))
    # at most twice in the file, each under libxml2's 10 MB and both under FILE_BYTES ("\n" is
    # written "&#10;", five bytes)
    size = int(rng.choice([300_000, 1_000_000]))
    name = character * size
    what = str(rng.choice(["child", "twice", "poe", "type"]))
    if what == "poe":
        path = tmp / f"case{i}.json"
        tree = {"format": "poe", "joints": [{"name": name, "twist": [0, 0, 0, 0, 0, 0]}],
                "tool": {"twist": [0, 0, 0, 1, 0, 0]}}  # fmt: skip
        path.write_text(json.dumps(tree, ensure_ascii=False))
        return Case("long name", f"POE joint name of {size:,}", str(path), "zero twist")
    path = tmp / f"case{i}.urdf"
    from lxml import etree

    robot = etree.Element("robot", name="r")
    etree.SubElement(robot, "link", name="base")
    if what == "twice":
        etree.SubElement(robot, "link", name=name)
        etree.SubElement(robot, "link", name=name)
        refusal = "is declared twice"
    else:
        joint = etree.SubElement(robot, "joint", name=name if what == "child" else "j",
                                 type="revolute" if what == "child" else name)  # fmt: skip
        etree.SubElement(joint, "parent", link="base")
        etree.SubElement(joint, "child", link=name if what == "child" else "base")
        refusal = "names undeclared link" if what == "child" else "unknown type"
    path.write_bytes(etree.tostring(robot, encoding="utf-8"))
    return Case("long name", f"{what} of {size:,} characters", str(path), refusal)


def xml_bomb(rng: Rng, tmp: Path, i: int) -> Case:
    """XML beyond libxml2's limits: an attribute or text node over 10 MB, nesting 300 deep,
    entities expanding a billion-fold."""
    what = str(rng.choice(["attribute", "text", "depth", "entities"]))
    path = tmp / f"case{i}.urdf"
    if what == "attribute":
        text = '<robot name="' + "a" * 11_000_000 + '"><link name="l"/></robot>'
    elif what == "text":
        text = '<robot name="r"><link name="l">' + "x" * 11_000_000 + "</link></robot>"
    elif what == "depth":
        text = '<robot name="r">' + "<a>" * 300 + "</a>" * 300 + "</robot>"
    else:
        entities = '<!ENTITY e0 "lol">' + "".join(
            f'<!ENTITY e{k} "{f"&e{k - 1};" * 10}">' for k in range(1, 10)
        )
        text = f'<?xml version="1.0"?><!DOCTYPE robot [{entities}]><robot name="&e9;"/>'
    path.write_text(text)
    return Case("xml bomb", what, str(path), "beyond the XML parser's limits")


def yaml_bomb(rng: Rng, tmp: Path, i: int) -> Case:
    """YAML aliases expanding a billion-fold, or nesting thousands deep."""
    what = str(rng.choice(["aliases", "depth"]))
    path = tmp / f"case{i}.yaml"
    if what == "aliases":
        lines = ["a0: &a0 [lol, lol, lol, lol, lol, lol, lol, lol, lol, lol]"]
        lines += [f"a{k}: &a{k} [{', '.join([f'*a{k - 1}'] * 10)}]" for k in range(1, 10)]
        path.write_text("\n".join(lines) + "\nformat: poe\n")
        refusal = f"more than {MAPPING_VALUES:,} values"
    else:
        path.write_text("format: poe\njoints: " + "[" * 20_000 + "]" * 20_000 + "\n")
        refusal = "nested too deeply"
    return Case("yaml bomb", what, str(path), refusal)


CLASSES: dict[str, Callable[[Rng, Path, int], Case]] = {
    "yaml 1.1 number": yaml11_number,
    "yaml 1.2 number": yaml12_number,
    "number grammar": number_grammar,
    "urdf limits": urdf_limits,
    "repeated key": repeated_key,
    "not a file": not_a_file,
    "huge file": huge_file,
    "long chain": long_chain,
    "long name": long_name,
    "xml bomb": xml_bomb,
    "yaml bomb": yaml_bomb,
}
HEAVY = ("long chain",)  # one case of each in a sample; each costs seconds


# ----------------------------------------------------------------------------- running


def command(argv: list[str]) -> Run:
    """``urdf2dh ARGV`` in this process, its output (and C++ code's on descriptor 2) caught."""
    out, err = io.StringIO(), io.StringIO()
    started = time.perf_counter()
    with (
        native_stderr() as native,
        contextlib.redirect_stdout(out),
        contextlib.redirect_stderr(err),
    ):
        try:
            code = cli(argv)
        except SystemExit as e:  # argparse: a usage error
            code = e.code if isinstance(e.code, int) else 2
    seconds = time.perf_counter() - started
    text = err.getvalue() + "".join(f"{line}\n" for line in native)
    return Run(tuple(argv), code, out.getvalue(), text, seconds)


def run_case(case: Case, tmp: Path, index: int) -> Outcome:
    """Run the case's commands and judge them."""
    runs, problems = [], []
    for name in case.commands:
        output = tmp / f"out{index}.json"
        argv = {
            "convert": ["convert", case.path, "--format", "json", "-o", str(output)],
            "verify": ["verify", case.path, "--samples", "10"],
            "info": ["info", case.path],
            "convert --all-tips": ["convert", case.path, "--all-tips", "-o", str(output)],
            "verify --all-tips": ["verify", case.path, "--all-tips", "--samples", "10"],
        }[name]
        run = command(argv)
        runs.append(run)
        problems += [f"{name}: {p}" for p in judge(case, run)]
        if name.startswith("convert") and run.code != 0 and output.exists():
            problems.append("convert failed, yet wrote its output")
        if name == "convert" and case.exit_0 and run.code != 0:
            problems.append(f"convert refused a valid file: {run.err.strip()[:300]}")
        output.unlink(missing_ok=True)
    return Outcome(case, tuple(runs), tuple(problems))


def judge(case: Case, run: Run) -> list[str]:
    """The invariants of the module docstring that ``run`` breaks."""
    problems = []
    text = run.out + run.err
    if "Traceback" in text:
        problems.append("traceback")
    if "internal error" in text:
        problems.append(f"internal error: {run.err.strip()[:300]}")
    if run.code not in (0, 1, 2):
        problems.append(f"exit code {run.code}")
    if run.seconds > SECONDS:
        problems.append(f"took {run.seconds:.0f} s")
    if run.code == 2:
        lines = run.err.splitlines()
        if len(lines) != 1 or not lines[0].startswith("urdf2dh: error: "):
            problems.append(f"error is not one line: {run.err[:300]!r}")
        elif len(lines[0]) > MESSAGE_LENGTH + len("urdf2dh: error: "):
            problems.append(f"error line of {len(lines[0]):,} characters")
        elif case.path not in lines[0]:
            problems.append(f"error does not name the file: {lines[0][:300]}")
        elif case.refusal is not None and not any(
            phrase in lines[0]
            for phrase in ((case.refusal,) if isinstance(case.refusal, str) else case.refusal)
        ):
            problems.append(f"refused, but not for {case.refusal!r}: {lines[0][:300]}")
    elif case.refusal is not None:
        problems.append(f"exit {run.code}: not refused ({case.refusal!r} expected)")
    return problems


def cases(
    count: int, seed: int, tmp: Path, classes: tuple[str, ...] = tuple(CLASSES)
) -> list[Case]:
    """``count`` seeded cases over ``classes`` in turn (each class of HEAVY at most once)."""
    rng = np.random.default_rng(seed)
    out: list[Case] = []
    heavy_done: set[str] = set()
    for i in range(count):
        kind = classes[i % len(classes)]
        if kind in HEAVY:
            if kind in heavy_done and count < 4 * len(classes):
                continue
            heavy_done.add(kind)
        out.append(CLASSES[kind](rng, tmp, i))
    return out


def run_corpus(count: int, seed: int) -> list[Outcome]:
    """Make and run ``count`` seeded cases."""
    with tempfile.TemporaryDirectory(prefix="urdf2dh-hostile-files-") as directory:
        tmp = Path(directory)
        try:
            return [run_case(c, tmp, i) for i, c in enumerate(cases(count, seed, tmp))]
        finally:
            for s in _SOCKETS:
                s.close()
            _SOCKETS.clear()


def report(outcomes: list[Outcome], classes: dict[str, object] | None = None) -> str:
    """Runs by class (of ``classes``, default :data:`CLASSES`) and outcome, then every case
    that broke an invariant."""
    lines = [f"{len(outcomes)} hostile inputs, {sum(len(o.runs) for o in outcomes)} runs", ""]
    by_class = Counter((o.case.kind, r.code) for o in outcomes for r in o.runs)
    lines.append("By class (runs by exit code):")
    for kind in CLASSES if classes is None else classes:
        codes = {code: n for (k, code), n in by_class.items() if k == kind}
        if codes:
            shown = ", ".join(f"exit {c}: {n}" for c, n in sorted(codes.items()))
            slowest = max(r.seconds for o in outcomes if o.case.kind == kind for r in o.runs)
            lines.append(f"  {kind:<16} {shown}  (slowest run {slowest:.1f} s)")
    broken = [o for o in outcomes if o.problems]
    lines += ["", f"Cases that broke an invariant: {len(broken)}"]
    for o in broken:
        lines.append(f"  {o.case.kind} ({o.case.description[:80]}): " + "; ".join(o.problems))
    return "\n".join(lines)


def corpus_main(
    argv: list[str] | None,
    description: str,
    run: Callable[[int, int], list[Outcome]],
    classes: dict[str, object],
    count: int,
) -> int:
    """A corpus script's command line: ``--count`` cases, ``--seed``; the report by
    ``classes``; exit 1 if a case broke an invariant (scripts/hostile_mjcf.py runs its own
    corpus through it)."""
    return seeded_main(description, run, lambda outcomes: report(outcomes, classes), count, argv)


def main(argv: list[str] | None = None) -> int:
    return corpus_main(argv, __doc__.splitlines()[0], run_corpus, CLASSES, 240)


if __name__ == "__main__":
    sys.exit(main())
