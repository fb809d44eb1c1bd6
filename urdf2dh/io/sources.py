"""SOURCE resolution (docs/commands/index.md): a URDF file, a POE model file, a table file, or
a bundled robot.

:func:`open_source` reads and checks the file once; :meth:`Source.model` then builds the POE
model of the chain between the requested links.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path

from ..checks import check_flag, check_instance, check_optional_name, check_source
from ..errors import SHOWN_LENGTH, InputError, SourceError, UsageError, choices, shown
from ..model.poe import PoeModel
from ..schemas import TABLE_FILE as SCHEMA
from ..tolerances import DEFAULT, Tolerances
from .catalog import ROBOTS, Bundled, robot_path
from .encodings import check_text, first_character
from .fields import JointBound
from .files import SOURCE_ROLE, read_file
from .mappings import read_mapping
from .urdf import UrdfTree, parse_tree, tree_to_poe
from .xacro import XacroOptions

__all__ = ["Source", "load", "open_source"]


@dataclass(frozen=True, slots=True)
class Source:
    """A resolved SOURCE. URDF sources keep their text (for Pinocchio) and tree."""

    kind: str  # "urdf", "poe" or "table"
    display: str
    name: str
    tree: UrdfTree | None = None
    urdf_text: bytes | None = None
    poe: PoeModel | None = None
    bundled: Bundled | None = None

    def model(
        self,
        base: str | None = None,
        tip: str | None = None,
        ignore_mimic: bool = False,
    ) -> PoeModel:
        """The POE model of the chain ``base -> tip`` (defaults: the URDF's root link and
        its single deepest leaf, or the bundled robot's own)."""
        if self.tree is None:
            if base or tip:
                raise UsageError(
                    f"{self.display}: base and tip links apply to URDF sources; a {self.kind} file "
                    "is already a single chain"
                )
            assert self.poe is not None
            return self.poe
        if self.bundled is not None:
            base = base or self.bundled.base
            tip = tip or self.bundled.tip
        return tree_to_poe(self.tree, base, tip, ignore_mimic, self.name)


def _from_file(
    path: Path,
    display: str,
    tol: Tolerances,
    bundled: Bundled | None,
    xacro: XacroOptions | None = None,
    bound: JointBound | None = None,
) -> Source:
    role = f"the installed file of bundled robot '{bundled.name}'" if bundled else SOURCE_ROLE
    data = read_file(path, display, role)
    check_text(data, display, "a URDF, POE or table file")
    suffix = path.suffix.lower()
    if suffix == ".xacro":
        from .xacro import expand

        data = expand(path, display, xacro)
    if suffix in (".xacro", ".urdf", ".xml") or first_character(data) == "<":
        tree = parse_tree(data, display, bound)
        return Source(
            "urdf", display, bundled.name if bundled else tree.name, tree, tree.xml, bundled=bundled
        )
    tree_data = read_mapping(path, display, data)
    if isinstance(tree_data, dict) and tree_data.get("format") == "poe":
        from .poefile import read_poe

        poe = read_poe(tree_data, display, tol)
        name = bundled.name if bundled else poe.name
        return Source("poe", display, name, poe=poe, bundled=bundled)
    if isinstance(tree_data, dict) and "schema" in tree_data:
        from .tablefile import read_table

        table = read_table(tree_data, display, tol)
        return Source(
            "table", display, table.robot or path.stem, poe=table.to_poe(), bundled=bundled
        )
    raise InputError(
        f"{display}: not a URDF, POE model ('format: poe') or table file ('schema: {SCHEMA}')"
    )


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
        xacro = replace(xacro or XacroOptions(), packages={
            **(xacro.packages if xacro else {}), **package_paths})  # fmt: skip
    if not source:
        raise SourceError(
            "SOURCE is empty: give a URDF, xacro, POE or table file, or a bundled robot's name "
            f"{choices(ROBOTS, limit=30)}"
        )
    path = Path(source)
    if _exists(path):
        return _from_file(path, source, tol, None, xacro, bound)
    if source in ROBOTS:
        bundled = ROBOTS[source]
        file = robot_path(bundled)
        return _from_file(file, file.name, tol, bundled, bound=bound)
    looks_like_file = any(ch in source for ch in "/\\.")
    if looks_like_file:
        shortened = source if len(source) <= SHOWN_LENGTH else shown(source)
        raise SourceError(f"{shortened}: no such file")
    raise SourceError(
        f"{shown(source)} is neither a file nor a bundled robot; bundled robots are "
        f"{choices(ROBOTS, limit=30)}"
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
