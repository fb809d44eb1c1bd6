"""Several chains of one URDF tree in one run: ``--all-tips`` or ``--tip`` given more than once
(``convert``, ``verify``, ``export``).

:func:`chain_tips` says which tips; :func:`chain_models` builds one POE model per tip, every
error naming its tip (:class:`TipError`); :func:`file_names` turns the tips into the file names
of ``-o DIR``, refusing a link name that cannot be one; :func:`join_tables` puts several tables
on stdout where a format can hold them.

The rules:

* The base is ``--base``, else a bundled robot's own base, else the URDF's root link.
* ``--all-tips``: every leaf below the base, in the file's link order, except leaves whose chain
  holds only fixed joints (sensor and collision frames: their table would be a constant
  transform); no leaf left is an error. ``--tip`` given several times: those tips, in the order
  given, whatever their joints; a tip given twice is an error.
* ``-o DIR/`` (a trailing slash, or an existing directory) writes ``DIR/<tip><suffix>`` per
  tip; ``-o FILE`` (any other name) writes the one document stdout would. A tip whose name
  cannot be a file name is refused (exit 2) naming the link: empty, ``.`` or ``..``, holding
  ``/``, ``\\`` or a character that ``str.isprintable`` rejects (control characters, line
  breaks, NUL), starting with ``-``, longer than 255 bytes with its suffix, or equal to another
  tip's file name but for case.
* stdout: ``text`` and ``markdown`` print each table under a heading naming its tip; ``json``
  one object keyed by tip; ``yaml`` one document per tip (each names its ``tip_link``); ``csv``,
  ``urdf`` and ``poe`` are one file per chain and need ``-o DIR/``; so does ``export``.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

from ..emit.formats import SUFFIXES
from ..errors import ChainError, Urdf2DhError, UsageError, near, shown
from ..io.files import write_directory
from ..tolerances import JOINTS

if TYPE_CHECKING:
    import argparse

    from ..conventions.table import Table
    from ..io.sources import Source
    from ..io.urdf import UrdfTree
    from ..model.poe import PoeModel

__all__ = [
    "DIRECTORY_HINT",
    "FORMAT_SUFFIXES",
    "STDOUT_FORMATS",
    "TipError",
    "chain_models",
    "chain_tips",
    "chains_of",
    "check_stdout_format",
    "file_names",
    "heading",
    "join_tables",
    "names_directory",
    "naming_tip",
    "one_tip",
    "per_chain",
    "several",
    "several_of",
    "to_directory",
    "write_tips",
]

#: ``convert --format`` -> the suffix of each file in ``-o DIR``.
FORMAT_SUFFIXES = {fmt: suffixes[0] for fmt, suffixes in SUFFIXES.items()}

#: Formats that hold several tables on stdout (the others need ``-o DIR``).
STDOUT_FORMATS = ("text", "markdown", "json", "yaml")

NAME_MAX = 255  # bytes of a file name (Linux, macOS, Windows alike)


class TipError(Urdf2DhError):
    """An error met on one chain of several, naming the tip; it keeps the original's exit code
    (2 for bad input, 1 for a table that failed its own check)."""

    def __init__(self, tip: str, error: Urdf2DhError) -> None:
        super().__init__(f"tip {shown(tip)}: {error}", remedy=error.remedy)
        self.exit_code = error.exit_code


def several(all_tips: bool, tips: Sequence[str] | None) -> bool:
    """Whether the options ask for several chains (then ``-o`` names a directory)."""
    return all_tips or len(tips or ()) > 1


def heading(name: str) -> str:
    """A name from a file as a heading shows it: as it is, or ``repr``-escaped when it holds a
    character that would break the line (a control character, a line break)."""
    return name if name.isprintable() else repr(name)


def chain_tips(
    source: Source, base: str | None, tips: Sequence[str] | None, all_tips: bool
) -> tuple[str, list[str]]:
    """The base link and the tips of a run over several chains (module docstring).

    Raises
    ------
    UsageError
        A source that is not a URDF, or a tip given twice.
    ChainError
        An unknown base, or (``all_tips``) no leaf below the base with a moving joint on its
        chain.
    """
    tree = source.tree
    if tree is None:
        raise UsageError(
            f"{source.display}: --all-tips and several --tip apply to URDF sources; a "
            f"{source.kind} file is a single chain"
        )
    base = base or (source.bundled.base if source.bundled else None) or tree.root
    if base not in tree.links:
        from ..io.urdf.tree import names

        raise ChainError(
            f"{tree.path}: unknown base link {shown(base)}{near(base, tree.links)}; links are "
            f"{names(tree.links)}"
        )
    if not all_tips:
        chosen = list(tips or ())
        for i, tip in enumerate(chosen):
            if tip in chosen[:i]:
                raise UsageError(f"--tip {shown(tip)} is given twice")
        _within_bound(tree, base, chosen)
        return base, chosen
    order = {link: i for i, link in enumerate(tree.links)}
    leaves = sorted(tree.leaves(base), key=order.__getitem__)
    moving = [t for t in leaves if any(j.type != "fixed" for j in tree.chain(base, t))]
    if not moving:
        raise ChainError(
            f"{tree.path}: no leaf below base link {shown(base)} has a moving joint on its chain"
        )
    _within_bound(tree, base, moving)
    return base, moving


def _within_bound(tree: UrdfTree, base: str, tips: Sequence[str]) -> None:
    """At most :data:`~urdf2dh.tolerances.JOINTS` joints on the chains of one run, counted chain by
    chain (a comb of 3,000 links has 4.5 million)."""
    start = tree.depth(base) if base in tree.links else 0
    total = sum(tree.depth(t) - start for t in tips if t in tree.links)
    if total > JOINTS:
        raise UsageError(
            f"{tree.path}: the {len(tips):,} chains have {total:,} joints in all; one run "
            f"converts at most {JOINTS:,} (name fewer tips with --tip)"
        )


@contextmanager
def naming_tip(tip: str) -> Iterator[None]:
    """Re-raise an urdf2dh error met meanwhile as a :class:`TipError` naming ``tip``."""
    try:
        yield
    except TipError:
        raise
    except Urdf2DhError as e:
        raise TipError(tip, e) from e


def chain_models(
    source: Source, base: str, tips: Sequence[str], ignore_mimic: bool
) -> list[PoeModel]:
    """The POE model of the chain ``base -> tip`` for each tip; the first failure (a floating
    joint, a mimic joint without ``ignore_mimic``, an unknown tip) names its tip."""
    models = []
    for tip in tips:
        with naming_tip(tip):
            models.append(source.model(base, tip, ignore_mimic))
    return models


def _why_not_a_file_name(name: str, suffix: str) -> str | None:
    if name in ("", ".", ".."):
        return "it is empty, '.' or '..'"
    for bad in ("/", "\\"):
        if bad in name:
            return f"it holds {shown(bad)}"
    if not name.isprintable():
        return "it holds a control character"
    if name.startswith("-"):
        return "it starts with '-'"
    if len((name + suffix).encode("utf-8", "surrogatepass")) > NAME_MAX:
        return f"a file name has at most {NAME_MAX} bytes"
    return None


def file_names(display: str, tips: Sequence[str], suffix: str) -> dict[str, str]:
    """Tip -> its file name ``<tip><suffix>`` in ``-o DIR``.

    Raises
    ------
    UsageError
        A tip whose name cannot be a file name (module docstring), or two tips whose file names
        differ only in case.
    """
    out: dict[str, str] = {}
    folded: dict[str, str] = {}
    for tip in tips:
        why = _why_not_a_file_name(tip, suffix)
        if why is not None:
            raise UsageError(
                f"{display}: tip link {shown(tip)} cannot name a file in the output directory "
                f"({why})"
            )
        name = tip + suffix
        other = folded.setdefault(name.casefold(), tip)
        if other != tip:
            raise UsageError(
                f"{display}: tip links {shown(other)} and {shown(tip)} differ only in case; "
                "their files would be one on a case-insensitive file system"
            )
        out[tip] = name
    return out


DIRECTORY_HINT = "-o DIR/ (a trailing slash, or an existing directory)"


def names_directory(output: str) -> bool:
    """Whether ``-o`` names a directory for one file per chain: it ends with a slash, or it is
    an existing directory (or a symbolic link to one). Anything else is one file."""
    return output.endswith(("/", os.sep)) or Path(output).is_dir()


def check_stdout_format(fmt: str) -> None:
    """Refuse (before any conversion) a format that cannot hold several tables in one
    document (stdout, or ``-o FILE``)."""
    if fmt not in STDOUT_FORMATS:
        raise UsageError(
            f"--format {fmt} writes one file per chain; with several tips give {DIRECTORY_HINT}"
        )


def join_tables(tables: Sequence[Table], fmt: str) -> str:
    """Several tables as one stdout text in ``fmt`` (one of :data:`STDOUT_FORMATS`)."""
    from ..emit.formats import render

    check_stdout_format(fmt)
    if fmt == "json":
        import json

        return json.dumps({t.tip_link: t.to_dict() for t in tables}, indent=2) + "\n"
    if fmt == "yaml":
        return "".join(f"---\n{render(t, fmt)}" for t in tables)
    if fmt == "text":
        return "\n".join(f"==> {heading(t.tip_link)} <==\n{render(t, fmt)}" for t in tables)
    # markdown
    return "\n".join(f"## {heading(t.tip_link)}\n\n{render(t, fmt)}" for t in tables)


# --------------------------------------------------------------------------- a command's run


def one_tip(args: argparse.Namespace) -> str | None:
    """The tip of a single-chain run of a command that takes several (``args.tips``)."""
    return args.tips[0] if args.tips else None


def several_of(args: argparse.Namespace) -> bool:
    """Whether the command's options ask for several chains."""
    return several(args.all_tips, args.tips)


def chains_of(
    args: argparse.Namespace, source: Source, suffix: str | None = None
) -> list[PoeModel]:
    """The models of a run over several chains; ``suffix``: of the files of ``-o DIR/``, whose
    names are checked before any conversion."""
    base, tips = chain_tips(source, args.base, args.tips, args.all_tips)
    if suffix is not None:
        file_names(source.display, tips, suffix)
    return chain_models(source, base, tips, args.ignore_mimic)


def per_chain(models: list[PoeModel], what: str) -> Iterator[PoeModel]:
    """The chains of a run, with a progress bar on a terminal."""
    from ..progress import progress

    return progress(models, len(models), what)


def to_directory(args: argparse.Namespace) -> bool:
    """Whether a run over several chains writes one file per chain (``-o DIR/``)."""
    return args.output is not None and names_directory(args.output)


def write_tips(
    args: argparse.Namespace, source: Source, texts: list[tuple[PoeModel, str]], suffix: str
) -> None:
    """Write ``(model, text)`` pairs as ``-o DIR/<tip><suffix>``, all or nothing."""
    names = file_names(source.display, [m.tip_link for m, _ in texts], suffix)
    write_directory({names[m.tip_link]: text for m, text in texts}, args.output)
