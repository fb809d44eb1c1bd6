"""URDF -> chain -> POE: fixed joints folded, continuous joints revolute, meshes never needed."""

from __future__ import annotations

import numpy as np
import pytest

from urdf2dh.errors import ChainError
from urdf2dh.io.urdf import parse_tree, tree_to_poe

ARM = """<robot name="arm">
  <link name="base"><visual><geometry><mesh filename="package://nowhere/base.stl"/></geometry>
  </visual></link>
  <link name="l1"><visual><geometry><mesh filename="file:///missing/l1.dae"/></geometry></visual>
  </link>
  <link name="l2"/><link name="l3"/><link name="flange"/><link name="camera"/>
  <joint name="mount" type="fixed"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1" rpy="0 0 1.5707963267948966"/></joint>
  <joint name="j1" type="continuous"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.2 0 0"/><axis xyz="0 0 2"/></joint>
  <joint name="j2" type="prismatic"><parent link="l2"/><child link="l3"/>
    <origin xyz="0 0.3 0" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="0.4" effort="1" velocity="1"/></joint>
  <joint name="to_flange" type="fixed"><parent link="l3"/><child link="flange"/>
    <origin xyz="0 0 0.05"/></joint>
  <joint name="to_camera" type="fixed"><parent link="l2"/><child link="camera"/></joint>
</robot>"""


def test_missing_meshes_fixed_folding_and_joint_kinds():
    tree = parse_tree(ARM.encode(), "arm.urdf")
    assert tree.root == "base"
    model = tree_to_poe(tree, tip="flange")
    assert [j.name for j in model.joints] == ["j1", "j2"]
    assert [j.kind for j in model.joints] == ["revolute", "prismatic"]
    j1, j2 = model.joints
    assert np.allclose(j1.axis, [0, 0, 1]) and j1.scale == 1.0  # axis normalised
    assert np.allclose(j1.point, [0, 0.2, 0.1])  # mount's quarter turn folded in
    assert j1.lower is None  # continuous
    assert (j2.lower, j2.upper) == (0.0, 0.4)
    # Rz(90) Rx(90) takes z to +x: j2 slides along +x, and the flange sits 0.05 along it
    assert np.allclose(j2.axis, [1, 0, 0], atol=1e-15)
    assert np.allclose(model.home[:3, 3], [-0.3 + 0.05, 0.2, 0.1], atol=1e-12)


def test_default_tip_is_the_single_deepest_leaf():
    tree = parse_tree(ARM.encode(), "arm.urdf")
    assert tree.default_tip("base") == "flange"
    assert tree_to_poe(tree).tip_link == "flange"
    with pytest.raises(ChainError, match="not below base link 'flange'"):
        tree_to_poe(tree, base="flange", tip="camera")
