"""``urdf2dh match TABLE SOURCE``: which table is this? What a datasheet's, a paper's or a
vendor's table says of a robot, against the robot's model (docs/commands/match.md).

:func:`match` tries every reading of TABLE that its own statements leave open (standard or
modified D-H; degrees or radians; metres, millimetres, centimetres or inches:
:mod:`.readings`), lays each onto SOURCE's chain (each joint's direction and zero offset, the
base and tool transforms: :mod:`.chainfit`), refines the continuous parts by least squares, and
judges what is left against what the table's written digits can say (each number moved by the
step of its last digit, the effects added). The :class:`Match` says in words what differs, and
holds TABLE corrected: SOURCE's exact table in TABLE's convention and layout (its frames the
nearest to TABLE's that are exactly SOURCE's), checked as every table is.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..checks import check_count, check_instance, check_optional_name, check_seed, check_source
from ..conventions.base import Guide
from ..conventions.table import Table
from ..errors import InputError, UsageError, choices, shown, visible
from ..geometry import frames
from ..io.readings import Reading, readings
from ..model.poe import PoeModel
from ..tolerances import DEFAULT, DIFF_PARALLEL_DEG, MATCH_ROUND_OFF, Tolerances
from . import chainfit
from .chainfit import Fit, Mismatch, Tolerance

__all__ = ["Disagreement", "JointMatch", "Match", "match"]

Mat = NDArray[np.float64]

CHECK_SAMPLES = 200  # configurations the residual and the precision bound are measured at
FIT_SAMPLES = 24  # configurations the refinement fits
FITS = 4  # of each reading's fits that agree link by link (symmetries), the best refined
NEAREST = 6  # candidates refined where nothing matches (the best match shown)
AS_NEAR = 2.0  # ... residuals this many times the least are as near: the fewest changes wins
_COLUMN = {"angle": "alpha", "distance": "a", "offset": "d", "turn": "theta"}


@dataclass(frozen=True, slots=True)
class JointMatch:
    """How the table's joint follows the source's: its row, direction and zero.

    The table's joint position is ``sign * q + offset`` (``q`` the source's, radians or the
    source's length unit); ``shown`` is the offset as the words say it (a multiple of 15
    degrees where it is one to the table's precision)."""

    name: str
    row: str
    kind: str
    sign: int
    offset: float
    shown: str


@dataclass(frozen=True, slots=True)
class Disagreement:
    """A cell of TABLE that no reading, direction, offset, base or tool makes agree: its row and
    column, the table's value and the source's in the same layout (radians or the source's
    length unit), and the joints it lies between."""

    row: str
    column: str
    joints: str
    table: float
    source: float


@dataclass(frozen=True)
class Match:
    """The result of :func:`match`.

    Attributes
    ----------
    table, source
        What was compared (TABLE as given; SOURCE's name and chain).
    matched
        Whether TABLE describes SOURCE's chain at the precision it is written in.
    reading
        How TABLE was read: ``lengths in mm; angles in degrees; modified D-H``.
    convention, length_unit, angle_units
        The same as values (``dh``/``mdh``; ``mm``; ``(theta's, alpha's)`` ``deg``/``rad``).
    joints
        Per joint, how the table's follows the source's.
    base
        ``(4, 4)`` the table's base frame in SOURCE's base link.
    tool
        ``(4, 4)`` SOURCE's tip in the table's last frame.
    residual, allowed
        ``(position, rotation)``: the largest difference of the forward kinematics after the
        match, at ``samples`` configurations, and what TABLE's written precision allows.
    size, length_unit_source
        SOURCE's size and length unit.
    differences
        What differs, in words, one item each.
    disagreements
        Where nothing makes them agree (empty for a match).
    corrected
        TABLE corrected: a checked table of SOURCE in TABLE's convention and layout (``None``
        where TABLE does not match).
    notes
        What else a person should know.
    fit, chain
        The match itself (directions, offsets, base and tool) and TABLE's chain as read, for
        :meth:`poses`.
    """

    table: str
    source: str
    matched: bool
    reading: str
    convention: str
    length_unit: str
    angle_units: tuple[str, str]
    joints: tuple[JointMatch, ...]
    base: Mat
    tool: Mat
    residual: tuple[float, float]
    allowed: tuple[float, float]
    samples: int
    size: float
    length_unit_source: str
    differences: tuple[str, ...]
    disagreements: tuple[Disagreement, ...] = ()
    corrected: Table | None = None
    notes: tuple[str, ...] = ()
    fit: Fit | None = field(default=None, repr=False, compare=False)
    chain: PoeModel | None = field(default=None, repr=False, compare=False)

    def poses(self, q: NDArray[np.float64], source: PoeModel) -> Mat:
        """TABLE's poses ``(N, 4, 4)`` at ``source``'s configurations ``q`` ``(N, dof)``, the
        match applied: ``base . T_table(sign * q + offset) . tool`` (to compare with
        ``source.fk_batch(q)``)."""
        if self.fit is None or self.chain is None:
            raise ValueError("Match.poses: no fit (the table has another number of joints)")
        return chainfit.poses(self.fit, self.chain, source, np.asarray(q, dtype=float))

    def text(self) -> str:
        """The report ``urdf2dh match`` prints."""
        unit = visible(self.length_unit_source)
        head = "matches" if self.matched else "no match"
        out = [f"match: {visible(self.table)} -> {visible(self.source)}: {head}"]
        if self.matched:
            out.append(f"  {self.reading}")
        else:
            out.append(f"  the best match: {self.reading}")
        out += [f"  {d}" for d in self.differences]
        pos, rot = self.residual
        apos, arot = self.allowed
        if math.isfinite(pos):
            out.append(
                f"  residual after the match: {pos:.3g} {unit}, {rot:.3g} rad at {self.samples} "
                f"configurations ({pos / self.size:.2g} x the robot's size); the table's written "
                f"precision allows {apos:.3g} {unit}, {arot:.3g} rad"
            )
        if self.disagreements:
            out.append("  they disagree at:")
            for d in self.disagreements:
                out.append(f"    {_disagreement(d, unit)}")
        out += [f"  note: {n}" for n in self.notes]
        return "\n".join(out) + "\n"

    def _repr_markdown_(self) -> str:
        """In a notebook: the report as a list."""
        from ..escape import markdown_text

        lines = self.text().splitlines()
        return "\n".join(["**" + markdown_text(lines[0]) + "**", ""] + [
            "- " + markdown_text(line.strip()) for line in lines[1:]]) + "\n"  # fmt: skip


def _disagreement(d: Disagreement, unit: str) -> str:
    if d.column in ("alpha", "theta"):
        values = f"{math.degrees(d.table):.6g} deg in the table, {math.degrees(d.source):.6g} deg"
    else:
        values = f"{d.table:.6g} {unit} in the table, {d.source:.6g} {unit}"
    return f"row {shown(d.row)} {d.column} ({d.joints}): {values} in the source"


def match(
    table: str | os.PathLike[str],
    source: str | os.PathLike[str],
    *,
    base: str | None = None,
    tip: str | None = None,
    convention: str | None = None,
    length_unit: str | None = None,
    angle_unit: str | None = None,
    tol: Tolerances = DEFAULT,
    samples: int = CHECK_SAMPLES,
    seed: int = 0,
    xacro: Any = None,
) -> Match:
    """Which table is ``table``, against the chain of ``source``?

    Parameters
    ----------
    table
        A hand-written table (a CSV or YAML file of rows with ``theta``, ``d``, ``a``,
        ``alpha``: :mod:`urdf2dh.io.handtable`), or any SOURCE file (a table file, a POE model
        file, ...) whose chain is compared as it is.
    source
        The robot (:func:`urdf2dh.load`'s SOURCE).
    base, tip
        The source's chain (its defaults otherwise).
    convention, length_unit, angle_unit
        What the table is known to be written in (``dh`` or ``mdh``; ``m``, ``mm``, ...;
        ``deg`` or ``rad``), where it does not say; ``None``: found.
    tol
        The tolerances of the corrected table's conversion and check.
    samples, seed
        The configurations the residual is measured at.
    xacro
        How a ``.xacro`` source is expanded (:class:`urdf2dh.XacroOptions`).

    Returns
    -------
    Match
        What differs, the residual, and TABLE corrected (where it matches).

    Raises
    ------
    Urdf2DhError
        A file that cannot be read (the message names it, and the row and column).
    UsageError
        An unknown ``convention``, ``length_unit`` or ``angle_unit``.
    """
    from ..io.handtable import read_hand_table
    from ..io.sources import open_source

    table = check_source(table, "match: table")
    source = check_source(source, "match: source")
    base = check_optional_name(base, "match: base")
    tip = check_optional_name(tip, "match: tip")
    check_instance(tol, Tolerances, "match: tol", "urdf2dh.Tolerances(...) or urdf2dh.DEFAULT")
    check_count(samples, "match: samples")
    check_seed(seed, "match: seed")
    _check_choice(convention, ("dh", "mdh"), "convention")
    _check_choice(angle_unit, ("deg", "rad"), "angle_unit")
    if length_unit is not None:
        from ..units import metres_per

        try:
            metres_per(length_unit)
        except InputError as e:
            raise UsageError(f"match: length_unit: {e}") from None
    model = open_source(source, tol, xacro=xacro).model(base, tip)
    path = _table_path(table)
    hand = None
    if path.suffix.lower() == ".csv" or _looks_hand_written(path):
        hand = read_hand_table(path, table if path.name in table else path.name)
    if hand is not None:
        kinds = tuple(j.kind for j in model.joints)
        options = readings(hand, kinds, model.length_unit, convention, length_unit, angle_unit)
        return _best(table, model, [(r, _reading_model(r, model)) for r in options], tol,
                     samples, seed)  # fmt: skip
    other = open_source(str(path), tol).model()
    if other.length_unit != model.length_unit:
        from ..units import factor

        other = other.scaled(factor(other.length_unit, model.length_unit), model.length_unit)
    return _best(table, model, [(None, other)], tol, samples, seed, _table_convention(path))


def _table_path(table: str) -> Path:
    """TABLE's file: the file named, else the file of the bundled table of that name."""
    from ..io.catalog import lookup, robot_path

    path = Path(table)
    bundled = None if path.exists() else lookup(table)
    return path if bundled is None else robot_path(bundled)


def _check_choice(value: str | None, valid: tuple[str, ...], name: str) -> None:
    if value is not None and value not in valid:
        raise UsageError(f"match: unknown {name} {shown(value)}; valid: {choices(valid)}")


def _looks_hand_written(path: Path) -> bool:
    """Whether a YAML or JSON file holds a hand-written table (not a table or POE file)."""
    from ..io.files import read_file
    from ..io.handtable import is_hand_table
    from ..io.mappings import read_mapping

    if path.suffix.lower() not in (".yaml", ".yml", ".json") or not path.is_file():
        return False
    return is_hand_table(read_mapping(path, str(path), read_file(path, str(path))))


def _table_convention(path: Path) -> str:
    """The convention of a table file (for the corrected table), else ``dh``."""
    from ..io.files import read_file
    from ..io.mappings import read_mapping

    try:
        tree = read_mapping(path, str(path), read_file(path, str(path)))
    except InputError:
        return "dh"
    conv = tree.get("convention") if isinstance(tree, dict) else None
    return conv if conv in ("dh", "mdh") else "dh"


def _reading_model(reading: Reading, source: PoeModel) -> PoeModel | None:
    """The reading's chain, its joints named as the source's (``None``: another joint count)."""
    if len(reading.joint_rows) != source.n:
        return None
    return reading.model(tuple(j.name for j in source.joints))


@dataclass(frozen=True, slots=True)
class _Candidate:
    reading: Reading | None
    model: PoeModel
    fit: Fit
    residual: tuple[float, float]
    allowed: tuple[float, float]

    @property
    def matched(self) -> bool:
        return self.residual[0] <= self.allowed[0] and self.residual[1] <= self.allowed[1]

    def rank(self, size: float) -> tuple[float, ...]:
        f = self.fit
        changes = (sum(s < 0 for s in f.signs) + sum(abs(o) > 1e-9 for o in f.offsets)
                   + _moves(f.base, size) + _moves(f.tool, size))  # fmt: skip
        badness = self.residual[0] / size + self.residual[1]
        stated = 0 if self.reading is None else -sum(self.reading.stated)
        return (0.0 if self.matched else 1.0, 0.0 if self.matched else f.cost, changes,
                stated, badness)  # fmt: skip


def _moves(t: Mat, size: float) -> int:
    turned = not np.allclose(t[:3, :3], np.eye(3), atol=1e-9)
    moved = not np.allclose(t[:3, 3], 0.0, atol=1e-9 * size)
    return int(turned) + int(moved)


def _tolerance(reading: Reading | None, size: float) -> Tolerance:
    """How far links may disagree and still be searched on: the table's steps, with room for
    how they add up along a link, and a floor of the source's round-off."""
    if reading is None:
        return Tolerance(1e3 * MATCH_ROUND_OFF, 1e3 * MATCH_ROUND_OFF * size)
    angle = float(reading.steps[:, [0, 3]].max(initial=0.0))
    length = float(reading.steps[:, [1, 2]].max(initial=0.0))
    return Tolerance(
        8.0 * angle + 1e3 * MATCH_ROUND_OFF,
        8.0 * length + 8.0 * angle * size + 1e3 * MATCH_ROUND_OFF * size,
    )


def _best(
    display: str,
    source: PoeModel,
    options: list[tuple[Reading | None, PoeModel | None]],
    tol: Tolerances,
    samples: int,
    seed: int,
    file_convention: str = "dh",
) -> Match:
    size = source.size()
    q_fit = source.sample(FIT_SAMPLES, (seed, 1))
    q_check = source.sample(samples, seed)
    target, fit_target = source.fk_batch(q_check), source.fk_batch(q_fit)
    candidates: list[_Candidate] = []
    counts = set()
    for reading, model in options:
        if model is None:
            assert reading is not None
            counts.add(len(reading.joint_rows))
            continue
        if model.n != source.n:
            counts.add(model.n)
            continue
        fits = chainfit.fit_lines(model, source, _tolerance(reading, size))
        if fits[0].cost == 0.0:  # the links agree: placed, the nearest few refined
            placed = [chainfit.place(model, source, fit, q_fit) for fit in fits]
            placed.sort(key=lambda f: _badness(f, model, source, q_fit, fit_target, size))
            fits = [chainfit.refine(model, source, fit, q_fit) for fit in placed[:FITS]]
        for fit in fits:
            candidates.append(_judged(reading, model, fit, source, q_check, target,
                                      fit.cost == 0.0))  # fmt: skip
    if not candidates:
        found = " or ".join(str(c) for c in sorted(counts))
        return _unmatched(display, source, samples, found)
    best = min(candidates, key=lambda c: c.rank(size))
    if not best.matched:
        best = _nearest(candidates, source, q_fit, q_check, target)
    best = _judged(best.reading, best.model, best.fit, source, q_check, target)
    if best.matched:
        best = _snapped(best, source, q_fit, q_check, target)
    return _result(display, source, best, tol, samples, file_convention)


def _nearest(
    candidates: list[_Candidate], source: PoeModel, q_fit: Mat, q_check: Mat, target: Mat
) -> _Candidate:
    """The best match where nothing matches: the :data:`NEAREST` candidates whose links
    disagree least placed and refined, then the one with the smallest residual, or, among
    those within :data:`AS_NEAR` times it, the one with the fewest changes."""
    size = source.size()
    fit_target = source.fk_batch(q_fit)
    leading = sorted(candidates, key=lambda c: c.rank(size))[:NEAREST]
    refined = []
    for c in leading:
        placed = chainfit.place(c.model, source, c.fit, q_fit)
        fit = chainfit.refine(c.model, source, placed, q_fit)
        if _badness(fit, c.model, source, q_fit, fit_target, size) > _badness(
            c.fit, c.model, source, q_fit, fit_target, size
        ):
            fit = c.fit  # the refinement went astray: the fit of the links' equations
        refined.append(_judged(c.reading, c.model, fit, source, q_check, target, False))
    least = min(c.rank(size)[-1] for c in refined)
    near = [c for c in refined if c.rank(size)[-1] <= AS_NEAR * least]
    return min(near, key=lambda c: c.rank(size)[2:])


def _badness(
    fit: Fit, model: PoeModel, source: PoeModel, q: Mat, target: Mat, size: float
) -> float:
    pos, rot = _pose_errors(chainfit.poses(fit, model, source, q), target)
    return pos / size + rot


def _judged(
    reading: Reading | None,
    model: PoeModel,
    fit: Fit,
    source: PoeModel,
    q: Mat,
    target: Mat,
    bound: bool = True,
) -> _Candidate:
    """A fit with its residual and what the table's precision allows (``bound``: worked out;
    else only the source's round-off, for a fit whose links disagree anyway)."""
    ours = chainfit.poses(fit, model, source, q)
    allowed = _allowed(reading if bound else None, fit, source, q, ours, source.size())
    return _Candidate(reading, model, fit, _pose_errors(ours, target), allowed)


def _snapped(
    candidate: _Candidate, source: PoeModel, q_fit: Mat, q_check: Mat, target: Mat
) -> _Candidate:
    """The candidate with each offset that can be a round value at the table's precision made
    one (a prismatic joint's 0, where a slide of the base or tool along its axis is the same;
    a revolute joint's multiple of 15 degrees), the base, tool and other offsets fitted again."""
    fit, held = candidate.fit, set[int]()
    for i, joint in enumerate(source.joints):
        if i in (0, source.n - 1):
            continue
        offset = fit.offsets[i]
        if joint.kind == "prismatic":
            target_value = 0.0
        else:
            target_value = math.pi / 12 * round(offset / (math.pi / 12))
        if abs(target_value - offset) <= 1e-15:
            continue
        offsets = list(fit.offsets)
        offsets[i] = target_value
        trial_fit = chainfit.refine(candidate.model, source, replace(fit, offsets=tuple(offsets)),
                                    q_fit, frozenset(held | {i}))  # fmt: skip
        trial = _judged(candidate.reading, candidate.model, trial_fit, source, q_check, target)
        if trial.matched:
            candidate, fit = trial, trial_fit
            held.add(i)
    size = source.size()
    clean = replace(fit, base=_rounded(fit.base, size), tool=_rounded(fit.tool, size))
    trial = _judged(candidate.reading, candidate.model, clean, source, q_check, target)
    return trial if trial.matched else candidate


def _rounded(t: Mat, size: float) -> Mat:
    """A base or tool transform with its fit's round-off taken off: a turn within
    :data:`~urdf2dh.tolerances.MATCH_ROUND_OFF` of a multiple of 15 degrees about an axis
    within it of a coordinate axis made that, a translation component within it x size of 0
    made 0."""
    from ..geometry.se3 import rot_axis

    out = t.copy()
    r = t[:3, :3]
    angle, axis = _turn(r)
    step = math.pi / 12
    if angle > 0.0:
        nearest = np.round(axis)
        if np.abs(axis - nearest).max() <= MATCH_ROUND_OFF and np.abs(nearest).sum() == 1.0:
            axis = nearest
        whole = step * round(angle / step)
        if abs(angle - whole) <= MATCH_ROUND_OFF:
            angle = whole
        out[:3, :3] = rot_axis(axis, angle)
    p = out[:3, 3]
    out[:3, 3] = np.where(np.abs(p) <= MATCH_ROUND_OFF * size, 0.0, p)
    return out


def _unmatched(display: str, source: PoeModel, samples: int, found: str) -> Match:
    """No match possible: the table has another number of joints."""
    name = f"{source.name or source.source} ({source.base_link} -> {source.tip_link})"
    why = (
        f"the table has {found} joints, the source's chain {source.n}: choose the chain with "
        "--base and --tip, or mark rows that are no joint as type fixed"
    )
    inf = (math.inf, math.inf)
    return Match(display, name, False, "no reading with as many joints", "", "", ("", ""),
                 (), np.eye(4), np.eye(4), inf, inf, samples, source.size(),
                 source.length_unit, (why,))  # fmt: skip


def _pose_errors(a: Mat, b: Mat) -> tuple[float, float]:
    from ..geometry.se3 import pose_errors

    return pose_errors(a, b)


def _allowed(
    reading: Reading | None, fit: Fit, source: PoeModel, q: Mat, ours: Mat, size: float
) -> tuple[float, float]:
    """What the table's written digits can change of its poses: each number moved by its step,
    the effects added, the worst configuration; plus the source's round-off."""
    position = np.zeros(len(q))
    rotation = np.zeros(len(q))
    if reading is not None:
        names = tuple(j.name for j in source.joints)
        for _, _, moved in reading.perturbed():
            renamed = PoeModel(
                tuple(replace(j, name=n) for j, n in zip(moved.joints, names, strict=True)),
                moved.home,
            )
            other = chainfit.poses(fit, renamed, source, q)
            position += np.linalg.norm(other[:, :3, 3] - ours[:, :3, 3], axis=1)
            rotation += _turns(ours, other)
    return (
        float(position.max()) + MATCH_ROUND_OFF * size,
        float(rotation.max()) + MATCH_ROUND_OFF,
    )


def _turns(a: Mat, b: Mat) -> Mat:
    """The angle of each rotation from ``a`` to ``b`` ``(N,)`` (atan2: exact near 0)."""
    m = np.einsum("nji,njk->nik", a[:, :3, :3], b[:, :3, :3])
    sin = 0.5 * np.linalg.norm(
        np.stack([m[:, 2, 1] - m[:, 1, 2], m[:, 0, 2] - m[:, 2, 0], m[:, 1, 0] - m[:, 0, 1]], 1),
        axis=1,
    )
    cos = 0.5 * (np.trace(m, axis1=1, axis2=2) - 1.0)
    out: Mat = np.arctan2(sin, cos)
    return out


def _result(
    display: str,
    source: PoeModel,
    best: _Candidate,
    tol: Tolerances,
    samples: int,
    file_convention: str,
) -> Match:
    fit, reading = best.fit, best.reading
    size, unit = source.size(), source.length_unit
    convention = reading.convention if reading is not None else file_convention
    rows = (
        [reading.names[i] for i in reading.joint_rows]
        if reading is not None
        else [j.name for j in best.model.joints]
    )
    angle_step = 0.0 if reading is None else float(reading.steps[:, [0, 3]].max(initial=0.0))
    length_step = max(
        0.0 if reading is None else float(reading.steps[:, [1, 2]].max(initial=0.0)),
        MATCH_ROUND_OFF * size,
    )
    joints = tuple(
        JointMatch(
            j.name, row, j.kind, s, o, _offset_words(o, j.kind, angle_step, length_step, unit)
        )
        for j, row, s, o in zip(source.joints, rows, fit.signs, fit.offsets, strict=True)
    )
    corrected, notes = _corrected(source, best, convention, tol, samples)
    differences = _differences(best, source, joints)
    disagreements: list[Disagreement] = []
    if not best.matched:
        disagreements = _cell_disagreements(best, corrected, source) or _disagreements(
            best, corrected, rows, source)  # fmt: skip
        notes += _near_parallel_note(best, source)
    source_name = f"{source.name or source.source} ({source.base_link} -> {source.tip_link})"
    description = reading.describe() if reading is not None else "the file's own chain"
    return Match(
        display,
        source_name,
        best.matched,
        description,
        convention,
        reading.length_unit if reading is not None else unit,
        reading.angle_units if reading is not None else ("rad", "rad"),
        joints,
        fit.base,
        fit.tool,
        best.residual,
        best.allowed,
        samples,
        size,
        unit,
        tuple(differences),
        tuple(disagreements),
        corrected if best.matched else None,
        tuple(notes),
        fit,
        best.model,
    )


def _offset_words(
    offset: float, kind: str, angle_step: float, length_step: float, unit: str
) -> str:
    if kind == "prismatic":
        return "0" if abs(offset) <= length_step else f"{offset:+.6g} {visible(unit)}"
    special = math.pi / 12 * round(offset / (math.pi / 12))
    if abs(offset - special) <= max(angle_step, 1e-9):
        return f"{math.degrees(special):+.0f} deg" if special else "0"
    return f"{math.degrees(offset):+.6g} deg"


def _differences(best: _Candidate, source: PoeModel, joints: tuple[JointMatch, ...]) -> list[str]:
    out = []
    for i, j in enumerate(joints, 1):
        label = f"joint {i} ({shown(j.name)}, row {shown(j.row)})"
        if j.sign < 0:
            out.append(f"{label} turns the other way" if j.kind != "prismatic"
                       else f"{label} slides the other way")  # fmt: skip
        if j.shown != "0":
            zero = "its zero is" if j.kind != "prismatic" else "its zero lies"
            out.append(f"{label}: {zero} {j.shown} from the source's")
    unit = visible(source.length_unit)
    base_link = shown(source.base_link) if source.base_link else "the source's base"
    tip_link = shown(source.tip_link) if source.tip_link else "the source's tip"
    fit, size = best.fit, source.size()
    base_words = _transform_words(fit.base, unit, size)
    tool_words = _transform_words(fit.tool, unit, size)
    first, last = source.joints[0], source.joints[-1]
    at_tip = source.home[:3, :3] @ fit.tool[:3, :3].T  # the table's last frame at home
    same_base = _turns_about(fit.base[:3, :3], first.axis) and first.kind == "revolute"
    same_tool = _turns_about(fit.tool[:3, :3], at_tip.T @ last.axis) and last.kind == "revolute"
    if not base_words:
        out.append(f"base: the table's frame 0 is {base_link}")
    else:
        out.append(f"base: the table's frame 0 is {base_words} from {base_link}" + (
            " (about joint 1's axis: equally, joint 1's zero)" if same_base else ""))  # fmt: skip
    if not tool_words:
        out.append(f"tool: {tip_link} is the table's last frame")
    else:
        out.append(f"tool: {tip_link} is {tool_words} from the table's last frame" + (
            " (about the last joint's axis: equally, its zero)" if same_tool else ""))  # fmt: skip
    return out


def _turns_about(r: Mat, axis: Mat) -> bool:
    """Whether the rotation ``r`` turns about ``axis`` (and turns at all)."""
    turn = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    if float(np.trace(r)) > 3.0 - 1e-12:
        return False
    if np.linalg.norm(turn) < 1e-9:  # a half turn: about an axis that r keeps
        return bool(np.allclose(r @ axis, axis, atol=1e-9))
    return bool(np.linalg.norm(np.cross(turn / np.linalg.norm(turn), axis)) < 1e-9)


def _transform_words(t: Mat, unit: str, size: float) -> str:
    """A transform in words: ``0.1 m along z, turned 180 deg about z`` ('' for the identity)."""
    parts = []
    p = t[:3, 3]
    if np.abs(p).max() > 1e-9 * size:
        axes = [k for k in range(3) if abs(p[k]) > 1e-9 * size]
        if len(axes) == 1:
            parts.append(f"{p[axes[0]]:.6g} {unit} along {'xyz'[axes[0]]}")
        else:
            parts.append("at (" + ", ".join(f"{v:.6g}" for v in p) + f") {unit}")
    r = t[:3, :3]
    angle, axis = _turn(r)
    if angle > 1e-9:
        named = [k for k in range(3) if abs(abs(axis[k]) - 1.0) < 1e-9]
        degrees = math.degrees(angle)
        shown_angle = f"{degrees:.0f}" if abs(degrees - round(degrees)) < 1e-7 else f"{degrees:.6g}"
        if named:
            k = named[0]
            sign = "" if axis[k] > 0 else "-"
            parts.append(f"turned {sign}{shown_angle} deg about {'xyz'[k]}")
        else:
            text = ", ".join(f"{v:.4g}" for v in axis)
            parts.append(f"turned {shown_angle} deg about ({text})")
    return ", ".join(parts)


def _turn(r: Mat) -> tuple[float, Mat]:
    """A rotation's angle in ``[0, pi]`` and its axis (:func:`~urdf2dh.geometry.lie.log_so3`:
    exact for tiny angles, where ``acos`` of the trace is not); a half turn's axis with its
    largest component positive."""
    from ..geometry.lie import log_so3

    w = log_so3(r)
    angle = float(np.linalg.norm(w))
    if angle == 0.0:
        return 0.0, np.array([0.0, 0.0, 1.0])
    axis: Mat = w / angle
    if angle > math.pi - 1e-6 and axis[np.argmax(np.abs(axis))] < 0:
        axis = -axis
    return angle, axis


def _corrected(
    source: PoeModel, best: _Candidate, convention: str, tol: Tolerances, samples: int
) -> tuple[Table | None, list[str]]:
    """SOURCE's exact table in the table's convention, its frames nearest the table's (as
    laid onto the source), its joints turning as the table's: TABLE corrected."""
    from ..conventions.convert import to_table
    from ..errors import Urdf2DhError

    fit = best.fit
    flipped = PoeModel(
        tuple(
            replace(j, axis=-j.axis, scale=-j.scale) if s < 0 else j
            for j, s in zip(source.joints, fit.signs, strict=True)
        ),
        source.home, source.name, source.source, source.base_link, source.tip_link,
        source.length_unit, source.warnings,
    )  # fmt: skip
    at_zero = np.array(fit.offsets)
    if best.reading is not None:
        table_frames = best.reading.frames(at_zero)
    else:
        table_frames = _model_frames(best.model, at_zero)
    guide = Guide(tuple(frames.frame_of(fit.base @ f) for f in table_frames))
    try:
        return to_table(flipped, convention, tol, style=guide), []
    except Urdf2DhError as e:
        return None, [f"TABLE corrected cannot be written: {e}"]


def _model_frames(model: PoeModel, q: Mat) -> list[Mat]:
    """A model's frame on each joint axis, then its tip, at joint positions ``q``."""
    links, motions = model.link_form()
    out, f = [], np.eye(4)
    for i in range(model.n):
        f = f @ links[i]
        out.append(f)
        rot, trans = motions[i]
        c, s = math.cos(rot * q[i]), math.sin(rot * q[i])
        f = f @ np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, trans * q[i]], [0, 0, 0, 1.0]])
    out.append(f @ links[-1])
    return out


def _near_parallel(best: _Candidate, source: PoeModel) -> list[tuple[int, float]]:
    """The links (0-based, with the source's angle between its axes) whose axes are within
    :data:`~urdf2dh.tolerances.DIFF_PARALLEL_DEG` of (anti-)parallel in the source or the table
    but not parallel in both: D-H's common normal runs off there (a calibrated robot's d of
    hundreds of metres), and with it d and a."""
    out = []
    for link in range(source.n - 1):
        angles = []
        for model in (source, best.model):
            u, v = model.joints[link].axis, model.joints[link + 1].axis
            angles.append(math.atan2(float(np.linalg.norm(np.cross(u, v))), abs(float(u @ v))))
        near = max(angles) <= math.radians(DIFF_PARALLEL_DEG)
        if near and max(angles) > MATCH_ROUND_OFF:
            out.append((link, angles[0]))
    return out


def _near_parallel_note(best: _Candidate, source: PoeModel) -> tuple[str, ...]:
    links = _near_parallel(best, source)
    if not links or best.reading is None:
        return ()
    pairs = ", ".join(f"{k + 1} and {k + 2} ({math.degrees(a):.3g} deg)" for k, a in links)
    return (
        f"joints {pairs} are nearly parallel in the source (or the table) but not parallel in "
        "both: D-H's common normal runs off there, and d and a with it (Wu 2019 sec. V-B); their "
        "distance is compared where the second axis crosses the plane normal to the first, d "
        "next to them not at all",
    )


def _cell_disagreements(
    best: _Candidate, corrected: Table | None, source: PoeModel
) -> list[Disagreement]:
    """TABLE's cells against TABLE corrected (SOURCE's exact table in TABLE's layout), where a
    cell's value is SOURCE's own geometry: the angle and distance between consecutive axes, and
    the distance along an axis between its neighbours' normals; theta is a joint's zero and the
    first and last rows' lengths the base's and tool's, so they are not compared. Cells that
    differ by more than twice their written step are disagreements. Next to nearly parallel
    axes (:func:`_near_parallel`) the distance is the link equations' (where the second axis
    crosses the plane normal to the first) and d is not compared."""
    reading = best.reading
    if reading is None or corrected is None:
        return []
    rows = reading.joint_rows
    if rows != list(range(rows[0], rows[0] + len(rows))):
        return []  # fixed rows between joints: no row-by-row layout
    n, size = source.n, source.size()
    sliding = [j.kind == "prismatic" for j in source.joints]
    near = {k for k, _ in _near_parallel(best, source)}
    equations = best.fit.equations
    out = []
    for k in range(n):
        link = k if reading.convention == "dh" else k - 1  # the link a row's alpha and a hold
        cells = []
        if 0 <= link < n - 1 and not (sliding[link] or sliding[link + 1]):
            cells += ["alpha", "a"]
        if 0 < k < n - 1 and not any(sliding[k - 1 : k + 2]) and not {k - 1, k} & near:
            cells.append("d")
        params = corrected.rows[k].params.values()
        for column in cells:
            j = ("theta", "d", "a", "alpha").index(column)
            table_value = float(reading.values[rows[k], j])
            value = params[column]
            assert isinstance(value, float)
            if column == "a" and link in near and link < len(equations):
                value = math.copysign(equations[link].a[1], table_value)
            floor = MATCH_ROUND_OFF * (1.0 if column == "alpha" else size)
            difference = table_value - value
            if column == "alpha":
                difference = math.remainder(difference, 2.0 * math.pi)
            if abs(difference) > 2.0 * float(reading.steps[rows[k], j]) + floor:
                joints = (
                    f"joints {link + 1} and {link + 2}: the "
                    + ("angle between their axes" if column == "alpha" else "axes' distance")
                    if column != "d"
                    else f"joint {k + 1}: where its neighbours' normals meet its axis"
                )
                out.append(Disagreement(reading.names[rows[k]], column, joints, table_value,
                                        value))  # fmt: skip
    return out


def _disagreements(
    best: _Candidate, corrected: Table | None, rows: list[str], source: PoeModel
) -> list[Disagreement]:
    """The cells where the chains disagree (the links' mismatches), with the source's value in
    the table's layout where the corrected table has it."""
    out = []
    names = [j.name for j in source.joints]
    seen: set[tuple[str, str]] = set()
    tol = _tolerance(best.reading, source.size())
    tolerance = {"alpha": tol.angle, "theta": tol.angle, "a": tol.length, "d": tol.length}
    for m in best.fit.mismatches:
        column = _COLUMN[m.what]
        if m.what in ("angle", "distance"):
            joints = f"joints {m.link + 1} and {m.link + 2}: " + (
                "the angle between their axes" if m.what == "angle" else "their axes' distance"
            )
            row_index = m.link if best.reading is None or best.reading.convention == "dh" else (
                m.link + 1)  # fmt: skip
        else:
            joints = f"joint {m.link + 1}: " + (
                "where its links meet its axis" if m.what == "offset" else "its axis' turn"
            )
            row_index = m.link
        row = rows[row_index] if row_index < len(rows) else names[min(row_index, len(names) - 1)]
        table_value, source_value = _cell_values(m, best, corrected, row_index, column)
        if (row, column) in seen or abs(table_value - source_value) <= tolerance[column]:
            continue  # the same cell twice, or a cell the source's layout gives as written
        seen.add((row, column))
        out.append(Disagreement(row, column, joints, table_value, source_value))
    return out


def _cell_values(
    m: Mismatch, best: _Candidate, corrected: Table | None, row: int, column: str
) -> tuple[float, float]:
    """The table's cell and the corrected table's (SOURCE's in the table's layout), where both
    exist; else the link's own figures."""
    reading = best.reading
    if reading is not None and corrected is not None and row < corrected.n:
        index = reading.joint_rows[row]
        table_value = float(reading.values[index, ("theta", "d", "a", "alpha").index(column)])
        params = corrected.rows[row].params.values()
        if column in params:
            value = params[column]
            assert isinstance(value, float)
            return table_value, value
    if m.what == "offset":
        return m.table, m.source
    return m.table, m.source
