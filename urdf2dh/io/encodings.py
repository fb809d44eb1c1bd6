"""What an input file's bytes hold: nothing, binary data, or text in a Unicode encoding.

Every reader (URDF, xacro, POE and table files) asks :func:`check_text` before it parses, so an
empty or binary file gets the same one-line error whatever its suffix. A byte order mark (BOM)
names the encoding of the text after it; UTF-16 and UTF-32 text holds zero bytes and is not
binary.
"""

from __future__ import annotations

import codecs

from ..errors import InputError

__all__ = ["BOMS", "check_text", "first_character", "sniff", "xml_root"]

#: Byte order marks and the encodings they announce (UTF-32's before UTF-16's: ``FF FE 00 00``
#: starts with UTF-16-LE's ``FF FE``).
BOMS: tuple[tuple[bytes, str], ...] = (
    (codecs.BOM_UTF32_LE, "utf-32-le"),
    (codecs.BOM_UTF32_BE, "utf-32-be"),
    (codecs.BOM_UTF8, "utf-8"),
    (codecs.BOM_UTF16_LE, "utf-16-le"),
    (codecs.BOM_UTF16_BE, "utf-16-be"),
)

SNIFF = 4096  # bytes looked at for a zero byte: a text file has none, most binary files do


def sniff(data: bytes) -> tuple[str, int]:
    """The encoding a BOM announces and the BOM's length; ``("utf-8", 0)`` without one.

    Parameters
    ----------
    data
        The file's bytes.

    Returns
    -------
    tuple of (str, int)
        A Python codec name and the number of bytes the text starts after.
    """
    if data[:1] in (b"\xef", b"\xff", b"\xfe", b"\x00"):
        for bom, encoding in BOMS:
            if data.startswith(bom):
                return encoding, len(bom)
    return "utf-8", 0


def _head(data: bytes) -> tuple[str, bytes]:
    """The encoding and the first :data:`SNIFF` bytes of the text, as UTF-8 when the file is
    UTF-16 or UTF-32 (undecodable units become U+FFFD: this only looks)."""
    encoding, start = sniff(data)
    head = data[start : start + SNIFF]
    if encoding != "utf-8":
        head = head.decode(encoding, errors="replace").encode("utf-8")
    return encoding, head


def check_text(data: bytes, display: str, expected: str) -> None:
    """Refuse an empty (or all-whitespace) file and a binary one, naming the file.

    Parameters
    ----------
    data
        The file's bytes.
    display
        The file's name in messages.
    expected
        What the file should have been, for the binary-file message (``"URDF XML"``).

    Raises
    ------
    InputError
        ``"<display>: empty file"`` or ``"<display>: binary file, not <expected>"``.
    """
    encoding, start = sniff(data)
    body = data[start:]
    if encoding == "utf-8":
        empty = not body.strip()
    else:
        empty = not body.decode(encoding, errors="replace").strip()
    if empty:
        raise InputError(f"{display}: empty file")
    _, head = _head(data)
    if b"\x00" in head:
        raise InputError(f"{display}: binary file, not {expected}")


def first_character(data: bytes) -> str:
    """The first character of the text that is not white space (``""`` if none).

    Parameters
    ----------
    data
        The file's bytes (any encoding :func:`sniff` recognises; bytes that do not decode are
        replaced, since this only looks).

    Returns
    -------
    str
        One character, or the empty string.
    """
    _, head = _head(data)
    return head.lstrip()[:1].decode("utf-8", errors="replace")


_NAME_END = b" \t\r\n/>"  # what ends an element's name in a start tag


def _skip(body: bytes, at: int, start: bytes, end: bytes) -> int | None:
    """The index after the markup ``start ... end`` found at ``at``, or ``None``."""
    if not body.startswith(start, at):
        return None
    stop = body.find(end, at + len(start))
    return -1 if stop < 0 else stop + len(end)


def xml_root(data: bytes) -> str | None:
    """The name of the root element of XML text (a namespace prefix dropped), or ``None`` when
    the text does not start as XML does: white space, an XML declaration, comments, processing
    instructions and a document type declaration, then ``<name``. This only looks; the parser
    judges the document.

    Parameters
    ----------
    data
        The file's bytes (any encoding :func:`sniff` recognises; the markup before the root is
        ASCII in every encoding an XML declaration may name).

    Returns
    -------
    str or None
        The root element's local name (``robot``, ``mujoco``).
    """
    encoding, start = sniff(data)
    body = data[start:]
    if encoding != "utf-8":
        body = body.decode(encoding, errors="replace").encode("utf-8")
    at = 0
    while True:
        while at < len(body) and body[at] in b" \t\r\n":
            at += 1
        after = _skip(body, at, b"<?", b"?>")
        if after is None:
            after = _skip(body, at, b"<!--", b"-->")
        if after is None and body.startswith(b"<!DOCTYPE", at):
            bracket, close = body.find(b"[", at), body.find(b">", at)
            if 0 <= bracket < close:  # an internal subset: to its "]", then the ">"
                close = body.find(b">", max(body.find(b"]", bracket), bracket))
            after = -1 if close < 0 else close + 1
        if after is None:
            break
        if after < 0:
            return None
        at = after
    if not body.startswith(b"<", at):
        return None
    end = at + 1
    while end < len(body) and body[end] not in _NAME_END:
        end += 1
    name = body[at + 1 : end].decode("utf-8", errors="replace")
    return name.rpartition(":")[2] or None
