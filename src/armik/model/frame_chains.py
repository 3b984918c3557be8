"""The kernel's view of any frame of a model: the chain of joints that moves it, read from a
Pinocchio model that may be a tree (several tips over a shared torso, an elbow of an arm).

Each frame's chain is a ``chain.Chain`` whose physical joints are the joints from the
model's root to the frame, each driven by its own value in q (the model's velocity index:
the joint values of an ``ArmModel`` or a ``Union``), so that ``fk.forward`` and
``fk.jacobian_local`` give that frame's placement and LOCAL Jacobian over every joint of
q, zero in the columns of joints off its path. The chains are packed end to end
(``FrameChains``), for the compiled task table (``armik.kernel.task_rows``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pinocchio as pin

from armik.kernel.chain import CONTINUOUS, PRISMATIC, REVOLUTE, Chain, flat_kinds, flatten, halton


class FrameChains(NamedTuple):
    """Chains packed end to end: chain c is ``packed[offsets[c]:offsets[c + 1]]`` with the
    kinds ``kinds[kind_offsets[c]:kind_offsets[c + 1]]``; ``halton`` is the restart table
    (n columns: the chains' ``dof``)."""

    packed: np.ndarray
    offsets: np.ndarray
    kinds: np.ndarray
    kind_offsets: np.ndarray
    halton: np.ndarray


def frame_chains(arm, frame_ids: tuple[int, ...]) -> FrameChains | None:
    """The chains of ``frame_ids`` (frames of ``arm.model``), in that order; None where a
    frame has no compiled form (no joint moves it, a joint of more than one degree of
    freedom). An arm with mimic joints is read from its model of physical joints, each
    driven as ``ArmModel.joint_map`` says."""
    n = arm.dof
    if getattr(arm, "mimics", ()):
        model = arm.physical_model
        driver, multiplier, offset = (np.asarray(x) for x in arm.joint_map)
        by_value = np.array(arm.kernel_chain.kind, dtype=np.int64)
    else:
        model = arm.model
        driver = np.array([model.joints[j].idx_v for j in range(1, model.njoints)], dtype=int)
        multiplier, offset = np.ones(len(driver)), np.zeros(len(driver))
        by_value = None
    axes, kinds = _joint_axes(model)
    if axes is None:
        return None
    if by_value is None:
        by_value = np.empty(n, dtype=np.int64)  # the kind of each joint value
        for j in range(1, model.njoints):
            by_value[driver[j - 1]] = kinds[j]
    lo, hi = np.asarray(arm.lower, dtype=float), np.asarray(arm.upper, dtype=float)
    sample_lo = np.where(np.isfinite(lo), lo, -np.pi)
    span = np.where(np.isfinite(hi), hi, np.pi) - sample_lo
    packed, kind_parts = [], []
    for fid in frame_ids:
        own = arm.model.frames[fid]  # by name and type: a joint and its link may share a name
        frame = model.frames[model.getFrameId(own.name, own.type)]
        path = [j for j in model.supports[frame.parentJoint] if j > 0]
        if not path:
            return None
        on = [j - 1 for j in path]  # their indices in ``driver``, ``multiplier``, ``offset``
        placements = [model.jointPlacements[j] for j in path]
        placements[0] = arm.T_base_world * placements[0]  # the base frame folded in
        joints = [
            (M.rotation, M.translation, axes[j], kinds[j], driver[i], multiplier[i], offset[i])
            for M, j, i in zip(placements, path, on)
        ]
        if len(joints) == n and [x[4:] for x in joints] != [(k, 1.0, 0.0) for k in range(n)]:
            # n physical joints are read by ``fk`` as q itself: one that never moves (driven
            # by q[0] times 0) makes them n + 1, read through their drivers
            joints.append(
                (np.eye(3), np.zeros(3), np.array([0.0, 0.0, 1.0]), REVOLUTE, 0, 0.0, 0.0)
            )
        R, t, axis, kind, drivers, times, plus = (np.array(x) for x in zip(*joints))
        ch = Chain(
            R,
            t,
            axis,
            by_value,
            frame.placement.rotation.copy(),
            frame.placement.translation.copy(),
            lo,
            hi,
            sample_lo,
            span,
            halton(n).copy(),
            np.zeros(3),
            np.inf,
            arm.T_base_world.rotation.copy(),
            arm.T_base_world.translation.copy(),
            kind.astype(np.int64),
            drivers.astype(np.int64),
            times.astype(float),
            plus.astype(float),
        )
        packed.append(flatten(ch))
        kind_parts.append(flat_kinds(ch))
    return FrameChains(
        np.concatenate(packed),
        np.cumsum([0] + [len(p) for p in packed]).astype(np.int64),
        np.concatenate(kind_parts),
        np.cumsum([0] + [len(k) for k in kind_parts]).astype(np.int64),
        halton(n).copy(),  # writable: numba types read-only arrays apart
    )


def _joint_axes(model: pin.Model) -> tuple[dict | None, dict]:
    """Each joint's unit axis in its own frame and its kind (``chain``'s), from its motion
    subspace at the neutral configuration; (None, {}) where a joint is neither a revolute
    nor a prismatic joint of one degree of freedom."""
    data = model.createData()
    pin.computeJointJacobians(model, data, pin.neutral(model))
    axes, kinds = {}, {}
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.nv != 1:
            return None, {}
        S = np.reshape(pin.getJointJacobian(model, data, j, pin.LOCAL), (6, -1))[:, joint.idx_v]
        lin, ang = S[:3], S[3:]
        if np.linalg.norm(ang) > 0.5 and np.linalg.norm(lin) < 1e-12:
            axes[j] = ang / np.linalg.norm(ang)
            kinds[j] = CONTINUOUS if joint.nq == 2 else REVOLUTE
        elif np.linalg.norm(lin) > 0.5 and np.linalg.norm(ang) < 1e-12:
            axes[j] = lin / np.linalg.norm(lin)
            kinds[j] = PRISMATIC
        else:
            return None, {}
    return axes, kinds
