"""Is a file written for a hostile robot safe? Compared with its clean twin, in its language.

A file is safe when it parses in its language (as its consumer reads it) into exactly the
structure the clean twin's file has (statements, assignments, keys, live lines, elements, table
cells), and every place that held a placeholder name holds the hostile name: exactly where the
language has string values (Python, MATLAB, XML attributes, JSON, YAML, CSV cells, Pinocchio's
model), or as :func:`urdf2dh.errors.visible` shows it where it has none (comments, text and
Markdown for people). :func:`judge` raises :class:`Unsafe` with the reason otherwise.
"""

from __future__ import annotations

import ast
import csv
import io
import json
import re
from collections.abc import Callable
from typing import Any

import numpy as np
import yaml
from hal_reader import HalSyntaxError, read_hal
from lxml import etree
from matlab_reader import Call, Chars, MatlabSyntaxError, Str, read_matlab
from view_reader import read_page

from urdf2dh.emit.names import RENAMED
from urdf2dh.emit.scene import short
from urdf2dh.errors import visible
from urdf2dh.escape import html_text, ikdh_name

LANGUAGE = {
    "rtb": "python",
    "kdl": "python",
    "matlab": "matlab",
    "corke-matlab": "matlab",
    "linuxcnc": "hal",
    "ur": "yaml-comments",
    "urdf": "xml",
    "json": "json",
    "yaml": "yaml",
    "poe": "yaml",
    "csv": "csv",
    "text": "text",
    "markdown": "markdown",
    "opw": "yaml-comments",  # main's OPW target: YAML, names in comments only
    "eaik": "python",
    "ikdh": "ikdh",  # YAML read by ikdh's line scanner: names in comments and the name line
    "html": "html",  # plot's interactive view
}
# CSV: cells a spreadsheet reads as formulas (OWASP), with the full-width forms
FORMULA = ("=", "+", "-", "@", "\t", "\r", "\uff1d", "\uff0b", "\uff0d", "\uff20")
# the self-check's measured errors (round-off of this machine; the unit may hold line breaks)
CHECK = re.compile(r"(check: FK against the source at \d+ configurations:).*?error \S+ rad", re.S)


class Unsafe(AssertionError):
    """The hostile file differs from its clean twin beyond the names."""


def substitute(text: str, names: dict[str, str], show: Callable[[str], str] = str) -> str:
    """``text`` with every placeholder replaced by its name as ``show`` writes it."""
    if not names:
        return text
    pattern = "|".join(re.escape(k) for k in sorted(names, key=len, reverse=True))
    return re.sub(pattern, lambda m: show(names[m[0]]), text)


class Renames:
    """The made-up names a file says it changed (its notes, :mod:`urdf2dh.emit.names`): a
    string may differ from the clean twin's only as ``name`` -> ``name_<k>``, and only where a
    note states that change (shown as ``show`` writes names in the file's notes); every note
    must account for a change."""

    def __init__(self, notes: list[str], show: Callable[[str], str] = str) -> None:
        self.notes, self.show, self.used = notes, show, set()

    def allow(self, got: str, want: str) -> bool:
        if not re.fullmatch(re.escape(want) + r"_(?:[2-9]|[1-9]\d+)", got, re.S):
            return False
        said = f" {self.show(want)} to {self.show(got)}: "
        hits = [i for i, note in enumerate(self.notes) if said in note]
        self.used.update(hits)
        return bool(hits)

    def check(self, where: str) -> None:
        unused = [n for i, n in enumerate(self.notes) if i not in self.used]
        if unused:
            raise Unsafe(f"{where}: a renaming note with no renamed name: {unused[0]!r}")


NO_RENAMES = Renames([])


def _notes(lines: list[str], prefix: str = "") -> tuple[list[str], list[str]]:
    """``lines`` without the renaming notes, and the notes."""
    notes = [x for x in lines if x.startswith(prefix + RENAMED)]
    return [x for x in lines if not x.startswith(prefix + RENAMED)], notes


def _same(
    got: Any, clean: Any, names: dict[str, str], where: str, renames: Renames = NO_RENAMES
) -> None:
    """Trees equal but for the names in string leaves (and the renamings the file states)."""
    if isinstance(clean, dict):
        if not isinstance(got, dict) or list(got) != [substitute(k, names) for k in clean]:
            raise Unsafe(
                f"{where}: keys {list(got) if isinstance(got, dict) else got!r}, "
                f"clean {list(clean)!r}"
            )
        for (k, v), g in zip(clean.items(), got.values(), strict=True):
            _same(g, v, names, f"{where}.{k}", renames)
    elif isinstance(clean, list | tuple):
        if not isinstance(got, list | tuple) or len(got) != len(clean):
            raise Unsafe(f"{where}: {got!r} is not a list like {clean!r}")
        for i, (g, c) in enumerate(zip(got, clean, strict=True)):
            _same(g, c, names, f"{where}[{i}]", renames)
    elif isinstance(clean, str):
        want = substitute(clean, names)
        if got != want and not (isinstance(got, str) and renames.allow(got, want)):
            raise Unsafe(f"{where}: {got!r}, expected {substitute(clean, names)!r}")
    elif got != clean or type(got) is not type(clean):
        raise Unsafe(f"{where}: {got!r} != clean {clean!r}")


def _comments(
    got: list[str], clean: list[str], names: dict[str, str], where: str, squeeze: bool = False
) -> None:
    """Comments equal to the clean ones with the names as :func:`visible` shows them (with runs
    of spaces as one where ``squeeze``: columns padded to the names' widths)."""

    def norm(text: str) -> str:
        text = CHECK.sub(r"\1", text)
        return re.sub(" +", " ", text) if squeeze else text

    want = [norm(substitute(c, names, visible)) for c in clean]
    got = [norm(g) for g in got]
    if got != want:
        bad = next(
            i for i, (g, w) in enumerate(zip([*got, ""], [*want, ""], strict=False)) if g != w
        )
        raise Unsafe(
            f"{where} comment {bad}: {got[bad : bad + 1]!r}, expected {want[bad : bad + 1]!r}"
        )


# --------------------------------------------------------------------------- per language


def _unique(names: list[Any], what: str) -> None:
    dup = next((n for i, n in enumerate(names) if n in names[:i]), None)
    if dup is not None:
        raise Unsafe(f"two {what}s named {dup!r}")


def _kdl_names(tree: ast.AST) -> None:
    """A KDL chain's segment names are each used once (a ``KDL::Tree`` refuses a second), and so
    are its joint names."""
    calls: dict[str, list[Any]] = {"Segment": [], "Joint": []}
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            if node.func.attr in calls and node.args and isinstance(node.args[0], ast.Constant):
                calls[node.func.attr].append(node.args[0].value)
    for kind, seen in calls.items():
        _unique(seen, f"KDL {kind.lower()}")


def _python(text: str, clean: str, names: dict[str, str]) -> None:
    trees = []
    for t in (text, clean):
        try:
            tree = ast.parse(t)
        except SyntaxError as e:
            raise Unsafe(f"Python does not parse: {e}") from e
        _kdl_names(tree)
        strings, notes = [], []
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                kept, said = _notes(node.value.split("\n"))
                strings.append("\n".join(kept))
                notes += said
                node.value = "S"
        trees.append((ast.dump(tree), strings, notes))
    (shape, strings, notes), (clean_shape, clean_strings, _) = trees
    if shape != clean_shape:
        raise Unsafe("Python statements differ from the clean file's")
    renames = Renames(notes)
    _same(
        [CHECK.sub(r"\1", s) for s in strings],
        [CHECK.sub(r"\1", s) for s in clean_strings],
        names,
        "python strings",
        renames,
    )
    renames.check("python")


def _matlab_values(value: Any, strings: list[str]) -> Any:
    if isinstance(value, Str | Chars):
        strings.append(value.value)
        return type(value)("S")
    if isinstance(value, Call):
        return Call(value.name, tuple(_matlab_values(a, strings) for a in value.args))
    if isinstance(value, np.ndarray):
        return (value.shape, tuple(value.ravel().tolist()))
    return value


def _matlab(text: str, clean: str, names: dict[str, str]) -> None:
    got, want = read_matlab(text), read_matlab(clean)
    built = [
        s.value.name for s in got.statements if s.target == "robot" and isinstance(s.value, Call)
    ]
    if built == ["rigidBodyTree"]:  # as addBody builds it: every body and joint named once
        from consumers import RigidBodyTree

        try:
            RigidBodyTree(text)
        except AssertionError as e:
            raise Unsafe(f"MATLAB rigidBodyTree: {e}") from e
    for script, shapes, strings in (
        (got, g_shapes := [], g_strings := []),
        (want, w_shapes := [], w_strings := []),
    ):
        for s in script.statements:
            shapes.append((s.target, _matlab_values(s.value, strings)))
    if g_shapes != w_shapes:
        raise Unsafe("MATLAB statements differ from the clean file's")
    comments, notes = _notes(got.comments, " ")
    renames = Renames(notes, visible)
    _same(g_strings, w_strings, names, "MATLAB strings", renames)
    renames.check("MATLAB")
    _comments(comments, want.comments, names, "MATLAB")


# the comments urdf2dh reads a controller file back with (io/halfile, io/opwfile): JSON, ASCII
CHAIN = re.compile(r"urdf2dh (?:chain|joint \d+): ")


def _chain_comments(text: str) -> tuple[str, list[Any]]:
    """``text`` (comments run together) without its ``urdf2dh chain:`` comment and the
    ``urdf2dh joint i:`` ones right after it, and their JSON values: each its prefix, then ASCII
    JSON as :func:`visible` shows it (backslashes doubled)."""
    start = text.find("urdf2dh chain: ")
    if start < 0:
        return text, []
    plain, where, i = [], [], start  # text[start:] with doubled backslashes single; its places
    while i < len(text):
        where.append(i)
        pair = text.startswith("\\\\", i)
        plain.append(text[i])
        i += 2 if pair else 1
    where.append(len(text))
    joined = "".join(plain)
    values, at, decoder = [], 0, json.JSONDecoder()
    while (m := CHAIN.match(joined, at)) is not None:
        try:
            value, at = decoder.raw_decode(joined, m.end())
        except json.JSONDecodeError as e:
            raise Unsafe(f"an urdf2dh chain comment is not JSON: {e}") from e
        if not joined[m.start() : at].isascii():
            raise Unsafe("an urdf2dh chain comment holds a character beyond ASCII")
        values.append(value)
    return text[:start] + text[where[at] :], values


def _hal(text: str, clean: str, names: dict[str, str]) -> None:
    got, want = read_hal(text), read_hal(clean)
    if got.commands != want.commands:
        raise Unsafe(f"HAL live lines {got.commands!r} differ from the clean file's")
    joined = "".join(c[1:] if c.startswith(" ") else c for c in got.comments)
    clean_joined = "".join(c[1:] for c in want.comments)
    joined, chain = _chain_comments(joined)
    clean_joined, clean_chain = _chain_comments(clean_joined)
    _same(chain, clean_chain, names, "HAL chain comments")
    _comments([joined], [clean_joined], names, "HAL")


def _yaml_comments(text: str, clean: str, names: dict[str, str]) -> None:
    try:
        tree = yaml.safe_load(text)
    except yaml.YAMLError as e:
        raise Unsafe(f"YAML does not load: {e}") from e
    if tree != yaml.safe_load(clean):
        raise Unsafe("YAML keys or values differ from the clean file's")
    lines, clean_lines = text.split("\n"), clean.split("\n")
    if len(lines) != len(clean_lines):
        raise Unsafe("the YAML file has another number of lines than the clean one")
    comments = [x[1:].lstrip() for x in lines if x.startswith("#")]
    clean_comments = [x[1:].lstrip() for x in clean_lines if x.startswith("#")]
    chain = [v for x in comments if CHAIN.match(x) for v in _chain_comments(x)[1]]
    clean_chain = [v for x in clean_comments if CHAIN.match(x) for v in _chain_comments(x)[1]]
    _same(chain, clean_chain, names, "YAML chain comments")
    _comments(
        ["# " + x for x in comments if not CHAIN.match(x)],
        ["# " + x for x in clean_comments if not CHAIN.match(x)],
        names,
        "YAML",
        squeeze=True,
    )


def _ikdh(text: str, clean: str, names: dict[str, str]) -> None:
    """An ikdh robot file: the clean file's YAML but for the ``name:`` line, which holds the name
    as :func:`urdf2dh.escape.ikdh_name` writes it, and its comments; read by ikdh's own line
    scanner (``ikdh.load_robot``), the same table and limits as the clean file's."""
    import tempfile

    import ikdh

    try:
        got, want = yaml.safe_load(text), yaml.safe_load(clean)
    except yaml.YAMLError as e:
        raise Unsafe(f"YAML does not load: {e}") from e
    if not isinstance(got, dict) or got.get("name") != ikdh_name(substitute(want["name"], names)):
        raise Unsafe(f"ikdh name line {got.get('name') if isinstance(got, dict) else got!r}")
    if {**got, "name": None} != {**want, "name": None}:
        raise Unsafe("YAML keys or values differ from the clean file's")
    read = []
    with tempfile.TemporaryDirectory() as work:
        for i, t in enumerate((text, clean)):
            path = f"{work}/{i}.yaml"
            with open(path, "w") as f:
                f.write(t)
            robot = ikdh.load_robot(path)
            read.append([list(getattr(robot.dh, k)) for k in ("a", "d", "alpha", "theta")]
                        + [list(robot.limits.lo), list(robot.limits.hi)])  # fmt: skip
    if read[0] != read[1]:
        raise Unsafe("ikdh reads another table from it than from the clean file")
    _yaml_comments(
        text.replace(f"name: {got['name']}", "name: N"),
        clean.replace(f"name: {want['name']}", "name: N"),
        names,
    )


def _tree(text: str, clean: str, names: dict[str, str], load: Callable[[str], Any]) -> None:
    try:
        got = load(text)
    except Exception as e:
        raise Unsafe(f"does not load: {type(e).__name__}: {e}") from e
    _same(_mask(got), _mask(load(clean)), names, "tree")


def _mask(tree: Any) -> Any:
    if isinstance(tree, dict):
        return {k: ("..." if k == "check" else _mask(v)) for k, v in tree.items()}
    if isinstance(tree, list):
        return [_mask(v) for v in tree]
    return tree


def _xml(text: str, clean: str, names: dict[str, str]) -> None:
    try:
        root = etree.fromstring(text.encode("utf-8"))
    except etree.XMLSyntaxError as e:
        raise Unsafe(f"XML does not parse: {e}") from e
    clean_root = etree.fromstring(clean.encode("utf-8"))
    for tag in ("link", "joint"):  # a URDF names each link once and each joint once
        _unique([e.get("name") for e in root.iter(tag)], f"URDF {tag}")
    got_nodes = list(root.itersiblings(preceding=True))[::-1] + list(root.iter())
    notes = [g.text for g in got_nodes if isinstance(g, etree._Comment)]
    notes = _notes(notes, " ")[1]
    got_nodes = [g for g in got_nodes if not (isinstance(g, etree._Comment) and g.text in notes)]
    renames = Renames(notes, lambda n: re.sub("-(?=-)", "- ", visible(n)))
    want_nodes = list(clean_root.itersiblings(preceding=True))[::-1] + list(clean_root.iter())
    if len(got_nodes) != len(want_nodes):
        raise Unsafe("XML has other nodes than the clean file")
    for g, w in zip(got_nodes, want_nodes, strict=True):
        if isinstance(w, etree._Comment):
            want = re.sub("-(?=-)", "- ", substitute(w.text, names, visible))
            if not isinstance(g, etree._Comment) or g.text != want:
                raise Unsafe(f"XML comment {g.text!r}, expected {want!r}")
            continue
        if g.tag != w.tag or list(g.attrib) != list(w.attrib):
            raise Unsafe(f"XML element {g.tag} {dict(g.attrib)} unlike {w.tag} {dict(w.attrib)}")
        _same(dict(g.attrib), dict(w.attrib), names, f"<{g.tag}>", renames)
    renames.check("XML")
    import pinocchio as pin

    model, clean_model = pin.buildModelFromXML(text), pin.buildModelFromXML(clean)
    _same(list(model.names), list(clean_model.names), names, "Pinocchio joint names", renames)
    _same(model.name, clean_model.name, names, "Pinocchio model name")


def _csv(text: str, clean: str, names: dict[str, str]) -> None:
    rows = list(csv.reader(io.StringIO(text, newline="")))
    clean_rows = list(csv.reader(io.StringIO(clean, newline="")))
    if [len(r) for r in rows] != [len(r) for r in clean_rows]:
        raise Unsafe("CSV rows or cells differ from the clean file's")
    for row, clean_row in zip(rows, clean_rows, strict=True):
        for cell, want in zip(row, clean_row, strict=True):
            if want in names:  # a name: as visible() shows it, never starting a formula
                name = visible(names[want])
                want = "'" + name if name.startswith(FORMULA) else name
                if not cell.isprintable() or cell.startswith(FORMULA):
                    raise Unsafe(f"CSV cell {cell!r} holds an invisible character or a formula")
            if cell != want:
                raise Unsafe(f"CSV cell {cell!r}, expected {want!r}")


def _text(text: str, clean: str, names: dict[str, str]) -> None:
    lines, clean_lines = text.split("\n"), clean.split("\n")
    if len(lines) != len(clean_lines):
        raise Unsafe("the text has another number of lines than the clean one")
    if not all(line.isprintable() for line in lines):
        raise Unsafe("the text holds unprintable characters (terminal controls)")
    for line, want in zip(lines, clean_lines, strict=True):
        if want and set(want) <= {"-", " "}:  # the rule under the header: as wide as columns
            if len(line.split()) != len(want.split()) or not set(line) <= {"-", " "}:
                raise Unsafe(f"text rule {line!r} unlike {want!r}")
            continue
        want = " ".join(CHECK.sub(r"\1", substitute(want, names, visible)).split())
        if " ".join(CHECK.sub(r"\1", line).split()) != want:
            raise Unsafe(f"text line {line!r}, expected {want!r}")


def _markdown_tokens(text: str) -> list[tuple[str, str]]:
    from markdown_it import MarkdownIt

    out: list[tuple[str, str]] = []
    for block in MarkdownIt("commonmark").enable("table").parse(text):
        for t in block.children or [block]:
            if t.type == "text" and out and out[-1][0] == "text":
                out[-1] = ("text", out[-1][1] + t.content)
            else:
                out.append((t.type, t.content if t.type == "text" else t.tag))
    return out


def _markdown(text: str, clean: str, names: dict[str, str]) -> None:
    got, want = _markdown_tokens(text), _markdown_tokens(clean)
    if [t for t, _ in got] != [t for t, _ in want]:
        raise Unsafe("Markdown renders to other elements than the clean file")
    for (kind, g), (_, w) in zip(got, want, strict=True):
        if kind == "text":
            w = CHECK.sub(r"\1", substitute(w, names, visible))
            if CHECK.sub(r"\1", g) != w:
                raise Unsafe(f"Markdown text {g!r}, expected {w!r}")
        elif g != w:
            raise Unsafe(f"Markdown element {g!r}, expected {w!r}")


def _html(text: str, clean: str, names: dict[str, str]) -> None:
    """An HTML view: the same elements and attributes, the same scripts but for the figure's
    JSON, the page's text with the names as a picture shows them (:func:`short`, then
    :func:`visible`), and every string of the figure with the names as :func:`html_text` writes
    them (plotly reads those strings as HTML): no name adds a tag, an attribute, a script or
    a line of code."""
    try:
        got, want = read_page(text), read_page(clean)
    except (AssertionError, ValueError) as e:
        raise Unsafe(f"the page does not read as a view: {e}") from e
    if got.tags != want.tags:
        raise Unsafe("the page's elements or attributes differ from the clean page's")
    others = [s for s in got.scripts if "Plotly.newPlot(" not in s]
    if others != [s for s in want.scripts if "Plotly.newPlot(" not in s]:
        raise Unsafe("a script other than the figure's differs from the clean page's")
    if got.around != want.around or got.div != want.div:
        raise Unsafe("the figure's script differs from the clean page's around its data")
    shown = {k: visible(short(v)) for k, v in names.items()}
    if got.texts != [substitute(t, shown) for t in want.texts]:
        raise Unsafe(f"page text {got.texts!r}, expected {want.texts!r} with the names")
    written = {k: html_text(short(v)) for k, v in names.items()}
    _same([got.data, got.layout, got.config], [want.data, want.layout, want.config], written,
          "figure")  # fmt: skip


JUDGES: dict[str, Callable[[str, str, dict[str, str]], None]] = {
    "python": _python,
    "matlab": _matlab,
    "hal": _hal,
    "yaml-comments": _yaml_comments,
    "ikdh": _ikdh,
    "xml": _xml,
    "json": lambda t, c, n: _tree(t, c, n, json.loads),
    "yaml": lambda t, c, n: _tree(t, c, n, yaml.safe_load),
    "csv": _csv,
    "text": _text,
    "markdown": _markdown,
    "html": _html,
}


def judge(what: str, data: bytes, clean: bytes, names: dict[str, str]) -> None:
    """Raise :class:`Unsafe` unless ``data`` (written for target or format ``what``) is its
    clean twin ``clean`` with the placeholder names replaced (``names``: placeholder -> name)."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise Unsafe(f"not UTF-8: {e}") from e
    if what not in LANGUAGE:
        raise KeyError(f"no judge for {what!r}: add its language to safety.LANGUAGE")
    try:
        JUDGES[LANGUAGE[what]](text, clean.decode("utf-8"), names)
    except (HalSyntaxError, MatlabSyntaxError) as e:
        raise Unsafe(f"{what}: does not read as its consumer reads it: {e}") from e
