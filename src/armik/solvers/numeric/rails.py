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
that the kernel's FK at q0 and at q0 with each such joint moved gives that centre by one
small least-squares solve, clipped into a one-sided limit (a batch's rows in one FK call). Where
turning joints come before a rail (``TURNING``: a telescope on a turntable), they turn it:
where q0's rails pass more than ``FAR`` from the target, the centre is the one of q0's and
of ``SWEEP`` configurations of those joints whose rails bring the tip nearest. The first
attempt still starts at q0, and every other arm's chain is the one it always had.
"""

from __future__ import annotations

import numpy as np

from armik.kernel import warmup
from armik.kernel.chain import PRISMATIC, Flat, flatten
from armik.kernel.entry import ENTRIES
from armik.kernel.fk_many import fk_many
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

SWEEP = 32  # configurations of the turning joints before a rail tried for its centre
CHUNK = 1024  # rows of a batch whose centres are found together
# m: q0's rails passing farther than this from the target are swept for a nearer turn (half
# the restart box's width: nearer, the descent closes the gap in a few steps)
FAR = np.pi


def _turning(arm: ArmModel) -> np.ndarray:
    """The turning driving joints that come before an unlimited rail (``UNLIMITED``): they
    turn it (joints are numbered from the base)."""
    rails_ = UNLIMITED(arm)
    if not len(rails_):
        return rails_
    ch = arm.kernel_chain.chain
    before = np.arange(arm.dof) < rails_.max()
    return np.flatnonzero(before & (ch.kind != PRISMATIC))


# the turning joints that turn an unlimited rail (often none: a gantry's come after it)
TURNING: Derived[np.ndarray] = Derived("turning joints before a rail", _turning)


def _sweep(arm: ArmModel, turning: np.ndarray) -> np.ndarray:
    """(SWEEP, len(turning)): values of ``turning`` spread over the restart box (the first
    points of the kernel's Halton table)."""
    ch = arm.kernel_chain.chain
    rows = ch.halton[np.arange(SWEEP) % len(ch.halton)][:, turning]
    return ch.sample_lo[turning] + ch.sample_span[turning] * rows


def _box_places(arm: ArmModel) -> tuple[np.ndarray, np.ndarray]:
    """Where ``kernel.chain.flatten`` writes the restart box (``Chain.sample_lo``, then
    ``sample_span``) in the flat chain: found by flattening the chain with each marked."""
    ch = arm.kernel_chain.chain
    marked = np.full(len(ch.kind), np.nan)
    lo = np.flatnonzero(np.isnan(flatten(ch._replace(sample_lo=marked))))
    span = np.flatnonzero(np.isnan(flatten(ch._replace(sample_span=marked))))
    return lo, span


# the indexes of the restart box's lower corners and spans in the arm's ``Flat.packed``
BOX_PLACES: Derived[tuple[np.ndarray, np.ndarray]] = Derived("restart box", _box_places)


def centres(arm: ArmModel, p_t: np.ndarray, q0: np.ndarray, joints: np.ndarray) -> np.ndarray:
    """The values of ``joints`` (unlimited prismatic) that, the other joints at ``q0``, bring
    the tip nearest ``p_t`` (base frame), within their one-sided limits."""
    return centres_many(arm, np.asarray(p_t, dtype=float)[None], q0[None], joints)[0]


def centres_many(arm: ArmModel, P: np.ndarray, Q0: np.ndarray, joints: np.ndarray) -> np.ndarray:
    """``centres`` of positions ``P`` (m, 3) from joint values ``Q0`` (m, n), (m, k); on an
    arm whose turning joints come before a rail (``TURNING``), where q0's rails pass more
    than ``FAR`` from the target, the best of q0's and those from ``SWEEP`` configurations
    of those joints (the rest at q0): the one whose rails bring the tip nearest (a rail
    turned away from the target at q0 reached it nowhere near the box, and a target 300 m
    along it was never solved)."""
    x, miss = _centres_at(arm, P, Q0, joints)
    turning = TURNING(arm)
    far = np.flatnonzero(miss > FAR) if len(turning) else miss[:0]
    for i in range(0, len(far), CHUNK):  # (1 + SWEEP) (1 + k) placements a row
        rows = far[i : i + CHUNK]
        x[rows] = _swept(
            arm,
            np.asarray(P, dtype=float)[rows],
            np.asarray(Q0, dtype=float)[rows],
            joints,
            turning,
        )
    return x


def _swept(arm: ArmModel, P: np.ndarray, Q0: np.ndarray, joints: np.ndarray, turning: np.ndarray):
    """``centres_many``'s centres of rows ``P``, ``Q0`` over the sweep of ``turning``."""
    m = len(P)
    swept = np.repeat(Q0[:, None, :], 1 + SWEEP, axis=1)  # (m, 1 + SWEEP, n), row 0: q0
    swept[:, 1:, turning] = _sweep(arm, turning)
    x, miss = _centres_at(arm, np.repeat(P, 1 + SWEEP, axis=0), swept.reshape(-1, arm.dof), joints)
    best = miss.reshape(m, 1 + SWEEP).argmin(axis=1)  # q0's where it is as near as any
    return x.reshape(m, 1 + SWEEP, len(joints))[np.arange(m), best]


def _centres_at(arm: ArmModel, P: np.ndarray, Q0: np.ndarray, joints: np.ndarray):
    """(centres, distances): ``centres`` of positions ``P`` (m, 3) from joint values ``Q0``
    (m, n), (m, k), and how far from ``P`` the rails at them bring the tip (m,): the
    tip's position is affine in the prismatic joints' values, ``base + C x``, so that the
    kernel's FK (``kernel.fk_many``) at q0 with those joints at 0, then each at 1 m, gives
    it (exact moves, whatever q0's values along the rails: 1e17 m plus 1 m is 1e17 m)."""
    m, k = len(P), len(joints)
    if m == 0:
        return np.empty((0, k)), np.empty(0)
    Q = np.repeat(np.asarray(Q0, dtype=float)[:, None, :], 1 + k, axis=1)  # (m, 1 + k, n)
    Q[:, :, joints] = np.vstack([np.zeros(k), np.eye(k)])
    out = np.empty((m * (1 + k), 4, 4))
    fk_many(*arm.kernel_chain.flat, Q.reshape(m * (1 + k), arm.dof), out)
    at = out[:, :3, 3].reshape(m, 1 + k, 3)
    C = at[:, 1:] - at[:, :1]  # (m, k, 3): each joint's direction
    r = np.asarray(P, dtype=float) - at[:, 0]
    x0 = np.asarray(Q0, dtype=float)[:, joints]
    if k == 1:  # the nearest point along the rail (a rail that moves nothing: q0)
        c, cc = C[:, 0], (C[:, 0] ** 2).sum(axis=1)
        x = np.where(cc > 0.0, (c * r).sum(axis=1) / np.where(cc > 0.0, cc, 1.0), x0[:, 0])
        x = x[:, None]
    else:  # least squares, q0's values along directions the rails do not span
        x = np.empty((m, k))
        for i in range(m):
            U, sv, Vt = np.linalg.svd(C[i].T)
            rank = int((sv > 1e-12 * max(float(sv.max(initial=0.0)), 1.0)).sum())
            V, Vn = Vt[:rank].T, Vt[rank:].T
            x[i] = V @ ((U[:, :rank].T @ r[i]) / sv[:rank]) + Vn @ (Vn.T @ x0[i])
    ch = arm.kernel_chain.chain
    x = np.clip(x, ch.lower[joints], ch.upper[joints])
    miss = np.linalg.norm(r - np.einsum("mkd,mk->md", C, x), axis=1)
    return x, miss


def toward(arm: ArmModel, p_t: np.ndarray, q0: np.ndarray, joints: np.ndarray) -> Flat:
    """``arm``'s flat chain with the restart box of ``joints`` (``UNLIMITED``) 2 pi wide
    around ``centres``, inside their one-sided limits."""
    flat = arm.kernel_chain.flat
    if not (np.isfinite(p_t).all() and np.isfinite(q0).all()):
        return flat  # input the kernel's entry refuses (the general path reads it)
    return _boxed(arm, centres(arm, p_t, q0, joints), joints)


def _boxed(arm: ArmModel, centre: np.ndarray, joints: np.ndarray) -> Flat:
    """``arm``'s flat chain, the restart box of ``joints`` 2 pi wide around ``centre``."""
    ch, flat = arm.kernel_chain.chain, arm.kernel_chain.flat
    lo = np.maximum(centre - np.pi, ch.lower[joints])
    lo = np.minimum(lo, ch.upper[joints] - 2.0 * np.pi)
    lows, spans = BOX_PLACES(arm)
    packed = flat.packed.copy()
    packed[lows[joints]] = lo
    packed[spans[joints]] = 2.0 * np.pi
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
        return out_q, info, err
    # rows the kernel's entry refuses (not finite) keep the chain: the general path reads them
    rows = np.flatnonzero(np.isfinite(p_t).all(axis=1) & np.isfinite(q0).all(axis=1))
    centre = dict(zip(rows.tolist(), centres_many(arm, p_t[rows], q0[rows], joints)))
    for i in range(n_targets):
        r = slice(i, i + 1)
        flat = _boxed(arm, centre[i], joints) if i in centre else arm.kernel_chain.flat
        entry(*flat, sf, si, R_t[r], p_t[r], q0[r], seeds[r], out_q[r], info[r], err[r])
    return out_q, info, err
