"""Every MJCF feature urdf2dh reads, on small hand-written models, against both oracles: MuJoCo
(which defines MJCF) and Pinocchio's MJCF parser. Each model puts the feature on the chain it
checks, so that reading it otherwise would move the tip. Where Pinocchio 4.1 reads a feature
otherwise than MuJoCo, Pinocchio does not judge (its reason said), and a test shows that it
does misread it: the list of those (``PINOCCHIO_MISREADS``) stays true."""

from __future__ import annotations

import math

import numpy as np
import pytest
from mjcf_oracle import agrees, opened, oracles_differ, pinocchio_model, write

from urdf2dh.check.verify import PINOCCHIO_MISREADS, PINOCCHIO_WORLD_BODY
from urdf2dh.errors import ChainError
from urdf2dh.io.mjcf import FEATURES
from urdf2dh.io.sources import open_source

ARM = """<mujoco model="arm">
  {compiler}
  {defaults}
  <worldbody>
    <body name="base" pos="0.1 -0.2 0.3" {base}>
      <geom size="0.02"/>
      <body name="l1" pos="0 0 0.3" {l1}>
        <joint name="j1" {j1}/>
        <geom size="0.02"/>
        <body name="l2" pos="0.25 0.05 0" {l2}>
          <joint name="j2" {j2}/>
          <geom size="0.02"/>
          <body name="l3" pos="0.2 0 0.04" {l3}>
            <joint name="j3" {j3}/>
            <geom size="0.02"/>
            <site name="tool" {tool}/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
  {tail}
</mujoco>
"""
PLAIN = {"compiler": "", "defaults": "", "base": "", "l1": "", "l2": "", "l3": "",
         "tool": 'pos="0.05 0.01 0.1"',
         "j1": 'axis="0 0 1"', "j2": 'axis="0 1 0"', "j3": 'axis="1 0 0"', "tail": ""}  # fmt: skip


def arm(**slots: str) -> str:
    return ARM.format(**(PLAIN | slots))


# feature -> (the model, what Pinocchio says where it does not judge, or None)
CASES = {
    "degrees are MJCF's default angle": (
        arm(l2='euler="30 -20 45"', j2='axis="0 1 0" range="-90 90" ref="10"'),
        None,
    ),
    "radians, euler zyx (intrinsic)": (
        arm(
            compiler='<compiler angle="radian" eulerseq="zyx"/>',
            l2='euler="0.5 -0.3 1.2"',
            l3='euler="-1 0.2 0.1"',
        ),
        None,
    ),
    "euler zxz (a proper Euler sequence)": (
        arm(compiler='<compiler eulerseq="zxz"/>', l2='euler="30 50 -70"'),
        None,
    ),
    "euler XYZ (extrinsic)": (
        arm(compiler='<compiler eulerseq="XYZ"/>', l2='euler="30 50 -70"'),
        "extrinsic-euler",
    ),
    "euler xYz (mixed)": (
        arm(compiler='<compiler eulerseq="xYz"/>', l2='euler="30 50 -70"'),
        "extrinsic-euler",
    ),
    "quat, unnormalised, w first, negative w": (
        arm(l2='quat="-1 2 0.5 3"', tool='quat="0 0 0 1"'),
        None,
    ),
    "axisangle of a unit axis, in degrees": (
        arm(l2='axisangle="0 0.6 0.8 70"'),
        None,
    ),
    "axisangle of an axis not of unit length": (
        arm(l2='axisangle="0 3 4 70"'),
        "axisangle-length",
    ),
    "xyaxes, y not perpendicular to x": (
        arm(l2='xyaxes="1 1 0 0.3 1 0.5"'),
        None,
    ),
    "zaxis, and zaxis against z (half a turn about x)": (
        arm(l2='zaxis="1 -2 0.5"', l3='zaxis="0 0 -3"'),
        None,
    ),
    "a joint's pos off the body's origin": (
        arm(j2='axis="0 1 0" pos="0.03 -0.04 0.05"', j3='axis="1 1 0" pos="-0.1 0 0.02"'),
        None,
    ),
    "several joints in one body, each about its own pos": (
        arm(
            j2='axis="0 1 0" pos="0.03 0 0"/><joint name="j2b" axis="1 0 0" pos="0 0.02 0.05"'
            ' ref="20"/><joint name="j2c" type="slide" axis="0 1 1" pos="0.1 0 0" ref="0.02"'
        ),
        None,
    ),
    "ref: hinge in degrees, slide in length": (
        arm(j1='axis="0 0 1" ref="35"', j3='type="slide" axis="1 0 0.5" ref="0.04"'),
        None,
    ),
    "slide joints": (
        arm(j2='type="slide" axis="0 1 0" range="-0.1 0.2"', j3='type="slide" axis="1 0 1"'),
        None,
    ),
    "default classes, childclass, class on the element": (
        arm(
            defaults="""<default><joint axis="1 0 0"/>
            <default class="arm"><joint axis="0 1 0" range="-100 100"/>
              <default class="wrist"><joint axis="1 1 0" ref="15"/></default></default>
            <default class="slider"><joint type="slide" axis="0 0 1"/></default></default>""",
            l1='childclass="arm"',
            j1="",
            j2='class="wrist"',
            j3='class="slider"',
        ),
        None,
    ),
    "a joint's pos from its default class": (
        arm(
            defaults='<default><default class="off"><joint pos="0.02 0.03 0"/></default></default>',
            j2='class="off" axis="0 1 0"',
        ),
        "joint-pos-defaults",
    ),
    "a site placed by its default class": (
        arm(defaults='<default><site pos="0 0 0.2" euler="0 90 0"/></default>', tool=""),
        "site-defaults",
    ),
    "a site placed by fromto": (
        arm(tool='type="capsule" size="0.01" fromto="0 0 0 0.1 0.2 0.05"'),
        "site-fromto",
    ),
    "<frame> elements: nested, around bodies, joints and sites, with childclass": (
        """<mujoco><default><default class="c"><joint axis="0 1 0"/></default></default>
        <worldbody><body name="base"><geom size="0.02"/>
          <frame pos="0.1 0 0.2" euler="0 0 30">
            <body name="l1" pos="0 0.1 0"><geom size="0.02"/><joint name="j1" axis="0 0 1"/>
              <frame pos="0 0 0.1" euler="40 0 0" childclass="c">
                <frame pos="0.05 0 0" zaxis="1 0 1"><joint name="j2" pos="0 0.02 0"/></frame>
                <body name="l2" pos="0.2 0 0"><geom size="0.02"/><joint name="j3"/>
                  <frame euler="0 20 0"><site name="tool" pos="0 0 0.1"/></frame>
                </body>
              </frame>
            </body>
          </frame></body></worldbody></mujoco>""",
        "frame",
    ),
    "several <compiler> elements, one after <worldbody>": (
        arm(l2='euler="0.5 -0.3 1.2"', tail='<compiler eulerseq="zyx"/><compiler angle="radian"/>'),
        "compiler-order",
    ),
    "unnamed bodies and joints": (
        """<mujoco><worldbody>
          <body><joint name="j1" axis="0 0 1"/><geom size="0.02"/>
            <body pos="0.2 0 0" euler="0 20 0"><joint axis="0 1 0" pos="0.01 0 0"/>
              <geom size="0.02"/><site name="tool" pos="0.1 0 0"/></body></body>
        </worldbody></mujoco>""",
        "unnamed-body",
    ),
    "bodies without joints on the chain, a site as the base beside the chain": (
        arm(l2='euler="0 0 20"', tool='pos="0.05 0.01 0.1" euler="10 0 0"').replace(
            '<geom size="0.02"/>\n      <body name="l1"',
            '<geom size="0.02"/><body name="plate" pos="0 0.1 0.05" euler="5 0 0">'
            '<site name="mount" pos="0.01 0 0.02" euler="0 0 45"/></body>\n      <body name="l1"',
        ),
        None,
    ),
}
BASE_TIP = {
    "bodies without joints on the chain, a site as the base beside the chain": ("mount", "tool"),
    "unnamed bodies and joints": ("world", "tool"),
}


@pytest.mark.parametrize("case", CASES)
def test_a_feature_read_as_the_oracles_read_it(case, tmp_path):
    text, misread = CASES[case]
    source = opened(tmp_path, text)
    base, tip = BASE_TIP.get(case, ("base", "tool"))
    model = source.model(base, tip)
    assert model.n >= 2
    expected = None if misread is None else PINOCCHIO_MISREADS[misread]
    worst = agrees(source, model, expected)
    assert worst["mujoco"] <= 1e-14
    if misread is not None:
        assert misread in source.mjcf.features


@pytest.mark.parametrize(
    "case", [c for c, (_, misread) in CASES.items() if misread not in (None, "frame")]
)
def test_pinocchio_does_misread_what_it_is_not_asked_to_judge(case, tmp_path):
    text, misread = CASES[case]
    source = opened(tmp_path, text)
    assert misread in source.mjcf.features
    nq = source.mjcf.nq
    assert oracles_differ(source.document.decode(), "tool", nq) > 1e-6, case


def test_pinocchio_does_not_read_frames(tmp_path):
    text = CASES["<frame> elements: nested, around bodies, joints and sites, with childclass"][0]
    model = pinocchio_model(text)
    assert model.nq == 0 and opened(tmp_path, text).mjcf.nq == 3  # the bodies in frames are lost


def test_a_chain_from_the_world_through_a_placed_body_without_joints(tmp_path):
    """Pinocchio drops where a jointless body of <worldbody> stands (Menagerie's UR10e: its
    base turned a quarter about z): MuJoCo alone judges a chain from the world through one."""
    source = opened(tmp_path, arm(base='euler="0 0 90"'))
    agrees(source, source.model("world", "tool"), PINOCCHIO_WORLD_BODY)
    agrees(source, source.model("base", "tool"))  # from the body itself, both judge
    assert oracles_differ(source.document.decode(), "tool", 3) > 1e-6


def test_features_a_model_does_not_use_are_not_noted(tmp_path):
    source = opened(tmp_path, CASES["default classes, childclass, class on the element"][0])
    assert source.mjcf.features == frozenset()
    assert set(PINOCCHIO_MISREADS) <= set(FEATURES)


def test_the_joint_zero_is_qpos_zero_not_ref(tmp_path):
    """The chain's home pose is MuJoCo's pose at qpos = 0: the file draws the arm at ref."""
    text = arm(compiler='<compiler angle="radian"/>', j1='axis="0 0 1" ref="0.5"',
               j3='type="slide" axis="1 0 0" ref="0.04"')  # fmt: skip
    model = opened(tmp_path, text).model("base", "tool")
    plain = opened(
        tmp_path,
        arm(compiler='<compiler angle="radian"/>'),
    ).model("base", "tool")
    # at q = 0 the tip lies where the file without refs draws it, turned back by ref
    assert not np.allclose(model.home, plain.home)
    q = np.array([0.5, 0.0, 0.04])
    assert np.allclose(model.fk(q), plain.fk(np.zeros(3)), atol=1e-14)


def test_ranges_in_the_compiler_unit_and_autolimits(tmp_path):
    text = arm(j1='axis="0 0 1" range="-90 45"', j2='type="slide" axis="0 1 0" range="-0.1 0.2"',
               j3='axis="1 0 0" range="-10 10" limited="false"')  # fmt: skip
    model = opened(tmp_path, text).model()
    lower = [j.lower for j in model.joints]
    upper = [j.upper for j in model.joints]
    assert lower[:2] == [pytest.approx(-math.pi / 2, abs=1e-15), -0.1] and lower[2] is None
    assert upper[:2] == [pytest.approx(math.pi / 4, abs=1e-15), 0.2] and upper[2] is None
    text = arm(compiler='<compiler angle="radian" autolimits="false"/>',
               j1='axis="0 0 1" range="-1 2" limited="true"')  # fmt: skip
    radian = opened(tmp_path, text).model()
    assert (radian.joints[0].lower, radian.joints[0].upper) == (-1.0, 2.0)
    reversed_range = opened(tmp_path, arm(j1='axis="0 0 1" range="10 -10"')).model()
    assert reversed_range.joints[0].lower is None  # MuJoCo: no limits (autolimits)


def test_a_linear_coupling_is_a_mimic_joint_as_mujoco_reads_it(tmp_path):
    """j3 = ref3 + a0 + a1 (j2 - ref2): MuJoCo's oracle sets j3 from its own compiled equality,
    so the offset's refs are checked too."""
    text = arm(j2='axis="0 1 0" ref="12"', j3='axis="1 0 0" ref="-7"',
               tail='<equality><joint joint1="j3" joint2="j2" polycoef="0.1 -2.5 0 0 0"/>'
                    "</equality>")  # fmt: skip
    source = opened(tmp_path, text)
    model = source.model("base", "tool")
    follower = model.joints[2]
    assert follower.mimic is not None and follower.mimic.joint == "j2"
    ref2, ref3 = math.radians(12), math.radians(-7)
    assert follower.mimic.multiplier == -2.5
    assert follower.mimic.offset == pytest.approx(ref3 + 0.1 + 2.5 * ref2, abs=1e-15)
    assert model.dof == 2
    agrees(source, model)
    inactive = opened(tmp_path, text.replace("<joint joint1", '<joint active="false" joint1'))
    assert inactive.model("base", "tool").dof == 3


@pytest.mark.parametrize(
    ("tail", "refusal"),
    [
        ('<equality><joint joint1="j3" joint2="j2" polycoef="0 1 0.5 0 0"/></equality>',
         "follows 'j2' by a polynomial of degree 2"),
        ('<equality><joint joint1="j3" polycoef="0.2"/></equality>',
         "is held at 0.2 from its ref by an <equality><joint> without joint2"),
    ],
)  # fmt: skip
def test_a_coupling_no_mimic_relation_describes_is_refused_unless_ignored(tail, refusal, tmp_path):
    source = opened(tmp_path, arm(tail=tail))
    with pytest.raises(ChainError, match="only linear couplings are mimic joints") as e:
        source.model("base", "tool")
    assert refusal in str(e.value) and "joint 'j3' on the chain 'base' -> 'tool'" in str(e.value)
    assert e.value.remedy is not None and e.value.remedy.argument == "ignore_mimic"
    model = source.model("base", "tool", ignore_mimic=True)
    assert model.dof == 3 and any("treated as an independent joint" in w for w in model.warnings)
    assert source.model("base", "l2").dof == 2  # a chain without it is read


@pytest.mark.parametrize("kind", ["free", "ball"])
def test_free_and_ball_joints_are_refused_on_a_chain_and_read_above_its_base(kind, tmp_path):
    joint = '<freejoint name="float"/>' if kind == "free" else '<joint name="float" type="ball"/>'
    text = arm(base='euler="0 0 10"').replace(
        '<geom size="0.02"/>\n      <body name="l1"',
        f'{joint}<geom size="0.02"/>\n      <body name="l1"',
    )
    source = opened(tmp_path, text)
    with pytest.raises(
        ChainError, match=f"joint 'float' on the chain 'world' -> 'tool' is a {kind} joint"
    ):
        source.model("world", "tool")
    model = source.model("base", "tool")
    assert model.dof == 3
    agrees(source, model)


def test_include_files_are_spliced_from_the_sources_directory(tmp_path):
    """Includes: defaults and bodies from other files, a nested include found beside the file
    that includes it (MuJoCo looks beside the SOURCE first)."""
    (tmp_path / "parts").mkdir()
    write(tmp_path / "parts", '<mujoco><default><default class="c"><joint axis="0 1 0" '
          'ref="10"/></default></default></mujoco>', "defaults.xml")  # fmt: skip
    write(tmp_path / "parts", '<mujoco><body name="l2" pos="0.2 0 0.1" euler="0 30 0">'
          '<geom size="0.02"/><joint name="j2" class="c"/><include file="tip.xml"/></body>'
          "</mujoco>", "link.xml")  # fmt: skip
    write(tmp_path / "parts", '<anything><site name="tool" pos="0 0.05 0.1"/></anything>',
          "tip.xml")  # fmt: skip
    main = write(tmp_path, '<mujoco><include file="parts/defaults.xml"/><worldbody>'
                 '<body name="base"><geom size="0.02"/><body name="l1" pos="0 0 0.3">'
                 '<geom size="0.02"/><joint name="j1"/><include file="parts/link.xml"/>'
                 "</body></body></worldbody></mujoco>")  # fmt: skip
    source = open_source(str(main))
    model = source.model("base", "tool")
    assert [j.name for j in model.joints] == ["j1", "j2"]
    assert b"include" not in source.document
    agrees(source, model)


def test_sites_and_bodies_sharing_a_name_are_both_links(tmp_path):
    text = arm(tool='pos="0.05 0.01 0.1"').replace('<site name="tool"', '<site name="l3"')
    tree = opened(tmp_path, text).tree
    assert "l3" in tree.links and "site:l3" in tree.links
    model = opened(tmp_path, text).model("base", "site:l3")
    assert model.n == 3
