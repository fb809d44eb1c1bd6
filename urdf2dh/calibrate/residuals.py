"""Measurement residuals of an :class:`~.chart.Estimate` and their analytic Jacobian.

Residuals, per measurement (model minus measured, both in the device frame):

* position ``x(q) - x_meas`` of the tool origin (poses) or of marker ``k``, ``x = P_n(q) c_k``
  (positions), divided by the position noise ``sigma_p``;
* for poses, rotation ``phi = log(R(q) R_meas^T)`` (a rotation vector in the device frame),
  divided by the rotation noise ``sigma_r``.

Jacobian. A change of the coordinates moves the tool by a small space-frame twist
``d = [dw, dv]`` (``T' = exp([d]) T``), so ``dx = dv + dw x x`` and
``dphi = J_l(phi)^-1 dw`` (left Jacobian of SO(3); exact, not just near ``phi = 0``). With
``P_i = exp([xi_1] q_1) ... exp([xi_i] q_i)`` and the charts of :mod:`.chart`:

* a joint's line moved by ``exp(eta)``: ``exp(eta) exp([xi] q) exp(-eta)`` gives
  ``d = Ad(P_(i-1)) eta - Ad(P_i) eta`` (when the tool moves with the last line, the second
  term cancels: ``d = Ad(P_(n-1)) eta``);
* its scale ``s + ds`` (``exp([xi_hat] s q)``): ``d = Ad(P_(i-1)) xi_hat q_i ds``;
* its pitch ``h + dh`` (``[0, u]`` commutes with ``xi_hat``): ``d = Ad(P_(i-1)) [0, u] s q_i dh``;
* the home pose ``M exp(zeta)``: ``d = Ad(T) zeta``; a marker ``c + dc``: ``dx = R_(P_n) dc``.

``Ad([R, t]) [w, v] = [R w, R v + t x R w]`` (Wu 2019 eq. 4). Everything is evaluated for all
measurements at once, ``N`` configurations as ``(N, ...)`` stacks.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..screws import Joint
from .chart import Estimate, normal_basis, sizes, tool_screws
from .lie import ad_apply, cross_columns, left_jacobian_inverse, log_so3

__all__ = ["Data", "evaluate", "model_poses", "prefix_products"]

Mat = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Data:
    """What the model is compared with.

    Attributes
    ----------
    q
        ``(N, n)`` joint positions.
    points
        ``(N, 3)`` measured tool points in the device frame.
    rotations
        ``(N, 3, 3)`` measured tool orientations (pose measurements), else ``None``.
    marker_rows
        ``(N,)`` for position measurements, the row of :attr:`Estimate.markers` each
        measurement saw, else ``None``.
    """

    q: Mat
    points: Mat
    rotations: Mat | None = None
    marker_rows: NDArray[np.int64] | None = None

    def __post_init__(self) -> None:
        n = len(self.q)
        if self.points.shape != (n, 3):
            raise ValueError(f"points must be ({n}, 3), not {self.points.shape}")
        if self.rotations is not None and self.rotations.shape != (n, 3, 3):
            raise ValueError(f"rotations must be ({n}, 3, 3), not {self.rotations.shape}")
        if (self.rotations is None) == (self.marker_rows is None):
            raise ValueError("data holds rotations (poses) or marker rows (positions)")

    @property
    def rows(self) -> int:
        """Residuals per measurement: 6 for poses, 3 for positions."""
        return 6 if self.rotations is not None else 3

    def __len__(self) -> int:
        return len(self.q)


def _joint_exp(j: Joint, q: Mat) -> Mat:
    """``exp([xi] q)`` for ``q (N,)``: ``(N, 4, 4)`` (Rodrigues; ``1 - cos = 2 sin^2(t/2)``)."""
    out = np.zeros((len(q), 4, 4))
    out[:, 3, 3] = 1.0
    s = j.scale * q
    if j.kind == "prismatic":
        out[:, :3, :3] = np.eye(3)
        out[:, :3, 3] = s[:, None] * j.axis
        return out
    assert j.point is not None
    k = np.array(
        [[0.0, -j.axis[2], j.axis[1]], [j.axis[2], 0.0, -j.axis[0]], [-j.axis[1], j.axis[0], 0.0]]
    )
    half = np.sin(0.5 * s)
    r = np.eye(3) + np.sin(s)[:, None, None] * k + (2.0 * half * half)[:, None, None] * (k @ k)
    out[:, :3, :3] = r
    out[:, :3, 3] = j.point - r @ j.point + (j.pitch * s)[:, None] * j.axis
    return out


def prefix_products(est: Estimate, q: Mat) -> list[Mat]:
    """``[P_0 = I, P_1, ..., P_n]``, each ``(N, 4, 4)``."""
    out = [np.broadcast_to(np.eye(4), (len(q), 4, 4))]
    for i, j in enumerate(est.joints):
        out.append(out[-1] @ _joint_exp(j, q[:, i]))
    return out


def model_poses(est: Estimate, q: Mat) -> Mat:
    """``(N, 4, 4)`` the tool poses ``P_n(q) M`` (pose estimates only)."""
    assert est.home is not None
    return prefix_products(est, q)[-1] @ est.home


def _space_columns(est: Estimate, data: Data, prefix: list[Mat], tool: Mat | None) -> Mat:
    """``(N, 6, p)`` the tool's space-frame twist per coordinate (module docstring); the marker
    coordinates of position estimates are left at zero (they move points, not the tool)."""
    q = data.q
    blocks = []
    last = est.n - 1
    for i, j in enumerate(est.joints):
        before, after = prefix[i], prefix[i + 1]
        e1, e2 = normal_basis(j.axis)
        zero = np.zeros(3)
        if j.kind == "prismatic":
            eta = np.array([np.r_[e1, zero], np.r_[e2, zero]]).T
        else:
            assert j.point is not None
            p = j.point
            eta = np.array(
                [
                    np.r_[e1, np.cross(p, e1)],
                    np.r_[e2, np.cross(p, e2)],
                    np.r_[zero, e1],
                    np.r_[zero, e2],
                ]
            ).T
        cols = ad_apply(before, eta)
        if not (est.keep_tool_axis and i == last):
            cols = cols - ad_apply(after, eta)
        blocks.append(cols)
        if j.kind == "helical":
            blocks.append(
                ad_apply(before, np.r_[zero, j.axis][:, None]) * (j.scale * q[:, i])[:, None, None]
            )
        if est.scales:
            if j.kind == "prismatic":
                xi_hat = np.r_[zero, j.axis]
            else:
                assert j.point is not None
                xi_hat = np.r_[j.axis, np.cross(j.point, j.axis) + j.pitch * j.axis]
            blocks.append(ad_apply(before, xi_hat[:, None]) * q[:, i, None, None])
    if tool is not None:
        basis = tool_screws(est) if est.keep_tool_axis else np.eye(6)
        blocks.append(ad_apply(tool, basis))
    else:
        assert est.markers is not None
        blocks.append(np.zeros((len(q), 6, 3 * len(est.markers))))
    return np.concatenate(blocks, axis=2)


def evaluate(
    est: Estimate, data: Data, sigma_pos: float, sigma_rot: float, jacobian: bool = True
) -> tuple[Mat, Mat | None]:
    """Weighted residuals ``(N * rows,)`` and, if asked, their Jacobian ``(N * rows, p)`` with
    respect to the local coordinates of ``est`` (rows: position x, y, z then, for poses,
    rotation x, y, z of each measurement in turn)."""
    prefix = prefix_products(est, data.q)
    last = prefix[-1]
    if est.home is not None:
        tool = last @ est.home
        x = tool[:, :3, 3]
    else:
        assert est.markers is not None and data.marker_rows is not None
        tool = None
        c = est.markers[data.marker_rows]
        x = np.einsum("nij,nj->ni", last[:, :3, :3], c) + last[:, :3, 3]
    res = np.empty((len(data), data.rows))
    res[:, :3] = (x - data.points) / sigma_pos
    phi = None
    if data.rotations is not None:
        assert tool is not None
        phi = log_so3(tool[:, :3, :3] @ np.swapaxes(data.rotations, 1, 2))
        res[:, 3:] = phi / sigma_rot
    if not jacobian:
        return res.ravel(), None
    cols = _space_columns(est, data, prefix, tool)
    jac = np.empty((len(data), data.rows, cols.shape[2]))
    jac[:, :3] = (cols[:, 3:] + cross_columns(cols[:, :3], x[:, :, None])) / sigma_pos
    if phi is not None:
        jac[:, 3:] = left_jacobian_inverse(phi) @ cols[:, :3] / sigma_rot
    else:
        assert est.markers is not None and data.marker_rows is not None
        start = sum(sizes(est)[:-1])
        for k in range(len(est.markers)):
            rows = data.marker_rows == k
            jac[rows, :3, start + 3 * k : start + 3 * k + 3] = last[rows, :3, :3] / sigma_pos
    return res.ravel(), jac.reshape(len(data) * data.rows, -1)
