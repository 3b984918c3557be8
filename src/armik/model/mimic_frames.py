"""Frames that hang from a mimic joint off the chain whose driver moves on the chain (a
parallelogram's passive link, a finger driven by a chain joint).

The reduced model holds every joint off the chain fixed at its reference value, so such a
frame would stay put while its driver turns; ROS tools (robot_state_publisher, yourdfpy)
move the mimic joint with its driver. Their placements and Jacobians are read on the
URDF's whole model instead, each mimic joint at multiplier x driver + offset; so are the
collision objects they carry (``followed_objects``, ``place_followed``).
"""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from armik.model.derived import Derived, DerivedBy
from armik.model.mimic import joint_of
from armik.model.reduce import frame_id, set_joint

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel


def followers(arm: ArmModel) -> dict[int, tuple[int, float, float]]:
    """Whole-model joint id of each mimic joint the chain's model holds fixed although its
    driver moves on the chain -> (driver's index in q, multiplier, offset). A mimic joint
    locked by name stays at its value. Found once per arm (every collision query reads it)."""
    return _FOLLOWERS(arm)


def _followers(arm: ArmModel) -> dict[int, tuple[int, float, float]]:
    chain, info = arm.chain, arm.info
    fixed = set(chain.locked_joints)
    out = {}
    for name, driver in info.mimic.items():
        if driver not in arm.joint_names or name in chain.locked:
            continue
        jid = joint_of(chain.full, name)
        if jid in fixed:
            m, c = info.mimic_factors.get(name, (1.0, 0.0))
            out[jid] = (arm.joint_names.index(driver), m, c)
    return out


_FOLLOWERS: Derived[dict] = Derived("mimic joints off the chain that follow it", _followers)


def full_frame(arm: ArmModel, frame: str) -> int | None:
    """The whole model's id of ``frame`` when a follower (``followers``) moves it, else
    None: its placement in the chain's model is then the whole story. Found once per arm
    and frame."""
    if not followers(arm):
        return None
    return _FULL_FRAME(arm, frame)


def _full_frame(arm: ArmModel, frame: str) -> int | None:
    moved = followers(arm)
    full = arm.chain.full
    if not full.existFrame(frame):
        return None
    fid = frame_id(full, frame)
    j = full.frames[fid].parentJoint
    while j > 0:
        if j in moved:
            return fid
        j = full.parents[j]
    return None


_FULL_FRAME: DerivedBy[int | None] = DerivedBy("a frame a follower moves", _full_frame)


def _data(arm: ArmModel) -> pin.Data:
    """This thread's data of the whole model (``placement``, ``jacobian``)."""
    local = _LOCAL(arm)
    data = getattr(local, "data", None)
    if data is None:
        data = local.data = arm.chain.full.createData()
    return data


_LOCAL: Derived[threading.local] = Derived(
    "each thread's data of the whole model", lambda arm: threading.local()
)


def _full_q(arm: ArmModel, q: np.ndarray) -> np.ndarray:
    """The whole model's configuration at q: the reference one (locked values), the
    chain's joints at q, and every mimic joint of a moving driver following it."""
    full = arm.chain.full
    qf = np.array(arm.chain.q_ref, dtype=float)
    for name, value in zip(arm.joint_names, q):
        set_joint(full, qf, joint_of(full, name), float(value))
    for mimic in arm.chain.mimics:
        k = arm.joint_names.index(mimic.driver)
        set_joint(full, qf, joint_of(full, mimic.name), mimic.multiplier * q[k] + mimic.offset)
    for jid, (k, m, c) in followers(arm).items():
        set_joint(full, qf, jid, m * q[k] + c)
    return qf


def placement(arm: ArmModel, q: object, fid: int) -> pin.SE3:
    """``T_base_frame`` of the whole model's frame ``fid`` at q."""
    full, data = arm.chain.full, _data(arm)
    pin.framesForwardKinematics(full, data, _full_q(arm, arm.check_q(q)))
    return arm.T_base_world * data.oMf[fid]


def jacobian(arm: ArmModel, q: object, fid: int, kind: pin.ReferenceFrame) -> np.ndarray:
    """The 6 x dof Jacobian of the whole model's frame ``fid`` at q (``kind``: LOCAL or
    LOCAL_WORLD_ALIGNED): each mimic joint's column folded into its driver's, times its
    multiplier, as the chain's model folds them (``_fold``)."""
    qv = np.asarray(arm.check_q(q), dtype=float)
    Jf = pin.computeFrameJacobian(arm.chain.full, _data(arm), _full_q(arm, qv), fid, kind)
    return Jf.reshape(6, -1) @ _FOLD(arm)  # type: ignore[no-any-return]


def placed(
    arm: ArmModel, q: object, fid: int, kind: pin.ReferenceFrame
) -> tuple[pin.SE3, np.ndarray]:
    """(``placement``, ``jacobian``) of frame ``fid`` at q from one pass of the whole
    model's kinematics (the task solver asks for both at every step)."""
    full, data = arm.chain.full, _data(arm)
    pin.computeJointJacobians(full, data, _full_q(arm, np.asarray(arm.check_q(q), dtype=float)))
    T = arm.T_base_world * pin.updateFramePlacement(full, data, fid)
    return T, pin.getFrameJacobian(full, data, fid, kind).reshape(6, -1) @ _FOLD(arm)


def followed_objects(arm: ArmModel, geom: pin.GeometryModel) -> tuple:
    """(object index, whole-model joint id, placement in that joint) of each object of
    ``geom`` (on the whole model) that a follower (``followers``) moves."""
    moved = followers(arm)
    if not moved:
        return ()
    parents = arm.chain.full.parents
    out = []
    for i, o in enumerate(geom.geometryObjects):
        j = o.parentJoint
        while j > 0 and j not in moved:
            j = parents[j]
        if j > 0:
            out.append((i, o.parentJoint, o.placement.copy()))
    return tuple(out)


def place_followed(
    arm: ArmModel, q: np.ndarray, gd: pin.GeometryData, followed: tuple, data: pin.Data
) -> None:
    """Put each of ``followed``'s objects (``followed_objects``) where the whole model
    places it at q, in ``gd``'s world placements (the chain's model left them at the
    reference value); ``data``: the whole model's, the caller's thread's."""
    full = arm.chain.full
    pin.forwardKinematics(full, data, _full_q(arm, np.asarray(q, dtype=float)))
    for i, joint, placement in followed:
        gd.oMg[i] = data.oMi[joint] * placement


def place_followed_moving(
    arm: ArmModel, q: np.ndarray, gd: pin.GeometryData, followed: tuple, data: pin.Data
) -> None:
    """``place_followed``, with the whole model's joint Jacobians at q computed in ``data``
    too, for ``followed_jacobian`` (a servo's collision rows on a followed object)."""
    full = arm.chain.full
    pin.computeJointJacobians(full, data, _full_q(arm, np.asarray(q, dtype=float)))
    for i, joint, placement in followed:
        gd.oMg[i] = data.oMi[joint] * placement


def followed_jacobian(arm: ArmModel, data: pin.Data, joint: int) -> np.ndarray:
    """The 6 x dof Jacobian (LOCAL_WORLD_ALIGNED, at the origin of the whole model's joint
    ``joint``) over the chain's joints, from ``data``'s Jacobians (``place_followed_moving``):
    each mimic joint's column folded into its driver's, times its multiplier."""
    J = pin.getJointJacobian(arm.chain.full, data, joint, pin.LOCAL_WORLD_ALIGNED)
    return J.reshape(6, -1) @ _FOLD(arm)  # (one joint: Pinocchio gives (6,))  # type: ignore[no-any-return]


def _fold(arm: ArmModel) -> np.ndarray:
    """(whole model's nv, dof): a whole-model Jacobian's columns onto the chain's joints."""
    full = arm.chain.full
    F = np.zeros((full.nv, arm.dof))
    for k, name in enumerate(arm.joint_names):
        F[full.joints[joint_of(full, name)].idx_v, k] = 1.0
    for mimic in arm.chain.mimics:
        k = arm.joint_names.index(mimic.driver)
        F[full.joints[joint_of(full, mimic.name)].idx_v, k] += mimic.multiplier
    for jid, (k, m, _) in followers(arm).items():
        F[full.joints[jid].idx_v, k] += m
    return F


_FOLD: Derived[np.ndarray] = Derived("a whole-model Jacobian's columns on the chain", _fold)
