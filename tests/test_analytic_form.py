"""The analytic form of a D-H table (urdf2dh/conventions/analytic.py) and the analytic IK
families read off it (urdf2dh/conventions/families.py), against Pinocchio and the solvers'
own rules."""

from __future__ import annotations

import math

import numpy as np
import pytest
from oracle import EXACT, assert_fk_matches, pin_reference

from urdf2dh import load, to_table
from urdf2dh.conventions.analytic import analytic_form, pi_text
from urdf2dh.conventions.families import Relations, families
from urdf2dh.errors import UsageError
from urdf2dh.io.catalog import ROBOTS
from urdf2dh.io.sources import open_source
from urdf2dh.tolerances import DEFAULT
from urdf2dh.tolerances import EXACT as EXACT_TOL


@pytest.mark.parametrize("robot", sorted(ROBOTS))
def test_the_analytic_form_moves_as_the_source_within_what_it_declares(robot):
    source = open_source(robot)
    model = source.model()
    chain = analytic_form(to_table(model, "dh"))
    q, reference = pin_reference(source, model, samples=200, seed=23)
    c = chain.check
    assert_fk_matches(f"analytic form {robot}", chain.fk_batch(q), reference, model.size(), q,
                      rel=EXACT + c.declared_position / model.size(),
                      rot=EXACT + c.declared_rotation)  # fmt: skip
    last = chain.rows[-1].params
    assert last.alpha == 0.0 and last.a == 0.0  # the tip's tilt is the tool's
    # every snap is within the tolerance, and beyond round-off
    for s in chain.snaps:
        lever = 1.0 if s.parameter in ("theta", "alpha") else model.size()
        assert DEFAULT.written * lever < s.change <= DEFAULT.solver_snap * lever, s


def test_the_ur5s_rounded_pi_is_made_exact_and_its_tilt_goes_to_the_tool():
    chain = analytic_form(to_table(load("ur5"), "dh"))
    assert [(s.row, s.parameter, pi_text(s.exact)) for s in chain.snaps] == [
        ("shoulder_lift_joint", "theta", "pi"),
        ("wrist_1_joint", "theta", "pi"),
    ]
    assert all(abs(s.change - 4.9e-12) < 1e-13 for s in chain.snaps)
    tilt = math.atan2(chain.tool[2, 1], chain.tool[1, 1])  # Rx(alpha_6) of the table
    assert 4.8e-12 < tilt < 5e-12
    assert 0.0 < chain.check.declared_position < 1e-10
    assert "theta of 'shoulder_lift_joint': pi - 4.9e-12 rad, written pi" in chain.warnings()[0]


def test_exact_tolerances_snap_nothing_and_stay_exact():
    table = to_table(load("kinova"), "dh", EXACT_TOL)
    chain = analytic_form(table, EXACT_TOL)
    assert chain.snaps == () and chain.check.declared_position == 0.0
    assert chain.check.max_position_error <= 1e-14 * table.size
    assert Relations.of(chain).concurrent == ()  # its wrist misses by 5e-13 m: not spherical


def test_other_conventions_are_refused():
    with pytest.raises(UsageError, match="made from a dh table, not mdh"):
        analytic_form(to_table(load("ur5"), "mdh"))


RELATIONS = {  # robot: (parallel, meeting, concurrent), first axis of each pair or triple
    "ur5": ((2, 3), (1, 4, 5), ()),
    "puma560-nominal": ((2,), (1, 4, 5), (4,)),
    "z1": ((2, 3), (1, 5), ()),
    "stanford": ((3,), (1, 2, 4, 5), (4,)),
}


@pytest.mark.parametrize("robot", sorted(RELATIONS))
def test_relations_of_known_arms(robot):
    r = Relations.of(analytic_form(to_table(load(robot), "dh")))
    assert (r.parallel, r.meeting, r.concurrent) == RELATIONS[robot]


def test_families_name_each_solver_and_why_not():
    lines = families(load("ur5")).lines()
    assert lines[0].startswith("analytic IK: axes 2, 3, 4 parallel")
    assert "  three parallel axes (axes 2, 3, 4): --to eaik (EAIK 6R-THREE_INNER_PARALLEL), " \
           "--to rtb (closed form)" in lines  # fmt: skip
    assert "  general 6R: --to ikdh (Husty-Pfurner)" in lines
    assert any(x.startswith("  not opw: wrist axes do not intersect: offset wrist") for x in lines)
    puma = families(load("puma560-nominal"))
    assert [f.name for f in puma.families] == ["spherical wrist", "OPW", "general 6R"]
    assert puma.refused == ()
    panda = families(load("panda"))
    # joint 4's limits exclude 0
    assert [f.name for f in panda.families] == [
        "7R with a locked joint (joint 5, 6 or 7 held at 0)"
    ]
    assert panda.reason("eaik") is None
    assert panda.reason("ikdh") == "not 6R: ikdh takes six revolute joints, the chain has 7 joints"
    stanford = families(load("stanford"))
    assert stanford.reason("eaik") == "not 6R: EAIK takes revolute joints only, not joints 3 " \
                                      "(prismatic)"  # fmt: skip
    assert [(f.name, f.exports) for f in stanford.families] == [
        ("spherical wrist", (("rtb", "closed form"),))
    ]


def test_families_of_a_chain_without_joints():
    from urdf2dh import PoeModel

    f = families(PoeModel((), np.eye(4)))
    assert f.relations is None and f.families == () and f.reason("eaik") == "no joints"


def test_info_names_the_families_and_the_exports(capsys):
    from urdf2dh import info
    from urdf2dh.cli import main

    assert main(["info", "puma560-nominal"]) == 0
    out = capsys.readouterr().out
    assert "analytic IK: axes 4, 5, 6 meet in one point; axes 1, 2 meet; axes 2, 3 parallel" in out
    assert "  spherical wrist (axes 4, 5, 6): --to eaik (EAIK 6R-SPHERICAL_*), --to rtb " \
           "(closed form)\n" in out  # fmt: skip
    assert "  OPW: --to opw (ortho-parallel base, spherical wrist)\n" in out
    assert "  general 6R: --to ikdh (Husty-Pfurner)\n" in out
    described = info("stanford")
    assert described.families is not None
    assert described.families.reason("ikdh") is not None
    assert "- not ikdh: not 6R" in described._repr_markdown_()
