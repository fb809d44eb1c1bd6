"""Hostile names (security): a robot, link or joint name (or a file name) can no longer
turn an exported file against its reader.

Every target and format is run on robots whose names hold each character that ends a string,
a comment or a line somewhere, and on a seeded sample of the corpus (scripts/hostile_names.py
runs all of it). Each file must read, in its own language and as its consumer reads it, exactly
as its clean twin's does with the names put in (safety.py); a name a language cannot carry is
refused with exit 2 and one line naming it. The escaping functions are also checked one by one
against those readers, on seeded random text.
"""

from __future__ import annotations

import ast
import csv
import html
import io
import re
from dataclasses import replace

import numpy as np
import pytest
import yaml
from consumers import FakeKdl, RigidBodyTree, SerialLink, genserkins_links, kdl_fk, real_pykdl
from corpus import Corpus
from hal_reader import FGETS_BYTES, read_hal
from hostile import (
    CLASSIC,
    CONTROLS,
    FRAGMENTS,
    KINDS,
    RUNS,
    Names,
    chain,
    clean_names,
    run,
    write_source,
)
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree
from matlab_reader import read_matlab
from safety import FORMULA, judge

from urdf2dh import cli, load, to_table
from urdf2dh import escape as esc
from urdf2dh.emit.export import export_table, table_choices
from urdf2dh.emit.scene import short
from urdf2dh.errors import ExportError, shown, visible

DANGEROUS = {
    "quote": "'",
    "double-quote": '"',
    "triple-double": '"""',
    "triple-single": "'''",
    "backslash": "\\",
    "LF": "\n",
    "CR": "\r",
    "CRLF": "\r\n",
    "U+2028": "\u2028",
    "U+2029": "\u2029",
    "NEL": "\x85",
    "percent": "%",
    "hash": "#",
    "semicolon": ";",
    "dashes": "--",
    "cdata-end": "]]>",
    "xacro": "${x}",
    "bidi": "\u202e",
    "pipe": "|",
    "formula": "=1+1",
    "fullwidth-formula": "\uff1dcmd|' /C calc'!A0",
    "invisible": "\u200b\u200d\u2066\u202e\u2069\u200e\u00ad\ufeff\U000e0041\U000e007f\u180e",
    "all": "\"\"\"'''\\\n\r\u2028%#;--]]>${x}|",
}
SAMPLE = sorted({0, *np.random.default_rng(12).choice(200, size=20, replace=False).tolist()})


@pytest.fixture(scope="module")
def corpus():
    c = Corpus()
    yield c
    c.close()


def names_with(d: str, geometry: str) -> Names:
    """Every name of the chain holding ``d``: alone, first, last, in the middle."""
    c = chain(geometry)
    forms = [d, f"{d}x", f"x{d}", f"x{d}y", f"{d}{d}"]
    joints = tuple(forms[i % 5] + "j" * (i // 5) for i in range(c.movable))
    return Names(
        f"robot{d}",
        f"{d}base",
        f"tip{d}",
        joints,
        tuple(f"l{i}{d}" for i in range(len(c.joints) - 1)),
        tuple(f"f{i}{d}" for i in range(len(c.joints) - c.movable)),
        "file" + "".join(c for c in d if c not in "/\x00\ud800"),
    )


def _failures(verdicts):
    return [(v.run, v.result, v.detail[:300]) for v in verdicts if v.result != "written"]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("d", DANGEROUS.values(), ids=DANGEROUS.keys())
def test_every_target_writes_dangerous_characters_safely(corpus, d, kind):
    others = [r for r in RUNS if r != ("export", "ur")]
    verdicts = corpus.check(names_with(d, "genser6"), "genser6", kind, others)
    verdicts += corpus.check(names_with(d, "ur5"), "ur5", kind, [("export", "ur")])
    assert _failures(verdicts) == []


@pytest.mark.parametrize("control", CONTROLS, ids=[repr(c) for c in CONTROLS])
def test_names_xml_cannot_carry_are_refused_by_urdf_only(corpus, control):
    names = names_with(control, "genser6")
    verdicts = {
        v.run: v
        for v in corpus.check(
            names, "genser6", "poe-json", [r for r in RUNS if r != ("export", "ur")]
        )
    }
    refusal = verdicts.pop("convert urdf")
    assert refusal.result == "refused"
    assert "XML 1.0 cannot carry" in refusal.detail and shown(names.joints[0]) in refusal.detail
    assert _failures(verdicts.values()) == []  # CSV included: visible text holds any name


@pytest.mark.parametrize("seed", SAMPLE)
def test_corpus_sample(corpus, seed):
    assert _failures(v for v in corpus.robot(seed) if v.result != "refused") == []


# --------------------------------------------------------------------------- consumers


def _table(tmp_path, names, target, geometry="genser6", convention=None):
    source = write_source(tmp_path, geometry, names, "urdf")
    model = load(str(tmp_path / source), names.base, names.tip)
    convention, style = table_choices(target, convention, None)
    return to_table(model, convention, style=style)


def test_the_classic_attacks_run_nothing_and_keep_their_names(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    clean = clean_names("genser6")
    texts = {}
    for names in (CLASSIC, clean):
        for target in ("rtb", "kdl", "matlab", "corke-matlab", "linuxcnc"):
            texts[names.robot, target] = export_table(_table(tmp_path, names, target), target)
    namespace: dict = {"__name__": "__main__guarded"}
    exec(compile(texts[CLASSIC.robot, "rtb"], "rtb.py", "exec"), namespace)
    robot = namespace["robot"]
    assert robot.name == CLASSIC.robot and robot.n == 6  # (DHRobot renames its links)
    kdl = real_pykdl() or FakeKdl
    q = np.random.default_rng(3).uniform(-1, 1, (5, 6))
    assert np.allclose(
        kdl_fk(kdl, texts[CLASSIC.robot, "kdl"], q),
        kdl_fk(kdl, texts[clean.robot, "kdl"], q),
        atol=1e-12,
    )
    tree = RigidBodyTree(texts[CLASSIC.robot, "matlab"])
    assert tree.base == CLASSIC.base and CLASSIC.tip in tree.bodies
    assert [tree.bodies[b]["joint"]["name"] for b in tree.order] == list(CLASSIC.joints)
    assert SerialLink(texts[CLASSIC.robot, "corke-matlab"]).name == CLASSIC.robot
    hal = texts[CLASSIC.robot, "linuxcnc"]
    assert genserkins_links(hal) == genserkins_links(texts[clean.robot, "linuxcnc"])
    assert len(read_hal(hal).commands) == 18
    assert not (tmp_path / "PWNED").exists()


def test_plot_labels_take_any_name(tmp_path):
    """The picture's title names the robot and its chain: as drawn, visible text (no
    mathtext from ``$``), shortened; no name becomes SVG markup."""
    names = names_with("$\\evil{$\n--><script>x</script>", "genser6")
    source = write_source(tmp_path, "genser6", names, "urdf")
    got = run(tmp_path, source, "plot", "svg", names, "urdf")
    assert (got.code, got.stderr, got.crashed) == (0, "", None)
    svg = etree.fromstring(got.output)
    assert not [e for e in svg.iter() if "script" in str(e.tag)]
    comments = [html.unescape(c.text).strip().replace("- -", "--") for c in svg.iter(etree.Comment)]
    title = f"{visible(short(names.robot))}: standard D-H frames at home"
    chain = f"{visible(short(names.base))} -> {visible(short(names.tip))}"
    assert title in comments and chain in comments  # (a comment per line)


def test_a_hostile_length_unit_stays_in_its_place(tmp_path):
    """A POE file's ``length_unit`` is text from the file too: formats and targets that take
    any unit write it as they write names; those that convert it refuse it on one line."""
    unit = 'mm] |\n"""\nimport os\n<script>\x1b[2J%\r\nsetp genserkins.A-0 9'
    names, clean = clean_names("genser6"), {}
    for label, u in (("clean", "QZU"), ("hostile", unit)):
        (tmp_path / label).mkdir()
        source = write_source(tmp_path / label, "genser6", names, "poe-json", u)
        clean[label] = {r: run(tmp_path / label, source, *r, names, "poe-json") for r in RUNS}
    for r in RUNS:
        got, want = clean["hostile"][r], clean["clean"][r]
        assert got.crashed is None and got.code == want.code, (r, got.stderr)
        if got.code:
            assert got.stderr.count("\n") == 1 and got.stderr[:-1].isprintable()
            assert visible(unit) in got.stderr or shown(unit) in got.stderr
        elif r[1] != "poe":  # (the POE file keeps the unit, as YAML)
            judge(r[1], got.output, want.output, {"QZU": unit})


def test_ur_yaml_keeps_its_keys(tmp_path):
    names = Names(
        "x: 1\nevil: [2]",
        "b\u2028evil: 1",
        "t\x85evil: 1",
        ("a\nevil: 1", "b\revil: 2", "c\r\nevil: 3", "d\u2029", "e#", "f'\""),
        tuple(f"l{i}\n- x" for i in range(len(chain("ur5").joints) - 1)),
        tuple(f"f{i}" for i in range(3)),
        "s",
    )
    text = export_table(_table(tmp_path, names, "ur", "ur5"), "ur")
    assert list(yaml.safe_load(text)) == ["kinematics"]
    assert "# UR default_kinematics.yaml for x: 1\\nevil: [2] (" in text


def test_refusals_name_the_joint_on_one_line(tmp_path):
    source = write_source(tmp_path, "genser6", CLASSIC, "urdf")
    got = run(tmp_path, source, "export", "linuxcnc", CLASSIC, "urdf", ["--convention", "dh"])
    assert got.code == 2 and got.output is None and got.stderr.count("\n") == 1
    assert "linuxcnc takes mdh tables, not dh" in got.stderr
    assert shown(CLASSIC.joints[0]) in got.stderr  # 'j1"\nsystem(...)%', its line break escaped
    # the chain the other way round (--base and --tip swapped): a chain error naming both
    swapped = [f"--base={CLASSIC.tip}", f"--tip={CLASSIC.base}"]
    got = run(tmp_path, source, "export", "ur", CLASSIC, "table", swapped)
    assert got.code == 2 and got.stderr.count("\n") == 1 and shown(CLASSIC.tip) in got.stderr
    with pytest.raises(ExportError) as e:
        esc.xml_attribute("j\x01\n", "joint")
    assert str(e.value).count("\n") == 0 and "'j\\x01\\n'" in str(e.value)


# --------------------------------------------------------------------------- the functions

TEXT = st.lists(st.one_of(st.characters(), st.sampled_from(FRAGMENTS + CONTROLS)), max_size=12).map(
    "".join
)
EXAMPLES = settings(derandomize=True, max_examples=300, deadline=None)


@EXAMPLES
@given(TEXT)
def test_python_literals_hold_any_name(text):
    assert ast.literal_eval(esc.python_string(text)) == text
    doc = esc.python_docstring([f"a {text}", text], block=True)
    assert ast.literal_eval(doc) == f"a {text}\n{text}\n"
    assert len(ast.parse(f"x = 1\n{doc}\ny = 2\n").body) == 3


@EXAMPLES
@given(TEXT)
def test_matlab_literals_hold_any_name(text):
    for quote in "\"'":
        script = read_matlab(f"x = {esc.matlab_string(text, quote)};  {esc.matlab_comment(text)}\n")
        assert len(script.statements) == 1 and script.statements[0].value.value == text
        assert script.comments == [" " + visible(text)]


@EXAMPLES
@given(TEXT)
def test_comments_never_end_early(text):
    assert yaml.safe_load(f"a: 1\n{esc.yaml_comment(text)}\nb: 2\n") == {"a": 1, "b": 2}
    lines = esc.hal_comment(text * 40)
    hal = read_hal("\n".join(["setp x 1", *lines, "setp y 2"]) + "\n")
    assert hal.commands == [["setp", "x", "1"], ["setp", "y", "2"]]
    assert all(len(line.encode()) < FGETS_BYTES for line in lines)
    assert "".join(c[1:] for c in hal.comments[: len(lines)]) == visible(text * 40)
    root = etree.fromstring(f"<r>{esc.xml_comment(text)}</r>".encode())
    assert len(root) == 1 and root[0].text == " " + re.sub("-(?=-)", "- ", visible(text)) + " "


@EXAMPLES
@given(TEXT)
def test_xml_attributes_hold_any_name_xml_can_carry(text):
    try:
        value = esc.xml_attribute(text, "joint")
    except ExportError:
        assert any(not esc._xml_char(c) for c in text)
        return
    assert etree.fromstring(f"<a n={value}/>".encode()).get("n") == text


@EXAMPLES
@given(TEXT)
def test_markdown_and_csv_cells_hold_any_name(text):
    from markdown_it import MarkdownIt

    tokens = (
        MarkdownIt("commonmark")
        .enable("table")
        .parse(f"| h | g |\n|---|---|\n| {esc.markdown_text(text)} | x |\n")
    )
    cells = [t for t in tokens if t.type == "inline"]
    assert len(cells) == 4 and {c.type for c in cells[2].children} <= {"text", "text_special"}
    assert "".join(c.content for c in cells[2].children) == visible(text)
    cell = esc.csv_cell(text)
    rows = list(csv.reader(io.StringIO(f"a,{cell},b\n", newline="")))
    want = visible(text)
    assert rows == [["a", "'" + want if want.startswith(FORMULA) else want, "b"]]
    assert rows[0][1].isprintable() and not rows[0][1].startswith(FORMULA)
    assert esc.csv_names(["x", rows[0][1]], [text]) == ["x", text]


@EXAMPLES
@given(TEXT)
def test_messages_show_names_on_one_line(text):
    assert len(shown(text).splitlines()) <= 1 and shown(text).isprintable()
    assert visible(text).isprintable() and ast.literal_eval(repr(text)) == text
    if len(text) <= 120:
        assert shown(text) == repr(text)


def test_measure_writes_names_as_csv_text_and_calibrate_reads_them_back(tmp_path, monkeypatch):
    """``measure``'s header: each joint name as ``csv_cell`` writes it (visible text, a leading
    ``'`` before a formula start), and ``calibrate`` finds the joints by those cells."""
    hostile = ("=SUM(A1)", "\u202eevil\u202c", "a,b\"c", "\u200bzero\u00adsoft", "@x",
               "\uff1dcmd\U000e0041")  # fmt: skip
    names = replace(clean_names("ur5"), joints=hostile)
    source = write_source(tmp_path, "ur5", names, "poe-json")
    monkeypatch.chdir(tmp_path)
    assert cli.main(["measure", source, "--configs", "40", "-o", "m.csv"]) == 0
    header = next(csv.reader(io.StringIO((tmp_path / "m.csv").read_text(), newline="")))
    assert header[:6] == ["'=SUM(A1)", "\\u202eevil\\u202c", 'a,b"c', "\\u200bzero\\xadsoft",
                          "'@x", "'\uff1dcmd\\U000e0041"]  # fmt: skip
    assert all(c.isprintable() and not c.startswith(FORMULA) for c in header)
    assert cli.main(["calibrate", source, "m.csv", "-o", "back.yaml"]) == 0
