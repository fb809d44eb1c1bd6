"""MuJoCo, the second forward-kinematics oracle; the only module that imports ``mujoco``.

MuJoCo compiles the model and its ``mj_kinematics`` gives the pose of every body and site:

* an MJCF SOURCE: MuJoCo parses the document urdf2dh read (its includes spliced in), so the check
  covers urdf2dh's reading of MJCF (defaults, frames, orientations, joints, ``ref``) against
  MuJoCo's own; a joint urdf2dh made a mimic joint is set as MuJoCo's compiled equality
  constraint sets it (``joint1 = ref1 + a0 + a1 (joint2 - ref2) + ...``), so the coupling is
  MuJoCo's reading too;
* a URDF SOURCE (or a xacro file's expansion): MuJoCo's URDF import reads the same text, its
  ``<inertial>`` elements taken out (MuJoCo refuses inertias its compiler would not take, and no
  inertia moves a frame). Static bodies are not fused (``<compiler fusestatic="false">``), so
  every link keeps its frame and any link can be the base or the tip; mimic joints are set from
  the chain's own relation;
* a POE or table file: MuJoCo's model is assembled from the screws, one body per joint (a
  helical joint a hinge and a slide along one axis).

Meshes, height fields, skins and texture files are never read: mesh and height-field geoms become
small spheres and their assets are removed; masses and inertias come from the geoms, with a floor
(``inertiafromgeom``, ``boundmass``, ``boundinertia``), so that a model whose inertials MuJoCo
would refuse compiles all the same. None of that moves a frame.
Joints off the chain stay at MuJoCo's ``qpos0``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ..errors import OracleError, shown
from ..geometry.se3 import inv

if TYPE_CHECKING:
    from ..io.sources import Source
    from ..model.poe import PoeModel

__all__ = ["mujoco_evaluator"]

Mat = NDArray[np.float64]
NAME = "mujoco"


def _refusal(source: Source, why: str) -> OracleError:
    return OracleError(NAME, f"{source.display}: MuJoCo {why}")


def _mujoco(source: Source) -> Any:
    try:
        import mujoco
    except ImportError as e:
        raise _refusal(source, "is not installed; install it with: pip install mujoco") from e
    return mujoco


def _stripped(mj: Any, spec: Any) -> Any:
    """The spec with no file to read: meshes, height fields, skins and texture files gone."""
    kept = (mj.mjtGeom.mjGEOM_MESH, mj.mjtGeom.mjGEOM_HFIELD, mj.mjtGeom.mjGEOM_SDF)
    for geom in spec.geoms:
        if geom.type in kept:
            geom.type = mj.mjtGeom.mjGEOM_SPHERE
            geom.size = [1e-3, 0.0, 0.0]
            geom.meshname = ""
            geom.hfieldname = ""
    for assets in (spec.meshes, spec.hfields, spec.skins):
        for asset in list(assets):
            spec.delete(asset)
    for texture in spec.textures:
        texture.file = ""
        texture.cubefiles = [""] * 6
        texture.builtin = mj.mjtBuiltin.mjBUILTIN_FLAT
        texture.width = texture.height = 1
    for body in spec.bodies:  # inertia from the geoms: a file's own may not be one MuJoCo takes
        body.explicitinertial = False
    spec.compiler.fusestatic = False
    spec.compiler.inertiafromgeom = mj.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
    spec.compiler.boundmass = 1e-9
    spec.compiler.boundinertia = 1e-12
    return spec


def _without_inertials(source: Source) -> str:
    """The URDF text without its links' ``<inertial>`` elements: MuJoCo's URDF import refuses
    an inertia its compiler would not take (TIAGo's antennas), and inertias move no frame."""
    from lxml import etree

    assert source.document is not None
    parser = etree.XMLParser(resolve_entities=False, no_network=True)
    root = etree.fromstring(source.document, parser=parser)
    for link in root.iterchildren("link"):
        for inertial in link.findall("inertial"):
            link.remove(inertial)
    return str(etree.tostring(root, encoding="unicode"))


def _from_poe(mj: Any, poe: PoeModel) -> Any:
    """MuJoCo's model of a chain given by its screws: body ``k`` holds joint ``k`` at the home
    pose (every body frame the world's there), the tip a site."""
    spec = mj.MjSpec()
    body = spec.worldbody
    prev = np.zeros(3)
    for j in poe.joints:
        point = prev if j.point is None else j.point
        body = body.add_body(name=f"body {j.name}")
        body.add_geom(size=[1e-3, 0, 0])
        if j.kind in ("revolute", "helical"):
            body.add_joint(name=j.name, type=mj.mjtJoint.mjJNT_HINGE, axis=j.axis.tolist(),
                           pos=point.tolist())  # fmt: skip
        if j.kind in ("prismatic", "helical"):
            body.add_joint(name=f"{j.name} lead" if j.kind == "helical" else j.name,
                           type=mj.mjtJoint.mjJNT_SLIDE, axis=j.axis.tolist(),
                           pos=point.tolist())  # fmt: skip
        prev = point
    quat = np.empty(4)
    mj.mju_mat2Quat(quat, poe.home[:3, :3].flatten())
    body.add_site(name="tip", pos=poe.home[:3, 3].tolist(), quat=quat.tolist())
    return spec


def _compiled(mj: Any, source: Source, poe: PoeModel) -> Any:
    """MuJoCo's compiled model of the SOURCE; an :class:`OracleError` with MuJoCo's reason."""
    warnings: list[str] = []
    previous = mj.get_mju_user_warning()
    # MuJoCo's own handler prints a warning and appends it to MUJOCO_LOG.TXT in the working
    # directory ("joint 'j1' has equal lower and upper limits"): collected here instead
    mj.set_mju_user_warning(warnings.append)
    try:
        if source.kind == "mjcf":
            assert source.document is not None
            spec = mj.MjSpec.from_string(source.document.decode("utf-8"))
        elif source.kind == "urdf":
            spec = mj.MjSpec.from_string(_without_inertials(source))
        else:
            spec = _from_poe(mj, poe)
        return _stripped(mj, spec).compile()
    except (ValueError, RuntimeError) as e:  # mujoco's parse and compile errors
        why = " ".join(str(e).split())
        raise _refusal(source, f"cannot compile it ({why})") from e
    finally:
        mj.set_mju_user_warning(previous)


def _frame(mj: Any, model: Any, source: Source, link: str) -> tuple[str, int]:
    """The MuJoCo object (``body`` or ``site``, and its id) whose frame is link ``link``."""
    kind, name = "body", link
    if source.mjcf is not None:
        element = source.mjcf.links[link]
        if element.kind == "frame" or element.name is None:
            raise _refusal(source, f"has no frame for link {shown(link)} (no body or site of the "
                           "file: urdf2dh made it)")  # fmt: skip
        kind, name = (
            ("body", element.name) if element.kind == "world" else (element.kind, element.name)
        )
    obj = mj.mjtObj.mjOBJ_SITE if kind == "site" else mj.mjtObj.mjOBJ_BODY
    found = mj.mj_name2id(model, obj, name)
    if found < 0:
        raise _refusal(source, f"has no {kind} {shown(name)}")
    return kind, int(found)


def _joint(mj: Any, model: Any, source: Source, name: str) -> int:
    """The id of the MuJoCo joint that is joint ``name`` of the chain."""
    given: str | None = name
    if source.mjcf is not None:
        element = source.mjcf.joints[name]
        given = element.name
        if given is None:  # urdf2dh named it: MuJoCo's joint at the same qpos address
            found = [i for i in range(model.njnt) if model.jnt_qposadr[i] == element.qpos]
            return found[0] if found else -1
    return int(mj.mj_name2id(model, mj.mjtObj.mjOBJ_JOINT, given))


def _couplings(mj: Any, model: Any) -> dict[int, tuple[int, NDArray[np.float64]]]:
    """Joint id -> (the joint it follows, polycoef) of MuJoCo's active joint equalities."""
    out = {}
    for k in range(model.neq):
        if model.eq_type[k] == mj.mjtEq.mjEQ_JOINT and model.eq_active0[k]:
            out[int(model.eq_obj1id[k])] = (int(model.eq_obj2id[k]), model.eq_data[k, :5].copy())
    return out


def mujoco_evaluator(source: Source, poe: PoeModel) -> Callable[[Mat], Mat]:
    """MuJoCo's pose ``(N, 4, 4)`` of the tip in the base as a function of configurations ``q``
    ``(N, dof)`` of the chain's actuated joints (module docstring).

    Raises
    ------
    OracleError
        Where MuJoCo cannot judge the chain: not installed, the model does not compile, or the
        base, tip or a joint is not one of MuJoCo's (a frame urdf2dh made between a body's
        joints).
    """
    mj = _mujoco(source)
    model = _compiled(mj, source, poe)
    data = mj.MjData(model)
    addresses, scales = [], []
    for j in poe.joints:
        found = _joint(mj, model, source, j.name)
        if found < 0:
            raise _refusal(source, f"has no joint {shown(j.name)}")
        addresses.append(int(model.jnt_qposadr[found]))
        scales.append(j.scale)
    leads = []  # a POE helical joint's slide: (its address, the hinge's row, pitch)
    if source.kind not in ("mjcf", "urdf"):
        for i, j in enumerate(poe.joints):
            if j.kind == "helical":
                lead = model.joint(f"{j.name} lead").id
                leads.append((int(model.jnt_qposadr[lead]), i, j.pitch))
    couplings = _couplings(mj, model) if source.kind == "mjcf" else {}
    followers = []  # (address, leader address, polycoef) of rows MuJoCo's equalities set
    for i, j in enumerate(poe.joints):
        found = _joint(mj, model, source, j.name)
        if j.mimic is not None and found in couplings:
            leader, coefficients = couplings[found]
            followers.append((addresses[i], int(model.jnt_qposadr[leader]), coefficients))
    if source.kind in ("mjcf", "urdf"):
        kinds = [_frame(mj, model, source, link) for link in (poe.base_link, poe.tip_link)]
    else:  # the chain runs from the world to the site "tip"
        kinds = [("body", 0), ("site", int(model.site("tip").id))]

    def pose(kind: str, index: int) -> Mat:
        out = np.eye(4)
        if kind == "site":
            out[:3, :3] = data.site_xmat[index].reshape(3, 3)
            out[:3, 3] = data.site_xpos[index]
        else:
            out[:3, :3] = data.xmat[index].reshape(3, 3)
            out[:3, 3] = data.xpos[index]
        return out

    def evaluate(q: Mat) -> Mat:
        rows = poe.positions(q)
        out = np.empty((rows.shape[0], 4, 4))
        for k, row in enumerate(rows):
            data.qpos[:] = model.qpos0
            for address, scale, value in zip(addresses, scales, row, strict=True):
                data.qpos[address] = scale * value
            for address, i, pitch in leads:
                data.qpos[address] = pitch * scales[i] * row[i]
            for address, leader, c in followers:
                x = data.qpos[leader] - model.qpos0[leader]
                data.qpos[address] = (
                    model.qpos0[address] + c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * c[4])))
                )
            mj.mj_kinematics(model, data)
            base, tip = (pose(kind, index) for kind, index in kinds)
            out[k] = tip if kinds[0] == ("body", 0) else inv(base) @ tip
        return out

    return evaluate
