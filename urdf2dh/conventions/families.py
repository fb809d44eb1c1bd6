"""The analytic inverse-kinematics families of a chain, and which export solves each.

Read off the chain's analytic form (:mod:`urdf2dh.conventions.analytic`: a standard D-H chain
whose relations are exact), where for consecutive axes ``i, i+1`` (row ``i``)

* the axes are parallel when ``alpha_i`` is 0 or pi;
* they meet when ``a_i = 0`` and they are not parallel;
* axes ``i, i+1, i+2`` meet in one point when both pairs meet and ``d_(i+1) = 0``.

=========================  =================================================================
family                     solved by
=========================  =================================================================
spherical wrist            axes 4, 5, 6 (or 1, 2, 3) meet in one point: ``eaik`` (EAIK's
                           subproblems), ``rtb`` (its closed form)
three parallel axes        axes 2-4 or 3-5 parallel, or 1-3 (4-6) with axes 5, 6 (1, 2)
                           meeting: ``eaik``; any three consecutive: ``rtb`` (closed form)
OPW                        ortho-parallel base and spherical wrist: ``opw``
                           (:mod:`urdf2dh.conventions.opw`)
general 6R                 six revolute joints: ``ikdh`` (Husty-Pfurner); ``rtb``
                           (Raghavan-Roth) where no structure above gives a closed form
7R with a locked joint     seven revolute joints, one of which held leaves a chain EAIK solves:
                           ``eaik`` (EAIK's ``fixed_axes``)
=========================  =================================================================

The rules are those of the solvers (EAIK 1.2's ``determine_Kinematic_Class``,
roboticstoolbox-python 1.5's ``classify`` and ``make_solver``, ikdh 1.2's robot file, which holds
revolute joints only); the tests hold each verdict to the real solver's.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, replace

from ..errors import ExportError
from ..model.poe import JointMotion, PoeModel
from ..tolerances import DEFAULT, Tolerances
from .analytic import AnalyticChain, analytic_form
from .dh import DhLink

__all__ = [
    "IK_TARGETS",
    "Families",
    "Family",
    "Relations",
    "eaik_family",
    "families",
    "held_family",
    "ikdh_method",
    "kinds_of",
    "lockable",
    "refusal",
    "rtb_method",
]

IK_TARGETS = ("eaik", "rtb", "ikdh", "opw")
LETTER = {"revolute": "R", "prismatic": "P", "helical": "H"}


@dataclass(frozen=True, slots=True)
class Relations:
    """Which consecutive axes of a chain are parallel or meet, and which three meet in a point
    (1-based joint numbers of the first axis of each pair or triple), and its joint kinds."""

    kinds: str
    parallel: tuple[int, ...]
    meeting: tuple[int, ...]
    concurrent: tuple[int, ...]

    @classmethod
    def of(cls, chain: AnalyticChain) -> Relations:
        links: tuple[DhLink, ...] = chain.links()
        kinds = kinds_of(chain.rows)
        par = [i + 1 for i, p in enumerate(links[:-1]) if p.alpha in (0.0, math.pi)]
        meet = [i + 1 for i, p in enumerate(links[:-1]) if p.a == 0.0 and i + 1 not in par]
        concurrent = [
            i for i in meet if i + 1 in meet and links[i].d == 0.0 and kinds[i - 1 : i + 2] == "RRR"
        ]
        return cls(kinds, tuple(par), tuple(meet), tuple(concurrent))

    def parallel_three(self, first: int) -> bool:
        """Axes ``first``, ``first + 1``, ``first + 2`` parallel (and revolute)."""
        return (
            first in self.parallel
            and first + 1 in self.parallel
            and self.kinds[first - 1 : first + 2] == "RRR"
        )

    def structure(self) -> str:
        """``axes 2, 3, 4 parallel; axes 5, 6 meet`` (or ``no consecutive axes parallel or
        meeting``)."""
        parts = [f"axes {i}, {i + 1}, {i + 2} meet in one point" for i in self.concurrent]
        parts += [f"axes {i}, {i + 1}, {i + 2} parallel" for i in range(1, len(self.kinds) - 1)
                  if self.parallel_three(i)]  # fmt: skip
        inside = {j for i in self.concurrent for j in (i, i + 1)}
        parts += [f"axes {i}, {i + 1} meet" for i in self.meeting if i not in inside]
        inside = {j for i in range(1, len(self.kinds) - 1) if self.parallel_three(i)
                  for j in (i, i + 1)}  # fmt: skip
        parts += [f"axes {i}, {i + 1} parallel" for i in self.parallel if i not in inside]
        return "; ".join(parts) or "no consecutive axes parallel or meeting"


@dataclass(frozen=True, slots=True)
class Family:
    """An analytic family the chain belongs to: its ``name`` (``spherical wrist``, ...), the
    axes concerned (1-based) and the exports that solve it, each with how (``(target,
    how)``)."""

    name: str
    axes: tuple[int, ...]
    exports: tuple[tuple[str, str], ...]

    def text(self) -> str:
        axes = f" (axes {', '.join(map(str, self.axes))})" if self.axes else ""
        how = ", ".join(f"--to {t}" + (f" ({h})" if h else "") for t, h in self.exports)
        return f"{self.name}{axes}: {how}"


@dataclass(frozen=True, slots=True)
class Families:
    """The analytic inverse-kinematics families of a chain (:func:`families`).

    Attributes
    ----------
    relations
        Its axes' relations in the analytic form (``None`` without one: no joints).
    families
        Each family that applies, with the exports that solve it.
    refused
        ``(target, reason)`` for each of :data:`IK_TARGETS` that cannot take the chain.
    """

    relations: Relations | None
    families: tuple[Family, ...]
    refused: tuple[tuple[str, str], ...]

    def reason(self, target: str) -> str | None:
        """Why ``target`` cannot take the chain, or ``None`` when it can."""
        return dict(self.refused).get(target)

    def lines(self) -> list[str]:
        """What ``urdf2dh info`` prints of them."""
        out = []
        if self.relations is not None:
            out.append(f"analytic IK: {self.relations.structure()}")
        out += [f"  {f.text()}" for f in self.families]
        out += [f"  not {t}: {why}" for t, why in self.refused]
        return out


def eaik_family(r: Relations) -> tuple[str, tuple[int, ...], str] | str:
    """EAIK's family of a chain, ``(name, axes, EAIK's class)`` (``6R-SPHERICAL_*``: one of
    EAIK's spherical classes, by how axes 1-3 lie), or why it has none."""
    if len(r.kinds) != 6 or r.kinds != "RRRRRR":
        return _not_6r(r.kinds, "EAIK")
    if 4 in r.concurrent or 1 in r.concurrent:
        first = 4 if 4 in r.concurrent else 1
        name = "spherical wrist" if first == 4 else "spherical wrist at the base"
        return name, (first, first + 1, first + 2), "6R-SPHERICAL_*"
    for first in (2, 3):
        if r.parallel_three(first):
            return "three parallel axes", (first, first + 1, first + 2), "6R-THREE_INNER_PARALLEL"
    for first, meet in ((1, 5), (4, 1)):
        if r.parallel_three(first) and meet in r.meeting:
            return (
                f"three parallel axes, axes {meet}, {meet + 1} meeting",
                (first, first + 1, first + 2),
                "6R-THREE_PARALLEL_TWO_INTERSECTING",
            )
    return (
        "no decomposition EAIK knows for this geometry: neither axes 4, 5, 6 (the wrist) nor "
        "1, 2, 3 meet in one point, and no three parallel axes are 2-4, 3-5, or 1-3 (4-6) with "
        f"axes 5, 6 (1, 2) meeting ({r.structure()})"
    )


def _not_6r(kinds: str, solver: str) -> str:
    if len(kinds) != 6:
        return f"not 6R: {solver} takes six revolute joints, the chain has {len(kinds)} joints"
    kind = {v: k for k, v in LETTER.items()}
    other = [f"{i + 1} ({kind[k]})" for i, k in enumerate(kinds) if k != "R"]
    return f"not 6R: {solver} takes revolute joints only, not joints {', '.join(other)}"


def rtb_method(r: Relations) -> tuple[str, tuple[int, ...]] | str:
    """roboticstoolbox-python's analytic method for the chain (``closed form`` with the axes
    of its first structure, or ``general 6R``), or why it has none."""
    if len(r.kinds) != 6:
        return (
            f"not 6 joints: roboticstoolbox's analytic IK takes six, the chain has {len(r.kinds)}"
        )
    if r.concurrent:
        return "closed form", tuple(range(r.concurrent[0], r.concurrent[0] + 3))
    firsts = [i for i in range(1, 5) if r.parallel_three(i)]
    if firsts:
        return "closed form", (firsts[0], firsts[0] + 1, firsts[0] + 2)
    if r.kinds != "RRRRRR":
        return (
            "no closed form (no three axes meet in one point or are parallel), and "
            "roboticstoolbox's general 6R method takes revolute joints only"
        )
    return "general 6R", ()


def ikdh_method(kinds: str) -> str | None:
    """Why ikdh cannot take a chain of joints ``kinds`` (``RRRRRR``, :func:`kinds_of`), or
    ``None``."""
    if kinds == "RRRRRR":
        return None
    return _not_6r(kinds, "ikdh")


def kinds_of(rows: Iterable[JointMotion]) -> str:
    """The joints' kinds as letters: ``R`` revolute, ``P`` prismatic, ``H`` helical."""
    return "".join(LETTER[r.kind] for r in rows)


def refusal(target: str, chain: AnalyticChain) -> str | None:
    """Why ``target`` (``eaik``, ``rtb``, ``ikdh``) cannot solve the chain analytically, or
    ``None``."""
    r = Relations.of(chain)
    if target == "ikdh":
        return ikdh_method(r.kinds)
    verdict = eaik_family(r) if target == "eaik" else rtb_method(r)
    return verdict if isinstance(verdict, str) else None


def families(model: PoeModel, tol: Tolerances = DEFAULT) -> Families:
    """The analytic families of ``model``'s chain and the exports that solve each (module doc).

    Raises
    ------
    ConversionError
        The chain's table fails its self-check (as :func:`urdf2dh.to_table`).
    """
    from .convert import to_table
    from .opw import opw_from_poe

    if model.n == 0:
        return Families(None, (), tuple((t, "no joints") for t in IK_TARGETS))
    chain = analytic_form(to_table(model, "dh", tol), tol)
    r = Relations.of(chain)
    found: list[Family] = []
    refused: list[tuple[str, str]] = []
    eaik, rtb = eaik_family(r), rtb_method(r)
    if isinstance(eaik, tuple):
        rtb_how = ("rtb", "closed form") if isinstance(rtb, tuple) else None
        found.append(Family(eaik[0], eaik[1], (("eaik", f"EAIK {eaik[2]}"),)
                            + ((rtb_how,) if rtb_how else ())))  # fmt: skip
    else:
        refused.append(("eaik", eaik))
        if isinstance(rtb, tuple) and rtb[0] == "closed form":
            name = "spherical wrist" if rtb[1][0] in r.concurrent else "three parallel axes"
            found.append(Family(name, rtb[1], (("rtb", "closed form"),)))
    try:
        opw_from_poe(model, tol)
        found.append(Family("OPW", (), (("opw", "ortho-parallel base, spherical wrist"),)))
    except ExportError as e:
        refused.append(("opw", str(e).removeprefix("opw: ")))
    ikdh = ikdh_method(r.kinds)
    if ikdh is None:
        general = [("ikdh", "Husty-Pfurner")]
        if isinstance(rtb, tuple) and rtb[0] == "general 6R":
            general.append(("rtb", "Raghavan-Roth"))
        found.append(Family("general 6R", (), tuple(general)))
    else:
        refused.append(("ikdh", ikdh))
    if isinstance(rtb, str):
        refused.append(("rtb", rtb))
    locks = lockable(model, tol)
    if locks:
        held = ", ".join(map(str, locks[:-1])) + (" or " if len(locks) > 1 else "")
        name = f"7R with a locked joint (joint {held}{locks[-1]} held at 0)"
        found.append(Family(name, (), (("eaik", f"joint {locks[-1]} held: EAIK's fixed_axes"),)))
        refused = [x for x in refused if x[0] != "eaik"]
    return Families(r, tuple(found), tuple(sorted(refused, key=lambda x: IK_TARGETS.index(x[0]))))


def held_family(
    model: PoeModel, k: int, tol: Tolerances = DEFAULT
) -> tuple[str, tuple[int, ...], str] | str:
    """EAIK's family (:func:`eaik_family`) of ``model``'s chain with joint ``k`` (1-based) held
    at 0, its axes numbered in the shorter chain, or why it has none."""
    from .convert import to_table

    held = replace(model, joints=model.joints[: k - 1] + model.joints[k:])
    return eaik_family(Relations.of(analytic_form(to_table(held, "dh", tol), tol)))


def lockable(model: PoeModel, tol: Tolerances = DEFAULT) -> tuple[int, ...]:
    """The joints (1-based) of a chain of seven revolute joints that, held at 0 (within their
    limits), leave a chain EAIK solves (EAIK's ``fixed_axes``); none for any other chain."""
    if kinds_of(model.joints) != "R" * 7:
        return ()
    return tuple(
        k
        for k, joint in enumerate(model.joints, 1)
        if (joint.lower is None or joint.upper is None or joint.lower <= 0.0 <= joint.upper)
        and isinstance(held_family(model, k, tol), tuple)
    )
