"""An arm model read into the compiled kernel's plain arrays (``armik.kernel.chain.Chain``):
the one place that reads a Pinocchio model for the kernel, so the kernel itself takes
arrays and never an arm model."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from armik.kernel.chain import (
    CONTINUOUS,
    PRISMATIC,
    REVOLUTE,
    Chain,
    Flat,
    KernelChain,
    flat_kinds,
    flatten,
    halton,
)

if TYPE_CHECKING:
    from armik.model.arm_view import ArmView


def build_chain(arm: ArmView) -> KernelChain:
    """Read ``arm``'s chain from its Pinocchio model of physical joints
    (``arm.physical_model``: a mimic joint there is a joint of its own) and its mimic map
    (``arm.joint_map``). Raises ``ValueError`` if the model is not a serial chain of
    one-degree-of-freedom joints ending at the tip frame."""
    model = arm.physical_model
    N = model.njoints - 1
    driver, multiplier, offset = arm.joint_map
    if model.nv != N or len(driver) != N:
        raise ValueError(f"expected {N} one-degree-of-freedom joints, model has nv = {model.nv}")
    frame = model.frames[arm.tip_frame_id]
    if frame.parentJoint != N:
        raise ValueError(f"tip frame {frame.name!r} is not attached to the last joint")
    data = model.createData()
    q = pin.neutral(model)
    pin.computeJointJacobians(model, data, q)
    joint_R = np.empty((N, 3, 3))
    joint_p = np.empty((N, 3))
    axis = np.empty((N, 3))
    joint_kind = np.empty(N, dtype=np.int64)
    for i in range(N):
        j = i + 1
        if model.parents[j] != j - 1:
            raise ValueError(f"joint {model.names[j]!r} does not follow the previous joint")
        M = model.jointPlacements[j]
        if j == 1:
            M = arm.T_base_world * M
        joint_R[i], joint_p[i] = M.rotation, M.translation
        # The joint's motion subspace, expressed in its own frame, at the neutral pose.
        # (Pinocchio hands a one-column Jacobian back as a vector: reshape it)
        S = np.reshape(pin.getJointJacobian(model, data, j, pin.LOCAL), (6, -1))
        S = S[:, model.joints[j].idx_v]
        lin, ang = S[:3], S[3:]
        if np.linalg.norm(ang) > 0.5 and np.linalg.norm(lin) < 1e-12:
            axis[i] = ang / np.linalg.norm(ang)
            joint_kind[i] = CONTINUOUS if model.joints[j].nq == 2 else REVOLUTE
        elif np.linalg.norm(lin) > 0.5 and np.linalg.norm(ang) < 1e-12:
            axis[i] = lin / np.linalg.norm(lin)
            joint_kind[i] = PRISMATIC
        else:
            raise ValueError(f"joint {model.names[j]!r} is neither revolute nor prismatic")
    kind = np.empty(arm.dof, dtype=np.int64)
    for k, i in enumerate(arm.driving_joints):
        kind[k] = joint_kind[i]
    # A driver of mimic joints has no 2 pi period (they would turn by multiplier x 2 pi):
    # the descent reads only whether a joint wraps, so it is not shifted, as a prismatic.
    for i in set(range(N)) - set(arm.driving_joints):  # the mimic joints
        kind[driver[i]] = PRISMATIC
    lo, hi = arm.sampling_box()
    n = arm.dof
    ch = Chain(
        joint_R,
        joint_p,
        axis,
        kind,
        frame.placement.rotation.copy(),
        frame.placement.translation.copy(),
        np.asarray(arm.lower, dtype=float).copy(),
        np.asarray(arm.upper, dtype=float).copy(),
        lo.astype(float),
        (hi - lo).astype(float),
        halton(n).copy(),  # writable: numba types read-only arrays apart
        np.asarray(arm.first_joint_origin, dtype=float).copy(),
        float(arm.reach) if math.isfinite(arm.reach) else math.inf,
        arm.T_base_world.rotation.copy(),
        arm.T_base_world.translation.copy(),
        joint_kind,
        np.asarray(driver, dtype=np.int64).copy(),
        np.asarray(multiplier, dtype=float).copy(),
        np.asarray(offset, dtype=float).copy(),
    )
    return KernelChain(ch, Flat(flatten(ch), flat_kinds(ch), ch.halton))
