"""The likely cause of a calibration the measurements contradict (:mod:`.plausible`): the reading
of the file, or the joints' kind, that explains the measurements.

**Another reading of the file.** Lengths in another unit, joint angles in degrees read as radians
(or the reverse; all of them, or one joint's column among the others), a quaternion's components in
another order or inverted, angles of another rotation sequence or unit, two joint or two position
columns swapped, a joint or a position axis counted the other way round: each leaves residuals at
the base-tool level (the nominal joints with base and tool fitted) that no measuring device leaves,
where the file read the right way fits that level to about the nominal's accuracy. So the other
readings of each aspect of the measurements (:func:`rereadings`) are tried on at most
:data:`SAMPLE` of their configurations. They are ranked by the rigid fit of the nominal's tool
points (:func:`.rigid.misfit`), the points alone and, for poses, with the tips of the tool's axes
at the robot's size (so that orientations count); the best :data:`CONFIRMED` by each are fitted at
the base-tool level and scored by their RMS position residual over the robot's size and, for poses,
their RMS rotation residual (rad) (:func:`score`). A reading is named when the product of the
factors by which the two fall reaches :data:`GAIN`, neither rising twofold (:func:`gain`), and,
where it changes the length unit, when the measured points then spread as the nominal's tool points
do. More are looked for from there, one per aspect of the file (a file with several mistakes), a
reading chosen before being dropped again where that fits better. Two aspects are looked for first
by what shows them apart from the others: the length unit by the spread of the measured points
against the nominal's tool points (joint values misread still spread the tool over the workspace),
and the orientations' reading, where a model was identified from the positions, by how well that
model's rotations explain them (a base and a tool rotation fitted: :func:`rotation_misfit`; it
shows where the nominal is too far from the robot for the base-tool level to). Each reading names
the option that reads the file so (a :class:`~urdf2dh.errors.Remedy`), or says what to change in
the file where no option does.

**Helical joints.** Revolute joints that advance along their axes as they turn (the PUMA of
Wu 2019) leave position residuals that rotations do not share; :func:`helical` identifies the
level again with every joint's pitch free and names the joints whose pitch moves the tool by
more than the residuals left, when that fits the positions :data:`HELICAL_GAIN` times better.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from .. import units
from ..errors import Remedy, visible
from ..model.poe import PoeModel
from ..tolerances import SPREAD
from .chart import absorbed
from .fit import fit_before
from .identify import identify
from .levels import BASE_TOOL
from .measurements import (
    POINT,
    QUATERNION,
    AsRead,
    Measurements,
    Reading,
    euler_quaternions,
)
from .residuals import errors, rms
from .rigid import misfit, pose_points, spread
from .start import FitOptions, nominal_points, to_data

__all__ = [
    "CONFIRMED",
    "GAIN",
    "HELICAL_GAIN",
    "SAMPLE",
    "Reread",
    "explained",
    "helical",
    "misread",
    "read_so",
    "rereadings",
    "spread_ratio",
]

Mat = NDArray[np.float64]

SAMPLE = 60  # configurations a reading is tried on, at most (seeded choice)
CONFIRMED = 3  # readings fitted at the base-tool level per round, the best by each rigid fit
GAIN = 5.0  # a reading is named when it scores this many times better than the one given
ROUNDS = 3  # readings composed at most (mistakes in one file)
HELICAL_GAIN = 3.0  # helical joints are named when they fit the positions this much better
_PROCRUSTES = 20  # alternating fits of base and tool rotations
_ITERATIONS = 50  # Levenberg-Marquardt iterations of a trial fit at most

_LETTERS = "xyzw"
_SEQUENCES = tuple(
    "".join(s)
    for case in ("xyz", "XYZ")
    for s in itertools.product(case, repeat=3)
    if s[0] != s[1] and s[1] != s[2]
)


@dataclass(frozen=True)
class Reread:
    """One other reading of one aspect of the measurements.

    Attributes
    ----------
    kind
        What it changes (:data:`.plausible.KINDS`).
    cause
        The cause it stands for, in words (``the file's lengths are in mm, not m``).
    remedy
        The option that reads the file so, or ``None`` (the file must change: ``cause`` says
        how).
    apply
        The measurements read so, from the measurements as given (the aspects other readings
        change left as they come).
    layout
        How a marker layout's lengths change with it (a layout is read in the file's unit).
    """

    kind: str
    cause: str
    remedy: Remedy | None
    apply: Callable[[Measurements], Measurements]
    layout: float = 1.0

    @property
    def aspect(self) -> str:
        """The aspect of the file it reads otherwise (one reading of each is composed)."""
        return _ASPECTS[self.kind]


_ASPECTS = {
    "length-unit": "lengths",
    "joint-degrees": "joint unit",
    "joint-column-degrees": "joint unit",
    "quaternion-order": "orientations",
    "orientation-inverted": "orientations",
    "euler-sequence": "orientations",
    "angle-degrees": "orientations",
    "joint-columns": "joint columns",
    "joint-sign": "joint columns",
    "position-columns": "position columns",
    "position-sign": "position columns",
}
_ORDER = ("lengths", "joint unit", "orientations", "joint columns", "position columns")


def _as_read(m: Measurements) -> AsRead:
    """How ``m`` was read (for measurements made in Python: as a file of its own names)."""
    if m.read_as is not None:
        return m.read_as
    orientation = QUATERNION if m.quaternions is not None else ()
    return AsRead(Reading(), None, m.joints, POINT, orientation)


def _renamed(pairs: list[tuple[str, str]]) -> Remedy:
    value = ",".join(f"{old}={new}" for old, new in pairs if old != new)
    return Remedy("reading.rename", "; read them with {}", value)


def _scaled(factor: float, sliding: list[int]) -> Callable[[Measurements], Measurements]:
    def apply(m: Measurements) -> Measurements:
        q = m.q.copy()
        q[:, sliding] *= factor
        return replace(m, q=q, points=m.points * factor)

    return apply


def _lengths(nominal: PoeModel, read: AsRead) -> Iterator[Reread]:
    current = read.length_unit or nominal.length_unit
    sliding = [k for k, j in enumerate(nominal.joints) if j.kind == "prismatic"]
    for unit in units.METRES_PER_UNIT:
        factor = units.factor(unit, current)
        if factor != 1.0:
            yield Reread(
                "length-unit",
                f"the file's lengths are in {unit}, not {current}",
                Remedy("reading.length_unit", "; read them with {}", unit),
                _scaled(factor, sliding),
                factor,
            )


def _joints_times(factor: float, columns: list[int]) -> Callable[[Measurements], Measurements]:
    def apply(m: Measurements) -> Measurements:
        q = m.q.copy()
        q[:, columns] *= factor
        return replace(m, q=q)

    return apply


def _degrees(nominal: PoeModel, read: AsRead) -> Iterator[Reread]:
    """The joint values in the other angle unit: all of them (an option reads them so), or one
    joint's column among the others read right (the file must change)."""
    turning = [k for k, j in enumerate(nominal.joints) if j.kind != "prismatic"]
    if not turning:
        return
    degrees = read.reading.degrees
    said = ("degrees", "radians") if not degrees else ("radians", "degrees")
    factor = math.pi / 180.0 if not degrees else 180.0 / math.pi
    yield Reread(
        "joint-degrees",
        f"the joint values are in {said[0]}, not {said[1]}",
        Remedy("reading.degrees", "; read them with {}" if not degrees else
               "; read them without {}"),
        _joints_times(factor, turning),
    )  # fmt: skip
    if len(turning) < 2:
        return
    names, columns = [j.name for j in nominal.joints], read.joint_columns
    for i in turning:
        yield Reread(
            "joint-column-degrees",
            f"joint {visible(names[i])} is in {said[0]} in the file while the other joints are "
            f"in {said[1]} (convert its column, {visible(columns[i])}, to {said[1]})",
            None,
            _joints_times(factor, [i]),
        )


def _quaternions(value: Mat) -> Callable[[Measurements], Measurements]:
    return lambda m: replace(m, quaternions=value)


def _orientations(m: Measurements, read: AsRead) -> Iterator[Reread]:
    if m.quaternions is None:
        return
    columns = read.orientation_columns
    if read.angles is not None:
        degrees = read.reading.degrees
        for sequence in _SEQUENCES:
            for deg in (degrees, not degrees):
                if sequence == read.reading.euler and deg == degrees:
                    continue
                parts = []
                if sequence != read.reading.euler:
                    parts.append(f"the angles follow the sequence {sequence}")
                if deg != degrees:
                    parts.append(f"the angles are in {'degrees' if deg else 'radians'}")
                yield Reread(
                    "euler-sequence" if deg == degrees else "angle-degrees",
                    " and ".join(parts),
                    Remedy("reading.euler", "; read them with {}", sequence)
                    if sequence != read.reading.euler
                    else None,
                    _quaternions(euler_quaternions(read.angles, sequence, deg)),
                )
        return
    for order in itertools.permutations(range(4)):
        if order == (0, 1, 2, 3):
            continue
        pairs = [(columns[order[r]], QUATERNION[r]) for r in range(4)] if columns else []
        held = ", ".join(_LETTERS[order.index(r)] for r in range(4))
        yield Reread(
            "quaternion-order",
            f"the columns read as qx, qy, qz, qw hold {held}",
            _renamed(pairs) if pairs else None,
            _quaternions(m.quaternions[:, list(order)]),
        )
    yield Reread(
        "orientation-inverted",
        "the orientations are inverted (the device's frame in the tool's): invert them in the file",
        None,
        _quaternions(m.quaternions * np.array([-1.0, -1.0, -1.0, 1.0])),
    )


def _swapped(i: int, k: int, joints: bool) -> Callable[[Measurements], Measurements]:
    def apply(m: Measurements) -> Measurements:
        a = (m.q if joints else m.points).copy()
        a[:, [i, k]] = a[:, [k, i]]
        return replace(m, q=a) if joints else replace(m, points=a)

    return apply


def _negated(i: int, joints: bool) -> Callable[[Measurements], Measurements]:
    def apply(m: Measurements) -> Measurements:
        a = (m.q if joints else m.points).copy()
        a[:, i] = -a[:, i]
        return replace(m, q=a) if joints else replace(m, points=a)

    return apply


def _columns(nominal: PoeModel, read: AsRead) -> Iterator[Reread]:
    kinds = [j.kind == "prismatic" for j in nominal.joints]
    names = [j.name for j in nominal.joints]
    columns = read.joint_columns
    for i, k in itertools.combinations(range(nominal.n), 2):
        if kinds[i] == kinds[k]:
            yield Reread(
                "joint-columns",
                f"the columns read as joints {visible(names[i])} and {visible(names[k])} are "
                "each other's",
                _renamed([(columns[i], names[k]), (columns[k], names[i])]),
                _swapped(i, k, joints=True),
            )
    for i in range(nominal.n):
        yield Reread(
            "joint-sign",
            f"joint {visible(names[i])} is counted the other way round in the file (negate "
            f"its column, {visible(columns[i])})",
            None,
            _negated(i, joints=True),
        )
    point = read.point_columns
    for i, k in itertools.combinations(range(3), 2):
        yield Reread(
            "position-columns",
            f"the columns read as {POINT[i]} and {POINT[k]} are each other's",
            _renamed([(point[i], POINT[k]), (point[k], POINT[i])]) if point else None,
            _swapped(i, k, joints=False),
        )
    for i in range(3):
        column = f", {visible(point[i])}" if point else ""
        yield Reread(
            "position-sign",
            f"the device's {POINT[i]} axis is counted the other way round (a left-handed frame:"
            f" negate the column{column})",
            None,
            _negated(i, joints=False),
        )


def rereadings(m: Measurements, nominal: PoeModel) -> Iterator[Reread]:
    """Every other reading of one aspect of ``m`` (module docstring)."""
    read = _as_read(m)
    yield from _lengths(nominal, read)
    yield from _degrees(nominal, read)
    yield from _orientations(m, read)
    yield from _columns(nominal, read)


def _with_layout(opts: FitOptions, trial: dict[str, Reread]) -> FitOptions:
    """``opts`` with its marker layout read as ``trial`` reads the file."""
    factor = math.prod(r.layout for r in trial.values())
    if opts.layout is None or factor == 1.0:
        return opts
    return replace(opts, layout={k: v * factor for k, v in opts.layout.items()})


def read_so(m: Measurements, readings: dict[str, Reread]) -> Measurements:
    """``m`` read as ``readings`` (one per aspect) say."""
    for aspect in _ORDER:
        if aspect in readings:
            m = readings[aspect].apply(m)
    return m


def spread_ratio(nominal: PoeModel, fit: Measurements, opts: FitOptions, ids: list[int]) -> float:
    """How many times farther the measured points spread about their centroid (RMS) than the
    nominal's tool points (the markers', placed by the layout) at the same configurations."""
    ours = (
        nominal.fk_batch(fit.q)[:, :3, 3] if opts.pose else nominal_points(nominal, fit, opts, ids)
    )
    nominal_spread = spread(ours)
    measured = spread(fit.points)
    return measured / nominal_spread if nominal_spread > 0.0 else math.nan


def _sample(m: Measurements) -> Measurements:
    _, count = m.configurations()
    if count <= SAMPLE:
        return m
    chosen = np.sort(np.random.default_rng((0, 9)).choice(count, SAMPLE, replace=False))
    return m.of_configurations(chosen)


def _rigid_scores(
    nominal: PoeModel, m: Measurements, opts: FitOptions, ids: list[int]
) -> tuple[float, float]:
    """The rigid fit's RMS residual of the nominal's tool points over the robot's size: of the
    points alone, and (poses) of the points with the tips of the tool's axes at the robot's
    size (the orientations too)."""
    size = nominal.size()
    out = []
    with np.errstate(all="ignore"):
        ours = nominal_points(nominal, m, opts, ids)
        theirs = pose_points(_poses(m), size) if opts.pose else m.points
        every = slice(None)
        for rows in (slice(0, None, 4), every) if opts.pose else (every, every):
            a, b = ours[rows], theirs[rows]
            if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
                out.append(math.inf)
                continue
            value = misfit(a, b) / size
            out.append(value if math.isfinite(value) else math.inf)
    return out[0], out[1]


def _poses(m: Measurements) -> Mat:
    from ..geometry.lie import rotation_of

    assert m.quaternions is not None
    poses = np.zeros((len(m), 4, 4))
    poses[:, :3, :3] = rotation_of(m.quaternions)
    poses[:, :3, 3] = m.points
    poses[:, 3, 3] = 1.0
    return poses


def score(nominal: PoeModel, m: Measurements, opts: FitOptions, ids: list[int]) -> Mat:
    """The base-tool level's fit to ``m``: ``(2,)`` its RMS position residual over the robot's
    size and, for poses, its RMS rotation residual (rad; 0 for positions); ``inf`` when it
    cannot be fitted."""
    from ..errors import Urdf2DhError

    trial = replace(opts, max_iterations=_ITERATIONS, noise_pos=None, noise_rot=None)
    try:
        with np.errstate(all="ignore"):
            _, before = fit_before(nominal, m, trial, ids)
            each = errors(absorbed(before.solution.estimate), to_data(m, opts.pose, ids))
            out = np.zeros(2)
            out[0] = rms(each[:, 0]) / nominal.size()
            if opts.pose:
                out[1] = rms(each[:, 1])
    except (Urdf2DhError, ValueError, np.linalg.LinAlgError):
        return np.full(2, math.inf)
    out[~np.isfinite(out)] = math.inf
    return out


def gain(old: Mat, new: Mat) -> float:
    """How many times better a reading scoring ``new`` fits than one scoring ``old``
    (:func:`score`): the product of the factors by which each kind of residual falls, none
    rising more than twofold (else 1)."""
    floor = 1e-12
    if not np.all(np.isfinite(new)) or np.any(new > 2.0 * old + floor):
        return 1.0
    return float(np.prod(np.maximum((old + floor) / (new + floor), 1.0)))


def _spread_fits(
    nominal: PoeModel, m: Measurements, trial: dict[str, Reread], opts: FitOptions, ids: list[int]
) -> bool:
    """Whether a reading that changes the length unit leaves the measured points spread as the
    nominal's tool points do (within :data:`~urdf2dh.tolerances.SPREAD`): shrinking them to a
    point would otherwise fit any tool that barely moves."""
    if "lengths" not in trial:
        return True
    ratio = spread_ratio(nominal, m, opts, ids)
    return bool(math.isfinite(ratio) and 1.0 / SPREAD <= ratio <= SPREAD)


def _unit_by_spread(
    nominal: PoeModel, m: Measurements, opts: FitOptions, ids: list[int], candidates: list[Reread]
) -> Reread | None:
    """The length unit that brings the measured points' spread about their centroid to within
    :data:`~urdf2dh.tolerances.SPREAD` of the nominal's tool points' where it is not so as
    read (:func:`.plausible.spread_ratio`): their spread shows the unit whatever else the file
    holds wrong (joint values misread still spread the tool over the robot's workspace)."""
    ratio = spread_ratio(nominal, m, opts, ids)
    if not math.isfinite(ratio) or ratio <= 0.0 or 1.0 / SPREAD <= ratio <= SPREAD:
        return None
    best, nearest = None, math.inf
    for r in candidates:
        if r.kind == "length-unit":
            other = spread_ratio(nominal, r.apply(m), _with_layout(opts, {r.aspect: r}), ids)
            off = abs(math.log(other)) if math.isfinite(other) and other > 0.0 else math.inf
            if off < nearest:
                best, nearest = r, off
    return best if nearest <= math.log(SPREAD) else None


def _polar(a: Mat) -> Mat:
    """The rotation nearest ``a`` (3x3)."""
    u, _, vt = np.linalg.svd(a)
    d = np.sign(np.linalg.det(u @ vt)) or 1.0
    out: Mat = u @ np.diag([1.0, 1.0, d]) @ vt
    return out


def rotation_misfit(model: Mat, measured: Mat) -> float:
    """RMS angle (rad) between rotations ``measured`` and ``B model T`` ``(N, 3, 3)``, with the
    base and tool rotations ``B``, ``T`` that fit best (alternating Procrustes fits)."""
    from ..geometry.lie import log_so3

    with np.errstate(all="ignore"):
        base, tool = np.eye(3), np.eye(3)
        for _ in range(_PROCRUSTES):
            base = _polar(np.einsum("nij,nkj->ik", measured, model @ tool))
            tool = _polar(np.einsum("nji,njk->ik", base @ model, measured))
        turn = log_so3(base @ model @ tool @ np.swapaxes(measured, 1, 2))
    value = float(np.sqrt(np.mean(np.sum(turn**2, axis=1))))
    return value if math.isfinite(value) else math.inf


def _orientation_by_model(
    reference: PoeModel, m: Measurements, candidates: list[Reread]
) -> Reread | None:
    """The reading of the orientations that the identified model ``reference`` (fitted to the
    positions, the orientations weighed by their large residuals) explains :data:`GAIN` times
    better than the reading as given, when the base-tool level cannot tell (a nominal far from
    the robot leaves a tenth of a radian there)."""
    from ..geometry.lie import rotation_of

    if m.quaternions is None:
        return None
    model = reference.fk_batch(m.q)[:, :3, :3]
    given = rotation_misfit(model, rotation_of(m.quaternions))
    best, least = None, given
    for r in candidates:
        if r.aspect == "orientations":
            other = r.apply(m).quaternions
            assert other is not None
            turn = rotation_misfit(model, rotation_of(other))
            if turn < least:
                best, least = r, turn
    return best if least * GAIN <= given else None


def misread(
    nominal: PoeModel,
    m: Measurements,
    opts: FitOptions,
    ids: list[int],
    reference: PoeModel | None = None,
) -> tuple[tuple[Reread, ...], Mat, Mat]:
    """The other readings of ``m`` that explain it (module docstring; at most one per aspect),
    and the scores of the reading as given and of theirs (:func:`score`). ``reference`` is the
    model identified from ``m`` as read, in the device frame, when there is one: the
    orientations' reading is looked for against it too."""
    sample = _sample(m)
    candidates = list(rereadings(sample, nominal))
    given = now = score(nominal, sample, opts, ids)
    chosen: dict[str, Reread] = {}
    turned = None if reference is None else _orientation_by_model(reference, sample, candidates)
    if turned is not None:
        chosen, now = {turned.aspect: turned}, score(nominal, turned.apply(sample), opts, ids)
    lengths = _unit_by_spread(nominal, sample, opts, ids, candidates)
    if lengths is not None:  # the length unit shows apart from everything else: start there
        first = {**chosen, lengths.aspect: lengths}
        value = score(nominal, read_so(sample, first), _with_layout(opts, first), ids)
        if gain(now, value) >= GAIN:
            chosen, now = first, value
    for _ in range(ROUNDS):
        trials = [{**chosen, r.aspect: r} for r in candidates if chosen.get(r.aspect) is not r]
        trials += [{a: r for a, r in chosen.items() if a != aspect} for aspect in chosen]
        reads = [read_so(sample, t) for t in trials]
        each = [_with_layout(opts, t) for t in trials]
        kept = [k for k, t in enumerate(trials) if _spread_fits(nominal, reads[k], t, each[k], ids)]
        trials, reads, each = (
            [trials[k] for k in kept],
            [reads[k] for k in kept],
            [each[k] for k in kept],
        )
        rigid = [_rigid_scores(nominal, reads[k], each[k], ids) for k in range(len(trials))]
        ranked = dict.fromkeys(
            k
            for kind in (0, 1)  # the best by the points alone, and with the orientations
            for k in sorted(range(len(trials)), key=lambda k: rigid[k][kind])[:CONFIRMED]
        )
        best, best_score, best_gain = None, now, 1.0
        for k in ranked:
            value = score(nominal, reads[k], each[k], ids)
            if gain(now, value) > best_gain:
                best, best_score, best_gain = trials[k], value, gain(now, value)
        if best is None or best_gain < GAIN:
            break
        chosen, now = best, best_score
    return tuple(chosen[a] for a in _ORDER if a in chosen), given, now


def explained(reads: tuple[Reread, ...], m: Measurements) -> tuple[str, tuple[Remedy, ...]]:
    """The causes ``reads`` stand for, in words, and the options that read the file so (one
    ``--degrees`` reads both joint values and angles: where only one of them is in degrees, the
    file must change)."""
    read = _as_read(m)
    joints = next((r for r in reads if r.kind == "joint-degrees"), None)
    angles = next((r for r in reads if r.kind == "angle-degrees"), None)
    as_read = "degrees" if read.reading.degrees else "radians"
    alone = "one option reads both alike; convert one of them in the file"
    causes, remedies = [], []
    for r in reads:
        cause, remedy = r.cause, r.remedy
        if r is joints and read.angles is not None:
            if angles is not None:
                cause = cause.replace("the joint values are", "the joint values and the angles are")
            else:
                cause += f", while the angles are in {as_read}: {alone}"
                remedy = None
        elif r is angles:
            parts = [c for c in cause.split(" and ") if not c.startswith("the angles are in")]
            if joints is None:
                parts.append(f"the angles are not in {as_read} while the joint values are: {alone}")
            cause = " and ".join(parts)
        if cause:
            causes.append(cause)
        if remedy is not None and remedy not in remedies:
            remedies.append(remedy)
    return " and ".join(causes), tuple(remedies)


def helical(
    nominal: PoeModel,
    fit: Measurements,
    opts: FitOptions,
    ids: list[int],
    rms_position: float,
) -> tuple[str, ...] | None:
    """The revolute joints whose pitch explains the position residuals (module docstring), or
    ``None`` when pitches do not fit the positions :data:`HELICAL_GAIN` times better than
    ``rms_position`` (the level's fit, model unit)."""
    from ..errors import Urdf2DhError

    turning = [j.name for j in nominal.joints if j.kind == "revolute"]
    if not turning or "all" in opts.helical or opts.level == BASE_TOOL.name:
        return None
    trial = replace(opts, helical=("all",))
    try:
        with np.errstate(all="ignore"):
            result = identify(nominal, fit, trial, ids)
            fitted = rms(errors(absorbed(result.estimate), to_data(fit, opts.pose, ids))[:, 0])
    except (Urdf2DhError, ValueError, np.linalg.LinAlgError):
        return None
    if not fitted * HELICAL_GAIN <= rms_position:
        return None
    chain = result.estimate.chain
    span = np.ptp(fit.q, axis=0)
    named = tuple(
        name
        for name, pitch, travel in zip(chain.names, chain.pitch, span, strict=True)
        if name in turning and abs(pitch) * travel > 3.0 * max(fitted, 1e-300)
    )
    return named or tuple(turning)
