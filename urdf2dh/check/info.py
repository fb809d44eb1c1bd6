"""``urdf2dh info``: what a SOURCE holds, the chain that would be converted, identifiability."""

from __future__ import annotations

from collections import Counter

from ..errors import ChainError, choices, visible
from ..io.sources import Source
from ..model.poe import PoeModel

__all__ = ["describe", "identifiability"]

LETTER = {"revolute": "R", "prismatic": "P", "helical": "H"}


def identifiability(model: PoeModel) -> dict[str, int]:
    """Parameter counts of Wu 2019 §V for a chain of ``h`` helical, ``r`` revolute and ``t``
    prismatic joints (``n`` in all).

    ``maximum`` is eq. (23), ``5h + 4r + 2t + n + 6`` (twists, scale factors, tool placement);
    ``conventional`` is eq. (22), ``4r + 2t + 6``, where helical joints count as revolute (the
    conventional setting leaves out helices and scale factors, §V-A). Of the six base/tool
    parameters, four sit in the base transform and two in the tool (§V-B, Fig. 3).
    """
    kinds = Counter(j.kind for j in model.joints)
    h, r, t = kinds["helical"], kinds["revolute"], kinds["prismatic"]
    n = model.n
    return {
        "helical": h,
        "revolute": r,
        "prismatic": t,
        "joints": n,
        "maximum": 5 * h + 4 * r + 2 * t + n + 6,
        "conventional": 4 * (r + h) + 2 * t + 6,
        "base": 4,
        "tool": 2,
    }


def _chain_lines(model: PoeModel) -> list[str]:
    ident = identifiability(model)
    letters = "".join(LETTER[j.kind] for j in model.joints) or "(none)"
    v = visible
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
        f"5*{ident['helical']} + 4*{ident['revolute']} + 2*{ident['prismatic']} + "
        f"{ident['joints']} + 6 = {ident['maximum']}"
    )
    out.append(
        f"conventional count (eq. 22, helical joints as revolute): 4r + 2t + 6 = "
        f"{ident['conventional']}; of its 6 base/tool parameters, {ident['base']} sit in the "
        f"base and {ident['tool']} in the tool"
    )
    out.extend(f"warning: {v(w)}" for w in model.warnings)
    return out


def describe(source: Source, base: str | None, tip: str | None, ignore_mimic: bool) -> str:
    """The text that ``urdf2dh info`` prints."""
    v = visible
    lines = [f"robot: {v(source.name)} ({source.kind}: {v(source.display)})"]
    tree = source.tree
    if tree is not None:
        types = Counter(j.type for j in tree.joints.values())
        lines.append(f"links: {len(tree.links)}; root: {v(tree.root)}")
        lines.append(
            f"joints: {len(tree.joints)} ("
            + ", ".join(f"{n} {t}" for t, n in sorted(types.items()))
            + ")"
        )
        for j in tree.joints.values():
            extra = f", mimics {v(j.mimic)}" if j.mimic else ""
            lines.append(f"  {v(j.name)}: {j.type}, {v(j.parent)} -> {v(j.child)}{extra}")
        start = base or (source.bundled.base if source.bundled else None) or tree.root
        lines.append(f"candidate tips below {v(start)}: {choices(tree.leaves(start), limit=40)}")
    try:
        model = source.model(base, tip, ignore_mimic)
    except ChainError as e:
        lines.append(f"chain: not determined ({v(str(e))})")
    else:
        lines.extend(_chain_lines(model))
    return "\n".join(lines) + "\n"
