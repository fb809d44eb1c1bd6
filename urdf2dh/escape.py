"""Names in generated text: one function per language we write, so no name can end a string,
a comment or a line early.

Robot, link and joint names (and the source's path) come from files we do not control. Each
output language gets exactly one way of writing them:

==================  =========================================================================
language            what a name becomes
==================  =========================================================================
Python              a string literal (:func:`python_string`, ``repr``) or a line of a
                    docstring (:func:`python_docstring`): Python escapes, so the docstring's
                    value holds the name exactly
MATLAB              a string ``"..."`` or char vector ``'...'`` with the quote doubled; a
                    character MATLAB cannot type in a literal joins as ``char([10 13])``
                    (:func:`matlab_string`); comments show :func:`visible` text
YAML                comments only (:func:`yaml_comment`): :func:`visible` text
ikdh robot file     its ``name:`` line, which ikdh's line scanner reads to the end (``#``
                    starts a comment there, a line holding ``dh:`` or ``limits:`` a section):
                    letters, digits, ``_``, ``-`` and ``.`` only, any other character
                    written ``_`` (:func:`ikdh_name`); comments as YAML's
HAL (LinuxCNC)      comments only (:func:`hal_comment`): :func:`visible` text, in lines
                    halcmd reads whole
XML (URDF)          attributes with XML's escapes (:func:`xml_attribute`), refusing the
                    characters XML 1.0 cannot carry; comments show :func:`visible` text with
                    ``--`` written ``- -`` (:func:`xml_comment`)
Markdown            :func:`visible` text with its markup characters backslash-escaped
                    (:func:`markdown_text`)
matplotlib          :func:`visible` text with ``$`` escaped (:func:`matplotlib_text`)
HTML                :func:`visible` text with ``& < > " '`` as character references
                    (:func:`html_text`): text and attribute values of a page, and the text of
                    a plotly figure (titles, labels, hover), which plotly reads as HTML
JavaScript          a page's only data is its plotly figure, which ``plotly.io.to_html``
                    writes as JSON with ``< > /`` (and U+2028, U+2029) as ``\\u`` escapes, so
                    no string ends the script or a line; its text is :func:`html_text`
CSV                 :func:`visible` text, RFC 4180 quoting (:func:`csv_cell`); a cell a
                    spreadsheet would read as a formula gets a leading ``'``
==================  =========================================================================

Where a language has no escapes (comments), a name is shown as :func:`visible` gives it: the
text of Python's ``repr`` without the quotes, so it stays on one line, shows what it holds
(``\\n``, ``\\x1b``, ``\\u2028``, ``\\u202e``) and can be read back.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence

from .errors import ExportError, shown, visible

__all__ = [
    "FORMULA",
    "HAL_LINE_BYTES",
    "csv_cell",
    "csv_names",
    "csv_text",
    "hal_comment",
    "html_text",
    "ikdh_name",
    "markdown_table",
    "markdown_text",
    "matlab_comment",
    "matlab_string",
    "matplotlib_text",
    "python_docstring",
    "python_string",
    "visible",
    "xml_attribute",
    "xml_comment",
    "yaml_comment",
]

# halcmd reads a HAL file with fgets into a 1024-byte buffer (MAX_CMD_LEN in halcmd.h): the
# rest of a longer line is read as a line of its own, so a long comment would end early.
HAL_LINE_BYTES = 1000


# --------------------------------------------------------------------------- Python


def python_string(text: str) -> str:
    """A Python string literal whose value is ``text`` (``repr``: escapes for every character
    that is not printable, so the literal is one line)."""
    return repr(text)


def python_docstring(lines: Iterable[str], block: bool = False) -> str:
    """A ``\"\"\"`` string literal whose value is ``lines`` joined by newlines (and a final
    newline where ``block``): each line is escaped as :func:`visible` does and ``"`` as
    ``\\"``, so nothing in it ends the literal and its value holds every name exactly."""
    body = "\n".join(visible(line).replace('"', '\\"') for line in lines)
    return '"""' + body + ('\n"""' if block else '"""')


# --------------------------------------------------------------------------- MATLAB


def _utf16_units(text: str) -> list[int]:
    data = text.encode("utf-16-le", "surrogatepass")
    return [int.from_bytes(data[i : i + 2], "little") for i in range(0, len(data), 2)]


def _runs(text: str) -> list[str]:
    """``text`` cut into runs of printable and of unprintable characters."""
    runs: list[str] = []
    for ch in text:
        if runs and runs[-1][-1].isprintable() == ch.isprintable():
            runs[-1] += ch
        else:
            runs.append(ch)
    return runs


def matlab_string(text: str, quote: str = '"') -> str:
    """A MATLAB expression whose value is ``text``: a string (``quote='"'``) or a char vector
    (``quote="'"``).

    The quote is doubled inside the literal; other printable characters are written as they
    are (``%`` and ``...`` mean nothing inside a literal). A literal cannot hold a line break
    or another unprintable character, so those join the literal as ``char([...])`` of their
    UTF-16 code units: ``"a" + char([10]) + "b"`` for strings (a string plus a char vector is
    a string; the expression always starts with a string literal), ``['a' char([10]) 'b']``
    for char vectors.
    """
    if quote not in ('"', "'"):
        raise ValueError(f"MATLAB quotes are ' and \", not {quote!r}")
    if not text:
        return quote * 2
    parts: list[str] = []
    for run in _runs(text):
        if run.isprintable():
            parts.append(quote + run.replace(quote, quote * 2) + quote)
        else:
            parts.append("char([" + " ".join(str(u) for u in _utf16_units(run)) + "])")
    if quote == '"':
        if not parts[0].startswith('"'):
            parts.insert(0, '""')
        return " + ".join(parts)
    if len(parts) == 1 and parts[0].startswith("'"):
        return parts[0]
    return "[" + " ".join(parts) + "]"


def matlab_comment(text: str) -> str:
    """A MATLAB ``%`` comment showing ``text`` (:func:`visible`: one line)."""
    return "% " + visible(text)


# --------------------------------------------------------------------------- YAML, HAL


def yaml_comment(text: str) -> str:
    """A YAML ``#`` comment showing ``text`` (:func:`visible`: no line break of YAML 1.1 or
    1.2 and no character YAML forbids)."""
    return "# " + visible(text)


def ikdh_name(text: str) -> str:
    """The value of an ikdh robot file's ``name:`` line for ``text``: letters, digits, ``_``,
    ``-`` and ``.`` kept, any other character ``_``, a letter first (``robot`` for no text),
    so that it is one plain YAML string and ikdh's scanner reads it whole (no ``#``, no
    ``:``)."""
    name = re.sub(r"[^A-Za-z0-9_.-]", "_", text)
    if not name[:1].isalpha():
        name = "robot_" + name if name else "robot"
    return name


def hal_comment(text: str) -> list[str]:
    """HAL ``#`` comment lines showing ``text`` (:func:`visible`), each at most
    :data:`HAL_LINE_BYTES` bytes of UTF-8, so halcmd reads every one whole. A line starting
    with ``#`` is a comment to its end for halcmd whatever follows, so ``#``, ``;`` and quotes
    stay as they are; so do ``$`` and ``[`` (halcmd's environment and INI substitutions: it
    cuts the comment off before substituting)."""
    out: list[str] = []
    line, size = "#", 1
    for ch in " " + visible(text):
        n = len(ch.encode("utf-8"))
        if size + n > HAL_LINE_BYTES:
            out.append(line)
            line, size = "# ", 2
        line, size = line + ch, size + n
    out.append(line)
    return out


# --------------------------------------------------------------------------- XML


def _xml_char(ch: str) -> bool:
    """XML 1.0's ``Char`` production (a character reference cannot carry any other)."""
    c = ord(ch)
    return c in (0x9, 0xA, 0xD) or 0x20 <= c <= 0xD7FF or 0xE000 <= c <= 0xFFFD or c >= 0x10000


_XML_ATTRIBUTE = {
    "&": "&amp;",
    "<": "&lt;",
    ">": "&gt;",
    '"': "&quot;",
    "\t": "&#9;",
    "\n": "&#10;",
    "\r": "&#13;",
}


def xml_attribute(text: str, what: str) -> str:
    """``"text"`` as an XML attribute value: ``& < > "`` as entities and tab, line feed and
    carriage return as character references (a literal one would be read as a space).
    ``what`` names the value for the error if it holds a character XML 1.0 cannot carry at
    all (most C0 controls, lone surrogates, U+FFFE, U+FFFF): :class:`ExportError`."""
    bad = next((ch for ch in text if not _xml_char(ch)), None)
    if bad is not None:
        raise ExportError(
            f"urdf: {what} {shown(text)} holds {shown(bad)} (U+{ord(bad):04X}), which XML 1.0 "
            "cannot carry; rename it in the source"
        )
    return '"' + "".join(_XML_ATTRIBUTE.get(ch, ch) for ch in text) + '"'


def xml_comment(text: str) -> str:
    """An XML comment showing ``text`` (:func:`visible`, with ``--``, which may not appear in
    a comment, written ``- -``)."""
    return "<!-- " + re.sub("-(?=-)", "- ", visible(text)) + " -->"


# --------------------------------------------------------------------------- matplotlib


def matplotlib_text(text: str) -> str:
    """``text`` as a matplotlib label (drawn with ``usetex=False``): :func:`visible` text with
    ``$`` as ``\\$``, so no name opens mathtext (whose parser fails on unknown commands)."""
    return visible(text).replace("$", "\\$")


# --------------------------------------------------------------------------- HTML, JavaScript


def html_text(text: str) -> str:
    """``text`` as HTML text or a quoted attribute value: :func:`visible` text (one line, no
    control characters) with ``& < > " '`` as character references, so no name opens a tag,
    an entity or ends an attribute. plotly draws its titles, labels and hover text as HTML
    (a few tags and the entities), so a figure's text is written with it too."""
    import html  # plots only

    return html.escape(visible(text), quote=True)


# --------------------------------------------------------------------------- Markdown, CSV

_MARKDOWN = set("\\`*[]<>|&~!$")  # ($: GitHub reads $...$ as math)


def markdown_text(text: str) -> str:
    """``text`` in Markdown (a table cell or a line): :func:`visible` text with every character
    that could start markup, a link, HTML or a new cell backslash-escaped; ``_`` only where it
    could begin or end emphasis (between two letters or digits it cannot); spaces at either
    end as ``&#32;`` (a cell's edge spaces are trimmed, and emphasis cannot open before one)."""
    shown_text = visible(text)
    out = []
    for i, ch in enumerate(shown_text):
        if ch == "_":
            before = shown_text[i - 1] if i else " "
            after = shown_text[i + 1] if i + 1 < len(shown_text) else " "
            if not (before.isalnum() and after.isalnum()):
                ch = "\\_"
        elif ch in _MARKDOWN:
            ch = "\\" + ch
        out.append(ch)
    text = "".join(out)
    body = text.strip(" ")  # edge spaces as references: cells and emphasis would drop them
    if body == text:
        return text
    left = len(text) - len(text.lstrip(" "))
    right = len(text) - len(text.rstrip(" ")) if body else 0
    return "&#32;" * left + body + "&#32;" * right


def markdown_table(head: Sequence[str], body: Iterable[Sequence[str]], texts: int = 1) -> list[str]:
    """The lines of a Markdown (GitHub) table: ``head`` and the rows of ``body`` as given (each
    cell Markdown already: a name through :func:`markdown_text`), the first ``texts`` columns
    left-aligned, the others (numbers) right-aligned."""
    align = "|" + "|".join("---" if i < texts else "---:" for i in range(len(head))) + "|"
    return ["| " + " | ".join(head) + " |", align, *("| " + " | ".join(r) + " |" for r in body)]


def text_table(head: Sequence[str], body: Iterable[Sequence[str]], texts: int = 1) -> list[str]:
    """The lines of a table for a terminal: ``head``, a rule, and the rows of ``body`` (each
    cell :func:`visible` text already), in columns two spaces apart, the first ``texts``
    left-aligned, the others (numbers) right-aligned."""
    rows = [list(head), *(list(r) for r in body)]
    widths = [max(len(r[i]) for r in rows) for i in range(len(head))]

    def line(cells: Sequence[str]) -> str:
        return "  ".join(
            c.ljust(w) if i < texts else c.rjust(w)
            for i, (c, w) in enumerate(zip(cells, widths, strict=True))
        ).rstrip()

    return [line(rows[0]), "  ".join("-" * w for w in widths), *(line(r) for r in rows[1:])]


# what spreadsheets read as the start of a formula (OWASP, "CSV Injection"), the full-width
# forms included (an IME writes them, and some spreadsheets take ＝ for =); tab and CR never
# start a cell's text, which is :func:`visible`
FORMULA = ("=", "+", "-", "@", "\uff1d", "\uff0b", "\uff0d", "\uff20")


def csv_text(text: str) -> str:
    """A name as a CSV cell shows it: :func:`visible` text (one line, no invisible character:
    no bidi control, zero-width character, BOM, soft hyphen or tag character, each written as
    its escape), with a leading ``'`` where it starts like a spreadsheet formula
    (:data:`FORMULA`), so a spreadsheet shows it as text."""
    shown_text = visible(text)
    return "'" + shown_text if shown_text.startswith(FORMULA) else shown_text


def csv_cell(text: str) -> str:
    """A name as a CSV cell (RFC 4180): :func:`csv_text`, quoted with ``"`` doubled where it
    holds a comma or a quote, so a CSV reader gets :func:`csv_text` back exactly. The one way
    a name reaches a CSV file (``--format csv``, ``measure``)."""
    out = csv_text(text)
    if "," in out or '"' in out:
        return '"' + out.replace('"', '""') + '"'
    return out


def csv_names(cells: Iterable[str], names: Iterable[str]) -> list[str]:
    """The names a CSV header's cells stand for: a cell that is one of ``names`` stands for
    itself, one that is a name's :func:`csv_text` (as :func:`csv_cell` wrote it) for that
    name, any other for itself."""
    names = set(names)
    written = {csv_text(n): n for n in names}
    return [c if c in names else written.get(c, c) for c in cells]
