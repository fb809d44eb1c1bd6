"""A corpus of the mistakes a lab makes with a calibration: the wrong unit, angle unit, column
names or order, quaternion order, rotation sequence, noise figure, model or device frame.

    PYTHONPATH=. python scripts/lab_mistakes.py              # every case, a table of outcomes
    PYTHONPATH=. python scripts/lab_mistakes.py --only units  # the cases of one class

Each scenario is a robot as built (seeded errors about its nominal) measured by a device in a
frame of its own and written as a lab writes it: joints under its own names, in degrees,
positions in millimetres, the orientation as the device gives it (a scalar-first quaternion, or
KUKA's A, B, C angles), a time column. The right command reads it with the options it needs
(``--rename``, ``--degrees``, ``--length-unit``, ``--euler``, ``--ignore``, ``--helical``,
``--marker-layout``). Each mistake changes the file or the command as a lab would (a forgotten
option, a wrong rename, an optimistic noise figure, a left-handed tracker frame, ...), and
``urdf2dh calibrate`` runs on it in-process. The outcome is one of:

* ``same model``: exit 0, and the model written is as accurate against the robot as built as
  the right file's (:data:`SAME`);
* ``refused, cause named``: exit 2 or 3, one line naming the cause (:attr:`Mistake.named`: the
  option that fixes it, or the words of the cause);
* ``refused, cause not named``, ``false refusal`` (a file that is right, refused),
  ``silent wrong model`` (exit 0, a model less accurate than the right file's), ``internal
  error`` (or a traceback, or another exit code): each a failure.

The script prints the outcomes by class, the failures, the counts of internal errors and silent
wrong models, and exits 1 when a case fails. The test suite runs the whole corpus
(tests/test_lab_mistakes.py).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import math
import re
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import cache
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import urdf2dh  # noqa: E402
from urdf2dh import units  # noqa: E402
from urdf2dh.calibration.measure import marker_layout, perturb, synthesize  # noqa: E402
from urdf2dh.calibration.measurements import Measurements  # noqa: E402
from urdf2dh.cli import main as cli  # noqa: E402
from urdf2dh.geometry.lie import quaternion_of, rotation_of  # noqa: E402
from urdf2dh.geometry.se3 import twist_exp  # noqa: E402
from urdf2dh.model.poe import PoeModel  # noqa: E402

Mat = np.ndarray
SAME = 2.0  # a model at most this many times less accurate than the right file's is the same
SAMPLES = 300  # configurations the models are compared at


@dataclass(frozen=True)
class LabFile:
    """How a lab writes its measurements (one scenario's right file, or a mistaken one).

    Attributes
    ----------
    joints
        The file's name of each joint (the chain's order).
    degrees
        Joint values (and angles) in degrees.
    length
        The unit of the positions (and of sliding joints).
    points
        The names of the x, y, z columns.
    orientation
        ``("quat", names, order)``: a quaternion whose columns ``names`` hold the components
        ``order`` (``"wxyz"``); ``("euler", names, sequence)``: angles of a scipy sequence;
        ``None``: positions.
    time
        A leading time column ``t``.
    shuffle
        Write the columns in a seeded order (``None``: as listed).
    frame
        ``(4, 4)`` the device frame in which the file measures (points and orientations).
    joint_sign, joint_swap, point_swap, point_sign
        Content that does not follow the header: a joint counted the other way, two joints' or
        two coordinates' values exchanged, a coordinate reversed (a left-handed frame).
    markers
        Markers per configuration (position measurements), else ``None``.
    radian_joints
        The joint values in radians whatever ``degrees`` says (the angles follow it).
    other_unit_joint
        One joint's column in the other angle unit than its neighbours' (radians among
        degrees, or degrees among radians).
    """

    joints: tuple[str, ...]
    degrees: bool = True
    length: str = "mm"
    points: tuple[str, str, str] = ("X", "Y", "Z")
    orientation: tuple[str, tuple[str, ...], str] | None = None
    time: bool = True
    shuffle: int | None = None
    frame: Mat = field(default_factory=lambda: np.eye(4))
    joint_sign: int | None = None
    joint_swap: tuple[int, int] | None = None
    point_swap: tuple[int, int] | None = None
    point_sign: int | None = None
    markers: int | None = None
    radian_joints: bool = False
    other_unit_joint: int | None = None


@dataclass(frozen=True)
class Scenario:
    """A robot as built, measured, and the right way to read its lab file."""

    name: str
    nominal: str
    truth: PoeModel
    measured: Measurements  # in the truth's base frame, the nominal's unit
    lab: LabFile
    args: tuple[str, ...]  # the options the right file needs
    noise: tuple[float, float]  # the measurements' noise: position (nominal's unit), rotation
    layout: dict[int, Mat] | None = None


@dataclass(frozen=True)
class Mistake:
    """One mistake: how it changes the file and the command, and what must be said of it.

    ``named`` is ``()`` when the file is right (the same model must come out), else the words
    of which one at least must be in the refusal (the option that fixes it, or the cause)."""

    kind: str
    name: str
    scenario: str
    change: Callable[[LabFile, tuple[str, ...]], tuple[LabFile, tuple[str, ...]]]
    named: tuple[str, ...] = ()


@dataclass(frozen=True)
class Outcome:
    mistake: Mistake
    code: int
    message: str
    verdict: str
    accuracy: float | None = None
    right: float | None = None
    seconds: float = 0.0


# ----------------------------------------------------------------------------- scenarios


def _frame(yaw: float, tilt: float, offset: tuple[float, float, float]) -> Mat:
    """A device frame: turned about z and tilted about x, then moved (metres)."""
    g = twist_exp(np.array([0.0, 0.0, yaw, 0.0, 0.0, 0.0])) @ twist_exp(
        np.array([tilt, 0.0, 0.0, 0.0, 0.0, 0.0])
    )
    g[:3, 3] = offset
    return g


def _rename(lab: LabFile, joints: tuple[str, ...]) -> str:
    pairs = [f"{a}={b}" for a, b in zip(lab.joints, joints, strict=True)]
    pairs += [f"{a}={b}" for a, b in zip(lab.points, "xyz", strict=True)]
    if lab.orientation is not None:
        kind, names, order = lab.orientation
        roles = (
            [f"q{c}" for c in order] if kind == "quat" else ["roll", "pitch", "yaw"][: len(names)]
        )
        pairs += [f"{a}={b}" for a, b in zip(names, roles, strict=True)]
    return ",".join(pairs)


def _reading(lab: LabFile, robot: PoeModel, *more: str) -> tuple[str, ...]:
    """The options that read a lab file (its names, a time column, degrees, mm) for ``robot``."""
    names = _rename(lab, tuple(j.name for j in robot.joints))
    return ("--rename", names, "--ignore", "t", "--degrees", "--length-unit", "mm", *more)


@cache
def scenarios() -> dict[str, Scenario]:
    """The five scenarios (seeded)."""
    out = {}
    ur5 = urdf2dh.load("ur5")
    actual, noise = perturb(ur5, 21, 0.002, 0.001), (3e-5, 5e-5)
    lab = LabFile(
        tuple(f"A{k}" for k in range(1, 7)),
        orientation=("quat", ("QW", "QX", "QY", "QZ"), "wxyz"),
        frame=_frame(2.1, 0.3, (2.4, -0.8, 0.6)),
    )
    out["tracker"] = Scenario(
        "tracker",
        "ur5",
        actual,
        synthesize(actual, 40, *noise, seed=22),
        lab,
        _reading(lab, actual),
        noise,
    )
    panda = urdf2dh.load("panda")
    actual, noise = perturb(panda, 23, 0.002, 0.001), (5e-4, 1e-3)
    lab = LabFile(
        tuple(f"J{k}" for k in range(1, 8)),
        orientation=("euler", ("A", "B", "C"), "ZYX"),
        frame=_frame(-0.7, -0.2, (0.9, 1.1, 0.4)),
    )
    out["camera"] = Scenario(
        "camera",
        "panda",
        actual,
        synthesize(actual, 50, *noise, seed=24),
        lab,
        _reading(lab, actual, "--euler", "ZYX"),
        noise,
    )
    puma, noise = urdf2dh.load("puma560-actual"), (0.01, 1e-5)
    lab = LabFile(
        tuple(f"j{k}" for k in range(1, 7)),
        degrees=False,
        length="mm",
        points=("x", "y", "z"),
        orientation=("quat", ("qx", "qy", "qz", "qw"), "xyzw"),
        time=False,
    )
    out["helical"] = Scenario(
        "helical",
        "puma560-nominal",
        puma,
        synthesize(puma, 60, *noise, seed=25),
        lab,
        ("--helical", "all"),
        noise,
    )
    actual, noise = perturb(ur5, 26, 0.002, 0.001), (5e-5, 0.0)
    layout = marker_layout(ur5, 3, 27)
    lab = LabFile(
        tuple(f"q{k}" for k in range(1, 7)),
        markers=3,
        frame=_frame(0.4, 0.1, (-1.5, 2.0, 0.2)),
    )
    out["markers"] = Scenario(
        "markers",
        "ur5",
        actual,
        synthesize(actual, 40, *noise, seed=28, layout=layout, pose=False),
        lab,
        _reading(lab, actual),
        noise,
        layout,
    )
    scara = urdf2dh.load("scara")
    actual, noise = perturb(scara, 29, 0.002, 0.001), (5e-5, 2e-4)
    lab = LabFile(
        ("axis1", "axis2", "axis3", "axis4"),
        orientation=("euler", ("Rx", "Ry", "Rz"), "xyz"),
        frame=_frame(1.2, 0.05, (0.3, -1.2, -0.5)),
    )
    out["scara"] = Scenario(
        "scara",
        "scara",
        actual,
        synthesize(actual, 40, *noise, seed=30),
        lab,
        _reading(lab, actual),
        noise,
    )
    return out


# ----------------------------------------------------------------------------- the lab's files


def write(sc: Scenario, lab: LabFile, path: Path) -> None:
    """The scenario's measurements as ``lab`` writes them."""
    from scipy.spatial.transform import Rotation

    m = sc.measured
    g = lab.frame
    points = m.points @ g[:3, :3].T + g[:3, 3]
    q = m.q.copy()
    if lab.joint_swap is not None:
        i, k = lab.joint_swap
        q[:, [i, k]] = q[:, [k, i]]
    if lab.joint_sign is not None:
        q[:, lab.joint_sign] *= -1.0
    if lab.point_swap is not None:
        i, k = lab.point_swap
        points[:, [i, k]] = points[:, [k, i]]
    if lab.point_sign is not None:
        points[:, lab.point_sign] *= -1.0
    columns: dict[str, Mat] = {}
    if lab.time:
        columns["t"] = np.arange(len(m)) * 0.5
    for k, name in enumerate(lab.joints):
        degrees = (lab.degrees and not lab.radian_joints) != (k == lab.other_unit_joint)
        columns[name] = np.degrees(q[:, k]) if degrees else q[:, k]
    scale = units.factor(sc.truth.length_unit, lab.length)
    for k, name in enumerate(lab.points):
        columns[name] = points[:, k] * scale
    if lab.orientation is not None:
        assert m.quaternions is not None
        rot = g[:3, :3] @ rotation_of(m.quaternions)
        kind, names, order = lab.orientation
        if kind == "quat":
            quat = quaternion_of(rot)  # x, y, z, w
            for name, c in zip(names, order, strict=True):
                columns[name] = quat[:, "xyzw".index(c)]
        else:
            angles = Rotation.from_matrix(rot).as_euler(order, degrees=lab.degrees)
            for k, name in enumerate(names):
                columns[name] = angles[:, k]
    if m.markers is not None:
        columns["marker"] = m.markers.astype(float)
    names = list(columns)
    if lab.shuffle is not None:
        names = [names[k] for k in np.random.default_rng(lab.shuffle).permutation(len(names))]
    rows = [",".join(names)]
    for r in range(len(m)):
        cells = []
        for name in names:
            v = columns[name][r]
            cells.append(str(int(v)) if name == "marker" else repr(float(v)))
        rows.append(",".join(cells))
    path.write_text("\n".join(rows) + "\n")


def write_layout(sc: Scenario, path: Path, unit: str = "mm", order: tuple[int, ...] = ()) -> None:
    assert sc.layout is not None
    ids = sorted(sc.layout)
    names = [ids[k] for k in order] if order else ids
    lines = ["marker,x,y,z"]
    for k, mark in zip(ids, names, strict=True):
        x, y, z = (float(v) for v in sc.layout[mark] * units.factor(sc.truth.length_unit, unit))
        lines.append(f"{k},{x!r},{y!r},{z!r}")
    path.write_text("\n".join(lines) + "\n")


# ----------------------------------------------------------------------------- the mistakes


def _drop(args: tuple[str, ...], option: str) -> tuple[str, ...]:
    """``args`` without ``option`` (and its value, when it takes one)."""
    out, skip = [], False
    for k, a in enumerate(args):
        if skip:
            skip = False
            continue
        if a == option:
            skip = k + 1 < len(args) and not args[k + 1].startswith("--")
            continue
        out.append(a)
    return tuple(out)


def _set(args: tuple[str, ...], option: str, value: str) -> tuple[str, ...]:
    return (*_drop(args, option), option, value)


def _renamed(args: tuple[str, ...], pairs: dict[str, str]) -> tuple[str, ...]:
    """``args`` with some of the --rename pairs' targets changed (``old -> new target``)."""
    k = args.index("--rename")
    items = []
    for item in args[k + 1].split(","):
        old, new = item.split("=")
        items.append(f"{old}={pairs.get(old, new)}")
    return (*args[: k + 1], ",".join(items), *args[k + 2 :])


def _as_is(lab: LabFile, args: tuple[str, ...]) -> tuple[LabFile, tuple[str, ...]]:
    return lab, args


def mistakes() -> list[Mistake]:
    """Every mistake of the corpus, by class (:data:`CLASSES`)."""
    out = [
        # the right files, and files that are right in another way
        Mistake("right", "the right file", "tracker", _as_is),
        Mistake("right", "the right file", "camera", _as_is),
        Mistake("right", "the right file", "helical", _as_is),
        Mistake("right", "the right file", "markers", _as_is),
        Mistake("right", "the right file", "scara", _as_is),
        Mistake(
            "columns",
            "columns in another order",
            "tracker",
            lambda lab, a: (replace(lab, shuffle=5), a),
        ),
        Mistake(
            "frames",
            "another tracker frame (y up, 4 m away)",
            "tracker",
            lambda lab, a: (replace(lab, frame=_frame(0.0, math.pi / 2, (4.0, 0.5, -1.0))), a),
        ),
        Mistake(
            "frames",
            "the robot's base frame",
            "camera",
            lambda lab, a: (replace(lab, frame=np.eye(4)), a),
        ),
        Mistake(
            "units",
            "positions in metres, said so",
            "tracker",
            lambda lab, a: (replace(lab, length="m"), _set(a, "--length-unit", "m")),
        ),
        Mistake(
            "noise",
            "the right noise stated",
            "tracker",
            lambda lab, a: (lab, (*a, "--noise-pos", "POS*1", "--noise-rot", "ROT*1")),
        ),
        # length units
        Mistake(
            "units",
            "millimetres without --length-unit",
            "tracker",
            lambda lab, a: (lab, _drop(a, "--length-unit")),
            ("--length-unit mm",),
        ),
        Mistake(
            "units",
            "millimetres read as centimetres",
            "camera",
            lambda lab, a: (lab, _set(a, "--length-unit", "cm")),
            ("--length-unit mm",),
        ),
        Mistake(
            "units",
            "metres read as millimetres",
            "tracker",
            lambda lab, a: (replace(lab, length="m"), a),
            ("--length-unit m",),
        ),
        Mistake(
            "units",
            "inches read as millimetres",
            "markers",
            lambda lab, a: (replace(lab, length="in"), a),
            ("--length-unit in",),
        ),
        Mistake(
            "units",
            "millimetres without --length-unit (markers)",
            "markers",
            lambda lab, a: (lab, _drop(a, "--length-unit")),
            ("--length-unit mm",),
        ),
        # angle units
        Mistake(
            "angles",
            "degrees without --degrees",
            "tracker",
            lambda lab, a: (lab, _drop(a, "--degrees")),
            ("--degrees",),
        ),
        Mistake(
            "angles",
            "degrees without --degrees (joints and angles)",
            "camera",
            lambda lab, a: (lab, _drop(a, "--degrees")),
            ("--degrees",),
        ),
        Mistake(
            "angles",
            "joints in radians, angles in degrees, read with --degrees",
            "camera",
            lambda lab, a: (replace(lab, radian_joints=True), a),
            ("convert one of them in the file",),
        ),
        Mistake(
            "angles",
            "one joint column left in radians among degrees",
            "tracker",
            lambda lab, a: (replace(lab, other_unit_joint=2), a),
            ("LAB:2, to degrees",),
        ),
        Mistake(
            "angles",
            "one joint column in degrees among radians",
            "tracker",
            lambda lab, a: (replace(lab, degrees=False, other_unit_joint=4), _drop(a, "--degrees")),
            ("LAB:4, to radians",),
        ),
        Mistake(
            "angles",
            "radians read with --degrees",
            "helical",
            lambda lab, a: (lab, (*a, "--degrees")),
            ("without --degrees",),
        ),
        Mistake(
            "angles",
            "degrees and millimetres, both forgotten",
            "tracker",
            lambda lab, a: (lab, _drop(_drop(a, "--degrees"), "--length-unit")),
            ("--length-unit mm",),
        ),
        # columns
        Mistake(
            "columns",
            "two joints' names exchanged in --rename",
            "tracker",
            lambda lab, a: (lab, _renamed(a, {"A2": "JOINT:2", "A3": "JOINT:1"})),
            ("LAB:1=JOINT:1",),
        ),
        Mistake(
            "columns",
            "x and y exchanged in --rename",
            "tracker",
            lambda lab, a: (lab, _renamed(a, {"X": "y", "Y": "x"})),
            ("X=x",),
        ),
        Mistake(
            "columns",
            "a time column not ignored",
            "camera",
            lambda lab, a: (lab, _drop(a, "--ignore")),
            ("column 't'",),
        ),
        Mistake(
            "columns",
            "a joint's values under another joint's header",
            "markers",
            lambda lab, a: (replace(lab, joint_swap=(3, 4)), a),
            ("LAB:3=JOINT:4",),
        ),
        # orientations
        Mistake(
            "quaternions",
            "a scalar-first quaternion read as scalar-last",
            "tracker",
            lambda lab, a: (lab, _renamed(a, {"QW": "qx", "QX": "qy", "QY": "qz", "QZ": "qw"})),
            ("QW=qw",),
        ),
        Mistake(
            "quaternions",
            "a scalar-last quaternion under scalar-first names",
            "helical",
            lambda lab, a: (replace(lab, orientation=("quat", lab.orientation[1], "wxyz")), a),
            ("--rename",),
        ),
        Mistake(
            "euler",
            "KUKA's A, B, C without --euler ZYX",
            "camera",
            lambda lab, a: (lab, _drop(a, "--euler")),
            ("--euler ZYX",),
        ),
        Mistake(
            "euler",
            "A, B, C read as extrinsic zyx",
            "camera",
            lambda lab, a: (lab, _set(a, "--euler", "zyx")),
            ("--euler ZYX",),
        ),
        # noise figures
        Mistake(
            "noise",
            "noise under-stated 100 times",
            "tracker",
            lambda lab, a: (lab, (*a, "--noise-pos", "POS*0.01", "--noise-rot", "ROT*0.01")),
            ("noise",),
        ),
        Mistake(
            "noise",
            "noise under-stated 10 times",
            "camera",
            lambda lab, a: (lab, (*a, "--noise-pos", "POS*0.1", "--noise-rot", "ROT*0.1")),
            ("noise",),
        ),
        Mistake(
            "noise",
            "noise over-stated 30 times",
            "tracker",
            lambda lab, a: (lab, (*a, "--noise-pos", "POS*30", "--noise-rot", "ROT*30")),
            ("noise",),
        ),
        Mistake(
            "noise",
            "position noise in metres for a file in millimetres",
            "tracker",
            lambda lab, a: (lab, (*a, "--noise-pos", "POS*0.001", "--noise-rot", "ROT*1")),
            ("noise",),
        ),
        Mistake(
            "noise",
            "the README's PUMA with its true noise",
            "helical",
            lambda lab, a: (lab, (*a, "--noise-pos", "POS*1", "--noise-rot", "ROT*1")),
        ),
        # model errors
        Mistake(
            "model",
            "helical joints taken for revolute ones",
            "helical",
            lambda lab, a: (lab, _drop(a, "--helical")),
            ("--helical",),
        ),
        Mistake(
            "model",
            "helical joints taken for revolute ones, the noise stated",
            "helical",
            lambda lab, a: (
                lab,
                (*_drop(a, "--helical"), "--noise-pos", "POS*1", "--noise-rot", "ROT*1"),
            ),
            ("--helical",),
        ),
        Mistake(
            "model",
            "a tip short of the measured one",
            "tracker",
            lambda lab, a: (lab, (*a, "--tip", "wrist_3_link")),
        ),
        Mistake(
            "model",
            "markers numbered otherwise in the layout",
            "markers",
            lambda lab, a: (lab, (*a, "--marker-layout", "LAYOUT:1,2,0")),
            ("layout",),
        ),
        Mistake(
            "model",
            "a marker layout in metres for a file in millimetres",
            "markers",
            lambda lab, a: (lab, (*a, "--marker-layout", "LAYOUT:m")),
            ("layout",),
        ),
        # device frames
        Mistake(
            "frames",
            "a left-handed tracker frame",
            "tracker",
            lambda lab, a: (replace(lab, point_sign=1), a),
            ("other way round", "left-handed"),
        ),
        Mistake(
            "frames",
            "a joint counted the other way round",
            "camera",
            lambda lab, a: (replace(lab, joint_sign=2), a),
            ("other way round",),
        ),
        Mistake(
            "units",
            "millimetres without --length-unit (a sliding joint)",
            "scara",
            lambda lab, a: (lab, _drop(a, "--length-unit")),
            ("--length-unit mm",),
        ),
        Mistake(
            "angles",
            "degrees without --degrees (a sliding joint, roll, pitch, yaw)",
            "scara",
            lambda lab, a: (lab, _drop(a, "--degrees")),
            ("--degrees",),
        ),
        Mistake(
            "euler",
            "roll, pitch, yaw read as intrinsic XYZ",
            "scara",
            lambda lab, a: (lab, _set(a, "--euler", "XYZ")),
            ("--euler xyz", "--euler ZYX"),
        ),
    ]
    return out


CLASSES = ("right", "units", "angles", "columns", "quaternions", "euler", "noise", "model",
           "frames")  # fmt: skip


# ----------------------------------------------------------------------------- running


def command(argv: list[str]) -> tuple[int, str, str, float]:
    """``urdf2dh ARGV`` in-process: exit code, stdout, stderr, seconds."""
    out, err = io.StringIO(), io.StringIO()
    started = time.perf_counter()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = cli(argv)
        except SystemExit as e:
            code = e.code if isinstance(e.code, int) else 2
    return code, out.getvalue(), err.getvalue(), time.perf_counter() - started


def accuracy(sc: Scenario, lab: LabFile, model: PoeModel) -> float:
    """RMS tool position error of ``model`` against the robot as built, measured in the lab
    file's frame (the nominal's unit), at seeded configurations."""
    q = sc.truth.sample(SAMPLES, 31)
    truth = sc.truth.fk_batch(q)
    if sc.measured.markers is not None:  # the tool frame the layout defines: compare markers
        assert sc.layout is not None
        local = np.array([sc.layout[k] for k in sorted(sc.layout)])
        theirs = np.einsum("nij,kj->nki", truth[:, :3, :3], local) + truth[:, None, :3, 3]
        mine_poses = model.fk_batch(q)
        mine = np.einsum("nij,kj->nki", mine_poses[:, :3, :3], local) + mine_poses[:, None, :3, 3]
        theirs = theirs.reshape(-1, 3)
        mine = mine.reshape(-1, 3)
    else:
        theirs, mine = truth[:, :3, 3], model.fk_batch(q)[:, :3, 3]
    g = lab.frame
    theirs = theirs @ g[:3, :3].T + g[:3, 3]
    return float(np.sqrt(np.mean(np.sum((mine - theirs) ** 2, axis=1))))


def _facts(sc: Scenario, lab: LabFile, text: str) -> str:
    """``text`` with the scenario's names where it holds ``JOINT:i`` (the chain's joint ``i``)
    or ``LAB:i`` (the file's name of it)."""
    joints = [j.name for j in urdf2dh.load(sc.nominal).joints]
    text = re.sub(r"JOINT:(\d+)", lambda g: joints[int(g.group(1))], text)
    return re.sub(r"LAB:(\d+)", lambda g: lab.joints[int(g.group(1))], text)


def _args(sc: Scenario, lab: LabFile, args: tuple[str, ...], work: Path) -> list[str]:
    """The arguments with a marker layout written where one is asked for (in the file's
    length unit, unless the mistake says another)."""
    out = list(args)
    for k, a in enumerate(out):  # the scenario's facts where the mistake names them
        if a.startswith(("POS*", "ROT*")):
            value = float(a[4:]) * sc.noise[0 if a[0] == "P" else 1]
            if a[0] == "P":
                value *= units.factor(sc.truth.length_unit, lab.length)
            out[k] = f"{value:.6g}"
        else:
            out[k] = _facts(sc, lab, a)
    if sc.layout is not None and "--marker-layout" not in out:
        out += ["--marker-layout", "LAYOUT:"]
    for k, a in enumerate(out):
        if a.startswith("LAYOUT:"):
            spec = a.split(":", 1)[1]
            path = work / f"layout-{abs(hash(spec))}.csv"
            if spec == "m":
                write_layout(sc, path, "m")
            elif spec:
                write_layout(sc, path, lab.length, tuple(int(x) for x in spec.split(",")))
            else:
                write_layout(sc, path, lab.length)
            out[k] = str(path)
    return out


def run_one(mistake: Mistake, work: Path, right: dict[str, float]) -> Outcome:
    """Run one mistake and judge it (module docstring)."""
    sc = scenarios()[mistake.scenario]
    lab, args = mistake.change(sc.lab, sc.args)
    path = work / f"{sc.name}-{abs(hash(mistake.name))}.csv"
    write(sc, lab, path)
    model_path = work / f"{sc.name}-{abs(hash(mistake.name))}.yaml"
    argv = [
        "calibrate", sc.nominal, str(path), *_args(sc, lab, args, work),
        "--convention", "poe", "--format", "yaml", "-o", str(model_path),
    ]  # fmt: skip
    code, _, err, seconds = command(argv)
    lines = [line for line in err.splitlines() if line.strip()]
    message = lines[-1] if lines else ""
    if code not in (0, 1, 2, 3) or "internal error" in err or "Traceback" in err:
        return Outcome(mistake, code, message, "internal error", seconds=seconds)
    if code != 0:
        if model_path.exists():
            return Outcome(mistake, code, message, "internal error", seconds=seconds)
        if not mistake.named:
            return Outcome(mistake, code, message, "false refusal", seconds=seconds)
        words = [_facts(sc, lab, word) for word in mistake.named]
        named = len(lines) == 1 and any(word in message for word in words)
        verdict = "refused, cause named" if named else "refused, cause not named"
        return Outcome(mistake, code, message, verdict, seconds=seconds)
    acc = accuracy(sc, lab, urdf2dh.load(str(model_path)))
    if mistake.kind == "right" and mistake.name == "the right file":
        right[sc.name] = acc
    base = right.get(sc.name)
    same = base is not None and acc <= SAME * base + 1e-9 * sc.truth.size()
    return Outcome(
        mistake, code, "", "same model" if same else "silent wrong model", acc, base, seconds
    )


def run_corpus(only: str | None = None) -> list[Outcome]:
    """Every case (the right files first: they set each scenario's accuracy)."""
    cases = sorted(mistakes(), key=lambda m: m.kind != "right" or m.name != "the right file")
    if only is not None:
        cases = [m for m in cases if m.kind == only or m.name == "the right file"]
    right: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as tmp:
        return [run_one(m, Path(tmp), right) for m in cases]


FAILURES = (
    "internal error",
    "silent wrong model",
    "refused, cause not named",
    "false refusal",
)


def report(outcomes: list[Outcome]) -> str:
    """The outcomes by class, then every failure, then the counts."""
    lines = []
    by_class = Counter((o.mistake.kind, o.verdict) for o in outcomes)
    for kind in CLASSES:
        parts = [f"{v}: {n}" for (k, v), n in sorted(by_class.items()) if k == kind]
        if parts:
            lines.append(f"{kind:12} {'; '.join(parts)}")
    failed = [o for o in outcomes if o.verdict in FAILURES]
    for o in failed:
        extra = f" (accuracy {o.accuracy:.3g} against {o.right:.3g})" if o.accuracy else ""
        lines.append(f"FAILED {o.mistake.scenario}: {o.mistake.name}: {o.verdict}{extra}: "
                     f"{o.message}")  # fmt: skip
    counts = Counter(o.verdict for o in outcomes)
    lines.append(
        f"{len(outcomes)} cases: {counts['same model']} same model, "
        f"{counts['refused, cause named']} refused naming the cause; internal errors "
        f"{counts['internal error']}, silent wrong models {counts['silent wrong model']}, "
        f"refusals without the cause {counts['refused, cause not named']}, false refusals "
        f"{counts['false refusal']}; {sum(o.seconds for o in outcomes):.1f} s"
    )
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=CLASSES, help="the cases of one class")
    parser.add_argument("--verbose", action="store_true", help="every case's message")
    args = parser.parse_args()
    outcomes = run_corpus(args.only)
    if args.verbose:
        for o in outcomes:
            print(f"{o.verdict:26} {o.mistake.scenario:8} {o.mistake.name}: {o.message[:300]}")
    print(report(outcomes))
    return 1 if any(o.verdict in FAILURES for o in outcomes) else 0


if __name__ == "__main__":
    sys.exit(main())
