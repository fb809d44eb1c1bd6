"""Unit properties of the geometry kit: exp/adjoint, the common normal (Wu 2019 Lemmas 1-4),
and CPC's R(b) (Sumenkov eq. 4) near its singular direction."""

from __future__ import annotations

import math

import numpy as np
import pytest

from urdf2dh import DEFAULT, Joint, PoeModel
from urdf2dh.conventions.cpc import r_rows, v_frame
from urdf2dh.geometry import se3
from urdf2dh.geometry.normals import common_normal
from urdf2dh.geometry.se3 import dh_matrix, matrix_of

RNG = np.random.default_rng(20261121)


def unit(v):
    return v / np.linalg.norm(v)


def test_poe_exponentials_match_the_general_exp_and_adjoint_identity():
    for _ in range(50):
        u, p = unit(RNG.normal(size=3)), RNG.normal(size=3)
        h, s = RNG.normal(), RNG.normal(size=4)
        xi = np.concatenate([u, np.cross(p, u) + h * u])
        helical = PoeModel((Joint("h", "helical", u, p, h, 1.0),), np.eye(4))
        batch = helical.fk_batch(s[:, None])
        for k in range(4):
            assert np.allclose(se3.twist_exp(xi, s[k]), batch[k], atol=1e-13)
        g = se3.twist_exp(RNG.normal(size=6))
        lhs = g @ se3.twist_exp(xi, 0.7) @ se3.inv(g)
        assert np.allclose(lhs, se3.twist_exp(se3.adjoint(g) @ xi, 0.7), atol=1e-12)


def _on_line(h, u, p):
    """The frame h has its z along u and its origin on the line (p, u)."""
    z, o = h[:3, 2], h[:3, 3]
    return np.allclose(z, u, atol=1e-12) and np.linalg.norm(np.cross(o - p, u)) < 1e-12


@pytest.mark.parametrize("tool", [False, True])
def test_common_normal_puts_the_frame_on_the_line(tool):
    for _ in range(200):
        u, p = unit(RNG.normal(size=3)), RNG.normal(size=3)
        link, found = common_normal(u, p, DEFAULT, ("a", "b"), 1.0, tool=tool)
        h = dh_matrix(link.theta, link.d, link.alpha, link.a)
        assert _on_line(h, u, p)
        assert found == []
        if tool:
            assert 0.0 <= link.alpha <= math.pi
        else:
            assert link.a >= 0.0


def test_intersecting_lines_get_positive_alpha_and_zero_a():
    for _ in range(100):
        u = unit(RNG.normal(size=3))
        meet = RNG.normal()
        p = np.array([0.0, 0.0, meet]) + RNG.normal() * u  # meets the z axis at height `meet`
        link, _ = common_normal(u, p, DEFAULT, ("a", "b"), 1.0)
        assert link.alpha > 0.0
        assert abs(link.a) < 1e-12
        assert link.d == pytest.approx(meet, abs=1e-12)


def test_parallel_lines_follow_wu_rules():
    for sign in (1.0, -1.0):
        u = np.array([0.0, 0.0, sign])
        p = np.array([0.3, -0.4, 2.0])
        link, _ = common_normal(u, p, DEFAULT, ("a", "b"), 1.0)
        assert (link.d, link.a) == (0.0, pytest.approx(0.5))  # d = 0 for parallel axes
        assert link.alpha == (0.0 if sign > 0 else math.pi)
        tool, _ = common_normal(u, p, DEFAULT, ("a", "b"), 1.0, tool=True)
        assert tool.d == 2.0  # Lemma 4: the offset goes into the last row, the tool's d is 0
        coincident, _ = common_normal(u, np.array([0.0, 0.0, 5.0]), DEFAULT, ("a", "b"), 1.0)
        assert (coincident.theta, coincident.a, coincident.d) == (0.0, 0.0, 0.0)


def test_nearly_parallel_meeting_lines_stay_exact():
    """A tool axis 4.9e-12 rad off the last axis but through it (UR5): exact, no judgement."""
    u = unit(np.array([4.9e-12, 0.0, 1.0]))
    p = np.array([0.0, 0.0, 0.0823])
    link, found = common_normal(u, p, DEFAULT, ("a", "b"), 1.0, tool=True)
    assert found == []
    h = dh_matrix(link.theta, link.d, link.alpha, link.a)
    assert _on_line(h, u, p)
    assert link.d == 0.0823


def test_nearly_parallel_apart_is_judged_and_reported():
    u = unit(np.array([3.7e-6, 0.0, 1.0]))
    link, found = common_normal(u, np.array([0.2, 0.0, 0.0]), DEFAULT, ("j1", "j2"), 1.0)
    assert link.alpha == 0.0 and link.d == 0.0
    assert [(j.kind, j.first, j.second) for j in found] == [("parallel", "j1", "j2")]
    assert found[0].angle == pytest.approx(3.7e-6, rel=1e-6)


@pytest.mark.parametrize("eps", [1e-1, 1e-4, 1e-8, 1e-12, 1e-15])
def test_r_of_b_is_a_rotation_near_minus_z(eps):
    for phi in np.linspace(0, 2 * math.pi, 7):
        b = np.array([eps * math.cos(phi), eps * math.sin(phi), -math.sqrt(1 - eps * eps)])
        r = np.array(r_rows(b))
        assert np.allclose(r.T @ r, np.eye(3), atol=2e-15)
        assert np.allclose(r[:, 2], b, atol=1e-16)
        assert np.linalg.det(r) == pytest.approx(1.0, abs=1e-14)


def test_r_of_b_matches_sumenkov_eq4_away_from_the_singularity():
    for _ in range(50):
        b = unit(RNG.normal(size=3))
        if b[2] < -0.5:
            b = -b
        bx, by, bz = b
        eq4 = np.array(
            [
                [1 - bx**2 / (1 + bz), -bx * by / (1 + bz), bx],
                [-bx * by / (1 + bz), 1 - by**2 / (1 + bz), by],
                [-bx, -by, bz],
            ]
        )
        assert np.allclose(np.array(r_rows(b)), eq4, atol=1e-15)
        v = matrix_of(v_frame(b, [0.1, -0.2, 0.3], 0.4))
        assert np.allclose(v[:3, 2], b)


def test_twist_exp_equals_the_matrix_exponential_at_every_scale():
    """se3.twist_exp (plain floats) against scipy's expm of the 4x4 twist matrix, from pure
    translations and angles near round-off to several turns."""
    from scipy.linalg import expm

    for scale in (0.0, 1e-12, 1e-7, 1e-3, 0.3, 1.0, 7.0):
        for _ in range(10):
            w, v = RNG.normal(size=3) * scale, RNG.normal(size=3)
            q = RNG.uniform(-2.0, 2.0)
            matrix = np.zeros((4, 4))
            matrix[:3, :3] = se3.skew(w * q)
            matrix[:3, 3] = v * q
            assert np.allclose(se3.twist_exp(np.r_[w, v], q), expm(matrix), atol=1e-13, rtol=0)
