"""YAML and JSON text -> a tree of plain values, read the same way whichever of the two it is.

POE model files and table files are YAML or JSON. Their numbers are read as JSON and YAML 1.2
(its core schema) read them, never as YAML 1.1 does (PyYAML's default, which reads ``0100`` as
64 and ``2:50`` as 170, a silently different table):

* numbers are the decimal numbers of urdf2dh's one grammar (:mod:`urdf2dh.numerals`), which
  the core schema reads alike: integers ``[-+]?(0|[1-9][0-9]*)``, floats such as ``1.5``,
  ``.5``, ``5.``, ``1e3``, ``-2.5E-3``; ``true``/``false``; ``null``, ``~`` or nothing;
* everything else is text: ``2:50`` (base 60), ``1_000``, ``0b101``, ``yes``, ``no``, ``on``,
  ``off``, and the core schema's numbers of other forms, ``0x1F``, ``0o17``, ``.inf``, ``.nan``,
  which no other file urdf2dh reads may hold either. An integer written with a leading zero
  (``0100``) is text too: YAML 1.2 reads it as 100 and YAML 1.1 as 64, so it is refused where a
  number is expected rather than read either way. Text where a number is expected is an error
  naming the field, and says why it is not a number, or what a YAML 1.1 reader would have made
  of it (:func:`urdf2dh.io.fields.check_number`).

A key that appears twice in one mapping, in YAML or JSON, is an error naming the key (and for
YAML its line); YAML 1.1's merge key (``<<: *defaults``) still merges, its keys overridden by
the mapping's own. A tree holds at most :data:`~urdf2dh.tolerances.MAPPING_VALUES` values (nodes as
written, and again with aliases counted each time they are used) and is nested at most
:data:`~urdf2dh.tolerances.MAPPING_DEPTH` levels deep.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any, ClassVar

from ..errors import InputError, shown
from ..numerals import DECIMAL
from ..tolerances import MAPPING_DEPTH, MAPPING_VALUES

__all__ = ["read_mapping", "yaml_text"]

# The YAML 1.2 core schema (YAML 1.2.2, section 10.3.2), its numbers restricted to urdf2dh's one
# grammar (no 0o17, 0x1F, .inf, .nan) and integers with a leading zero excepted (a float has a
# point or an exponent here: digits alone are an integer or, with a leading zero, text)
_CORE = (
    ("null", r"~|null|Null|NULL|", "~nN"),
    ("bool", r"true|True|TRUE|false|False|FALSE", "tTfF"),
    ("int", r"[-+]?(?:0|[1-9][0-9]*)", "-+0123456789"),
    ("float", rf"(?![-+]?[0-9]+$){DECIMAL}", "-+0123456789."),
)
_MERGE = "tag:yaml.org,2002:merge"


class _DuplicateKey(Exception):
    """A mapping's key seen twice (``line`` 0: unknown, as for JSON)."""

    def __init__(self, key: Any, line: int = 0) -> None:
        super().__init__(key)
        self.key, self.line = key, line


def read_mapping(path: Path, display: str, data: bytes) -> Any:
    """Parse YAML or JSON text (JSON for ``.json``, YAML otherwise) into plain values, with a
    one-line error naming the file (see the module docstring); UTF-8 only.

    Raises
    ------
    InputError
        Text that is not UTF-8, malformed, nested too deeply, over the value budget, or with a
        key twice in a mapping.
    """
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        raise InputError(f"{display}: not UTF-8 text (byte {e.start}); save it as UTF-8") from e
    try:
        tree = _json(text, display) if path.suffix.lower() == ".json" else yaml_text(text, display)
    except RecursionError as e:
        raise InputError(f"{display}: nested too deeply") from e
    except _DuplicateKey as e:
        key = shown(e.key) if isinstance(e.key, str) else repr(e.key)[:40]
        where = f" (line {e.line})" if e.line else ""
        raise InputError(
            f"{display}: key {key} appears twice in one mapping{where}; each key may appear once"
        ) from None
    _within_budget(tree, display)
    return tree


def _unique(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise _DuplicateKey(key)
        out[key] = value
    return out


def _json(text: str, display: str) -> Any:
    try:
        return json.loads(text, object_pairs_hook=_unique)
    except json.JSONDecodeError as e:
        raise InputError(f"{display}: malformed JSON (line {e.lineno}: {e.msg})") from e
    except ValueError as e:  # e.g. an integer of more digits than Python converts
        raise InputError(f"{display}: malformed JSON ({e})") from e


def yaml_text(text: str, display: str) -> Any:
    """YAML text as plain values (the module docstring's rules), or a one-line error."""
    import yaml

    loader = _loader()
    try:
        _scan(yaml, text, display, loader)
        return yaml.load(text, Loader=loader)  # a safe loader with our schema
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f"line {mark.line + 1}: " if mark is not None else ""
        problem = getattr(e, "problem", None) or str(e).splitlines()[0]
        if "nesting depth" in problem:  # libyaml 0.2.6 bounds depth itself, at our bound
            raise InputError(
                f"{display}: nested too deeply (more than {MAPPING_DEPTH:,} levels)"
            ) from e
        raise InputError(f"{display}: malformed YAML ({where}{problem})") from e
    except ValueError as e:  # an integer of more digits than Python converts
        raise InputError(f"{display}: malformed YAML ({e})") from e


def _scan(yaml: Any, text: str, display: str, loader: type) -> None:
    """Refuse a document nested deeper than :data:`~urdf2dh.tolerances.MAPPING_DEPTH` or of more
    than :data:`~urdf2dh.tolerances.MAPPING_VALUES` nodes, from its parser's events (a stream, in
    constant memory), before the loader builds them: libyaml's composer recurses once per level
    and holds every node."""
    depth = nodes = 0
    opening = (yaml.SequenceStartEvent, yaml.MappingStartEvent)
    closing = (yaml.SequenceEndEvent, yaml.MappingEndEvent)
    for event in yaml.parse(text, Loader=loader):
        if isinstance(event, opening):
            depth += 1
            nodes += 1
            if depth > MAPPING_DEPTH:
                raise InputError(
                    f"{display}: nested too deeply (more than {MAPPING_DEPTH:,} levels)"
                )
        elif isinstance(event, closing):
            depth -= 1
        elif isinstance(event, yaml.NodeEvent):  # a scalar or an alias
            nodes += 1
        if nodes > MAPPING_VALUES:
            raise InputError(f"{display}: more than {MAPPING_VALUES:,} values")


_LOADER: type | None = None


def _loader() -> type:
    """PyYAML's safe loader with the YAML 1.2 core schema and no duplicate keys; made once, on
    first use (PyYAML is imported only then)."""
    global _LOADER
    if _LOADER is None:
        _LOADER = _make_loader()
    return _LOADER


def _make_loader() -> type:
    import yaml

    # libyaml's parser where PyYAML has it (four times as fast); its composer recurses once per
    # level without a bound (a segmentation fault at ~50,000), which _scan rules out first
    base = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

    class Loader(base):  # type: ignore[misc, valid-type]
        yaml_implicit_resolvers: ClassVar[dict[str, list[tuple[str, re.Pattern[str]]]]] = {}

        def construct_mapping(self, node: Any, deep: bool = False) -> Any:
            seen: set[Any] = set()
            for key_node, _ in node.value:
                if key_node.tag == _MERGE:
                    continue
                key = self.construct_object(key_node, deep=True)
                try:
                    repeated = key in seen
                except TypeError:  # unhashable: the base class says so
                    continue
                if repeated:
                    raise _DuplicateKey(key, key_node.start_mark.line + 1)
                seen.add(key)
            return super().construct_mapping(node, deep)

    for name, pattern, first in _CORE:
        starts = [*first, ""] if name == "null" else list(first)  # "": the empty scalar
        Loader.add_implicit_resolver(
            f"tag:yaml.org,2002:{name}", re.compile(f"^(?:{pattern})$"), starts
        )
    Loader.add_implicit_resolver(_MERGE, re.compile(r"^(?:<<)$"), ["<"])
    Loader.add_constructor("tag:yaml.org,2002:int", _int)
    Loader.add_constructor("tag:yaml.org,2002:float", _float)
    return Loader


def _int(loader: Any, node: Any) -> int:
    return int(loader.construct_scalar(node))


def _float(loader: Any, node: Any) -> float:
    return float(loader.construct_scalar(node))  # of the grammar: 1e999 is inf, then refused


def _within_budget(tree: Any, display: str) -> None:
    """Count the values of a parsed tree (a shared, aliased one as often as it is reached)."""
    count, stack = 0, [tree]
    while stack:
        value = stack.pop()
        count += 1
        if count > MAPPING_VALUES:
            raise InputError(
                f"{display}: more than {MAPPING_VALUES:,} values (aliases counted as expanded)"
            )
        if isinstance(value, dict):
            stack.extend(value.values())
        elif isinstance(value, list):
            stack.extend(value)
