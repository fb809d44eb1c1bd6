"""Names the writers make up never collide with the robot's own (urdf2dh.emit.names).

MATLAB's bodies and joints, KDL's segments and fixed joints, the URDF writer's links and joints
are made up where the robot gives no name; a robot may use those names itself. Each colliding
robot (hostile.COLLIDING) is exported to every target and format and judged against its clean
twin (safety.judge: a renamed made-up name only where the file states it); and its files are
run by their consumers: roboticstoolbox and PyKDL for real (a KDL tree refuses a second segment
of one name), MATLAB's rigidBodyTree as addBody builds it (refusing a second body or joint of
one name), the URDF by Pinocchio. The robot's own names are kept exactly.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from consumers import FakeKdl, RigidBodyTree, SerialLink, kdl_fk, real_pykdl
from corpus import Corpus
from hostile import COLLIDING, KINDS, write_source
from oracle import assert_fk_matches

import urdf2dh
from urdf2dh import Joint, PoeModel, load, to_table
from urdf2dh.emit.export import export_table
from urdf2dh.emit.names import RENAMED, Namespace, renaming_notes
from urdf2dh.errors import ExportError, TableFileError

PYKDL = real_pykdl()
AGREE = 1e-12


@pytest.fixture(scope="module")
def corpus():
    c = Corpus()
    yield c
    c.close()


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("names", COLLIDING, ids=[f"colliding{i}" for i in range(len(COLLIDING))])
def test_colliding_robots_are_written_with_their_names(corpus, names, kind):
    verdicts = corpus.check(names, "genser6", kind)
    assert [(v.run, v.result, v.detail[:300]) for v in verdicts if v.result != "written"] == []


def _model(tmp_path: Path, names):
    source = write_source(tmp_path, "genser6", names, "urdf")
    return load(str(tmp_path / source), names.base, names.tip)


def _rtb_fk(script: str, q: np.ndarray) -> np.ndarray:
    namespace: dict = {"__name__": "generated_rtb"}
    exec(compile(script, "generated_rtb.py", "exec"), namespace)
    return np.array([namespace["robot"].fkine(row).A for row in q])


@pytest.mark.parametrize("convention", ["dh", "mdh"])
@pytest.mark.parametrize("names", COLLIDING, ids=[f"colliding{i}" for i in range(len(COLLIDING))])
def test_consumers_build_colliding_robots(tmp_path, names, convention):
    model = _model(tmp_path, names)
    q = np.random.default_rng(5).uniform(-2.5, 2.5, (8, 6))
    want, size = model.fk(q), model.size()
    table = to_table(model, convention)
    text = {t: export_table(table, t) for t in ("matlab", "kdl", "rtb", "corke-matlab")}

    tree = RigidBodyTree(text["matlab"])  # refuses a second body or joint of one name
    assert tree.base == names.base and names.tip in tree.bodies
    assert [tree.bodies[b]["joint"]["name"] for b in tree.order] == list(names.joints)
    got = np.array([tree.get_transform(row, names.tip) for row in q])
    assert_fk_matches(f"matlab {convention}", got, want, size, q, rel=AGREE, rot=AGREE)

    kdl = PYKDL or FakeKdl
    assert_fk_matches("kdl", kdl_fk(kdl, text["kdl"], q), want, size, q, rel=AGREE, rot=AGREE)
    if PYKDL is not None:  # the real KDL: a tree takes each segment name once
        namespace: dict = {"__name__": "generated_kdl"}
        exec(compile(text["kdl"], "generated_kdl.py", "exec"), namespace)
        chain = namespace["build_chain"]()
        assert PYKDL.Tree("root").addChain(chain, "root")
        segments = [chain.getSegment(i) for i in range(chain.getNrOfSegments())]
        moving = [s.getJoint().getName() for s in segments if s.getJoint().getTypeName() != "Fixed"]
        assert moving == list(names.joints)
        assert segments[0].getName() == names.base

    assert_fk_matches("rtb", _rtb_fk(text["rtb"], q), want, size, q, rel=AGREE, rot=AGREE)
    corke = np.array([SerialLink(text["corke-matlab"]).fkine(row) for row in q])
    assert_fk_matches("corke-matlab", corke, want, size, q, rel=AGREE, rot=AGREE)

    (tmp_path / "back.urdf").write_text(urdf2dh.render(table, "urdf"))
    back = urdf2dh.load(str(tmp_path / "back.urdf"), names.base, names.tip)
    assert [j.name for j in back.joints] == list(names.joints)
    assert_fk_matches("urdf", back.fk(q), want, size, q, rel=AGREE, rot=AGREE)


def test_the_files_state_each_renaming(tmp_path):
    names = COLLIDING[0]  # base body1, tip body2: MATLAB's joint bodies 1 and 2 move aside
    table = to_table(_model(tmp_path, names), "dh")
    matlab = export_table(table, "matlab")
    assert f"% {RENAMED} body body1 to body1_2: body1 is the robot's" in matlab.splitlines()
    assert 'body = rigidBody("body1_2");' in matlab and 'robot.BaseName = "body1";' in matlab
    names = COLLIDING[3]  # base joint1, tip joint6: KDL's segments of joints 1 and 6 move aside
    kdl = export_table(to_table(_model(tmp_path, names), "dh"), "kdl")
    assert f"{RENAMED} segment joint1 to joint1_2: joint1 is the robot's" in kdl
    assert f"{RENAMED} joint joint6 to joint6_2: joint6 is the robot's" in kdl
    assert "kdl.Segment('joint1_2', kdl.Joint('joint1', kdl.Joint.RotZ)" in kdl


def test_a_helical_lead_joint_keeps_clear_of_a_joint_named_like_it(tmp_path):
    """The URDF writer's ``<joint>_lead``: a robot with joints ``a`` (helical) and ``a_lead``."""
    z = np.array([0.0, 0.0, 1.0])
    home = np.eye(4)
    home[:3, 3] = (0.2, 0.0, 0.5)
    joints = (
        Joint("a", "helical", z, np.zeros(3), pitch=0.01),
        Joint("a_lead", "revolute", np.array([1.0, 0, 0]), np.array([0.0, 0, 0.3])),
        Joint("tool_joint", "revolute", z, np.array([0.2, 0, 0.4])),
    )
    model = PoeModel(joints, home, "r", "", "a_lead_link", "tool", "m")
    text = urdf2dh.render(urdf2dh.to_table(model, "dh"), "urdf")
    assert f"{RENAMED} joint a_lead to a_lead_2: a_lead is the robot's" in text
    assert f"{RENAMED} link a_lead_link to a_lead_link_2: a_lead_link is the robot's" in text
    assert f"{RENAMED} joint tool_joint to tool_joint_2: tool_joint is the robot's" in text
    (tmp_path / "h.urdf").write_text(text)
    back = urdf2dh.load(str(tmp_path / "h.urdf"), "a_lead_link", "tool")
    assert [(j.name, j.kind) for j in back.joints] == [(j.name, j.kind) for j in joints]
    q = np.random.default_rng(2).uniform(-2, 2, (6, 3))
    assert_fk_matches("urdf", back.fk(q), model.fk(q), model.size(), q, rel=AGREE, rot=AGREE)


@pytest.mark.parametrize("target", ["matlab", "kdl", "urdf"])
def test_two_robot_names_alike_are_refused(tmp_path, target):
    table = to_table(_model(tmp_path, COLLIDING[0]), "dh")
    rows = (replace(table.rows[0], name="j"), replace(table.rows[1], name="j"), *table.rows[2:])
    table = replace(table, rows=rows)
    with pytest.raises(ExportError, match=rf"^{target}: two joints are named 'j'; "):
        urdf2dh.render(table, "urdf") if target == "urdf" else export_table(table, target)


def test_the_matlab_reader_refuses_what_addbody_refuses():
    def script(second_body: str, second_joint: str) -> str:
        lines = ['robot = rigidBodyTree("DataFormat", "row");', 'robot.BaseName = "b";']
        lines.append("parent = robot.BaseName;")
        for body, joint in (("x", "j"), (second_body, second_joint)):
            lines += [
                f'body = rigidBody("{body}");',
                f'joint = rigidBodyJoint("{joint}", "fixed");',
            ]
            lines += ["body.Joint = joint;", "addBody(robot, body, parent);", "parent = body.Name;"]
        return "\n".join(lines) + "\n"

    assert sorted(RigidBodyTree(script("y", "k")).bodies) == ["x", "y"]
    for body, joint, what in (("x", "k", "body"), ("b", "k", "body"), ("y", "j", "joint")):
        with pytest.raises(AssertionError, match=f"duplicate {what} name"):
            RigidBodyTree(script(body, joint))


def test_a_namespace_keeps_the_robots_names_and_moves_its_own():
    space = Namespace("matlab", "body", ["body1", "body1_2"])
    assert [space.invent(n) for n in ("body1", "body1", "dh_base", "x")] == [
        "body1_3",
        "body1_4",
        "dh_base",
        "x",
    ]
    joints = Namespace("matlab", "joint", ["j"])
    assert joints.invent("x_fixed") == "x_fixed" and joints.invent("x_fixed") == "x_fixed_2"
    assert renaming_notes(space, joints) == [
        f"{RENAMED} body body1 to body1_3: body1 is the robot's",
        f"{RENAMED} body body1 to body1_4: body1 is the robot's",
        f"{RENAMED} joint x_fixed to x_fixed_2: x_fixed is taken",
    ]


def test_a_table_file_names_each_joint_once(tmp_path):
    tree = urdf2dh.to_table(urdf2dh.load("ur5"), "dh").to_dict()
    tree["joints"][3]["name"] = tree["joints"][1]["name"]
    (tmp_path / "t.json").write_text(json.dumps(tree))
    with pytest.raises(TableFileError, match=r"t.json: joint 'shoulder_lift_joint' appears twice"):
        urdf2dh.load(str(tmp_path / "t.json"))
