"""MJCF (MuJoCo's XML) -> kinematic tree -> serial chain; the only package that reads MJCF.

:mod:`.document` reads the text once (lxml, as the URDF reader does), refuses a document type
declaration and splices the ``<include>`` files in, confined beneath the SOURCE's directory;
:mod:`.placement` reads the compiler's settings and every form of position and orientation;
:mod:`.defaults` resolves default classes; :mod:`.tree` walks the bodies, joints, sites and
joint equalities into a :class:`~urdf2dh.io.urdf.UrdfTree`, so chains are taken from it as
from a URDF's (docs/mjcf.md). Meshes and other assets are never read.
"""

from __future__ import annotations

from ..sources import Content, Reading, Source
from .document import MjcfDocument, read_document
from .tree import FEATURES, Element, MjcfElements, build

__all__ = ["FEATURES", "Element", "MjcfDocument", "MjcfElements", "read_document", "read_source"]


def read_source(content: Content, reading: Reading) -> Source:
    """The SOURCE of an MJCF file (the ``mjcf`` entry of :data:`~urdf2dh.io.sources.READERS`)."""
    doc = read_document(content.path, content.display, content.data)
    tree, elements = build(doc, content.path, content.display)
    return Source("mjcf", content.display, content.name(tree.name), tree, tree.xml,
                  bundled=content.bundled, mjcf=elements)  # fmt: skip
