"""The minimal, singularity-free local parametrisation of a POE model that calibration identifies.

The model (Brockett 1984; Wu 2019 eq. 5, joint offsets absorbed) in the measuring device's frame::

    T(q) = exp([xi_1] q_1) ... exp([xi_n] q_n) M,    xi_i = s_i [u_i, p_i x u_i + h_i u_i]

A base transform ``B`` between the device and the robot needs no parameters of its own:
``B exp([xi] q) = exp([Ad_B xi] q) B`` (Wu 2019 eq. 3), so twists and ``M`` identified in the
device frame contain it. Joint offsets ``q_i -> q_i + dq_i`` need none either: they are absorbed
by the later twists and ``M`` (Wu 2019 §V-A), and would make the model redundant.

Every quantity is updated by a *local* chart centred on the current estimate (re-centred after
each step, a retraction), so no parameter is singular anywhere: parallel axes included, unlike
D-H. For joint ``i`` with unit direction ``u``, a point ``p`` on its line (the foot of the
perpendicular from the device origin) and ``e1, e2`` an orthonormal basis normal to ``u``:

* revolute, 4 + 1: the line moves rigidly by ``G = exp(eta)``,
  ``eta = a [e1, p x e1] + b [e2, p x e2] + c [0, e1] + d [0, e2]`` (turns about two axes
  through ``p`` normal to the line, shifts along them): ``xi' = s' Ad_G xi_hat``; and the
  scale ``s' = s + ds`` (Wu's q_bar, §II).
* helical, 5 + 1: the same, and the pitch ``h' = h + dh``.
* prismatic, 2 + 1: the direction turns, ``u' = exp(a e1 + b e2) u``; and the scale.
* pose measurements: the home pose ``M' = M exp(zeta)``, ``zeta`` in se(3): 6. With
  ``keep_tool_axis`` the tool keeps the nominal's placement relative to the last joint's line:
  it moves with that line (``M' = G_n M``) and only screws about and along it, 2.
* position measurements: each marker's home position in the device frame ``c_k' = c_k + dc``:
  3 per marker (the tool frame itself is not observed; see :mod:`.identify`).

This is Wu 2019 eq. (23) for poses, ``5h + 4r + 2t + n + 6`` coordinates; for positions with
``K`` markers ``5h + 4r + 2t + n + 3K``. The twists' variations are the adjoint error model of
Li, Wu, Löwe & Li (IEEE T-RO 32(5), 2016) with the pitch and scale of Wu 2019 added.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..screws import Joint
from ..se3 import twist_exp
from .lie import exp_so3, left_jacobian, log_se3

__all__ = ["Estimate", "count", "local_coordinates", "names", "normal_basis", "retract", "sizes"]

Mat = NDArray[np.float64]


def normal_basis(u: Mat) -> tuple[Mat, Mat]:
    """Orthonormal ``e1, e2`` normal to the unit ``u``: ``e1`` from the basis vector least
    aligned with ``u`` (a smooth choice near any ``u``), ``e2 = u x e1``."""
    k = int(np.argmin(np.abs(u)))
    e1 = -u[k] * u
    e1[k] += 1.0
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(u, e1)


def line_point(u: Mat, p: Mat) -> Mat:
    """The foot of the perpendicular from the origin on the line through ``p`` along unit ``u``."""
    return p - float(p @ u) * u


@dataclass(frozen=True, slots=True)
class Estimate:
    """A POE model being identified, in the device frame.

    Attributes
    ----------
    joints
        The joints (``helical`` ones have their pitch identified; revolute ones keep pitch 0).
        Revolute and helical joints carry the foot of the perpendicular as their point.
    home
        ``(4, 4)`` the tool's home pose ``M`` (pose measurements), else ``None``.
    markers
        ``(K, 3)`` each marker's home position in the device frame (position measurements).
    scales
        Whether the joints' scales are identified (else the nominal's are kept).
    keep_tool_axis
        Whether the tool keeps its placement relative to the last joint's line.
    """

    joints: tuple[Joint, ...]
    home: Mat | None = None
    markers: Mat | None = None
    scales: bool = True
    keep_tool_axis: bool = False

    def __post_init__(self) -> None:
        if (self.home is None) == (self.markers is None):
            raise ValueError("an estimate has a home pose (poses) or markers (positions)")
        if self.keep_tool_axis and (
            self.home is None or not self.joints or self.joints[-1].kind == "prismatic"
        ):
            raise InputError(
                "keeping the tool on the last joint's axis needs pose measurements "
                "and a revolute or helical last joint"
            )

    @property
    def n(self) -> int:
        return len(self.joints)


def _joint_size(j: Joint, scales: bool) -> int:
    return {"revolute": 4, "helical": 5, "prismatic": 2}[j.kind] + int(scales)


def sizes(est: Estimate) -> list[int]:
    """Local coordinates per block: one per joint, then the tool (or the markers)."""
    out = [_joint_size(j, est.scales) for j in est.joints]
    if est.home is not None:
        out.append(2 if est.keep_tool_axis else 6)
    else:
        assert est.markers is not None
        out.append(3 * len(est.markers))
    return out


def count(est: Estimate) -> int:
    """Number of local coordinates: the identifiable-parameter count (module docstring)."""
    return sum(sizes(est))


def names(est: Estimate, marker_ids: list[int] | None = None) -> list[str]:
    """A name per coordinate, e.g. ``j1.turn1``, ``j1.shift2``, ``j1.pitch``, ``j1.scale``,
    ``tool.rx`` ... ``tool.z`` (body frame), ``marker0.x`` (device frame)."""
    out: list[str] = []
    for j in est.joints:
        if j.kind == "prismatic":
            out += [f"{j.name}.turn1", f"{j.name}.turn2"]
        else:
            out += [f"{j.name}.{k}" for k in ("turn1", "turn2", "shift1", "shift2")]
            if j.kind == "helical":
                out.append(f"{j.name}.pitch")
        if est.scales:
            out.append(f"{j.name}.scale")
    if est.home is not None:
        out += (
            ["tool.turn", "tool.slide"]
            if est.keep_tool_axis
            else [f"tool.{k}" for k in ("rx", "ry", "rz", "x", "y", "z")]
        )
    else:
        assert est.markers is not None
        ids = marker_ids if marker_ids is not None else list(range(len(est.markers)))
        out += [f"marker{m}.{c}" for m in ids for c in "xyz"]
    return out


def line_motion(j: Joint, a: float, b: float, c: float, d: float) -> Mat:
    """``eta`` of the joint's line chart (module docstring) as a twist ``(6,)``."""
    e1, e2 = normal_basis(j.axis)
    rho, tau = a * e1 + b * e2, c * e1 + d * e2
    p = j.point if j.point is not None else np.zeros(3)
    return np.concatenate([rho, np.cross(p, rho) + tau])


def tool_screws(est: Estimate) -> Mat:
    """``(6, 2)``: with ``keep_tool_axis``, the last line's screws (turn about it, slide along
    it) in the tool's body frame: ``Ad(M^-1) [u, p x u]`` and ``Ad(M^-1) [0, u]``."""
    assert est.home is not None
    j = est.joints[-1]
    p = j.point if j.point is not None else np.zeros(3)
    twists = np.array(
        [np.concatenate([j.axis, np.cross(p, j.axis)]), np.concatenate([np.zeros(3), j.axis])]
    ).T
    r, t = est.home[:3, :3], est.home[:3, 3]
    w = r.T @ twists[:3]
    v = r.T @ (twists[3:] - np.cross(t[:, None], twists[:3], axis=0))
    return np.vstack([w, v])


def _moved(j: Joint, g: Mat) -> tuple[Mat, Mat]:
    """Direction and foot point of the joint's line moved by the rigid motion ``g``."""
    u = g[:3, :3] @ j.axis
    u /= np.linalg.norm(u)
    p = g[:3, :3] @ (j.point if j.point is not None else np.zeros(3)) + g[:3, 3]
    return u, line_point(u, p)


def retract(est: Estimate, delta: Mat) -> Estimate:
    """The estimate moved by local coordinates ``delta`` (``(count,)``), re-centred."""
    delta = np.asarray(delta, dtype=float)
    k, joints, last_motion = 0, [], np.eye(4)
    for j in est.joints:
        size = _joint_size(j, est.scales)
        x = delta[k : k + size]
        k += size
        scale = j.scale + (x[-1] if est.scales else 0.0)
        if j.kind == "prismatic":
            e1, e2 = normal_basis(j.axis)
            u = exp_so3(x[0] * e1 + x[1] * e2) @ j.axis
            joints.append(
                Joint(j.name, j.kind, u / np.linalg.norm(u), j.point, 0.0, scale, j.lower, j.upper)
            )
            last_motion = np.eye(4)
            continue
        last_motion = twist_exp(line_motion(j, *x[:4]))
        u, p = _moved(j, last_motion)
        pitch = j.pitch + (x[4] if j.kind == "helical" else 0.0)
        joints.append(Joint(j.name, j.kind, u, p, pitch, scale, j.lower, j.upper))
    if est.home is not None:
        if est.keep_tool_axis:
            zeta = tool_screws(est) @ delta[k : k + 2]
            home = last_motion @ est.home @ twist_exp(zeta)
        else:
            home = est.home @ twist_exp(delta[k : k + 6])
        return replace(est, joints=tuple(joints), home=home)
    assert est.markers is not None
    markers = est.markers + delta[k:].reshape(-1, 3)
    return replace(est, joints=tuple(joints), markers=markers)


def local_coordinates(est: Estimate, other: Estimate) -> Mat:
    """The coordinates ``delta`` around ``est`` with ``retract(est, delta)`` equal to ``other``
    (``other`` near ``est``; used to compare an identified model with the truth)."""
    out: list[float] = []
    motion = np.eye(4)
    for j, o in zip(est.joints, other.joints, strict=True):
        e1, e2 = normal_basis(j.axis)
        cross = np.cross(j.axis, o.axis)
        sin = float(np.linalg.norm(cross))
        rho = cross * (math.atan2(sin, float(j.axis @ o.axis)) / sin) if sin else 0.0 * cross
        out += [float(rho @ e1), float(rho @ e2)]
        if j.kind != "prismatic":
            # exp(eta) p = p + J(rho) tau must lie on the other line: solve for tau in e1, e2
            assert j.point is not None and o.point is not None
            proj = np.eye(3) - np.outer(o.axis, o.axis)
            lhs = proj @ left_jacobian(rho) @ np.array([e1, e2]).T
            tau, *_ = np.linalg.lstsq(lhs, proj @ (o.point - j.point), rcond=None)
            out += [float(tau[0]), float(tau[1])]
            motion = twist_exp(line_motion(j, *out[-4:]))
            if j.kind == "helical":
                out.append(o.pitch - j.pitch)
        if est.scales:
            out.append(o.scale - j.scale)
    if est.home is not None:
        assert other.home is not None
        if est.keep_tool_axis:
            zeta = log_se3(np.linalg.inv(est.home) @ np.linalg.inv(motion) @ other.home)
            out += np.linalg.lstsq(tool_screws(est), zeta, rcond=None)[0].tolist()
        else:
            out += log_se3(np.linalg.inv(est.home) @ other.home).tolist()
    else:
        assert est.markers is not None and other.markers is not None
        out += (other.markers - est.markers).ravel().tolist()
    return np.array(out)
