"""Cross-check against independent forward kinematics: Pinocchio (the default) and MuJoCo
(:mod:`urdf2dh.check.mujoco`), the oracles of :data:`ORACLES`.

The only module that imports ``pinocchio``. For a URDF source Pinocchio parses the same URDF
text itself (``buildModelFromXML``), so the check covers our URDF loading as well as the
conversions; for an MJCF source it parses the same MJCF (``buildModelFromMJCF``). POE and table
sources have neither: their Pinocchio model is assembled joint by joint from the screws
(``JointModelRZ``, ``PZ``, ``HelicalUnaligned``).

Pinocchio's MJCF parser (4.1) reads some of MJCF otherwise than MuJoCo, which defines the format
(:data:`PINOCCHIO_MISREADS`, each tested in ``tests/test_mjcf_oracles.py``): for a file that uses
one of those, Pinocchio does not judge, and says why; MuJoCo does.

Pinocchio's continuous joints have two configuration coordinates ``(cos q, sin q)``; joints off
the chain stay at their neutral position.
"""

from __future__ import annotations

import contextlib
import functools
import os
import sys
import tempfile
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray

from ..checks import (
    check_count,
    check_flag,
    check_instance,
    check_optional_name,
    check_seed,
    check_source,
)
from ..conventions import NAMES
from ..conventions.convert import to_table
from ..conventions.table import Table
from ..errors import InputError, OracleError, UsageError, choices, shown, visible
from ..escape import markdown_table, markdown_text
from ..geometry.frames import axis_frame, unit
from ..geometry.se3 import matrix_of
from ..io.fields import JointBound
from ..io.sources import Source, open_source
from ..io.urdf.chain import final_leader
from ..io.xacro import XacroOptions
from ..model.fk import BLOCK, chains_errors
from ..model.mimic import Mimic, actuated
from ..model.poe import PoeModel
from ..progress import progress
from ..tolerances import DEFAULT, EPS, VERIFY_JOINTS, Tolerances

__all__ = [
    "ORACLES",
    "ORACLE_CHOICES",
    "PINOCCHIO_MISREADS",
    "PINOCCHIO_WORLD_BODY",
    "VERIFY_BOUND",
    "Abstention",
    "ModelCheck",
    "Oracle",
    "VerifyReport",
    "check_verifiable",
    "compare_with_oracles",
    "native_stderr",
    "pinocchio_evaluator",
    "pinocchio_fk",
    "verify",
]

# Stack of the thread that runs Pinocchio's URDF parser (bytes), whatever the process's own stack
# limit: it recurses once per link (a segmentation fault beyond ~3,700 links on an 8 MiB stack);
# this is ample for VERIFY_JOINTS links.
PINOCCHIO_STACK = 256 * 2**20

VERIFY_STREAM = 1  # verify's configurations: seeded by --seed, apart from the self-check's

Mat = NDArray[np.float64]


def _pin() -> Any:
    try:
        import pinocchio
    except ImportError as e:  # pragma: no cover - pin is a hard dependency
        raise InputError("Pinocchio is not installed; install it with: pip install pin") from e
    return pinocchio


Mapping = list[tuple[int, int, float, float]]  # per driven column: idx_q, nq, scale, shift


def _model_from_poe(pin: Any, poe: PoeModel) -> tuple[Any, Mapping, int, int]:
    model = pin.Model()
    parent, prev = 0, np.eye(4)
    mapping = []
    for j in poe.joints:
        point = prev[:3, 3] if j.point is None else j.point
        frame = matrix_of(axis_frame(unit(j.axis.tolist()), point.tolist()))
        if j.kind == "revolute":
            jm = pin.JointModelRZ()
        elif j.kind == "prismatic":
            jm = pin.JointModelPZ()
        else:
            jm = pin.JointModelHelicalUnaligned(np.array([0.0, 0.0, 1.0]), j.pitch)
        parent = model.addJoint(parent, jm, pin.SE3(np.linalg.inv(prev) @ frame), j.name)
        mapping.append((model.joints[parent].idx_q, 1, j.scale, 0.0))
        prev = frame
    tip = model.addFrame(
        pin.Frame("tip", parent, pin.SE3(np.linalg.inv(prev) @ poe.home), pin.FrameType.OP_FRAME)
    )
    return model, mapping, 0, tip


@contextlib.contextmanager
def native_stderr() -> Iterator[list[str]]:
    """Collect the lines C++ code (urdfdom) writes to file descriptor 2 meanwhile, instead of
    showing them."""
    lines: list[str] = []
    sys.stderr.flush()
    saved = os.dup(2)
    with tempfile.TemporaryFile() as tmp:
        os.dup2(tmp.fileno(), 2)
        try:
            yield lines
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            tmp.seek(0)
            lines.extend(tmp.read().decode("utf-8", errors="replace").splitlines())


def _build(pin: Any, source: Source, mimic: bool) -> Any:
    """Pinocchio's model of the URDF text; an ``InputError`` with urdfdom's first reason."""
    assert source.document is not None
    error: BaseException | None = None
    with native_stderr() as log:  # urdfdom writes its reasons there, several lines a fault
        try:
            return _pinocchio_model(source.document, mimic)
        except Exception as e:  # Pinocchio raises RuntimeError/ValueError with C++ text
            error = e
    reasons = [line.split(":", 1)[1] for line in log if line.startswith("Error:")]
    why = f"urdfdom: {' '.join(reasons[0].split())}" if reasons else str(error)
    raise InputError(f"{source.display}: Pinocchio cannot load it ({why})") from error


@functools.lru_cache(maxsize=2)
def _pinocchio_model(text: bytes, mimic: bool) -> Any:
    """Pinocchio's model of URDF text, built once for the chains of one file (``verify
    --all-tips`` checks hundreds against the same model; a failure is not kept)."""
    pin = _pin()
    return _on_a_large_stack(lambda: pin.buildModelFromXML(text.decode(), mimic=mimic))


_T = TypeVar("_T")


def _on_a_large_stack(work: Callable[[], _T]) -> _T:
    """``work()`` on a thread with a stack of :data:`PINOCCHIO_STACK` bytes:
    Pinocchio's URDF parser recurses once per link, and the process's own stack (8 MiB, or
    whatever ``ulimit -s`` says) would overflow on a long chain."""
    outcome: list[Any] = []

    def run() -> None:
        try:
            outcome.append((True, work()))
        except BaseException as e:  # handed to the caller's thread, whatever it is
            outcome.append((False, e))

    previous = threading.stack_size(PINOCCHIO_STACK)
    try:
        worker = threading.Thread(target=run, name="pinocchio-urdf", daemon=True)
        worker.start()
    finally:
        threading.stack_size(previous)
    worker.join()
    ok, value = outcome[0]
    if not ok:
        raise value
    return value  # type: ignore[no-any-return]


#: verify's bound on the joints of a SOURCE (a URDF's every joint: Pinocchio builds the whole
#: file), checked by the reader once the joints are counted (:func:`open_source`'s ``bound``)
#: and again of the model (:func:`check_verifiable`).
VERIFY_BOUND = JointBound(
    VERIFY_JOINTS,
    "verify checks",
    "(Pinocchio's model of more takes minutes and gigabytes to build)",
)

#: MJCF features (:data:`urdf2dh.io.mjcf.FEATURES`) that Pinocchio's MJCF parser (4.1) reads
#: otherwise than MuJoCo -> what it does; each is shown by a test of ``tests/test_mjcf_oracles.py``.
PINOCCHIO_MISREADS = {
    "frame": "does not read <frame> elements",
    "extrinsic-euler": "reads the uppercase (extrinsic) letters of eulerseq as intrinsic axes",
    "axisangle-length": "does not normalise an axisangle's axis",
    "compiler-order": "reads only the first <compiler>, and only for what follows it",
    "site-defaults": "does not place a site by its default class",
    "site-fromto": "does not read a site's fromto",
    "joint-pos-defaults": "does not take a joint's pos from its default class",
    "unnamed-body": "merges unnamed bodies",
}
#: What Pinocchio 4.1 does with a body of the world body that has no joint (tested likewise).
PINOCCHIO_WORLD_BODY = "drops the pos and orientation of a body without joints in <worldbody>"


def _model_from_mjcf(pin: Any, source: Source, poe: PoeModel) -> tuple[Any, Mapping, int, int]:
    """Pinocchio's model of the MJCF text, how the chain's rows drive it (each row its joint's
    coordinate: MuJoCo's ``qpos`` layout, which Pinocchio's MJCF models share), base and tip."""
    from ..io.mjcf import FEATURES

    elements = source.mjcf
    assert elements is not None and source.document is not None
    misread = sorted(elements.features & PINOCCHIO_MISREADS.keys())
    if misread:
        raise OracleError(
            "pinocchio",
            f"{source.display}: Pinocchio {pin.__version__} {PINOCCHIO_MISREADS[misread[0]]}, "
            f"and the file has {FEATURES[misread[0]]}",
        )
    try:
        model = _pinocchio_mjcf(source.document)
    except Exception as e:  # Pinocchio raises RuntimeError/ValueError with C++ text
        why = " ".join(str(e).split())[:300]
        raise OracleError("pinocchio", f"{source.display}: Pinocchio cannot load it ({why})") from e
    if model.nq != elements.nq:
        raise OracleError(
            "pinocchio",
            f"{source.display}: Pinocchio's model has {model.nq} configuration coordinates, the "
            f"file's joints {elements.nq}",
        )
    mapping = [(elements.joints[j.name].qpos, 1, j.scale, 0.0) for j in poe.joints]
    tree = source.tree
    assert tree is not None
    if poe.base_link == tree.root and poe.tip_link != tree.root:
        first = tree.chain(tree.root, poe.tip_link)[0]
        if first.type == "fixed" and not np.array_equal(first.origin, np.eye(4)):
            raise OracleError(
                "pinocchio",
                f"{source.display}: Pinocchio {pin.__version__} {PINOCCHIO_WORLD_BODY}, and the "
                f"chain runs from the world through body {shown(first.child)}",
            )

    def frame(link: str) -> int:
        element = elements.links[link]
        if element.kind == "world":
            return 0
        kind = pin.FrameType.OP_FRAME if element.kind == "site" else pin.FrameType.BODY
        found = model.nframes if element.name is None else model.getFrameId(element.name, kind)
        if found >= model.nframes or element.kind == "frame":
            raise OracleError(
                "pinocchio",
                f"{source.display}: Pinocchio has no frame for {element.kind} {shown(link)}",
            )
        return int(found)

    return model, mapping, frame(poe.base_link), frame(poe.tip_link)


@functools.lru_cache(maxsize=2)
def _pinocchio_mjcf(text: bytes) -> Any:
    """Pinocchio's model of MJCF text (its parser reads a file: the text is written to a
    temporary one), built once for the chains of one file."""
    pin = _pin()
    with tempfile.TemporaryDirectory(prefix="urdf2dh-mjcf-") as directory:
        path = os.path.join(directory, "model.xml")
        with open(path, "wb") as f:
            f.write(text)
        return _on_a_large_stack(lambda: pin.buildModelFromMJCF(path))


def check_verifiable(source: Source, poe: PoeModel) -> None:
    """Refuse a model larger than :data:`~urdf2dh.tolerances.VERIFY_JOINTS` joints (a URDF's
    every joint: Pinocchio builds the whole file), naming the bound."""
    if source.tree is not None:
        VERIFY_BOUND.check(
            len(source.tree.joints), source.display, f"the {source.kind.upper()} has"
        )
    else:
        VERIFY_BOUND.check(poe.n, source.display, "the chain has")


def _model_from_urdf(
    pin: Any, source: Source, poe: PoeModel
) -> tuple[Any, Mapping, int, int, bool]:
    """Pinocchio's model, how the chain's configurations drive it, base and tip frames, and
    whether it is driven by every joint's position (``True``) or by the actuated ones only.

    Pinocchio couples mimic joints itself (a mimicking joint has no coordinate of its own), and
    helical joints arrive as a revolute joint and a prismatic one mimicking it
    (:mod:`urdf2dh.emit.urdf`). Where Pinocchio cannot build a URDF's mimic joints (a leader it has
    not met yet, as in Romeo's hands) and the chain has no helical joint, it is built without them
    and every joint of the chain is set to the position the coupling gives it.
    """
    helical = any(j.kind == "helical" for j in poe.joints)
    mimic = helical or any(j.mimic is not None for j in poe.joints)
    try:
        model = _build(pin, source, mimic)
    except InputError:
        if not mimic or helical:
            raise
        model, mimic = _build(pin, source, False), False
    mapping: Mapping = []
    driving = actuated(poe.joints) if mimic else range(poe.n)
    for j in (poe.joints[i] for i in driving):  # with mimic, the mimicking ones follow
        jid = model.getJointId(j.name)
        if jid >= model.njoints:
            raise InputError(f"{source.display}: Pinocchio has no joint {shown(j.name)}")
        scale, shift = 1.0, 0.0
        if model.joints[jid].nq == 0:
            # a joint of the chain standing in for a leader off it (or one --ignore-mimic made
            # independent): Pinocchio's mimic joint follows that leader, so the leader is set
            # to what gives the joint its position, q_leader = (q - offset) / multiplier
            relation = _urdf_leader(source, j.name)
            jid = model.getJointId(relation.joint)
            scale, shift = 1.0 / relation.multiplier, -relation.offset / relation.multiplier
        jm = model.joints[jid]
        mapping.append((jm.idx_q, jm.nq, scale, shift))

    def frame(link: str) -> int:
        fid = model.getFrameId(link, pin.FrameType.BODY)
        if fid >= model.nframes:
            raise InputError(f"{source.display}: Pinocchio has no frame for link {shown(link)}")
        return int(fid)

    return model, mapping, frame(poe.base_link), frame(poe.tip_link), not mimic


def _urdf_leader(source: Source, name: str) -> Mimic:
    """The joint a URDF joint finally follows (through mimics of mimics), and how."""
    assert source.tree is not None
    joint = source.tree.joints[name]
    if joint.mimic is None or joint.multiplier == 0.0:
        raise InputError(f"{source.display}: Pinocchio cannot drive joint {shown(name)}")
    return final_leader(source.tree, Mimic(joint.mimic, joint.multiplier, joint.offset))


def pinocchio_fk(source: Source, poe: PoeModel, q: Mat) -> Mat:
    """Pinocchio's pose ``(N, 4, 4)`` of the tip in the base link for configurations ``q``
    ``(N, dof)`` of the chain's actuated joints (mimic joints following them, other joints at
    their neutral position)."""
    return pinocchio_evaluator(source, poe)(q)


def pinocchio_evaluator(source: Source, poe: PoeModel) -> Callable[[Mat], Mat]:
    """:func:`pinocchio_fk` of one chain as a function of the configurations, its Pinocchio
    model built once for every block of configurations it is asked (``verify``'s blocks)."""
    pin = _pin()
    if source.kind == "urdf":
        model, mapping, base_f, tip_f, rows = _model_from_urdf(pin, source, poe)
    elif source.kind == "mjcf":  # every row drives its joint: Pinocchio reads no equality
        model, mapping, base_f, tip_f = _model_from_mjcf(pin, source, poe)
        rows = True
    else:  # our own model of Pinocchio joints, one per row, driven with the mimic coupling
        model, mapping, base_f, tip_f = _model_from_poe(pin, poe)
        rows = True
    poses = _frame_poser(pin, model)
    # the base link lies above the chain, so its pose moves with none of the sampled joints
    base = poses(base_f, pin.neutral(model)[None])[0]
    base_inverse = pin.SE3(base).inverse().homogeneous

    def evaluate(q: Mat) -> Mat:
        if rows:
            q = poe.positions(q)
        configs = np.repeat(pin.neutral(model)[None], q.shape[0], axis=0)
        for column, (idx, nq, scale, shift) in zip(q.T, mapping, strict=True):
            value = scale * column + shift
            if nq == 2:  # a continuous joint: (cos q, sin q)
                configs[:, idx], configs[:, idx + 1] = np.cos(value), np.sin(value)
            else:
                configs[:, idx] = value
        tip = poses(tip_f, configs)
        if np.array_equal(base_inverse, np.eye(4)):  # the base link is Pinocchio's root
            return tip
        moved: Mat = base_inverse @ tip
        return moved

    return evaluate


# Pinocchio's Data holds derivative tensors of nv^3 doubles: 58 MB at 100 joints, 8 GB at 500.
# Up to this many, forward kinematics uses it (the fastest); beyond, joint by joint.
DATA_JOINTS = 100


def _frame_poser(pin: Any, model: Any) -> Callable[[int, Mat], Mat]:
    """A function of a frame and configurations ``(N, nq)`` giving Pinocchio's pose
    ``(N, 4, 4)`` of the frame at each.

    Up to :data:`DATA_JOINTS` degrees of freedom, by ``forwardKinematics`` and
    ``updateFramePlacement`` on one ``Data``; beyond, the same recursion along the frame's
    support with each joint's own ``calc`` and one ``JointData`` per joint, ``oMi = oMi_parent
    . (jointPlacements[i] . M_i(q))``, so that memory stays linear in the joints."""
    if model.nv <= DATA_JOINTS:
        data = model.createData()

        def by_data(frame: int, configs: Mat) -> Mat:
            out = np.empty((configs.shape[0], 4, 4))
            for k, config in enumerate(configs):
                pin.forwardKinematics(model, data, config)
                out[k] = pin.updateFramePlacement(model, data, frame).homogeneous
            return out

        return by_data

    def joint_by_joint(frame: int, configs: Mat) -> Mat:
        placement = model.frames[frame].placement
        support = list(model.supports[model.frames[frame].parentJoint])[1:]  # 0: the universe
        joints = [model.joints[i] for i in support]
        steps = [model.jointPlacements[i] for i in support]
        datas = [j.createData() for j in joints]
        out = np.empty((configs.shape[0], 4, 4))
        for k, config in enumerate(configs):
            pose = pin.SE3.Identity()
            for joint, step, data in zip(joints, steps, datas, strict=True):
                joint.calc(data, config)
                pose = pose * (step * data.M)  # as Pinocchio: oMi = oMi_parent * liMi
            out[k] = (pose * placement).homogeneous
        return out

    return joint_by_joint


def _oracle_rounding(source: Source, poe: PoeModel) -> float:
    """What Pinocchio's base-to-tip position may be off by from float64 rounding alone.

    Pinocchio computes the base and tip poses in the URDF root's frame, so each of the ``k``
    placements composed from the root to the tip rounds at the scale of the base link's distance
    ``L`` from the root: a world joint 1e16 m away leaves it metres off. ``4 k eps L``, which is
    far below the check for any ordinary URDF (``L`` of a few metres).
    """
    tree = source.tree
    if tree is None or not poe.base_link or poe.base_link == tree.root:
        return 0.0
    above = tree.chain(tree.root, poe.base_link)
    t = np.eye(4)
    for joint in above:
        t = t @ joint.origin
    composed = len(tree.chain(tree.root, poe.tip_link)) + 1
    return 4.0 * composed * EPS * float(np.linalg.norm(t[:3, 3]))


@dataclass(frozen=True, slots=True)
class Oracle:
    """An independent forward kinematics a chain is checked against.

    Attributes
    ----------
    name
        What ``--oracle`` calls it (``pinocchio``).
    label
        Its name in reports (``Pinocchio``).
    evaluator
        The function of a SOURCE and a chain of it giving the oracle's tip poses ``(N, 4, 4)``
        in the base for configurations ``(N, dof)``; an :class:`~urdf2dh.errors.OracleError`
        where it cannot judge the chain.
    """

    name: str
    label: str
    evaluator: Callable[[Source, PoeModel], Callable[[Mat], Mat]]


def _pinocchio(source: Source, poe: PoeModel) -> Callable[[Mat], Mat]:
    return pinocchio_evaluator(source, poe)  # looked up when called (tests replace it)


def _mujoco(source: Source, poe: PoeModel) -> Callable[[Mat], Mat]:
    from .mujoco import mujoco_evaluator  # mujoco is imported only when asked for

    return mujoco_evaluator(source, poe)


ORACLES: dict[str, Oracle] = {
    o.name: o
    for o in (Oracle("pinocchio", "Pinocchio", _pinocchio), Oracle("mujoco", "MuJoCo", _mujoco))
}
#: What ``verify --oracle`` takes: an oracle's name, or both.
ORACLE_CHOICES = (*ORACLES, "both")


def _oracles(choice: str) -> tuple[Oracle, ...]:
    if choice == "both":
        return tuple(ORACLES.values())
    if choice not in ORACLES:
        raise UsageError(f"unknown oracle {shown(choice)}; valid: {choices(ORACLE_CHOICES)}")
    return (ORACLES[choice],)


def labels(oracles: tuple[str, ...]) -> str:
    """Oracles by name as a report names them: ``Pinocchio and MuJoCo``."""
    names = [ORACLES[o].label for o in oracles]
    return " and ".join(names) if len(names) < 3 else ", ".join(names)


@dataclass(frozen=True, slots=True)
class ModelCheck:
    """One model (the POE model, or a convention's table) against one oracle: its worst errors
    and what it was allowed.

    Attributes
    ----------
    label
        ``POE model``, or the table's convention.
    position, rotation
        The worst position error (length unit) and rotation error (rad) over the configurations.
    allowed_position, allowed_rotation
        What was allowed: ``check_position`` x size and ``check_rotation``, plus the deviation
        the table declared, plus the oracle's own rounding far from the tree's root.
    table
        The table checked (``None`` for the POE model): as ``convert`` writes it.
    oracle
        The oracle it was checked against (a name in :data:`ORACLES`).
    """

    label: str
    position: float
    rotation: float
    allowed_position: float
    allowed_rotation: float
    table: Table | None
    oracle: str = "pinocchio"

    @property
    def ok(self) -> bool:
        """Whether both errors are within what was allowed."""
        return self.position <= self.allowed_position and self.rotation <= self.allowed_rotation


@dataclass(frozen=True, slots=True)
class Abstention:
    """An oracle that did not judge the chain, and why (the message of its
    :class:`~urdf2dh.errors.OracleError`)."""

    oracle: str
    reason: str


@dataclass(frozen=True, slots=True)
class VerifyReport:
    """The result of :func:`verify`: every model of one chain against the oracles.

    Attributes
    ----------
    robot, source
        The SOURCE's name and file.
    base_link, tip_link
        The chain's links (empty for a POE or table file).
    joints
        Its movable joints.
    length_unit, size
        Its length unit and size (what position errors are measured against).
    samples, seed
        The configurations compared: how many, and the seed they were drawn with.
    checks
        For each oracle that judged, the POE model's check, then each convention's.
    abstentions
        The oracles asked that did not judge the chain, and why.
    """

    robot: str
    source: str
    base_link: str
    tip_link: str
    joints: int
    length_unit: str
    size: float
    samples: int
    seed: int
    checks: tuple[ModelCheck, ...]
    abstentions: tuple[Abstention, ...] = ()

    @property
    def ok(self) -> bool:
        """Whether every model agrees with every oracle that judged it."""
        return bool(self.checks) and all(c.ok for c in self.checks)

    @property
    def oracles(self) -> tuple[str, ...]:
        """The oracles that judged the chain, by name."""
        return tuple(dict.fromkeys(c.oracle for c in self.checks))

    @property
    def failed(self) -> tuple[str, ...]:
        """The labels of the models that do not agree (with the oracle's, where several
        judged)."""
        several = len(self.oracles) > 1
        return tuple(
            f"{c.label} ({ORACLES[c.oracle].label})" if several else c.label
            for c in self.checks
            if not c.ok
        )

    @property
    def chain(self) -> str:
        """``base -> tip`` (names as :func:`~urdf2dh.errors.visible` text), or ``""``."""
        v = visible
        return f"{v(self.base_link)} -> {v(self.tip_link)}" if self.base_link else ""

    def warnings(self) -> tuple[str, ...]:
        """The tables' warnings, in order (once each, whatever the oracles)."""
        first = self.oracles[0] if self.oracles else ""
        return tuple(
            w for c in self.checks if c.table is not None and c.oracle == first
            for w in c.table.warnings
        )  # fmt: skip

    def lines(self) -> list[str]:
        """The report ``urdf2dh verify`` prints for the chain (names as
        :func:`~urdf2dh.errors.visible` text)."""
        v = visible
        unit = v(self.length_unit)
        chain = f"{self.chain}, " if self.chain else ""
        several = len(self.oracles) > 1
        out = [
            f"{v(self.robot)}: {chain}{self.joints} joints; against {labels(self.oracles)} at "
            f"{self.samples} configurations (seed {self.seed}); robot size {self.size:.4g} {unit}",
            f"  {'oracle     ' if several else ''}{'model':<10} {'position error':>16} "
            f"{'relative':>10} {'rotation error':>16}  result",
        ]
        for c in self.checks:
            who = f"{ORACLES[c.oracle].label:<10} " if several else ""
            out.append(
                f"  {who}{c.label:<10} {c.position:>13.2e} {unit:<2} "
                f"{c.position / self.size:>10.2e} {c.rotation:>12.2e} rad  "
                f"{'ok' if c.ok else 'FAILED'}"
            )
        out.extend(f"  {ORACLES[a.oracle].label} did not judge: {v(a.reason)}"
                   for a in self.abstentions)  # fmt: skip
        out.extend(f"  warning: {v(w)}" for w in self.warnings())
        return out

    def __str__(self) -> str:
        """The report as ``urdf2dh verify`` prints it."""
        return "\n".join(self.lines()) + "\n"

    def __repr__(self) -> str:
        verdict = "ok" if self.ok else f"FAILED: {', '.join(self.failed)}"
        return (
            f"<VerifyReport {shown(self.robot)}: {len(self.checks)} models against Pinocchio at "
            f"{self.samples} configurations, {visible(verdict)}>"
        )

    def _repr_markdown_(self) -> str:
        """In a notebook: each model's errors against each oracle as a table (names escaped)."""
        t, unit = markdown_text, markdown_text(self.length_unit)
        chain = f" {t(self.base_link)} -> {t(self.tip_link)}" if self.base_link else ""
        out = [f"**{t(self.robot)}**{chain}: against {labels(self.oracles)} at "
               f"{self.samples} configurations (seed {self.seed}), robot size "
               f"{self.size:.4g} {unit}", ""]  # fmt: skip
        several = len(self.oracles) > 1
        rows = [[*([ORACLES[c.oracle].label] if several else []), c.label, f"{c.position:.2e}",
                 f"{c.position / self.size:.2e}", f"{c.rotation:.2e}",
                 f"{c.allowed_position:.2g}", "ok" if c.ok else "**FAILED**"]
                for c in self.checks]  # fmt: skip
        out += markdown_table(
            [*(["oracle"] if several else []), "model", f"position error [{unit}]", "relative",
             "rotation error [rad]", f"allowed [{unit}]", "result"], rows)  # fmt: skip
        out += [f"- {ORACLES[a.oracle].label} did not judge: {t(a.reason)}"
                for a in self.abstentions]  # fmt: skip
        out += [f"- {t(w)}" for w in self.warnings()]
        return "\n".join(out) + "\n"


def compare_with_oracles(
    source: Source,
    poe: PoeModel,
    samples: int = 1000,
    seed: int = 0,
    tol: Tolerances = DEFAULT,
    conventions: tuple[str, ...] = NAMES,
    check_samples: int | None = None,
    oracle: str = "pinocchio",
) -> tuple[tuple[ModelCheck, ...], tuple[Abstention, ...]]:
    """The source's POE model ``poe`` and each convention's table against the oracles.

    The tables are the ones ``convert`` writes (their own self-check included); the oracles are
    asked at configurations from a separate random stream, so that a declared deviation is
    tested where the table's check did not look. The tolerance is ``check_position x size``
    and ``check_rotation``, plus the deviation bound a table declared in its own check (non-zero
    only where a tolerance judgement was reported), plus the oracle's own rounding where the base
    link lies far from the tree's root (:func:`_oracle_rounding`).

    Parameters
    ----------
    oracle
        ``pinocchio``, ``mujoco`` or ``both`` (:data:`ORACLE_CHOICES`).

    Returns
    -------
    tuple
        The checks (for each oracle that judged: the POE model's, then each table's), and the
        oracles that did not judge the chain.

    Raises
    ------
    OracleError
        Where no oracle asked can judge the chain (the first one's reason).
    """
    asked = _oracles(oracle)
    check_verifiable(source, poe)
    evaluators, abstentions, refusals = [], [], []
    for o in asked:
        try:
            evaluators.append((o.name, o.evaluator(source, poe)))
        except OracleError as e:
            abstentions.append(Abstention(o.name, str(e)))
            refusals.append(e)
    if not evaluators:
        if len(refusals) == 1:
            raise refusals[0]
        raise OracleError(asked[0].name, "; ".join(str(e) for e in refusals))
    q = poe.sample(samples, (seed, VERIFY_STREAM))
    tables = [to_table(poe, conv, tol, samples=check_samples) for conv in conventions]
    chains = [poe.link_form(), *(t.link_form() for t in tables)]
    worst = np.zeros((len(evaluators), len(chains), 2))
    starts = range(0, q.shape[0], BLOCK)
    for lo in progress(starts, len(starts), "verify"):  # a bar on a terminal
        block = q[lo : lo + BLOCK]
        positions = poe.positions(block)
        for k, (_, evaluate) in enumerate(evaluators):
            found = chains_errors(chains, positions, evaluate(block))
            worst[k] = np.maximum(worst[k], found)  # NaN (a non-finite pose) stays NaN: a failure
    base_pos = tol.check_position * poe.size() + _oracle_rounding(source, poe)
    base_rot = tol.check_rotation
    checks = []
    for (name, _), errors in zip(evaluators, worst, strict=True):
        (model_pos, model_rot), *table_errors = ((float(p), float(r)) for p, r in errors)
        checks.append(ModelCheck("POE model", model_pos, model_rot, base_pos, base_rot, None, name))
        for table, (pos, rot) in zip(tables, table_errors, strict=True):
            check = table.check
            declared = (0.0, 0.0) if check is None else (check.declared_position,
                                                         check.declared_rotation)  # fmt: skip
            checks.append(ModelCheck(table.convention, pos, rot, base_pos + declared[0],
                                     base_rot + declared[1], table, name))  # fmt: skip
    return tuple(checks), tuple(abstentions)


def verify(
    source: str | os.PathLike[str] | Source,
    base: str | None = None,
    tip: str | None = None,
    ignore_mimic: bool = False,
    *,
    samples: int = 1000,
    seed: int = 0,
    tol: Tolerances = DEFAULT,
    conventions: tuple[str, ...] = NAMES,
    check_samples: int | None = None,
    xacro: XacroOptions | None = None,
    oracle: str = "pinocchio",
) -> VerifyReport:
    """The chain ``base -> tip`` of a SOURCE and each convention's table of it, against an
    independent forward kinematics (Pinocchio's, MuJoCo's, or both) at ``samples`` seeded
    configurations within the joint limits.

    For a URDF or MJCF file, the oracle reads the same text itself, so the check covers the
    file's reading too; for a POE or table file, its model is assembled joint by joint from the
    screws.

    Parameters
    ----------
    source
        A URDF, ``.xacro`` or MJCF file, a POE model file, a table file, a bundled robot's name,
        or a SOURCE already opened (:func:`urdf2dh.io.sources.open_source`).
    base, tip, ignore_mimic
        The chain, as :func:`urdf2dh.load` takes them.
    samples, seed
        Configurations compared (1 to :data:`~urdf2dh.tolerances.MAX_SAMPLES`) and their seed
        (drawn apart from each table's self-check).
    tol
        The tolerances of the conversions and of the comparison.
    conventions
        The conventions whose tables are checked (default: all).
    check_samples
        Configurations of each table's self-check (default: :func:`urdf2dh.to_table`'s).
    xacro
        How ``.xacro`` sources are expanded.
    oracle
        ``pinocchio`` (the default), ``mujoco``, or ``both``; with both, an oracle that cannot
        judge the chain (its reason in :attr:`VerifyReport.abstentions`) leaves it to the other.

    Returns
    -------
    VerifyReport
        Every model's worst errors against each oracle and what it was allowed; ``ok`` when all
        agree.

    Raises
    ------
    Urdf2DhError
        A SOURCE or chain that cannot be read (:class:`~urdf2dh.errors.InputError`,
        :class:`~urdf2dh.errors.ChainError`), a chain beyond
        :data:`~urdf2dh.tolerances.VERIFY_JOINTS` joints, a table that failed its own check
        (:class:`~urdf2dh.errors.ConversionError`), or no oracle asked able to judge the chain
        (:class:`~urdf2dh.errors.OracleError`).
    TypeError, ValueError
        An argument of the wrong type or out of range (an unknown ``oracle``:
        :class:`~urdf2dh.errors.UsageError`).
    """
    check_count(samples, "verify: samples")
    check_seed(seed, "verify: seed")
    check_instance(tol, Tolerances, "verify: tol", "urdf2dh.Tolerances(...) or urdf2dh.DEFAULT")
    check_instance(oracle, str, "verify: oracle")
    _oracles(oracle)
    if not isinstance(source, Source):
        source = open_source(
            check_source(source, "verify: source"), tol, xacro=xacro, bound=VERIFY_BOUND
        )
    model = source.model(
        check_optional_name(base, "verify: base"),
        check_optional_name(tip, "verify: tip"),
        check_flag(ignore_mimic, "verify: ignore_mimic"),
    )
    checks, abstentions = compare_with_oracles(
        source, model, samples, seed, tol, conventions, check_samples, oracle
    )
    return VerifyReport(
        source.name, source.display, model.base_link, model.tip_link, model.n, model.length_unit,
        model.size(), samples, seed, checks, abstentions,
    )  # fmt: skip
