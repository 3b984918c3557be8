"""Restarts along a prismatic joint without a limit (a rail whose URDF limits read "0 0",
``with_limits`` to infinity): centred where the rail brings the tip nearest the target.

The kernel draws restart seeds in the chain's sampling box, ``[-pi, pi]`` m for such a
joint (``ArmModel.sampling_box``), and a step moves at most ``kernel.step.MAX_STEP``, with
an attempt whose error falls too slowly given up (``kernel.descent``): a target tens of
metres along the rail was never reached (the gantry at 50 m: 1000 restarts,
``not_converged``). For a solve on such an arm the kernel gets a copy of the chain whose box
for those joints is as wide as before, ``2 pi``, but centred on the values that, the other
joints at q0, bring the tip nearest the target's position: the tip's position is affine in
the prismatic joints' values, each moving it along its axis (in the base frame at q0), so
that centre is one small least-squares solve, clipped into a one-sided limit. The first
attempt still starts at q0, and every other arm's chain is the one it always had.
"""

from __future__ import annotations

import numpy as np

from armik.kernel import warmup
from armik.kernel.chain import PRISMATIC, Flat
from armik.kernel.entry import ENTRIES
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived


def _unlimited(arm: ArmModel) -> np.ndarray:
    ch = arm.kernel_chain.chain
    wide = ~(np.isfinite(ch.lower) & np.isfinite(ch.upper))
    for j in np.flatnonzero(wide):  # every physical joint it drives slides (a mimic driver's
        driven = ch.joint_kind[ch.driver == j]  # kind reads PRISMATIC whatever it drives)
        wide[j] = len(driven) > 0 and bool((driven == PRISMATIC).all())
    return np.flatnonzero(wide)


# the driving joints that slide without a limit on one side at least (often none)
UNLIMITED: Derived[np.ndarray] = Derived("unlimited prismatic joints", _unlimited)


def _turn(axis: np.ndarray, angle: float) -> np.ndarray:
    K = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)


def centres(arm: ArmModel, p_t: np.ndarray, q0: np.ndarray, joints: np.ndarray) -> np.ndarray:
    """The values of ``joints`` (unlimited prismatic) that, the other joints at ``q0``, bring
    the tip nearest ``p_t`` (base frame), within their one-sided limits."""
    ch = arm.kernel_chain.chain
    R, t = np.eye(3), np.zeros(3)
    cols = np.zeros((3, len(ch.kind)))
    for i in range(len(ch.joint_kind)):
        t = t + R @ ch.joint_p[i]
        R = R @ ch.joint_R[i]
        x = ch.multiplier[i] * q0[ch.driver[i]] + ch.offset[i]
        if ch.joint_kind[i] == PRISMATIC:
            w = R @ ch.axis[i]
            t = t + x * w
            cols[:, ch.driver[i]] += ch.multiplier[i] * w
        else:
            R = R @ _turn(ch.axis[i], x)
    tip = t + R @ ch.tip_p
    shift = np.linalg.lstsq(cols[:, joints], np.asarray(p_t, dtype=float) - tip, rcond=None)[0]
    return np.clip(q0[joints] + shift, ch.lower[joints], ch.upper[joints])


def toward(arm: ArmModel, p_t: np.ndarray, q0: np.ndarray, joints: np.ndarray) -> Flat:
    """``arm``'s flat chain with the restart box of ``joints`` (``UNLIMITED``) 2 pi wide
    around ``centres``, inside their one-sided limits."""
    ch, flat = arm.kernel_chain.chain, arm.kernel_chain.flat
    if not (np.isfinite(p_t).all() and np.isfinite(q0).all()):
        return flat  # input the kernel's entry refuses (the general path reads it)
    n, N = len(ch.kind), len(ch.joint_kind)
    lo = centres(arm, p_t, q0, joints) - np.pi
    lo = np.maximum(lo, ch.lower[joints])
    lo = np.minimum(lo, ch.upper[joints] - 2.0 * np.pi)
    packed = flat.packed.copy()
    at = 15 * N + 12 + 2 * n  # ``kernel.chain.sample_box``: n lower corners, then n spans
    packed[at + joints] = lo
    packed[at + n + joints] = 2.0 * np.pi
    return Flat(packed, flat.kind, flat.halton)


def batch_kernel(arm: ArmModel, sf, si, R_t, p_t, q0, seeds, step_kind: int):
    """(out_q, info, err) of the kernel over these rows: one call, or on an arm with
    ``UNLIMITED`` joints one a row, each with its own restart box (``toward``)."""
    n_targets = len(p_t)
    out_q = np.empty((n_targets, 1, arm.dof))
    info = np.empty((n_targets, 5), dtype=np.int64)
    err = np.empty((n_targets, 2))
    if step_kind not in warmup.PREPARED:  # a warm process: nothing to prepare
        warmup.prepare(step_kind)
    entry = ENTRIES[step_kind]
    joints = UNLIMITED(arm)
    if not len(joints):
        entry(*arm.kernel_chain.flat, sf, si, R_t, p_t, q0, seeds, out_q, info, err)
    for i in range(n_targets if len(joints) else 0):
        r = slice(i, i + 1)
        flat = toward(arm, p_t[i], q0[i], joints)
        entry(*flat, sf, si, R_t[r], p_t[r], q0[r], seeds[r], out_q[r], info[r], err[r])
    return out_q, info, err
