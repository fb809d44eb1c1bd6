"""The export targets' consumers, for the tests: the real ones where they install here, and
otherwise evaluations of the generated text exactly as the consumer documents it.

Nothing here imports urdf2dh's own kinematics: every consumer is written from its documentation
with plain numpy, so a generated file is judged by the rules its reader applies.

* roboticstoolbox-python: real (a test dependency).
* PyKDL: real where Debian's ``python3-pykdl`` is installed (no wheel on PyPI), else
  :class:`FakeKdl`, which implements KDL's documented ``Frame.DH`` / ``Frame.DH_Craig1989``,
  ``Segment`` and ``ChainFkSolverPos_recursive`` semantics, so the generated script runs either way.
* MATLAB Robotics System Toolbox, Peter Corke's MATLAB toolbox, LinuxCNC genserkins: read back
  as MATLAB and halcmd read them (matlab_reader.py, hal_reader.py: literals, comments, line
  breaks), statement by statement (anything unexpected fails), and evaluated with the
  documented formulas.
* Universal_Robots_ROS2_Description: the yaml's joint origins are put into a URDF exactly as
  ``ur_macro.xacro`` places them, and Pinocchio evaluates that URDF.
"""

from __future__ import annotations

import glob
import importlib.util
import json
import math
import re
import shutil
import subprocess
import sys
import tempfile
import types
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from hal_reader import read_hal
from matlab_reader import Call, Chars, Ref, Str, read_matlab

# --------------------------------------------------------------------------- the report

REPORT_ENV = "URDF2DH_CONSUMER_REPORT"


def report(target: str, consumer: str, errors: tuple[float, float], size: float) -> None:
    """Record a target's worst FK error against Pinocchio in its consumer (position relative
    to the robot's size, rotation in radians) in the file ``$URDF2DH_CONSUMER_REPORT`` names,
    one JSON line each, for scripts/check-consumers' summary; nothing when it is unset."""
    import os

    path = os.environ.get(REPORT_ENV)
    if not path:
        return
    record = {"target": target, "consumer": consumer, "position": errors[0] / size}
    record["rotation"] = errors[1]
    with open(path, "a") as f:
        f.write(json.dumps(record) + "\n")


# --------------------------------------------------------------------------- elementary transforms


def rz(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def ry(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, 0, s, 0], [0, 1.0, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1.0]])


def rx(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[1.0, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def tr(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = (x, y, z)
    return out


def standard_dh(a: float, alpha: float, d: float, theta: float) -> np.ndarray:
    """``Rz(theta) Tz(d) Tx(a) Rx(alpha)``."""
    return rz(theta) @ tr(z=d) @ tr(x=a) @ rx(alpha)


def craig_dh(a: float, alpha: float, d: float, theta: float) -> np.ndarray:
    """``Rx(alpha) Tx(a) Rz(theta) Tz(d)`` (Craig 1989, modified D-H)."""
    return rx(alpha) @ tr(x=a) @ rz(theta) @ tr(z=d)


def motion(kind: str, q: float) -> np.ndarray:
    return rz(q) if kind == "revolute" else tr(z=q)


def _string(value: Any, what: str) -> str:
    """The text of a MATLAB string or char vector (anything else is not what we write)."""
    if not isinstance(value, Str | Chars):
        raise AssertionError(f"{what}: expected text, got {value!r}")
    return value.value


def _matrix(value: Any) -> np.ndarray:
    m = np.asarray(value, dtype=float)
    if m.shape != (4, 4):
        raise AssertionError(f"not a 4x4 matrix literal: {value!r}")
    return m


def _call(value: Any, name: str, arity: int | None = None) -> tuple[Any, ...]:
    if not isinstance(value, Call) or value.name != name:
        raise AssertionError(f"expected a call of {name}, got {value!r}")
    if arity is not None and len(value.args) != arity:
        raise AssertionError(f"{name} takes {arity} arguments here, got {value.args!r}")
    return value.args


# --------------------------------------------------------------------------- MATLAB RST


class RigidBodyTree:
    """MATLAB Robotics System Toolbox ``rigidBodyTree``, from a script like ours.

    The script is read as MATLAB reads it (:mod:`matlab_reader`: literals, comments,
    statements); every statement must be one of those our exports write. A body's pose in its
    parent is ``JointToParentTransform . J(q) . ChildToJointTransform``;
    ``setFixedTransform(j, [a alpha d theta], "dh")`` sets ``ChildToJoint`` to the standard D-H
    matrix and ``JointToParent`` to I, ``"mdh"`` sets ``JointToParent`` to Craig's matrix and
    ``ChildToJoint`` to I, ``setFixedTransform(j, T)`` sets ``JointToParent`` to T and
    ``ChildToJoint`` to I; theta is ignored for revolute joints, d for prismatic ones.
    """

    def __init__(self, script: str) -> None:
        parsed = read_matlab(script)
        self.statements = parsed.statements
        self.comments = parsed.comments
        self.base = "base"
        self.bodies: dict[str, dict[str, Any]] = {}
        self.order: list[str] = []  # movable joints in the order bodies were added
        body: dict[str, Any] | None = None
        joint: dict[str, Any] | None = None
        parent = None
        for s in parsed.statements:
            target, value = s.target, s.value
            if target == "robot":
                args = _call(value, "rigidBodyTree", 2)
                assert [_string(a, "rigidBodyTree") for a in args] == ["DataFormat", "row"]
            elif target == "robot.BaseName":
                self.base = _string(value, "BaseName")
            elif target == "parent" and value == Ref("robot.BaseName"):
                parent = self.base
            elif target == "body" and isinstance(value, Call):
                body = {"name": _string(_call(value, "rigidBody", 1)[0], "rigidBody")}
            elif target == "joint":
                name, kind = (
                    _string(a, "rigidBodyJoint") for a in _call(value, "rigidBodyJoint", 2)
                )
                assert kind in ("revolute", "prismatic", "fixed"), kind
                joint = {"name": name, "type": kind, "j2p": np.eye(4), "c2j": np.eye(4)}
            elif target in ("joint.PositionLimits", "joint.HomePosition"):
                assert joint is not None
                joint[target.split(".")[1]] = list(np.atleast_1d(np.asarray(value, float)))
            elif target is None and isinstance(value, Call) and value.name == "setFixedTransform":
                assert joint is not None and value.args[0] == Ref("joint")
                if len(value.args) == 3:
                    a, alpha, d, theta = (float(x) for x in np.asarray(value.args[1], float))
                    convention = _string(value.args[2], "setFixedTransform")
                    if joint["type"] == "revolute":
                        theta = 0.0
                    elif joint["type"] == "prismatic":
                        d = 0.0
                    if convention == "dh":
                        joint["j2p"], joint["c2j"] = np.eye(4), standard_dh(a, alpha, d, theta)
                    elif convention == "mdh":
                        joint["j2p"], joint["c2j"] = craig_dh(a, alpha, d, theta), np.eye(4)
                    else:
                        raise AssertionError(f"setFixedTransform convention {convention!r}")
                else:
                    _call(value, "setFixedTransform", 2)
                    joint["j2p"], joint["c2j"] = _matrix(value.args[1]), np.eye(4)
            elif target == "body.Joint" and value == Ref("joint"):
                assert body is not None
                body["joint"] = joint
            elif target is None and value == Call(
                "addBody", (Ref("robot"), Ref("body"), Ref("parent"))
            ):
                assert body is not None and parent is not None and "joint" in body
                # addBody refuses a body named as one in the tree (the base included), and a
                # body whose joint is named as a joint in the tree
                if body["name"] in self.bodies or body["name"] == self.base:
                    raise AssertionError(f"duplicate body name {body['name']}")
                if body["joint"]["name"] in {b["joint"]["name"] for b in self.bodies.values()}:
                    raise AssertionError(f"duplicate joint name {body['joint']['name']}")
                body["parent"] = parent
                self.bodies[body["name"]] = body
                if body["joint"]["type"] != "fixed":
                    self.order.append(body["name"])
            elif target == "parent" and value == Ref("body.Name"):
                assert body is not None
                parent = body["name"]
            else:
                raise AssertionError(f"MATLAB statement not understood (line {s.line}): {s!r}")

    def get_transform(self, q: np.ndarray, body: str) -> np.ndarray:
        """``getTransform(robot, q, body)``: the body's pose in the base."""
        index = {name: i for i, name in enumerate(self.order)}
        out = np.eye(4)
        while body != self.base:
            b = self.bodies[body]
            j = b["joint"]
            move = np.eye(4) if j["type"] == "fixed" else motion(j["type"], q[index[body]])
            out = j["j2p"] @ move @ j["c2j"] @ out
            body = b["parent"]
        return out


# --------------------------------------------------------------------------- Corke RTB (MATLAB)


class SerialLink:
    """Peter Corke's MATLAB ``SerialLink``, from ``L(i) = Link(...)`` statements and one
    ``robot = SerialLink(L, ...)`` (read as MATLAB reads them: :mod:`matlab_reader`):
    ``fkine = base . prod A_i . tool`` with standard ``Rz(theta) Tz(d) Tx(a) Rx(alpha)`` or
    modified ``Rx(alpha) Tx(a) Rz(theta) Tz(d)`` links, the joint variable plus ``offset``
    being theta (revolute) or d (prismatic)."""

    def __init__(self, script: str) -> None:
        parsed = read_matlab(script)
        self.statements = parsed.statements
        self.comments = parsed.comments
        self.links: list[dict[str, Any]] = []
        self.base = self.tool = np.eye(4)
        self.name = ""
        for s in parsed.statements:
            if s.target == f"L({len(self.links) + 1})":
                self.links.append(self._link(_call(s.value, "Link")))
            elif s.target == "robot":
                args = _call(s.value, "SerialLink", 7)
                assert args[0] == Ref("L")
                assert [_string(args[k], "SerialLink") for k in (1, 3, 5)] == [
                    "name",
                    "base",
                    "tool",
                ]
                self.name = _string(args[2], "SerialLink name")
                self.base, self.tool = _matrix(args[4]), _matrix(args[6])
            else:
                raise AssertionError(f"MATLAB statement not understood (line {s.line}): {s!r}")

    @staticmethod
    def _link(args: tuple[Any, ...]) -> dict[str, Any]:
        link: dict[str, Any] = {"theta": 0.0, "d": 0.0, "a": 0.0, "alpha": 0.0, "offset": 0.0}
        i = 0
        while i < len(args):
            key = _string(args[i], "Link option")
            if key in ("revolute", "prismatic"):
                link["kind"] = key
            elif key in ("standard", "modified"):
                link["flavour"] = key
            elif key in ("theta", "d", "a", "alpha", "offset"):
                link[key] = float(args[i + 1])
                i += 1
            elif key == "qlim":
                link["qlim"] = [float(x) for x in np.asarray(args[i + 1], float)]
                i += 1
            else:
                raise AssertionError(f"Link option not understood: {key}")
            i += 1
        return link

    def fkine(self, q: np.ndarray) -> np.ndarray:
        out = self.base.copy()
        for link, value in zip(self.links, q, strict=True):
            theta, d = link["theta"], link["d"]
            if link["kind"] == "revolute":
                theta = value + link["offset"]
            else:
                d = value + link["offset"]
            make = standard_dh if link["flavour"] == "standard" else craig_dh
            out = out @ make(link["a"], link["alpha"], d, theta)
        return out @ self.tool


# --------------------------------------------------------------------------- LinuxCNC genserkins


@dataclass(frozen=True)
class GenserHal:
    """What a HAL file of ours sets: genserkins' six links ``(A-i, ALPHA-i, D-i)`` and, per
    joint with joint-zero components, the ``(gain, offset)`` of ``urdf2dh-fb-i`` (drive
    feedback -> genserkins' angle) and ``urdf2dh-cmd-i`` (motion's command -> drive)."""

    links: list[tuple[float, float, float]]
    feedback: dict[int, tuple[float, float]]
    command: dict[int, tuple[float, float]]
    world: np.ndarray  # the base link's pose of LinuxCNC's world frame, as the file states it
    tool: np.ndarray  # the tip in the frame whose pose LinuxCNC reports, as the file states it

    def tip_poses(self, reported: np.ndarray, metres: float = 1.0) -> np.ndarray:
        """The tip's poses in the base link from the poses LinuxCNC reports (lengths times
        ``metres``)."""
        world, tool = self.world.copy(), self.tool.copy()
        world[:3, 3] *= metres
        out = np.array(reported, dtype=float)
        out[..., :3, 3] *= metres
        return world @ out @ tool

    def angles(self, q_deg: np.ndarray) -> np.ndarray:
        """genserkins' joints for drive positions ``q`` (degrees): HAL's ``scale`` is
        ``out = in * gain + offset``; joints without components pass ``q`` as it is."""
        out = np.array(q_deg, dtype=float)
        for i, (gain, offset) in self.feedback.items():
            out[..., i] = q_deg[..., i] * gain + offset
        return out

    def commands(self, angles_deg: np.ndarray) -> np.ndarray:
        out = np.array(angles_deg, dtype=float)
        for i, (gain, offset) in self.command.items():
            out[..., i] = angles_deg[..., i] * gain + offset
        return out


def genserkins_hal(hal: str) -> GenserHal:
    """The file's commands, read as halcmd reads them (:mod:`hal_reader`): ``setp`` of the 18
    genserkins pins, and for the joint zeros one ``loadrt scale names=...``, one ``addf NAME
    servo-thread`` per instance and ``setp NAME.gain|offset``. Anything else fails."""
    values: dict[str, float] = {}
    loaded: list[str] = []
    added: list[str] = []
    for tokens in read_hal(hal).commands:
        if tokens[:2] == ["loadrt", "scale"] and len(tokens) == 3 and not loaded:
            key, _, names = tokens[2].partition("=")
            assert key == "names", tokens
            loaded = names.split(",")
            continue
        if tokens[0] == "addf" and len(tokens) == 3 and tokens[2] == "servo-thread":
            added.append(tokens[1])
            continue
        m = (
            re.fullmatch(r"genserkins\.(A|ALPHA|D)-([0-5])|urdf2dh-(fb|cmd)-([0-5])\.(gain|offset)",
                         tokens[1])
            if len(tokens) == 3 and tokens[0] == "setp"
            else None
        )  # fmt: skip
        if not m:
            raise AssertionError(f"HAL command not understood: {tokens!r}")
        if m[1] is None and f"urdf2dh-{m[3]}-{m[4]}" not in loaded:
            raise AssertionError(f"HAL pin {tokens[1]} of a component not loaded")
        if tokens[1] in values:
            raise AssertionError(f"HAL pin {tokens[1]} set twice")
        values[tokens[1]] = float(tokens[2])
    assert sorted(added) == sorted(loaded), (added, loaded)
    links = [tuple(values[f"genserkins.{k}-{i}"] for k in ("A", "ALPHA", "D")) for i in range(6)]
    maps: dict[str, dict[int, tuple[float, float]]] = {"fb": {}, "cmd": {}}
    for name in loaded:
        way, i = re.fullmatch(r"urdf2dh-(fb|cmd)-([0-5])", name).groups()  # type: ignore[union-attr]
        maps[way][int(i)] = (values[f"{name}.gain"], values[f"{name}.offset"])
    assert maps["fb"].keys() == maps["cmd"].keys(), loaded
    notes = "".join(c[1:] if c.startswith(" ") else c for c in read_hal(hal).comments)
    world, tool = np.eye(4), np.eye(4)
    number = r"(-?[0-9.]+(?:e[-+][0-9]+)?)"
    m = re.search(rf"= Rz\({number} deg\) Tz\({number} (?:mm|inch)\) \. pose LinuxCNC", notes)
    if m:
        world = rz(math.radians(float(m[1]))) @ tr(z=float(m[2]))
    m = re.search(rf"pose LinuxCNC reports \. Rx\({number} deg\) Rz\({number} deg\)", notes)
    if m:
        tool = rx(math.radians(float(m[1]))) @ rz(math.radians(float(m[2])))
    return GenserHal(links, maps["fb"], maps["cmd"], world, tool)  # type: ignore[arg-type]


def genserkins_links(hal: str) -> list[tuple[float, float, float]]:
    """``(A-i, ALPHA-i, D-i)`` for i = 0..5 (:func:`genserkins_hal`)."""
    return genserkins_hal(hal).links


def genserkins_fk(links: list[tuple[float, float, float]], joints_deg: np.ndarray) -> np.ndarray:
    """genserkins' forward kinematics: joints in degrees, link i = go_dh_pose_convert(a, alpha,
    d, theta = joint i) = Rx(alpha) Tx(a) Rz(theta) Tz(d), multiplied from link 0."""
    out = np.eye(4)
    for (a, alpha, d), joint in zip(links, joints_deg, strict=True):
        out = out @ craig_dh(a, alpha, d, math.radians(joint))
    return out


SIM = Path(__file__).with_name("linuxcnc_sim.py")
DEBIAN_PYTHON = "/usr/bin/python3"


def real_linuxcnc() -> bool:
    """Whether Debian's LinuxCNC (``linuxcnc-uspace``: genserkins, halcmd, its ``hal`` module
    for Debian's Python) is installed, so :mod:`linuxcnc_sim` can run."""
    return (
        Path("/usr/lib/linuxcnc/modules/genserkins.so").exists()
        and shutil.which("halcmd") is not None
        and Path("/usr/lib/python3/dist-packages/hal.py").exists()
        and Path(DEBIAN_PYTHON).exists()
    )


def run_linuxcnc(files: list[tuple[str, np.ndarray]]) -> tuple[str, list[dict[str, np.ndarray]]]:
    """Each ``(HAL text, drive positions in degrees (N, 6))`` run in LinuxCNC by
    :mod:`linuxcnc_sim`: its version, and per file genserkins' joints, the command path's drive
    positions and the poses (4x4, lengths in the file's unit) LinuxCNC reports, with ``a b c``
    read as genserkins writes them (``go_quat_rpy_convert``: roll about x, pitch about y, yaw
    about z, ``R = Rz(c) Ry(b) Rx(a)``, degrees)."""
    request = {"files": [{"hal": text, "q": np.asarray(q).tolist()} for text, q in files]}
    with tempfile.TemporaryDirectory() as work:
        ask, answer = Path(work, "request.json"), Path(work, "answer.json")
        ask.write_text(json.dumps(request))
        proc = subprocess.run(
            [DEBIAN_PYTHON, str(SIM), str(ask), str(answer)],
            capture_output=True, text=True, timeout=600, env=_debian_env(),
        )  # fmt: skip
        if proc.returncode != 0:
            raise AssertionError(f"linuxcnc_sim failed:\n{proc.stdout}\n{proc.stderr}")
        reply = json.loads(answer.read_text())
    out = []
    for item in reply["files"]:
        poses = np.array([_xyzabc(*p) for p in item["poses"]])
        out.append(
            {
                "joints": np.array(item["joints"]),
                "commands": np.array(item["commands"]),
                "poses": poses,
            }
        )
    return reply["linuxcnc"], out


def _debian_env() -> dict[str, str]:
    """The environment without this virtual environment's Python settings."""
    import os

    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    env.pop("VIRTUAL_ENV", None)
    return env


def _xyzabc(x: float, y: float, z: float, a: float, b: float, c: float) -> np.ndarray:
    out = rz(math.radians(c)) @ ry(math.radians(b)) @ rx(math.radians(a))
    out[:3, 3] = (x, y, z)
    return out


# --------------------------------------------------------------------------- Octave

OCTAVE_DIR = Path(__file__).with_name("octave")  # corke/, rst/: our classes, from the docs


def octave_version() -> str | None:
    """GNU Octave's version where ``octave`` is on PATH (Debian's package), else ``None``."""
    if shutil.which("octave") is None:
        return None
    proc = subprocess.run(
        ["octave", "--no-gui", "--no-window-system", "--quiet", "--eval", "disp(version())"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    return proc.stdout.strip() if proc.returncode == 0 else None


def run_octave(jobs: list[tuple[str, str, str, np.ndarray]]) -> list[np.ndarray]:
    """Run generated MATLAB scripts in GNU Octave, one session for all: each job is ``(kind,
    script, tip, q (N, n))`` with kind ``corke`` (``robot.fkine(q)``, Corke's ``SerialLink``)
    or ``rst`` (``getTransform(robot, q, tip)``, a ``rigidBodyTree``); the classes are ours,
    written from the published definitions (tests/octave/). Returns each job's poses
    ``(N, 4, 4)``, printed by Octave with 17 significant digits."""
    with tempfile.TemporaryDirectory() as work:
        driver = [f"addpath('{OCTAVE_DIR / 'corke'}'); addpath('{OCTAVE_DIR / 'rst'}');"]
        for k, (kind, script, tip, q) in enumerate(jobs):
            Path(work, f"job{k}.m").write_text(script)
            np.savetxt(Path(work, f"q{k}.txt"), np.atleast_2d(q), fmt="%.17g")
            fk = (
                "robot.fkine(Q(i, :))"
                if kind == "corke"
                else f"getTransform(robot, Q(i, :), '{tip}')"
            )
            driver.append(
                f"clear robot L; source('{work}/job{k}.m'); Q = dlmread('{work}/q{k}.txt');"
                f"f = fopen('{work}/pose{k}.txt', 'w');"
                f"for i = 1:rows(Q), T = {fk}; fprintf(f, '%.17g ', T(1:3, :)'); "
                "fprintf(f, '\\n'); end; fclose(f);"
            )
        Path(work, "driver.m").write_text("\n".join(driver) + "\nexit(0);\n")
        proc = subprocess.run(
            ["octave", "--no-gui", "--no-window-system", "--quiet", f"{work}/driver.m"],
            capture_output=True, text=True, timeout=900, cwd=work,
        )  # fmt: skip
        if proc.returncode != 0:
            raise AssertionError(f"octave failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
        out = []
        for k in range(len(jobs)):
            rows = np.loadtxt(Path(work, f"pose{k}.txt"), ndmin=2).reshape(-1, 3, 4)
            poses = np.zeros((rows.shape[0], 4, 4))
            poses[:, :3], poses[:, 3, 3] = rows, 1.0
            out.append(poses)
    return out


# --------------------------------------------------------------------------- KDL


def real_pykdl() -> types.ModuleType | None:
    """PyKDL if it imports: from the environment, or Debian's python3-pykdl build for this
    Python (it installs outside the virtual environment)."""
    try:
        import PyKDL

        return PyKDL
    except ImportError:
        pass
    tag = f"cpython-{sys.version_info.major}{sys.version_info.minor}"
    for path in glob.glob(f"/usr/lib/python3/dist-packages/PyKDL.{tag}-*.so"):
        spec = importlib.util.spec_from_file_location("PyKDL", path)
        if spec is None or spec.loader is None:
            continue
        module = importlib.util.module_from_spec(spec)
        try:
            spec.loader.exec_module(module)
        except ImportError:
            return None
        return module
    return None


class _Frame:
    def __init__(self, m: np.ndarray | None = None) -> None:
        self.m = np.eye(4) if m is None else m

    @classmethod
    def DH(cls, a: float, alpha: float, d: float, theta: float) -> _Frame:
        return cls(standard_dh(a, alpha, d, theta))

    @classmethod
    def DH_Craig1989(cls, a: float, alpha: float, d: float, theta: float) -> _Frame:
        return cls(craig_dh(a, alpha, d, theta))

    def __mul__(self, other: _Frame) -> _Frame:
        return _Frame(self.m @ other.m)


class _Joint:
    Fixed, RotZ, TransZ = "Fixed", "RotZ", "TransZ"

    def __init__(self, name: str, kind: str) -> None:
        self.name, self.kind = name, kind

    def pose(self, q: float) -> np.ndarray:
        return {"Fixed": np.eye(4), "RotZ": rz(q), "TransZ": tr(z=q)}[self.kind]


class _Segment:
    def __init__(self, name: str, joint: _Joint, f_tip: _Frame) -> None:
        self.name, self.joint, self.f_tip = name, joint, f_tip


class _Chain:
    def __init__(self) -> None:
        self.segments: list[_Segment] = []

    def addSegment(self, segment: _Segment) -> None:
        self.segments.append(segment)

    def getNrOfJoints(self) -> int:
        return sum(s.joint.kind != "Fixed" for s in self.segments)


class _JntArray(list):  # type: ignore[type-arg]
    def __init__(self, n: int) -> None:
        super().__init__([0.0] * n)


class _Solver:
    """KDL ``ChainFkSolverPos_recursive``: the product of ``joint.pose(q) . f_tip``."""

    def __init__(self, chain: _Chain) -> None:
        self.chain = chain

    def JntToCart(self, q: _JntArray, out: _Frame) -> int:
        pose, k = np.eye(4), 0
        for s in self.chain.segments:
            value = 0.0
            if s.joint.kind != "Fixed":
                value, k = q[k], k + 1
            pose = pose @ s.joint.pose(value) @ s.f_tip.m
        out.m = pose
        return 0


FakeKdl = types.SimpleNamespace(
    Frame=_Frame,
    Joint=_Joint,
    Segment=_Segment,
    Chain=_Chain,
    JntArray=_JntArray,
    ChainFkSolverPos_recursive=_Solver,
)


def kdl_fk(kdl: Any, script: str, q: np.ndarray) -> np.ndarray:
    """Run the generated script's ``build_chain()`` with module ``kdl`` as ``PyKDL`` and
    evaluate its forward kinematics at configurations ``q`` (N, n)."""
    saved = sys.modules.get("PyKDL")
    sys.modules["PyKDL"] = kdl
    try:
        namespace: dict[str, Any] = {"__name__": "generated_kdl"}
        exec(compile(script, "generated_kdl.py", "exec"), namespace)
        chain = namespace["build_chain"]()
    finally:
        if saved is None:
            sys.modules.pop("PyKDL", None)
        else:
            sys.modules["PyKDL"] = saved
    solver = kdl.ChainFkSolverPos_recursive(chain)
    out = np.empty((len(q), 4, 4))
    for k, row in enumerate(q):
        joints = kdl.JntArray(chain.getNrOfJoints())
        for i, value in enumerate(row):
            joints[i] = float(value)
        frame = kdl.Frame()
        solver.JntToCart(joints, frame)
        out[k] = _to_matrix(frame)
    return out


def _to_matrix(frame: Any) -> np.ndarray:
    if isinstance(frame, _Frame):
        return frame.m
    out = np.eye(4)
    for i in range(3):
        for j in range(3):
            out[i, j] = frame.M[i, j]
        out[i, 3] = frame.p[i]
    return out


# --------------------------------------------------------------------------- UR description

UR_JOINTS = (
    ("shoulder", "shoulder_pan_joint", "base_link_inertia", "shoulder_link"),
    ("upper_arm", "shoulder_lift_joint", "shoulder_link", "upper_arm_link"),
    ("forearm", "elbow_joint", "upper_arm_link", "forearm_link"),
    ("wrist_1", "wrist_1_joint", "forearm_link", "wrist_1_link"),
    ("wrist_2", "wrist_2_joint", "wrist_1_link", "wrist_2_link"),
    ("wrist_3", "wrist_3_joint", "wrist_2_link", "wrist_3_link"),
)


def ur_description_urdf(kinematics: dict[str, Any]) -> str:
    """The kinematic skeleton ``ur_macro.xacro`` builds from a kinematics yaml: ``base_link`` ->
    ``base_link_inertia`` turned by pi about z, each joint's origin the yaml's x y z and
    roll pitch yaw verbatim with its axis along z, and ``wrist_3_link`` -> ``flange`` (rpy 0,
    -pi/2, -pi/2) -> ``tool0`` (rpy pi/2, 0, pi/2)."""

    def f(x: Any) -> str:
        return repr(float(x))

    pi = math.pi
    parts = [
        '<robot name="ur">',
        '<link name="base_link"/>',
        '<link name="base_link_inertia"/>',
        '<joint name="base_link-base_link_inertia" type="fixed"><parent link="base_link"/>'
        f'<child link="base_link_inertia"/><origin xyz="0 0 0" rpy="0 0 {f(pi)}"/></joint>',
    ]
    for key, joint, parent, child in UR_JOINTS:
        k = kinematics[key]
        parts.append(f'<link name="{child}"/>')
        parts.append(
            f'<joint name="{joint}" type="revolute"><parent link="{parent}"/>'
            f'<child link="{child}"/><origin xyz="{f(k["x"])} {f(k["y"])} {f(k["z"])}" '
            f'rpy="{f(k["roll"])} {f(k["pitch"])} {f(k["yaw"])}"/><axis xyz="0 0 1"/>'
            '<limit lower="-6.28" upper="6.28" effort="1" velocity="1"/></joint>'
        )
    parts += [
        '<link name="flange"/>',
        '<link name="tool0"/>',
        '<joint name="wrist_3-flange" type="fixed"><parent link="wrist_3_link"/>'
        f'<child link="flange"/><origin xyz="0 0 0" rpy="0 {f(-pi / 2)} {f(-pi / 2)}"/></joint>',
        '<joint name="flange-tool0" type="fixed"><parent link="flange"/>'
        f'<child link="tool0"/><origin xyz="0 0 0" rpy="{f(pi / 2)} 0 {f(pi / 2)}"/></joint>',
        "</robot>",
    ]
    return "\n".join(parts)
