"""EAIK (``eaik`` on PyPI): a Python script that builds the chain as EAIK's ``HomogeneousRobot``.

EAIK 1.2 (Ostermeier, Kulz & Althoff, RA-L 2025: IK by subproblem decomposition, every branch)
takes a robot three ways. ``DhRobot(alpha, a, d)`` has no theta offsets, base or tool, so its
joint zeros and end frame are not the source's; ``HPRobot(H, P)`` has no end rotation;
``HomogeneousRobot(frames)`` reads the frame of each joint at the zero configuration (its z axis
the joint's axis) and the end effector's frame, all in the base frame, and keeps everything: its
axes ``H``, the points ``P`` between them and the end rotation. The script builds that one from
the joint frames of the analytic form (:mod:`urdf2dh.conventions.analytic`), so that

* ``robot.fwdKin(q)`` is the pose of the tip link in the base link, ``q`` the source's joint
  positions (radians; each frame's z points the way its joint turns, its zero is the source's);
* ``robot.IK(T)`` takes that pose and returns every branch as rows of ``Q``, with ``is_LS``
  marking the least-squares ones (no exact solution on that branch); the exact ones reproduce
  ``T``. There is no base or tool to apply.

EAIK decides its decomposition from exact relations of the axes (parallel within 1e-13, meeting
within 1e-9 of a length unit); the analytic form makes the relations the chain has within
``Tolerances.solver_snap`` exact, and a chain EAIK has no decomposition for is refused with
what is missing (:func:`urdf2dh.conventions.families.eaik_family`).
"""

from __future__ import annotations

import math

import numpy as np

from ...conventions.analytic import AnalyticChain
from ...conventions.families import Relations, eaik_family, held_family, lockable
from ...conventions.table import Table
from ...escape import python_docstring
from .common import ExportOptions, Numbers
from .solvers import chain_header, solver_chain

__all__ = ["render"]

FORMULA = (
    "T(q) = prod_i exp(q_i [H_i]) . M: EAIK's HomogeneousRobot from the joint frames at q = 0 "
    "and the tip's frame M, in the base link"
)


def _array(m: np.ndarray, numbers: Numbers, indent: str) -> str:
    rows = ", ".join("[" + ", ".join(repr(v) for v in row) + "]" for row in numbers.matrix(m))
    return f"{indent}[{rows}],"


def _family(table: Table, opts: ExportOptions) -> tuple[AnalyticChain, str, int | None]:
    """The chain, the docstring's family line, and the joint held (1-based; ``None`` for a
    6R chain). A 7R chain has the last joint held whose holding at 0 leaves a chain EAIK
    solves (:func:`~urdf2dh.conventions.families.lockable`); others are refused."""
    locks = lockable(table.to_poe(), opts.tol) if table.n == 7 else ()
    unless = None if locks else ""
    if table.n == 7 and not locks:
        unless = "; and holding none of its joints at 0 leaves a chain EAIK solves"
    chain = solver_chain(table, "eaik", opts, unless)
    if not locks:
        family = eaik_family(Relations.of(chain))
        assert isinstance(family, tuple)  # solver_chain refused the chains without one
        axes = ", ".join(map(str, family[1]))
        return chain, f"family: {family[0]} (axes {axes}): EAIK's class {family[2]}", None
    k = locks[-1]
    held = held_family(table.to_poe(), k, opts.tol)
    assert isinstance(held, tuple)  # lockable holds only such joints
    others = (
        f" (joint {', '.join(map(str, locks[:-1]))} could be held instead)" if locks[:-1] else ""
    )
    return (
        chain,
        (
            f"family: 7R with joint {k} '{table.rows[k - 1].name}' held at 0 (EAIK's fixed_axes; "
            f"another value may change the family){others}: the other six are a {held[0]} (their "
            f"axes {', '.join(map(str, held[1]))}), EAIK's class {held[2]}"
        ),
        k,
    )


def _demo(table: Table, held: int | None) -> list[float]:
    """A configuration within the limits for the script's example (off the middle of each
    range, where arms are often singular; the held joint at 0)."""
    out = []
    for i, row in enumerate(table.rows, 1):
        lo, hi = (-math.pi, math.pi) if row.lower is None or row.upper is None else (
            row.lower, row.upper)  # fmt: skip
        out.append(0.0 if i == held else round(lo + (0.3 + 0.05 * i) * (hi - lo), 3))
    return out


def render(table: Table, opts: ExportOptions) -> str:
    """A Python script defining ``robot``, EAIK's ``HomogeneousRobot`` of the chain."""
    chain, family, held = _family(table, opts)
    numbers = Numbers.of(table, opts.tol)
    lines = chain_header(chain, "EAIK HomogeneousRobot", FORMULA)
    lines.append(family)
    names = [f"{i} '{r.name}'" for i, r in enumerate(chain.rows, 1)]
    lines.append("joints (radians, zeros and directions as the source's): " + ", ".join(names))
    out = [python_docstring(lines, block=True), ""]
    out += ["import numpy as np", "from eaik.IK_Homogeneous import HomogeneousRobot", ""]
    out.append("# each joint's frame at q = 0 (its z axis the joint's axis), then the tip's")
    out.append("frames = np.array([")
    frames = chain.joint_frames()
    for i, f in enumerate(frames):
        what = f"joint {i + 1}" if i < chain.n else "tip"
        out.append(f"    # {what}")
        out.append(_array(f, numbers, "    "))
    out.append("])")
    if held is None:
        out.append("robot = HomogeneousRobot(frames)")
    else:
        out.append(f"# joint {held} held at 0.0 rad: (its index, its value)")
        out.append(f"robot = HomogeneousRobot(frames, fixed_axes=[({held - 1}, 0.0)])")
    out += [
        "",
        'if __name__ == "__main__":',
        f"    pose = robot.fwdKin(np.array({_demo(table, held)!r}))",
        "    solutions = robot.IK(pose)  # every branch; is_LS marks the inexact ones",
        "    print(robot.getKinematicFamily(), solutions.num_solutions(), 'branches')",
        "    print(solutions.Q[~solutions.is_LS])",
    ]
    return "\n".join(out) + "\n"
