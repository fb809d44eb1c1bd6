"""Any table (or POE model, through its table) -> URDF text whose forward kinematics equals it.

Each joint's URDF frame is the table's own frame at that joint (the frame whose z is the joint
axis just before ``Q_i``), so URDF -> table -> URDF -> table returns the same table. Joint
limits travel with the rows.

URDF has no helical joint and no joint scale:

* a helical joint is written as a revolute joint followed by a coaxial prismatic joint
  ``<name>_lead`` that mimics it with ``multiplier = pitch`` (exact; Pinocchio builds it with
  ``mimic=True``, and :mod:`urdf2dh.io.urdf` reads the pair back as one helical joint);
* a joint with ``scale`` other than +-1 moves by ``s = scale q``: the URDF joint's position is
  ``|scale| q`` (its limits scaled alike), and a comment and the returned notes say so.

The base and tip links and the joints keep their names; the links between them
(``<joint>_link``, ``<joint>_lead_link``), the lead joints (``<joint>_lead``) and the tip's fixed
joint (``<tip>_joint``) are made up and keep clear of those (:mod:`urdf2dh.emit.names`: a
suffix ``_2`` where the robot has the name, stated in a comment).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from .. import units
from .._version import __version__
from ..conventions.table import Row, Table
from ..errors import shown
from ..escape import xml_attribute, xml_comment
from ..geometry import se3
from .names import Namespace, renaming_notes

__all__ = ["table_to_urdf"]


def _num(x: float) -> str:
    return repr(float(x) + 0.0)


def _origin(t: NDArray[np.float64]) -> str:
    xyz = " ".join(_num(v) for v in t[:3, 3])
    rpy = " ".join(_num(v) for v in se3.rpy(t))
    return f'<origin xyz="{xyz}" rpy="{rpy}"/>'


def _joint(name: str) -> str:
    return xml_attribute(name, "joint")


def _link(name: str) -> str:
    return xml_attribute(name, "link")


def table_to_urdf(table: Table) -> tuple[str, list[str]]:
    """URDF text for ``table`` (in metres, as URDF requires) and the notes about what URDF
    could not say directly."""
    metres = units.metres_per(table.length_unit)
    frames = [f.copy() for f in table.joint_frames()]
    for f in frames:
        f[:3, 3] *= metres
    link_names = Namespace("urdf", "link", [n for n in (table.base_link, table.tip_link) if n])
    joint_names = Namespace("urdf", "joint", [r.name for r in table.rows])
    base = table.base_link or link_names.invent("base")
    tip_name = table.tip_link or link_names.invent("tool")
    links = [base]
    joints: list[str] = []
    notes: list[str] = []
    parent, prev = base, np.eye(4)
    rows = {r.name: r for r in table.rows}
    coupled = {name for r in table.rows if r.mimic for name in (r.name, r.mimic.joint)}

    def urdf_position(row: Row) -> float:
        """URDF position of ``row`` per unit of its own ``q``."""
        return abs(row.scale) * (metres if row.kind == "prismatic" else 1.0)

    for row, frame in zip(table.rows, frames[:-1], strict=True):
        scale = row.scale
        sign = 1.0 if scale > 0 else -1.0
        axis = f'<axis xyz="0 0 {_num(sign)}"/>'
        if abs(abs(scale) - 1.0) > 1e-15:
            notes.append(
                f"joint {shown(row.name)} moves by s = {scale:.10g} q: its URDF position is "
                f"{abs(scale):.10g} q (URDF joints have no scale)"
            )
        limit = ""
        if row.lower is not None and row.upper is not None:
            unit = metres if row.kind == "prismatic" else 1.0
            lo, hi = sorted((unit * abs(scale) * row.lower, unit * abs(scale) * row.upper))
            limit = f'<limit lower="{_num(lo)}" upper="{_num(hi)}" effort="0" velocity="0"/>'
        child = link_names.invent(f"{row.name}_link")
        if row.kind == "prismatic":
            jtype = "prismatic"
            limit = limit or '<limit effort="0" velocity="0"/>'
        elif row.kind == "helical" or row.name in coupled:
            jtype = "revolute"
            if not limit:
                limit = (
                    f'<limit lower="{_num(-math.pi)}" upper="{_num(math.pi)}" '
                    'effort="0" velocity="0"/>'
                )
                notes.append(
                    f"joint {shown(row.name)}: limits unknown, [-pi, pi] written (URDF revolute "
                    "joints need limits, and mimic joints cannot follow continuous ones)"
                )
        else:
            jtype = "revolute" if limit else "continuous"
        mimic = ""
        if row.mimic is not None:  # q = m q_leader + o, in each joint's URDF position
            leader = rows[row.mimic.joint]
            multiplier = urdf_position(row) * row.mimic.multiplier / urdf_position(leader)
            mimic = (
                f'    <mimic joint={_joint(leader.name)} multiplier="{_num(multiplier)}" '
                f'offset="{_num(urdf_position(row) * row.mimic.offset)}"/>\n'
            )
        joints.append(
            f'  <joint name={_joint(row.name)} type="{jtype}">\n'
            f"    <parent link={_link(parent)}/><child link={_link(child)}/>\n"
            f"    {_origin(se3.inv(prev) @ frame)}\n    {axis}\n"
            + (f"    {limit}\n" if limit else "")
            + mimic
            + "  </joint>"
        )
        links.append(child)
        parent, prev = child, frame
        if row.kind == "helical":
            lead = link_names.invent(f"{row.name}_lead_link")
            joints.append(
                f"  <joint name={_joint(joint_names.invent(row.name + '_lead'))} "
                'type="prismatic">\n'
                f"    <parent link={_link(parent)}/><child link={_link(lead)}/>\n"
                f'    <origin xyz="0 0 0" rpy="0 0 0"/>\n    {axis}\n'
                f'    <limit effort="0" velocity="0"/>\n'
                f'    <mimic joint={_joint(row.name)} multiplier="{_num(metres * row.pitch)}" '
                'offset="0"/>\n  </joint>'
            )
            links.append(lead)
            parent = lead
    joints.append(
        f'  <joint name={_joint(joint_names.invent(tip_name + "_joint"))} type="fixed">\n'
        f"    <parent link={_link(parent)}/><child link={_link(tip_name)}/>\n"
        f"    {_origin(se3.inv(prev) @ frames[-1])}\n  </joint>"
    )
    links.append(tip_name)
    converted = f"; lengths converted from {table.length_unit} to m" if metres != 1.0 else ""
    header = [
        f"Written by urdf2dh {__version__} from {table.source or table.robot} "
        f"({table.convention} table{converted}).",
        "Kinematics only: no inertias, no geometry.",
        *notes,
        *renaming_notes(link_names, joint_names),
    ]
    text = (
        '<?xml version="1.0"?>\n'
        + "".join(xml_comment(h) + "\n" for h in header)
        + f"<robot name={xml_attribute(table.robot or 'robot', 'robot name')}>\n"
        + "".join(f"  <link name={_link(n)}/>\n" for n in links)
        + "\n".join(joints)
        + "\n</robot>\n"
    )
    return text, notes
