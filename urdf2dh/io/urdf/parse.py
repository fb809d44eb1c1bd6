"""URDF text -> checked :class:`~urdf2dh.io.urdf.tree.UrdfTree`, in one parse.

The bytes are checked for emptiness and binary content (:func:`urdf2dh.io.encodings.check_text`),
turned into one UTF-8 document (:func:`document`), parsed by lxml once, checked element by element
by :func:`~urdf2dh.io.urdf.validate.check_robot` (always: every fault is named there), and handed,
as the same element tree, to yourdfpy's element parsers, which make its ``Robot`` (joint origins as
4x4 matrices, axes, limits, mimic relations). Meshes are never loaded: a URDF whose mesh files are
absent loads all the same.
"""

from __future__ import annotations

import codecs
import re
from pathlib import Path
from typing import Any

from ...errors import InputError, shown
from ...tolerances import JOINTS
from ..encodings import check_text, sniff
from ..fields import JointBound
from ..files import read_file
from ..sources import Content, Reading, Source
from .tree import UrdfTree, build_tree
from .validate import check_robot

__all__ = [
    "check_size",
    "document",
    "keep_attribute_whitespace",
    "load_tree",
    "parse_tree",
    "parse_xml",
    "read_source",
    "yourdfpy_robot",
]

# An XML declaration and its pseudo-attributes (XML 1.0 §2.8); read from the bytes of a file
# without a BOM, where it is ASCII whatever the encoding it declares.
_DECLARATION = re.compile(rb"<\?xml[ \t\r\n](?P<body>[^>]*?)\?>")
_PSEUDO = re.compile(rb"""(version|encoding|standalone)\s*=\s*(?:"([^"]*)"|'([^']*)')""")
_DECLARATION_TEXT = re.compile(r"<\?xml[ \t\r\n][^>]*?\?>")
_VERSION_1 = re.compile(rb"1\.[0-9]+")  # the versions libxml2 reads; "0.0" and "2.0" it refuses
_LXML_SOURCE = re.compile(r" \(<string>, line [0-9]+\)$")  # lxml's suffix: the line is in it
# libxml2's advice to its callers (an option urdf2dh does not set), not to a URDF's author
_PARSER_HINT = re.compile(r",? (?:try|use|see) (?:XML_PARSE_HUGE|xmlCtxtSetMaxAmplification)[^,]*")
# An attribute value holding a tab, line feed or carriage return (the quick test), and the markup
# of a document as keep_attribute_whitespace walks it: comments, CDATA sections, processing
# instructions and the document type declaration passed over, start tags with their values
_SPACED_VALUE = re.compile(rb"""=[ \t\r\n]*(?:"[^"<]*[\t\r\n][^"<]*"|'[^'<]*[\t\r\n][^'<]*')""")
_MARKUP = re.compile(
    rb"<!--.*?-->|<!\[CDATA\[.*?\]\]>|<\?.*?\?>|<!DOCTYPE(?:[^\[>]|\[.*?\])*>"
    rb"""|<[^\s/!?>][^\s/>]*(?:\s+[^\s=/>]+\s*=\s*(?:"[^"<]*"|'[^'<]*'))*\s*/?>""",
    re.S,
)
_VALUE = re.compile(rb"""=(\s*)("[^"<]*"|'[^'<]*')""")
_UTF8 = ("utf-8", "ascii")  # codec names (codecs.lookup) whose text is UTF-8 as it stands
_WIDE = ("utf-16", "utf-32")  # declared without a BOM, yet the declaration was ASCII: UTF-8 too


def _text(data: bytes, encoding: str, display: str) -> str:
    """``data`` decoded, or a one-line error naming the first byte that is not ``encoding``."""
    try:
        return data.decode(encoding)
    except UnicodeDecodeError as e:
        hint = "" if encoding != "utf-8" else "; an XML declaration names any other encoding"
        raise InputError(
            f"{display}: not {encoding} text (byte {e.start}: {e.reason}){hint}"
        ) from e


def _decode(data: bytes, encoding: str, display: str) -> bytes:
    """``data`` in ``encoding`` as UTF-8, its XML declaration dropped."""
    text = _text(data, encoding, display)
    m = _DECLARATION_TEXT.match(text)
    return text[m.end() :].encode("utf-8") if m else text.encode("utf-8")


def document(data: bytes, display: str) -> bytes:
    """The file as the one UTF-8 document that lxml parses and Pinocchio is given.

    Pinocchio (urdfdom, tinyxml2) reads UTF-8 and ignores the XML declaration; lxml refuses a
    declared version other than 1.x (``<?xml version="0.0"?>``, which a widely used simulator
    writes) and reads UTF-16. The common file, UTF-8 declared as such (or not at all) and version
    1.x, is returned as it stands; otherwise the text is decoded as its BOM or declaration says
    and returned as UTF-8 without BOM or declaration, so that both parsers read the same text.

    Parameters
    ----------
    data
        The file's bytes (not empty, not binary).
    display
        The file's name in messages.

    Returns
    -------
    bytes
        UTF-8 XML.

    Raises
    ------
    InputError
        An unknown declared encoding, or bytes that are not text in the encoding announced.
    """
    encoding, start = sniff(data)
    if encoding != "utf-8":  # UTF-16 or UTF-32, announced by its BOM
        return _decode(data[start:], encoding, display)
    body = data[start:]
    m = _DECLARATION.match(body)
    if m is None:
        _text(body, "utf-8", display)  # a few microseconds; lxml's complaint would be vaguer
        return body
    pseudo = {key: a or b for key, a, b in _PSEUDO.findall(m["body"])}
    declared = pseudo.get(b"encoding", b"utf-8").decode("ascii", errors="replace")
    try:
        codec = codecs.lookup(declared).name
        b"<".decode(codec, errors="replace")  # bytes.decode refuses non-text codecs
    except LookupError as e:  # also a codec that is not a text encoding ("base64", "rot13")
        raise InputError(
            f"{display}: unknown text encoding {shown(declared)} in its XML declaration"
        ) from e
    if codec in _UTF8 or codec.startswith(_WIDE):
        _text(body, "utf-8", display)
        if codec in _UTF8 and _VERSION_1.fullmatch(pseudo.get(b"version", b"")):
            return body
        return body[m.end() :]  # a version lxml refuses, or a UTF-16 label on 8-bit text
    return _decode(body, codec, display)


def keep_attribute_whitespace(xml: bytes) -> bytes:
    """``xml`` with each tab and line break inside an attribute value written as a character
    reference, so that lxml keeps it as urdfdom's XML parser (tinyxml2) does.

    A conforming XML parser (lxml) turns each tab, line feed and carriage return of an attribute
    value into a space (XML 1.0, section 3.3.3); tinyxml2 keeps them (CR LF and CR become LF), and
    urdfdom, which separates numbers at spaces only, then refuses ``xyz="0<TAB>0 1"``. Written as
    ``&#9;`` and ``&#10;``, they reach urdf2dh's check as they reach urdfdom. A document without
    such a value (nearly every file) is returned as it is."""
    if not _SPACED_VALUE.search(xml):
        return xml

    def value(m: re.Match[bytes]) -> bytes:
        text = m[2].replace(b"\r\n", b"\n").replace(b"\r", b"\n")
        return b"=" + m[1] + text.replace(b"\t", b"&#9;").replace(b"\n", b"&#10;")

    def markup(m: re.Match[bytes]) -> bytes:
        tag = m[0]
        return tag if tag[1:2] in (b"!", b"?") else _VALUE.sub(value, tag)

    return _MARKUP.sub(markup, xml)


def parse_xml(xml: bytes, display: str) -> Any:
    """lxml's element tree of a UTF-8 document (comments and processing instructions dropped;
    no entity from outside the document is read, nothing from the network).

    Raises
    ------
    InputError
        ``"<display>: malformed XML (<lxml's reason>)"``, or for a document beyond libxml2's
        limits (a text node or attribute over 10 MB, nesting over 256 deep, entity expansion)
        ``"<display>: beyond the XML parser's limits (<its reason>)"``.
    """
    from lxml import etree

    parser = etree.XMLParser(  # one a parse: an lxml parser must not serve two threads at once
        remove_comments=True, remove_pis=True, resolve_entities=False, no_network=True
    )
    try:
        return etree.fromstring(xml, parser=parser)
    except etree.XMLSyntaxError as e:
        reason = _LXML_SOURCE.sub("", " ".join(str(e).split()))
        if e.code == etree.ErrorTypes.ERR_RESOURCE_LIMIT:
            # libxml2's bounds (text nodes and attributes of 10 MB, nesting 256 deep, entity
            # expansion): well-formed or not, the document is too large to read
            reason = _PARSER_HINT.sub("", reason)
            raise InputError(f"{display}: beyond the XML parser's limits ({reason})") from e
        if e.code == etree.ErrorTypes.ERR_NO_MEMORY:
            raise InputError(f"{display}: not enough memory to parse the XML ({reason})") from e
        raise InputError(f"{display}: malformed XML ({reason})") from e
    except MemoryError as e:
        raise InputError(f"{display}: not enough memory to parse the XML") from e


def check_size(root: Any, display: str, bound: JointBound | None = None) -> None:
    """Refuse a URDF of more than :data:`~urdf2dh.tolerances.JOINTS` joints (or links than a tree
    of as many joints has), or more joints than the command's ``bound``, before anything is done
    per element."""
    for kind, most in (("joint", JOINTS), ("link", JOINTS + 1)):
        count = sum(1 for _ in root.iterchildren(kind))
        if count > most:
            raise InputError(
                f"{display}: {count:,} {kind}s; urdf2dh reads URDFs of at most {JOINTS:,} joints "
                f"({JOINTS + 1:,} links)"
            )
        if kind == "joint" and bound is not None:
            bound.check(count, display, "the URDF has")


def yourdfpy_robot(root: Any, display: str) -> Any:
    """yourdfpy's ``Robot`` of a checked root element: its links by name, and its joints made by
    yourdfpy's joint parser (the one ``URDF.load`` uses), joint by joint so that a failure names
    the joint.

    A link's inertial, visual and collision elements are not read: the chain needs none of them,
    and urdfdom (Pinocchio's reader) keeps a link whatever they hold, so a file Pinocchio loads is
    not refused for them. A floating-point fault in yourdfpy's matrix code is a failure naming the
    joint, not a numpy warning; underflow (``rpy="1e-300 1e-300 0"``) is no fault."""
    import numpy as np

    from ._yourdfpy import urdf as yourdfpy  # its element parsers, without trimesh's package

    robot = yourdfpy.Robot(name=root.get("name"))
    robot.links.extend(yourdfpy.Link(name=el.get("name")) for el in root.iterchildren("link"))
    for el in root.iterchildren("joint"):
        if el.get("type") in ("fixed", "floating"):  # urdfdom reads no axis of these
            for axis in el.findall("axis"):
                el.remove(axis)
        try:
            with np.errstate(over="raise", invalid="raise", divide="raise"):
                robot.joints.append(yourdfpy.URDF._parse_joint(el))
        except Exception as e:  # yourdfpy raises many kinds (ValueError, KeyError, ...)
            reason = " ".join(f"{type(e).__name__}: {e}".split())
            raise InputError(
                f"{display}: joint {shown(el.get('name'))}: yourdfpy cannot read it ({reason})"
            ) from e
    return robot


def parse_tree(data: bytes, display: str, bound: JointBound | None = None) -> UrdfTree:
    """Parse URDF text into a checked :class:`UrdfTree`.

    Parameters
    ----------
    data
        The file's bytes (UTF-8, or any encoding its BOM or XML declaration names).
    display
        The file's name in messages.
    bound
        A command's bound on the joints (all of the file's), checked once they are counted.

    Returns
    -------
    UrdfTree
        The tree, with the document it was parsed from as UTF-8 (``UrdfTree.xml``).

    Raises
    ------
    InputError
        On one line naming the file, and the link, joint and attribute at fault.
    """
    check_text(data, display, "URDF XML")
    xml = document(data, display)
    root = parse_xml(keep_attribute_whitespace(xml), display)
    check_size(root, display, bound)
    check_robot(root, display)
    return build_tree(yourdfpy_robot(root, display), display, xml)


def load_tree(path: str | Path, display: str | None = None) -> UrdfTree:
    """Read and check a URDF file (``display`` names it in messages; default: ``path``)."""
    shown = display or str(path)
    return parse_tree(read_file(Path(path), shown), shown)


def read_source(content: Content, reading: Reading) -> Source:
    """The SOURCE of a URDF file (the ``urdf`` entry of :data:`~urdf2dh.io.sources.READERS`)."""
    return urdf_source(content, content.data, reading)


def urdf_source(content: Content, data: bytes, reading: Reading) -> Source:
    """The SOURCE of URDF text ``data`` read from ``content``'s file (or expanded from it), with
    ``reading``'s bound on its joints."""
    tree = parse_tree(data, content.display, reading.bound)
    return Source("urdf", content.display, content.name(tree.name), tree, tree.xml,
                  bundled=content.bundled)  # fmt: skip
