"""MJCF text -> one checked element tree, every ``<include>`` spliced in.

The SOURCE is parsed as the URDF reader parses XML (:func:`urdf2dh.io.urdf.parse.parse_xml`: one
UTF-8 document, comments and processing instructions dropped, no entity from outside the document,
nothing from the network, libxml2's bounds), and a document type declaration is refused: MJCF has
none, and an internal subset is the way entity bombs come.

``<include file="...">`` is replaced by the children of the included file's root element, as
MuJoCo does (the root's own name is not read); the file name is looked for beside the SOURCE,
then beside the file that includes it (MuJoCo's order), and each file may be included once. An
include may read only beneath the SOURCE's directory (symbolic links resolved), as a xacro
expansion may (docs/security.md): ``../x.xml``, an absolute path elsewhere or a link pointing out
is a one-line error naming it, and a SOURCE lying directly in the home directory or the root
includes nothing. At most :data:`~urdf2dh.tolerances.MJCF_INCLUDES` files are included, of at most
:data:`~urdf2dh.tolerances.FILE_BYTES` together; the document they make is nested at most
:data:`XML_DEPTH` elements deep. Every included file is an input of the run
(:func:`urdf2dh.io.files.read_file`): no output replaces it.

Meshes, textures and other assets are never read.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ...errors import InputError, Remedy, shown
from ...tolerances import FILE_BYTES, MJCF_INCLUDES
from ..encodings import check_text
from ..files import read_file
from ..urdf.parse import document, parse_xml
from ..xacro import broad_directories
from ..xacro_child import may_read, readable

__all__ = ["XML_DEPTH", "MjcfDocument", "read_document"]

XML_DEPTH = 256  # elements deep: libxml2's bound on one file, kept by the spliced document too


@dataclass(frozen=True, slots=True)
class MjcfDocument:
    """An MJCF document with its includes spliced in.

    Attributes
    ----------
    root
        The ``<mujoco>`` element (lxml).
    included
        The files included, as their names were given, in the order met.
    """

    root: Any
    included: tuple[str, ...]

    def text(self) -> bytes:
        """The document as UTF-8 XML: what the oracles read (its includes already spliced)."""
        from lxml import etree

        return bytes(etree.tostring(self.root, encoding="utf-8", xml_declaration=False))


def _parse(data: bytes, display: str) -> Any:
    """lxml's root element of MJCF text, a document type declaration refused."""
    check_text(data, display, "MJCF XML")
    root = parse_xml(document(data, display), display)
    if root.getroottree().docinfo.doctype:
        raise InputError(
            f"{display}: a document type declaration (<!DOCTYPE ...>) is not read; MJCF has none"
        )
    return root


def _depth(root: Any) -> int:
    deepest, stack = 0, [(root, 1)]
    while stack:
        el, depth = stack.pop()
        deepest = max(deepest, depth)
        stack.extend((child, depth + 1) for child in el)
    return deepest


class _Includes:
    """What the SOURCE's includes may read, and what they have read."""

    def __init__(self, path: Path, display: str) -> None:
        self.display = display
        self.home = Path(os.path.dirname(os.path.abspath(path)))
        self.trees, self.files, self.withheld = readable(str(path), {}, broad_directories())
        self.seen: set[str] = set()
        self.names: list[str] = []
        self.total = 0

    def refuse(self, name: str, why: str, remedy: Remedy | None = None) -> InputError:
        return InputError(f"{self.display}: <include file={shown(name)}>: {why}", remedy=remedy)

    def find(self, name: str, beside: Path) -> Path:
        """The file an include names: beside the SOURCE, else beside the including file."""
        if not name:
            raise self.refuse(name, "no file named")
        for directory in (self.home, beside):
            candidate = directory / name
            try:
                if candidate.exists():
                    return candidate
            except (OSError, ValueError):  # a name the system cannot look up names nothing
                break
        raise self.refuse(
            name, "no such file (looked for beside the SOURCE and the including file)"
        )

    def read(self, name: str, beside: Path) -> tuple[Any, Path]:
        """The root element of the file an include names, checked, and its directory."""
        path = self.find(name, beside)
        if not may_read(str(path), self.trees, self.files):
            if self.withheld:
                why = (
                    f"the SOURCE lies directly in {self.withheld}, whose files a model may not "
                    "include (docs/security.md); put the model in a directory of its own"
                )
            else:
                why = (
                    f"{os.path.normpath(path)} is outside the SOURCE's directory, the only one an "
                    "include may read (docs/security.md)"
                )
            raise self.refuse(name, why)
        real = os.path.realpath(path)
        if real in self.seen:
            raise self.refuse(name, "the file is included twice (MuJoCo includes a file once)")
        if len(self.seen) >= MJCF_INCLUDES:
            raise self.refuse(name, f"more than {MJCF_INCLUDES:,} files included")
        self.seen.add(real)
        self.names.append(name)
        shown_name = f"{self.display}: included {name}"
        data = read_file(path, shown_name)
        self.total += len(data)
        if self.total > FILE_BYTES:
            raise self.refuse(
                name, f"the included files hold more than {FILE_BYTES // 2**20} MiB together"
            )
        return _parse(data, shown_name), path.parent


def read_document(path: Path, display: str, data: bytes) -> MjcfDocument:
    """The checked MJCF document of the SOURCE file ``path`` (bytes ``data``), includes spliced.

    Raises
    ------
    InputError
        One line naming the file and the fault: malformed XML, a document type declaration, a
        root other than ``<mujoco>``, an include refused (outside the SOURCE's directory, missing,
        twice, beyond the bounds), or a document nested too deeply.
    """
    root = _parse(data, display)
    if root.tag != "mujoco":
        raise InputError(f"{display}: not an MJCF model (root element is <{root.tag}>)")
    includes = _Includes(path, display)
    pending = [(el, Path(os.path.dirname(os.path.abspath(path)))) for el in root.iter("include")]
    while pending:
        el, beside = pending.pop(0)
        name = el.get("file", "")
        included, directory = includes.read(name, beside)
        parent = el.getparent()
        if parent is None:  # pragma: no cover - the root is <mujoco>, never an include
            raise includes.refuse(name, "an include cannot be the root")
        at = parent.index(el)
        children = list(included)
        parent[at : at + 1] = children
        for child in children:
            pending.extend((inner, directory) for inner in child.iter("include"))
    depth = _depth(root)
    if depth > XML_DEPTH:
        raise InputError(
            f"{display}: elements nested {depth} deep with the includes spliced in; at most "
            f"{XML_DEPTH} (the XML parser's bound on one file)"
        )
    return MjcfDocument(root, tuple(includes.names))
