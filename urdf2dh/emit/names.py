"""Names a writer makes up, kept clear of the robot's own.

Several outputs need names the robot does not give: MATLAB's fixed bodies (``dh_base``,
``body<i>_offset``) and the bodies of its joints (``body<i>``), the fixed joints that carry them
(``<body>_fixed``), KDL's fixed joints and the segments of its rows, the URDF writer's links
(``<joint>_link``) and the lead joint of a helical joint (``<joint>_lead``). A robot may use any
of those names itself: a tip link called ``body2``, a joint called ``tool_fixed``. Two bodies,
segments, links or joints of one name make the file wrong for its reader (MATLAB's ``addBody``
refuses the second, a URDF parser keeps one of them, a KDL tree refuses the segment).

So each namespace of a written file (a MATLAB script's bodies, its joints; a URDF's links, its
joints; a KDL chain's segments, its joints) is a :class:`Namespace`: the robot's own names go in
first and are written exactly as the source spells them, and every name the writer makes up is
:meth:`Namespace.invent`\\ ed: the name itself if it is free, else the name with the first
suffix ``_2``, ``_3``, ... that is. Each such change is stated in the file
(:func:`renaming_notes`, a comment line each), so a reader can find the body or link it looks
for. Two of the robot's own names that are the same in one namespace cannot both be written:
:class:`~urdf2dh.errors.ExportError`, naming the name.
"""

from __future__ import annotations

from collections.abc import Iterable

from ..errors import ExportError, shown

__all__ = ["RENAMED", "Namespace", "renaming_notes"]

RENAMED = "urdf2dh renamed its"  # how every renaming note starts (the file's comments)


class Namespace:
    """One namespace of a written file: the names in it so far, and the made-up names that had
    to change.

    Parameters
    ----------
    target
        The output (``matlab``, ``kdl``, ``urdf``), for the error message.
    kind
        What the names name (``body``, ``joint``, ``link``, ``segment``).
    own
        The robot's own names in this namespace, written exactly; ``ExportError`` if one of them
        appears twice.
    """

    def __init__(self, target: str, kind: str, own: Iterable[str]) -> None:
        self.kind = kind
        self.own: set[str] = set()
        self.renamed: list[tuple[str, str]] = []
        for name in own:
            if name in self.own:
                raise ExportError(
                    f"{target}: two {kind}s are named {shown(name)}; {target} needs every "
                    f"{kind} name once (rename one in the source)"
                )
            self.own.add(name)
        self.taken = set(self.own)

    def invent(self, name: str) -> str:
        """``name`` if it is free, else ``name_2``, ``name_3``, ... (the first free one); taken
        from now on."""
        out, k = name, 1
        while out in self.taken:
            k += 1
            out = f"{name}_{k}"
        self.taken.add(out)
        if out != name:
            self.renamed.append((name, out))
        return out


def renaming_notes(*spaces: Namespace) -> list[str]:
    """One line per made-up name that had to change, for the file's comments (without the
    comment marker: each target writes them through its language's comment function)."""
    return [
        f"{RENAMED} {space.kind} {old} to {new}: "
        + (f"{old} is the robot's" if old in space.own else f"{old} is taken")
        for space in spaces
        for old, new in space.renamed
    ]
