"""The kernel's view of an arm: plain arrays read once from the reduced Pinocchio model.

Joint values are the user's (one per joint: rad or m); a continuous joint is one angle,
not Pinocchio's (cos, sin) pair. Frames: joint i is placed in joint i - 1 by
``joint_R[i], joint_p[i]`` (joint 0 in the arm's base frame: the base transform is folded
in), turns about or slides along ``axis[i]`` (unit, in its own frame), and the tip frame is
placed in the last joint by ``tip_R, tip_p``. The kernel's FK is therefore ``T_base_tip``.
"""

from __future__ import annotations

import math
from functools import cache
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
import pinocchio as pin

if TYPE_CHECKING:
    from ..arm import Arm

REVOLUTE, PRISMATIC, CONTINUOUS = 0, 1, 2
HALTON_POINTS = 512  # restart seeds cycle through this many points of the sequence
_PRIMES = (2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37)


class Chain(NamedTuple):
    """Plain arrays describing a serial chain (see the module docstring)."""

    joint_R: np.ndarray  # (n, 3, 3)
    joint_p: np.ndarray  # (n, 3) m
    axis: np.ndarray  # (n, 3) unit
    kind: np.ndarray  # (n,) int64: REVOLUTE, PRISMATIC or CONTINUOUS
    tip_R: np.ndarray  # (3, 3)
    tip_p: np.ndarray  # (3,) m
    lower: np.ndarray  # (n,) rad or m, -inf where unlimited
    upper: np.ndarray  # (n,)
    sample_lo: np.ndarray  # (n,) the restart box: the limits, [-pi, pi] where unlimited
    sample_span: np.ndarray  # (n,)
    halton: np.ndarray  # (HALTON_POINTS, n) in [0, 1)
    origin: np.ndarray  # (3,) first joint's origin in the base frame (m)
    reach: float  # upper bound on the distance from ``origin`` to the tip (m)


def build_chain(arm: Arm) -> Chain:
    """Read ``arm``'s chain from its Pinocchio model. Raises ``ValueError`` if the model
    is not a serial chain of one-degree-of-freedom joints ending at the tip frame."""
    model = arm.model
    n = model.njoints - 1
    if model.nv != n or arm.dof != n:
        raise ValueError(f"expected {n} one-degree-of-freedom joints, model has nv = {model.nv}")
    frame = model.frames[arm.tip_frame_id]
    if frame.parentJoint != n:
        raise ValueError(f"tip frame {frame.name!r} is not attached to the last joint")
    data = model.createData()
    q = pin.neutral(model)
    pin.computeJointJacobians(model, data, q)
    joint_R = np.empty((n, 3, 3))
    joint_p = np.empty((n, 3))
    axis = np.empty((n, 3))
    kind = np.empty(n, dtype=np.int64)
    for i in range(n):
        j = i + 1
        if model.parents[j] != j - 1:
            raise ValueError(f"joint {model.names[j]!r} does not follow the previous joint")
        M = model.jointPlacements[j]
        if j == 1:
            M = arm.T_base_world * M
        joint_R[i], joint_p[i] = M.rotation, M.translation
        # The joint's motion subspace, expressed in its own frame, at the neutral pose.
        S = pin.getJointJacobian(model, data, j, pin.LOCAL)[:, model.joints[j].idx_v]
        lin, ang = S[:3], S[3:]
        if np.linalg.norm(ang) > 0.5 and np.linalg.norm(lin) < 1e-12:
            axis[i] = ang / np.linalg.norm(ang)
            kind[i] = CONTINUOUS if model.joints[j].nq == 2 else REVOLUTE
        elif np.linalg.norm(lin) > 0.5 and np.linalg.norm(ang) < 1e-12:
            axis[i] = lin / np.linalg.norm(lin)
            kind[i] = PRISMATIC
        else:
            raise ValueError(f"joint {model.names[j]!r} is neither revolute nor prismatic")
    lo, hi = arm.sampling_box()
    return Chain(
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
    )


@cache
def halton(dim: int, n: int = HALTON_POINTS) -> np.ndarray:
    """The first n points of the dim-dimensional Halton sequence, in [0, 1)^dim (beyond 12
    dimensions: fixed pseudo-random points)."""
    if dim > len(_PRIMES):
        table = np.random.default_rng(0).random((n, dim))
    else:
        table = np.zeros((n, dim))
        for j, base in enumerate(_PRIMES[:dim]):
            k = np.arange(1, n + 1)
            f = 1.0
            while k.any():  # radical inverse, one digit of all n indices at a time
                f /= base
                table[:, j] += f * (k % base)
                k //= base
    table.setflags(write=False)
    return table
