"""SOURCE resolution (docs/commands/index.md): a file in one of the formats of :data:`READERS`,
or a bundled robot (:data:`~urdf2dh.io.catalog.ROBOTS`) or reference table
(:data:`~urdf2dh.io.catalog.REFERENCES`), whose installed file is read the same way.

=========  =================================================  ===============================
reader     recognised by                                      module
=========  =================================================  ===============================
``xacro``  the name ending ``.xacro``                         :mod:`.xacro` (expanded to URDF)
``mjcf``   XML whose root element is ``<mujoco>``             :mod:`.mjcf`
``urdf``   XML: the name ending ``.urdf``, or text from ``<``  :mod:`.urdf`
           (a root other than ``<robot>`` is its error)
``poe``    a YAML or JSON mapping with ``format: poe``         :mod:`.poefile`
``table``  a YAML or JSON mapping with a ``schema`` key        :mod:`.tablefile`
``ur``     a YAML mapping ``kinematics: {shoulder: ...}``   :mod:`.urkinematics`
           (Universal Robots' kinematics file)
``hal``    a ``.hal`` file, or text with                    :mod:`.halfile`
           ``setp genserkins.`` lines (LinuxCNC)
``opw``    a YAML mapping with                              :mod:`.opwfile`
           ``opw_kinematics_geometric_parameters`` (or a
           group of one holding it)
``hand``   a YAML or JSON list of rows ``theta, d, a, alpha``  :mod:`.readings` (its format:
           (or under ``joints:``) that says its convention    :mod:`.handtable`)
           and units: a datasheet's table
=========  =================================================  ===============================

The first reader in :data:`READERS` that claims a file reads it. Adding a format is its module
(a ``read_source(content, reading)`` function giving a :class:`Source`) and one entry here.
:func:`open_source` reads and checks the file once; :meth:`Source.model` then builds the POE
model of the chain between the requested links.

This module imports no numpy (the command line's ``--help`` lists the formats from the table);
a reader's module is imported when a file is read with it.
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..checks import check_flag, check_instance, check_optional_name, check_source
from ..errors import (
    SHOWN_LENGTH,
    InputError,
    SourceError,
    Urdf2DhError,
    UsageError,
    choices,
    near,
    shown,
)
from ..schemas import TABLE_FILE
from ..tolerances import DEFAULT, Tolerances
from .catalog import REFERENCES, ROBOTS, Bundled, lookup, robot_path
from .encodings import check_text, first_character, xml_root
from .files import SOURCE_ROLE, read_file

if TYPE_CHECKING:
    from ..model.poe import PoeModel
    from .fields import JointBound
    from .mjcf import MjcfElements
    from .urdf import UrdfTree
    from .xacro import XacroOptions

__all__ = [
    "READERS",
    "Content",
    "Reader",
    "Reading",
    "Source",
    "load",
    "open_source",
    "source_kinds",
]


@dataclass(frozen=True, slots=True)
class Source:
    """A resolved SOURCE: a kinematic tree to take chains from, or a single chain.

    Attributes
    ----------
    kind
        What the file holds once read (``urdf``, ``poe``, ``table``, ...): the model the oracles
        are given (a xacro file is ``urdf`` once expanded).
    display
        The file's name in messages.
    name
        The robot's name (a bundled robot's own).
    tree
        The kinematic tree (URDF), or ``None`` for a single chain.
    document
        The text an oracle reads (the URDF as parsed), or ``None``.
    poe
        The chain itself, for sources without a tree (POE and table files).
    bundled
        The bundled robot it is, if any (its default base and tip).
    mjcf
        For an MJCF file: its tree's links and joints as the model's bodies, sites and joints,
        and the features it uses (what an oracle reading the same file needs).
    """

    kind: str
    display: str
    name: str
    tree: UrdfTree | None = None
    document: bytes | None = None
    poe: PoeModel | None = None
    bundled: Bundled | None = None
    mjcf: MjcfElements | None = None

    def model(
        self,
        base: str | None = None,
        tip: str | None = None,
        ignore_mimic: bool = False,
    ) -> PoeModel:
        """The POE model of the chain ``base -> tip`` (defaults: the tree's root link and its
        single deepest leaf, or the bundled robot's own)."""
        if self.tree is None:
            if base or tip:
                raise UsageError(
                    f"{self.display}: base and tip links apply to URDF sources; a {self.kind} file "
                    "is already a single chain"
                )
            assert self.poe is not None
            return self.poe
        from .urdf import tree_to_poe

        if self.bundled is not None:
            base = base or self.bundled.base
            tip = tip or self.bundled.tip
        return tree_to_poe(self.tree, base, tip, ignore_mimic, self.name)


@dataclass(frozen=True, slots=True)
class Reading:
    """How files are read: the tolerances of typed numbers (POE and table files), how
    ``.xacro`` files are expanded, and a command's bound on a URDF's joints (refused as soon as
    they are counted, before the tree is built)."""

    tol: Tolerances = DEFAULT
    xacro: XacroOptions | None = None
    bound: JointBound | None = None


class Content:
    """A SOURCE file's bytes, and what the readers look at to claim it (each worked out once).

    Attributes
    ----------
    path, display
        The file, and its name in messages.
    data
        Its bytes (not empty, not binary).
    bundled
        The bundled robot whose installed file it is, if any.
    """

    def __init__(self, path: Path, display: str, data: bytes, bundled: Bundled | None) -> None:
        self.path, self.display, self.data, self.bundled = path, display, data, bundled

    @property
    def suffix(self) -> str:
        """The file name's suffix, lower case (``.urdf``)."""
        return self.path.suffix.lower()

    @cached_property
    def xml_root(self) -> str | None:
        """The name of the root element, if the text is XML that shows one
        (:func:`~urdf2dh.io.encodings.xml_root`)."""
        return xml_root(self.data)

    @cached_property
    def _parsed(self) -> tuple[Any, Urdf2DhError | None]:
        from .mappings import read_mapping

        try:
            return read_mapping(self.path, self.display, self.data), None
        except Urdf2DhError as e:
            return None, e

    @property
    def mapping(self) -> Any:
        """The text as YAML or JSON values (:func:`~urdf2dh.io.mappings.read_mapping`), or
        ``None`` when it is not well-formed YAML or JSON."""
        return self._parsed[0]

    def mapping_error(self) -> Urdf2DhError | None:
        """Why the text is not YAML or JSON, if it is not."""
        return self._parsed[1]

    def name(self, own: str) -> str:
        """The robot's name: a bundled robot's, else ``own`` (the file's)."""
        return self.bundled.name if self.bundled else own

    @property
    def text(self) -> str:
        """The bytes as UTF-8 text (a character that is not, as U+FFFD)."""
        return self.data.decode("utf-8", errors="replace")

    def chain_source(self, kind: str, model: PoeModel) -> Source:
        """The :class:`Source` of a file that holds one chain, ``model``: named as a bundled
        robot is, else as the model names itself, else as the file."""
        model = model.named(self.name(model.name or self.path.stem))
        return Source(kind, self.display, model.name, poe=model, bundled=self.bundled)


@dataclass(frozen=True, slots=True)
class Reader:
    """A SOURCE format: what it is called, how a file is recognised as one, and its reader.

    Attributes
    ----------
    name
        The format's name (``urdf``).
    title
        What a file of it is called in a list of the formats (``URDF``, ``POE``).
    described
        The format as an error listing the formats names it (``URDF (<robot>)``).
    module
        The module under :mod:`urdf2dh.io` whose ``read_source(content, reading)`` reads it.
    claims
        Whether a file is one (on its name and :class:`Content`); the first reader of
        :data:`READERS` that claims a file reads it.
    """

    name: str
    title: str
    described: str
    module: str
    claims: Callable[[Content], bool] = field(repr=False)

    def read(self, content: Content, reading: Reading) -> Source:
        """The :class:`Source` of a file this reader claims."""
        mod = importlib.import_module(f"urdf2dh.io.{self.module}")
        source = mod.read_source(content, reading)
        assert isinstance(source, Source)
        return source


def _mapping_key(key: str, value: str | None = None) -> Callable[[Content], bool]:
    """A claim on a YAML or JSON mapping holding ``key`` (with ``value``, if given)."""

    def claims(content: Content) -> bool:
        tree = content.mapping
        return isinstance(tree, dict) and key in tree and value in (None, tree[key])

    return claims


def _ur_kinematics(content: Content) -> bool:
    """A claim on a UR kinematics file (:func:`~urdf2dh.io.urkinematics.is_ur_kinematics`)."""
    from .urkinematics import is_ur_kinematics

    return is_ur_kinematics(content.mapping)


def _hal(content: Content) -> bool:
    """A claim on a genserkins HAL file (:func:`~urdf2dh.io.halfile.is_hal`)."""
    from .halfile import is_hal

    return is_hal(content.data, content.suffix)


def _opw(content: Content) -> bool:
    """A claim on an OPW parameter file (:func:`~urdf2dh.io.opwfile.is_opw`)."""
    from .opwfile import is_opw

    return is_opw(content.mapping)


def _ikdh(content: Content) -> bool:
    """A claim on an ikdh robot file (:func:`~urdf2dh.io.ikdhfile.is_ikdh`)."""
    from .ikdhfile import is_ikdh

    return is_ikdh(content.mapping)


def _hand_table(content: Content) -> bool:
    """A claim on a hand-written table (:func:`~urdf2dh.io.handtable.is_hand_table`)."""
    from .handtable import is_hand_table

    return is_hand_table(content.mapping)


READERS: dict[str, Reader] = {
    r.name: r
    for r in [
        Reader("xacro", "xacro", "xacro file (.xacro)", "xacro", lambda c: c.suffix == ".xacro"),
        Reader("mjcf", "MJCF", "MJCF (<mujoco>)", "mjcf", lambda c: c.xml_root == "mujoco"),
        Reader(
            "urdf",
            "URDF",
            "URDF (<robot>)",
            "urdf",
            lambda c: c.suffix in (".urdf", ".xml") or first_character(c.data) == "<",
        ),
        Reader("poe", "POE", "POE model ('format: poe')", "poefile", _mapping_key("format", "poe")),
        Reader(
            "table",
            "table",
            f"table file ('schema: {TABLE_FILE}')",
            "tablefile",
            _mapping_key("schema"),
        ),
        Reader(
            "ur",
            "UR kinematics",
            "UR kinematics file ('kinematics: {shoulder: ...}')",
            "urkinematics",
            _ur_kinematics,
        ),
        Reader(
            "hal",
            "LinuxCNC HAL",
            "LinuxCNC genserkins HAL file (.hal, 'setp genserkins.')",
            "halfile",
            _hal,
        ),
        Reader(
            "opw",
            "OPW",
            "OPW parameter file ('opw_kinematics_geometric_parameters')",
            "opwfile",
            _opw,
        ),
        Reader("ikdh", "ikdh", "ikdh robot file ('dh: {a, d, alpha, theta}')", "ikdhfile", _ikdh),
        Reader(
            "hand",
            "hand-written table",
            "hand-written table (rows of theta, d, a, alpha, with convention and units)",
            "readings",
            _hand_table,
        ),
    ]
}


def _listed(items: list[str]) -> str:
    return ", ".join(items[:-1]) + " or " + items[-1]


def source_kinds(described: bool = False) -> str:
    """The formats a SOURCE may be, for messages: ``URDF, xacro, ... or table``, or with
    ``described`` how each is recognised (``URDF (<robot>), ...``)."""
    return _listed([r.described if described else r.title for r in READERS.values()])


def _from_file(path: Path, display: str, reading: Reading, bundled: Bundled | None) -> Source:
    role = f"the installed file of bundled robot '{bundled.name}'" if bundled else SOURCE_ROLE
    data = read_file(path, display, role)
    check_text(data, display, f"a {source_kinds()} file")
    content = Content(path, display, data, bundled)
    for reader in READERS.values():
        if reader.claims(content):
            return reader.read(content, reading)
    error = content.mapping_error()
    if error is not None:
        raise error
    raise InputError(f"{display}: not a {source_kinds(described=True)}")


def open_source(
    source: str,
    tol: Tolerances = DEFAULT,
    package_paths: Mapping[str, str] | None = None,
    xacro: XacroOptions | None = None,
    bound: JointBound | None = None,
) -> Source:
    """Resolve SOURCE: an existing file, else a bundled robot name (``urdf2dh robots``).

    ``package_paths`` maps ROS package names to directories, and ``xacro`` says how to expand
    ``.xacro`` sources (its packages joined with ``package_paths``). ``bound``: a command's bound
    on a URDF's joints, refused as soon as they are counted (before the tree is built).
    """
    if package_paths:
        from .xacro import XacroOptions

        xacro = replace(xacro or XacroOptions(), packages={
            **(xacro.packages if xacro else {}), **package_paths})  # fmt: skip
    reading = Reading(tol, xacro, bound)
    if not source:
        raise SourceError(
            f"SOURCE is empty: give a {source_kinds()} file, or a bundled robot's name "
            f"{choices(ROBOTS, limit=30)}"
        )
    path = Path(source)
    if _exists(path):
        return _from_file(path, source, reading, None)
    bundled = lookup(source)
    if bundled is not None:
        file = robot_path(bundled)
        return _from_file(file, file.name, Reading(tol, bound=bound), bundled)
    looks_like_file = any(ch in source for ch in "/\\.")
    if looks_like_file:
        shortened = source if len(source) <= SHOWN_LENGTH else shown(source)
        raise SourceError(f"{shortened}: no such file")
    raise SourceError(
        f"{shown(source)} is neither a file nor a bundled robot"
        f"{near(source, [*ROBOTS, *REFERENCES])}; bundled robots are "
        f"{choices(ROBOTS, limit=30)} (urdf2dh robots lists them, and {len(REFERENCES)} "
        "reference tables)"
    )


def _exists(path: Path) -> bool:
    """Whether ``path`` names something: a name the system cannot look up (longer than a file
    name can be, holding a NUL) names nothing."""
    try:
        return path.exists()
    except (OSError, ValueError):
        return False


def load(
    source: str | os.PathLike[str],
    base: str | None = None,
    tip: str | None = None,
    ignore_mimic: bool = False,
    *,
    tol: Tolerances = DEFAULT,
    xacro: XacroOptions | None = None,
) -> PoeModel:
    """The POE model of the serial chain in a SOURCE.

    Parameters
    ----------
    source
        A URDF or ``.xacro`` file, a POE model file (docs/formats/poe-file.md), a table file
        (docs/formats/table-file.md), or the name of a bundled robot (``urdf2dh robots``).
    base, tip
        Links that bound the chain (URDF sources). The base defaults to the bundled robot's
        own, else the URDF's root link; the tip to the bundled robot's own, else the single
        deepest leaf below the base (a tie between leaves is an error naming them).
    ignore_mimic
        Treat mimic joints on the chain as independent joints (with a warning).
    tol
        The tolerances of reading a POE or table file (how far from orthonormal a typed
        rotation may be; round-off).
    xacro
        How ``.xacro`` sources are expanded (ROS packages, arguments, time and memory).

    Returns
    -------
    PoeModel
        The movable joints' screws at the home pose, ``(4, 4)`` home pose of the tip.

    Raises
    ------
    Urdf2DhError
        A one-line message naming the file, link or joint at fault (:class:`SourceError` for
        a SOURCE that is empty or names neither a file nor a bundled robot).
    TypeError
        An argument of the wrong type (``source`` neither text nor a path, ``ignore_mimic``
        not a bool).
    """
    source = check_source(source, "load: source")
    base = check_optional_name(base, "load: base")
    tip = check_optional_name(tip, "load: tip")
    ignore_mimic = check_flag(ignore_mimic, "load: ignore_mimic")
    check_instance(tol, Tolerances, "load: tol", "urdf2dh.Tolerances(...) or urdf2dh.DEFAULT")
    return open_source(source, tol, xacro=xacro).model(base, tip, ignore_mimic)
