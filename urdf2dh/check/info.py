"""What a SOURCE holds: its links and joints, the chain that would be converted, how many of its
parameters a calibration can identify, and the analytic IK families it belongs to (:func:`info`,
``urdf2dh info``)."""

from __future__ import annotations

import os
from collections import Counter
from dataclasses import dataclass

from ..checks import check_flag, check_optional_name, check_source
from ..conventions.families import Families, families
from ..errors import ChainError, ConversionError, choices, shown, visible
from ..escape import markdown_table, markdown_text
from ..io.sources import Source, open_source
from ..io.xacro import XacroOptions
from ..model.identifiability import BASE, TOOL, Identifiability
from ..model.poe import PoeModel

__all__ = ["Info", "TreeJoint", "info"]

LETTER = {"revolute": "R", "prismatic": "P", "helical": "H"}


@dataclass(frozen=True, slots=True)
class TreeJoint:
    """A joint of a URDF's or MJCF file's tree, as ``info`` lists it (``type`` a URDF joint
    type; for MJCF, a hinge is ``revolute`` or ``continuous``, a slide ``prismatic``, a ball or
    free joint ``floating``, and ``fixed`` an edge to a jointless body or a site)."""

    name: str
    type: str
    parent: str
    child: str
    mimics: str | None = None


@dataclass(frozen=True, slots=True)
class Info:
    """What a SOURCE holds (:func:`info`).

    Attributes
    ----------
    robot, kind, display
        The source's name, its kind (``urdf``, ``mjcf``, ``poe`` or ``table``) and its file.
    links, root, joints
        A URDF's or MJCF file's links (their number), root link and joints (empty for a POE or
        table file).
    start, tips
        The link the tips were looked for below (``--base``, a bundled robot's base, or the
        root) and the leaves below it (URDF sources).
    chain
        The chain that would be converted, or ``None`` where it cannot be determined.
    chain_error
        Why not, then.
    identifiable
        The chain's parameter counts (Wu 2019 §V), or ``None`` without a chain.
    families
        The chain's analytic inverse-kinematics families and the exports that solve each
        (:func:`urdf2dh.conventions.families.families`), or ``None`` without a chain (or where
        its table fails its self-check, which ``convert`` reports).
    """

    robot: str
    kind: str
    display: str
    links: int
    root: str
    joints: tuple[TreeJoint, ...]
    start: str
    tips: tuple[str, ...]
    chain: PoeModel | None
    chain_error: str | None
    identifiable: Identifiability | None
    families: Families | None = None

    def text(self) -> str:
        """What ``urdf2dh info`` prints (names as :func:`~urdf2dh.errors.visible` text)."""
        v = visible
        lines = [f"robot: {v(self.robot)} ({self.kind}: {v(self.display)})"]
        if self.root:  # a tree (URDF, MJCF)
            types = Counter(j.type for j in self.joints)
            lines.append(f"links: {self.links}; root: {v(self.root)}")
            lines.append(
                f"joints: {len(self.joints)} ("
                + ", ".join(f"{n} {t}" for t, n in sorted(types.items()))
                + ")"
            )
            for j in self.joints:
                extra = f", mimics {v(j.mimics)}" if j.mimics else ""
                lines.append(f"  {v(j.name)}: {j.type}, {v(j.parent)} -> {v(j.child)}{extra}")
            lines.append(f"candidate tips below {v(self.start)}: {choices(self.tips, limit=40)}")
        if self.chain is None:
            lines.append(f"chain: not determined ({v(self.chain_error or '')})")
        else:
            lines.extend(self._chain_lines())
        return "\n".join(lines) + "\n"

    def _chain_lines(self) -> list[str]:
        model, ident = self.chain, self.identifiable
        assert model is not None and ident is not None
        v = visible
        letters = "".join(LETTER[j.kind] for j in model.joints) or "(none)"
        out = [f"chain: {v(model.base_link)} -> {v(model.tip_link)}: {model.n} movable joints "
               f"{letters}"]  # fmt: skip
        for i, j in enumerate(model.joints, 1):
            follows = "" if j.mimic is None else (
                f", follows {v(j.mimic.joint)}: q = {j.mimic.multiplier:g} q_{v(j.mimic.joint)} "
                f"+ {j.mimic.offset:g}")  # fmt: skip
            out.append(f"  {i}. {v(j.name)} ({j.kind}{follows})")
        out.append(f"size: {model.size():.6g} {v(model.length_unit)} (the robot size that errors "
                   "and tolerances are measured against)")  # fmt: skip
        out.append(
            f"identifiable parameters (Wu 2019 eq. 23): 5h + 4r + 2t + n + 6 = "
            f"5*{ident.helical} + 4*{ident.revolute} + 2*{ident.prismatic} + "
            f"{ident.joints} + 6 = {ident.maximum}"
        )
        out.append(
            f"conventional count (eq. 22, helical joints as revolute): 4r + 2t + 6 = "
            f"{ident.conventional}; of its 6 base/tool parameters, {BASE} sit in the "
            f"base and {TOOL} in the tool"
        )
        if self.families is not None:
            out.extend(v(line) for line in self.families.lines())
        out.extend(f"warning: {v(w)}" for w in model.warnings)
        return out

    def __str__(self) -> str:
        """What ``urdf2dh info`` prints."""
        return self.text()

    def __repr__(self) -> str:
        return (
            f"<Info {shown(self.robot)} ({self.kind}): {self.links} links, "
            f"{len(self.joints)} joints>"
        )

    def _repr_markdown_(self) -> str:
        """In a notebook: the chain's joints and counts as tables (names escaped)."""
        t = markdown_text
        out = [f"**{t(self.robot)}** ({self.kind}: {t(self.display)})", ""]
        if self.root:
            out.append(f"{self.links} links (root {t(self.root)}), {len(self.joints)} joints; "
                       f"tips below {t(self.start)}: {', '.join(map(t, self.tips))}")  # fmt: skip
            out.append("")
        if self.chain is None:
            return "\n".join([*out, f"chain: not determined ({t(self.chain_error or '')})"]) + "\n"
        ident = self.identifiable
        assert ident is not None
        out += markdown_table(
            ["identifiable parameters", "count"],
            [["maximum, 5h + 4r + 2t + n + 6 (Wu 2019 eq. 23)", str(ident.maximum)],
             ["conventional, 4r + 2t + 6 (eq. 22)", str(ident.conventional)]],
        )  # fmt: skip
        if self.families is not None:
            out += ["", *(f"- {t(line.strip())}" for line in self.families.lines())]
        return "\n".join(out) + "\n\n" + self.chain._repr_markdown_()


def describe(source: Source, base: str | None, tip: str | None, ignore_mimic: bool) -> Info:
    """What an opened SOURCE holds, its chain ``base -> tip`` (:func:`info`)."""
    tree = source.tree
    joints: tuple[TreeJoint, ...] = ()
    start, links, root = "", 0, ""
    tips: tuple[str, ...] = ()
    if tree is not None:
        joints = tuple(
            TreeJoint(j.name, j.type, j.parent, j.child, j.mimic) for j in tree.joints.values()
        )
        start = base or (source.bundled.base if source.bundled else None) or tree.root
        tips, links, root = tuple(tree.leaves(start)), len(tree.links), tree.root
    error: str | None = None
    try:
        model: PoeModel | None = source.model(base, tip, ignore_mimic)
    except ChainError as e:
        model, error = None, str(e)
    ident = None if model is None else Identifiability.of(j.kind for j in model.joints)
    return Info(source.name, source.kind, source.display, links, root, joints, start, tips,
                model, error, ident, None if model is None else _families(model))  # fmt: skip


def _families(model: PoeModel) -> Families | None:
    try:
        return families(model)
    except ConversionError:  # the table fails its self-check: convert says so
        return None


def info(
    source: str | os.PathLike[str] | Source,
    base: str | None = None,
    tip: str | None = None,
    ignore_mimic: bool = False,
    *,
    xacro: XacroOptions | None = None,
) -> Info:
    """What a SOURCE holds: for a URDF its links, joints and candidate tips; the chain ``base ->
    tip`` that would be converted; the chain's identifiable parameter counts (Wu 2019 §V); the
    analytic inverse-kinematics families of the chain and the export each needs.

    Parameters
    ----------
    source
        A URDF or ``.xacro`` file, a POE model file, a table file, a bundled robot's name, or a
        SOURCE already opened (:func:`urdf2dh.io.sources.open_source`).
    base, tip
        Links that bound the chain (as :func:`urdf2dh.load` takes them).
    ignore_mimic
        Treat mimic joints on the chain as independent joints.
    xacro
        How ``.xacro`` sources are expanded.

    Returns
    -------
    Info
        Its :meth:`~Info.text` is what ``urdf2dh info`` prints; a chain that cannot be
        determined (an ambiguous tip, say) is reported in it, not raised.

    Raises
    ------
    Urdf2DhError
        A SOURCE that cannot be read (:class:`~urdf2dh.errors.InputError`, naming the file).
    TypeError
        An argument of the wrong type.
    """
    if not isinstance(source, Source):
        source = open_source(check_source(source, "info: source"), xacro=xacro)
    base = check_optional_name(base, "info: base")
    tip = check_optional_name(tip, "info: tip")
    return describe(source, base, tip, check_flag(ignore_mimic, "info: ignore_mimic"))
