"""MJCF default classes: where an element's attribute comes from when it does not write it.

``<default>`` elements at the top of the document make the class ``main``; a ``<default
class="name">`` inside another makes a class inheriting from it. Each class holds at most one
template per element kind (``<joint .../>``, ``<site .../>``, ``<equality .../>``). An element's
class is its ``class`` attribute, else the ``childclass`` of the nearest enclosing body or frame
(a body's own ``childclass`` reaches its own joints and sites), else ``main``. An attribute the
element does not write comes from its class's template, else from the class it inherits from,
and so on up to ``main`` (MuJoCo's XML reference, "Default settings").

An orientation (``quat``, ``axisangle``, ``euler``, ``xyaxes``, ``zaxis``) counts as one
attribute: an element that writes any of them takes none from its defaults, and otherwise takes
the nearest class's that writes one.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ...errors import InputError, shown
from .placement import ORIENTATIONS, Lookup

__all__ = ["MAIN", "Defaults"]

MAIN = "main"  # the class of the top-level <default>
KINDS = ("joint", "site", "equality")  # the templates a class holds that urdf2dh reads


@dataclass(frozen=True, slots=True)
class _Class:
    parent: str | None
    templates: dict[str, dict[str, str]]  # element kind -> attribute -> value


class Defaults:
    """The default classes of a document (module docstring).

    Parameters
    ----------
    root
        The ``<mujoco>`` element, includes spliced.
    display
        The file's name in messages.

    Raises
    ------
    InputError
        A class defined twice, a nested ``<default>`` without a class, or a template given twice
        in one class.
    """

    def __init__(self, root: Any, display: str) -> None:
        self.display = display
        self.classes: dict[str, _Class] = {MAIN: _Class(None, {})}
        for top in root.iterchildren("default"):
            self._read(top, MAIN, None)

    def _read(self, el: Any, name: str, parent: str | None) -> None:
        where = f"{self.display}: <default class={shown(name)}>"
        cls = self.classes.get(name)
        if cls is None:
            cls = self.classes[name] = _Class(parent, {})
        elif name != MAIN:
            raise InputError(f"{where} is defined twice")
        for child in el:
            if child.tag == "default":
                inner = child.get("class")
                if not inner:
                    raise InputError(f"{where}: a nested <default> has no class attribute")
                self._read(child, inner, name)
            elif child.tag in KINDS:
                if child.tag in cls.templates and name != MAIN:
                    raise InputError(f"{where} has two <{child.tag}> templates")
                cls.templates.setdefault(child.tag, {}).update(child.attrib)

    def check(self, name: str, where: str, attribute: str = "class") -> str:
        """``name`` if it is a class; an error naming ``where`` and the attribute otherwise."""
        if name not in self.classes:
            raise InputError(f"{where}: {attribute} {shown(name)} is no default class")
        return name

    def _lineage(self, name: str) -> list[dict[str, dict[str, str]]]:
        out = []
        current: str | None = name
        while current is not None:
            cls = self.classes[current]
            out.append(cls.templates)
            current = cls.parent
        return out

    def lookup(self, el: Any, childclass: str, where: str) -> Lookup:
        """The attribute values of element ``el`` (a ``joint``, ``site`` or ``equality``): its
        own, else its class's (``class``, else ``childclass``, the one in force around it)."""
        kind = el.tag if el.tag != "freejoint" else "joint"
        own = el.attrib
        name = self.check(own["class"], where) if "class" in own else childclass
        templates = [t.get(kind, {}) for t in self._lineage(name)]
        own_orientation = any(a in own for a in ORIENTATIONS)
        oriented = next((t for t in templates if any(a in t for a in ORIENTATIONS)), {})

        def get(attribute: str) -> str | None:
            if attribute in ORIENTATIONS:
                return own.get(attribute) if own_orientation else oriented.get(attribute)
            if attribute in own:
                return str(own[attribute])
            return next((t[attribute] for t in templates if attribute in t), None)

        return get
