"""One step of the descent: damped least squares, or a QP with the joint limits as a box.

Both solve H dq = g with H = A^T A + lambda I and g = A^T e (+ the null-space pull), with
lambda = mu c E + lambda_min, E = |e|^2 / 2 (Chan, Sugihara), and bound the step to a
Euclidean length of MAX_STEP (``dls`` on an arm with more than six joints solves the
equivalent 6 x 6 system instead: ``task_space_step``). ``dls`` takes a joint resting on a
limit that the step pushes further out out of the step (an active set); ``qp`` solves
the box QP exactly with a primal-dual active set checked by the KKT conditions, and calls
the QP backend when that fails (a few steps in 10^4). Results land in ws.vec[DQ]. ``dls``
and ``qp`` are the two steps; the descent takes one of them as an argument, so that a
program that only solves with ``dls`` never compiles the QP machinery.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, objmode

from armik.kernel.box_qp import solve_box_qp
from armik.kernel.chain import CONTINUOUS, PRISMATIC, lower, upper
from armik.kernel.linalg import (
    cholesky6,
    cholesky_factor,
    cholesky_solve,
    cholesky_substitute,
    copy_to,
    solve_spd,
)
from armik.kernel.problem import (
    DQ,
    FREE,
    GAP,
    GI,
    HELD,
    HH,
    LB,
    MULT,
    SIDE,
    UB,
    UNIT,
    XF,
    G,
    H,
    L,
    X,
)

MAX_STEP = 1.0  # rad or m: longest step (Euclidean)
# lambda = mu DAMPING_GAIN E + LAMBDA_MIN: c = 0.1 was measured against c = 1 and 0.01 with
# ``armik bench`` (fewer iterations on the Panda); mu grows when a step is rejected.
DAMPING_GAIN = 0.1
LAMBDA_MIN = 1e-9
ON_LIMIT = 1e-10  # rad or m: a joint this close to a limit rests on it
# m: a prismatic joint's null-space pull toward q0 counts at most this far: the pull grows
# with the damping (the squared error), and an arm on a rail 300 m long was pulled back
# along it toward q0 instead of onto the target (27 of 40 positions solved, 6 at 1000 m)
PULL_REACH = 1.0
KKT_TOL = 1e-12


@njit(cache=True, nogil=True, inline="always")
def wrapped(d):
    """d shifted by a multiple of 2 pi into [-pi, pi]."""
    return d - 2.0 * math.pi * math.floor((d + math.pi) / (2.0 * math.pi))


@njit(cache=True, nogil=True, inline="always")
def pull_gain(st, lam):
    """k of the null-space pull lam k (q0 - q): the null gain times the error's size,
    sqrt(2 lam) over the largest weight (lam grows with the weighted error squared; the
    weights scaled the error by up to their largest: unscaled, a largest weight of 100 made
    the pull hold 7-joint arms off the lightly weighted rows), at most the null gain."""
    return st.null_gain * min(1.0, math.sqrt(2.0 * lam) * st.pull_scale)


@njit(cache=True, nogil=True, inline="always")
def pulled(ch, st, q0, q, i):
    """Joint i's null-space pull before its gain: toward the posture's reference, weighted
    (``Settings.posture``), or toward q0 where the options name no posture; a continuous
    joint's the shorter way round."""
    if st.posture.shape[0] > 0:
        d = st.posture[i] - q[i]
        w = st.posture_w[i]
    else:
        d = q0[i] - q[i]
        w = 1.0
    if ch.kind[i] == CONTINUOUS:
        d = wrapped(d)
    elif ch.kind[i] == PRISMATIC:  # a rail's hundreds of metres would outweigh the error
        d = max(-PULL_REACH, min(PULL_REACH, d))
    return w * d


@njit(cache=True, nogil=True, inline="always")
def normal_equations(ch, st, ws, slot, q0, mu):
    """ws.mat[H] = A^T A + lambda I and ws.vec[G] = A^T e + the null-space pull, at state
    ``slot``."""
    A, e, Hm, g = ws.A[slot], ws.e[slot], ws.mat[H], ws.vec[G]
    n = A.shape[1]
    lam = mu * DAMPING_GAIN * 0.5 * ws.val[slot, 2] + LAMBDA_MIN
    for i in range(n):
        a0, a1, a2, a3, a4, a5 = A[0, i], A[1, i], A[2, i], A[3, i], A[4, i], A[5, i]
        g[i] = a0 * e[0] + a1 * e[1] + a2 * e[2] + a3 * e[3] + a4 * e[4] + a5 * e[5]
        for j in range(i + 1):
            s = (
                a0 * A[0, j]
                + a1 * A[1, j]
                + a2 * A[2, j]
                + a3 * A[3, j]
                + a4 * A[4, j]
                + a5 * A[5, j]
            )
            Hm[i, j] = s
            Hm[j, i] = s
        Hm[i, i] += lam
    if st.null_gain > 0.0:
        # lam k (q0 - q) only acts where A has no say: a pull in the null space. k shrinks
        # with the error so that the pull fades out and convergence stays fast.
        k = pull_gain(st, lam)
        q = ws.q[slot]
        for i in range(n):
            g[i] += lam * k * pulled(ch, st, q0, q, i)


@njit(cache=True, nogil=True, inline="always")
def bound_step(dq):
    n2 = 0.0
    for i in range(dq.shape[0]):
        n2 += dq[i] * dq[i]
    if n2 > MAX_STEP * MAX_STEP:
        f = MAX_STEP / math.sqrt(n2)
        for i in range(dq.shape[0]):
            dq[i] *= f


@njit(cache=True, nogil=True, inline="always")
def dls_step(ch, ws, slot):
    """ws.vec[DQ]: the damped least-squares step, joints on a limit held when pushed out."""
    Hm, g, dq, free, Lm = ws.mat[H], ws.vec[G], ws.vec[DQ], ws.ivec[FREE], ws.mat[L]
    q = ws.q[slot]
    lo, hi = lower(ch), upper(ch)
    free[:] = 1
    # six joints: the written-out Cholesky (the same numbers); else, or when it fails, the
    # general one (which fails alike, then raises the diagonal)
    if q.shape[0] != 6 or not cholesky6(Hm, g, dq):
        solve_spd(Hm, g, free, Lm, dq)
    blocked = False
    for i in range(q.shape[0]):
        if (q[i] <= lo[i] + ON_LIMIT and dq[i] < 0.0) or (q[i] >= hi[i] - ON_LIMIT and dq[i] > 0.0):
            free[i] = 0
            blocked = True
    if blocked:
        solve_spd(Hm, g, free, Lm, dq)  # zero on the held joints
    bound_step(dq)


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def inverse_spd(ws):
    """ws.mat[GI] = ws.mat[H]^-1 by Cholesky; False if H is not positive definite."""
    Hm, Gi, free, unit, x, Lm = (
        ws.mat[H],
        ws.mat[GI],
        ws.ivec[FREE],
        ws.vec[UNIT],
        ws.vec[X],
        ws.mat[L],
    )
    n = Hm.shape[0]
    free[:] = 1
    if not cholesky_factor(Hm, free, Lm):
        return False
    for c in range(n):
        unit[:] = 0.0
        unit[c] = 1.0
        cholesky_substitute(Lm, unit, free, x)
        for r in range(n):
            Gi[r, c] = x[r]
    return True


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def active_set(G_, x_free, lb, ub, start, side, held, sub, Hh, gap, mult, Lm, x):
    """The box QP's exact solution x by a primal-dual active-set iteration (Hintermueller,
    Ito and Kunisch), starting from the bounds that ``start`` crosses. Returns False if no
    set is found in 2n rounds. ``side``, ``held``, ``sub`` (int n-vectors), ``Hh``, ``Lm``
    (n x n), ``gap``, ``mult`` (n-vectors) are scratch.

    G_ = H^-1 and x_free = G_ g, the unconstrained minimiser. Holding the joints of a set B
    at their bounds b with multipliers m (H x - g = m on B, 0 elsewhere) gives
    x = x_free + G_[:, B] m with G_BB m = b - x_free_B. The set is optimal when every free
    joint stays in its box and every held joint's multiplier has the right sign (KKT).
    """
    n = x_free.shape[0]
    for i in range(n):  # +1 held at the lower bound, -1 at the upper, 0 free
        side[i] = 1 if start[i] <= lb[i] else (-1 if start[i] >= ub[i] else 0)
    for _ in range(2 * n):
        h = 0
        for i in range(n):
            if side[i] != 0:
                held[h] = i
                h += 1
        for a in range(h):
            i = held[a]
            gap[a] = (lb[i] if side[i] > 0 else ub[i]) - x_free[i]
            for b in range(h):
                Hh[a, b] = G_[i, held[b]]
        if h == 1:
            mult[0] = gap[0] / Hh[0, 0]
        elif h > 1:
            sub[:] = 0
            sub[:h] = 1
            if not cholesky_solve(Hh, gap, sub, Lm, mult):
                return False
        for i in range(n):
            s = x_free[i]
            for a in range(h):
                s += G_[i, held[a]] * mult[a]
            x[i] = s
        changed = False
        for a in range(h):  # multipliers: >= 0 held at lower, <= 0 held at upper
            i = held[a]
            if side[i] * mult[a] < -KKT_TOL:
                side[i] = 0
                changed = True
        for i in range(n):
            was_held = False
            for a in range(h):
                if held[a] == i:
                    was_held = True
            if was_held:
                continue
            if x[i] < lb[i]:
                side[i] = 1
                changed = True
            elif x[i] > ub[i]:
                side[i] = -1
                changed = True
        if not changed:
            for a in range(h):  # exactly on the bound, whatever the rounding
                i = held[a]
                x[i] = lb[i] if side[i] > 0 else ub[i]
            return True
    return False


@njit(cache=True, no_cfunc_wrapper=True, _nrt=True)  # not nogil: object mode needs the GIL
def backend_step(Hm, g, lb, ub, which):
    """The QP backend's solution (NaNs if none), called with the GIL held (object mode)."""
    with objmode(sol="float64[:]"):
        sol = solve_box_qp(Hm, g, lb, ub, which)
    return sol


# Called, not inlined: the qp step then takes 1.26-1.30 us a Panda iteration against
# 1.71-1.73 inlined (``benchmarks/kernel_iteration.py panda --qp``).
@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def qp_step(ch, st, ws, slot):
    """ws.vec[DQ]: the box-constrained step (limits as bounds on dq), scaled to MAX_STEP."""
    Hm, g, dq, x_free = ws.mat[H], ws.vec[G], ws.vec[DQ], ws.vec[XF]
    lb, ub, x = ws.vec[LB], ws.vec[UB], ws.vec[X]
    q = ws.q[slot]
    n = q.shape[0]
    lo, hi = lower(ch), upper(ch)
    ws.ivec[FREE][:] = 1
    if n != 6 or not cholesky6(Hm, g, dq):  # as in dls_step
        solve_spd(Hm, g, ws.ivec[FREE], ws.mat[L], dq)
    copy_to(x_free, dq)
    bound_step(dq)
    inside = True
    for i in range(n):
        lb[i] = lo[i] - q[i]
        ub[i] = hi[i] - q[i]
        if dq[i] < lb[i] or dq[i] > ub[i]:
            inside = False
    if inside:
        return
    found = False
    if inverse_spd(ws):
        scratch = (ws.ivec[SIDE], ws.ivec[HELD], ws.ivec[FREE], ws.mat[HH], ws.vec[GAP])
        rest = (ws.vec[MULT], ws.mat[L], x)
        found = active_set(ws.mat[GI], x_free, lb, ub, dq, *scratch, *rest)
        if not found:  # cycled: start again from the joints resting on a bound
            ws.vec[UNIT][:] = 0.0
            found = active_set(ws.mat[GI], x_free, lb, ub, ws.vec[UNIT], *scratch, *rest)
    if found:
        copy_to(dq, x)
    else:
        sol = backend_step(Hm.copy(), g.copy(), lb.copy(), ub.copy(), st.backend)
        if not np.isnan(sol[0]):
            copy_to(dq, sol)
        for i in range(n):  # backends meet bounds only to their tolerance
            dq[i] = min(max(dq[i], lb[i]), ub[i])
    bound_step(dq)


@njit(cache=True, nogil=True, inline="always")
def gram6(A, S):
    """S[a, b] = sum_i A[a, i] A[b, i] (b <= a) for the 6 rows of A, each sum in the order of
    i from 0.0 (the numbers of one loop per entry); the 21 sums run side by side in
    registers, so that each addition need not wait for the one before it (the loop per
    entry took most of the step's time on the Panda)."""
    s00 = s10 = s11 = s20 = s21 = s22 = s30 = s31 = s32 = s33 = 0.0
    s40 = s41 = s42 = s43 = s44 = s50 = s51 = s52 = s53 = s54 = s55 = 0.0
    for i in range(A.shape[1]):
        a0, a1, a2, a3, a4, a5 = A[0, i], A[1, i], A[2, i], A[3, i], A[4, i], A[5, i]
        s00 += a0 * a0
        s10 += a1 * a0
        s11 += a1 * a1
        s20 += a2 * a0
        s21 += a2 * a1
        s22 += a2 * a2
        s30 += a3 * a0
        s31 += a3 * a1
        s32 += a3 * a2
        s33 += a3 * a3
        s40 += a4 * a0
        s41 += a4 * a1
        s42 += a4 * a2
        s43 += a4 * a3
        s44 += a4 * a4
        s50 += a5 * a0
        s51 += a5 * a1
        s52 += a5 * a2
        s53 += a5 * a3
        s54 += a5 * a4
        s55 += a5 * a5
    S[0, 0] = s00
    S[1, 0], S[1, 1] = s10, s11
    S[2, 0], S[2, 1], S[2, 2] = s20, s21, s22
    S[3, 0], S[3, 1], S[3, 2], S[3, 3] = s30, s31, s32, s33
    S[4, 0], S[4, 1], S[4, 2], S[4, 3], S[4, 4] = s40, s41, s42, s43, s44
    S[5, 0], S[5, 1], S[5, 2], S[5, 3], S[5, 4], S[5, 5] = s50, s51, s52, s53, s54, s55


@njit(cache=True, nogil=True, inline="always")
def task_space_step(ch, st, ws, slot, q0, mu):
    """ws.vec[DQ]: the dls step through the 6 x 6 system of an arm with more than six
    joints; False (nothing decided) when a joint on a limit would be pushed out or the system
    is not positive definite in floating point: then the joint-space step decides.

    With H = A^T A + lambda I and the pull lambda k d (d = q0 - q), the push-through identity
    (A^T A + lambda I)^-1 A^T = A^T (A A^T + lambda I)^-1 gives
    dq = H^-1 (A^T e + lambda k d) = k d + A^T (A A^T + lambda I)^-1 (e - k A d):
    a 6 x 6 Cholesky instead of an n x n one (measured: 7 joints, ~40 % less time a step)."""
    A, e, S = ws.A[slot], ws.e[slot], ws.task
    r, y, d, dq = ws.tvec[0], ws.tvec[1], ws.vec[X], ws.vec[DQ]
    q = ws.q[slot]
    n = A.shape[1]
    lam = mu * DAMPING_GAIN * 0.5 * ws.val[slot, 2] + LAMBDA_MIN  # as ``normal_equations``
    k = 0.0
    if st.null_gain > 0.0:
        k = pull_gain(st, lam)
    for i in range(n):
        d[i] = pulled(ch, st, q0, q, i) if k > 0.0 else 0.0
    r0, r1, r2, r3, r4, r5 = e[0], e[1], e[2], e[3], e[4], e[5]
    for i in range(n):  # r = e - k A d, the six sums side by side (each in the order of i)
        di = d[i]
        r0 -= k * A[0, i] * di
        r1 -= k * A[1, i] * di
        r2 -= k * A[2, i] * di
        r3 -= k * A[3, i] * di
        r4 -= k * A[4, i] * di
        r5 -= k * A[5, i] * di
    r[0], r[1], r[2], r[3], r[4], r[5] = r0, r1, r2, r3, r4, r5
    gram6(A, S)
    for a in range(6):
        S[a, a] += lam
    if not cholesky6(S, r, y):
        return False
    lo, hi = lower(ch), upper(ch)
    for i in range(n):
        s = k * d[i]
        for a in range(6):
            s += A[a, i] * y[a]
        dq[i] = s
        if (q[i] <= lo[i] + ON_LIMIT and s < 0.0) or (q[i] >= hi[i] - ON_LIMIT and s > 0.0):
            return False
    bound_step(dq)
    return True


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def dls(ch, st, ws, slot, q0, mu):
    """ws.vec[DQ]: the dls step from state ``slot`` (damping multiplier mu)."""
    if ws.q.shape[1] > 6 and task_space_step(ch, st, ws, slot, q0, mu):
        return
    normal_equations(ch, st, ws, slot, q0, mu)
    dls_step(ch, ws, slot)


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=True)
def qp(ch, st, ws, slot, q0, mu):
    """ws.vec[DQ]: the qp step from state ``slot`` (damping multiplier mu)."""
    normal_equations(ch, st, ws, slot, q0, mu)
    qp_step(ch, st, ws, slot)
