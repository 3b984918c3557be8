"""One step of the descent: damped least squares, or a QP with the joint limits as a box.

Both solve H dq = g with H = A^T A + lambda I and g = A^T e (+ the null-space pull), with
lambda = mu c E + lambda_min, E = |e|^2 / 2 (Chan, Sugihara), and bound the step to a
Euclidean length of MAX_STEP. ``dls`` takes a joint resting on a limit that the step pushes
further out out of the step (an active set); ``qp`` solves the box QP exactly with a
primal-dual active set checked by the KKT conditions, and calls the QP backend when that
fails (a few steps in 10^4).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, objmode

from .backend import solve_box_qp
from .chain import CONTINUOUS
from .linalg import cholesky_solve, solve_spd
from .problem import STEP_DLS

MAX_STEP = 1.0  # rad or m: longest step (Euclidean)
# lambda = mu DAMPING_GAIN E + LAMBDA_MIN: c = 0.1 was measured against c = 1 and 0.01 with
# ``armik bench`` (fewer iterations on the Panda); mu grows when a step is rejected.
DAMPING_GAIN = 0.1
LAMBDA_MIN = 1e-9
ON_LIMIT = 1e-10  # rad or m: a joint this close to a limit rests on it
KKT_TOL = 1e-12


@njit(cache=True, nogil=True)
def wrapped(d):
    """d shifted by a multiple of 2 pi into [-pi, pi]."""
    return d - 2.0 * math.pi * math.floor((d + math.pi) / (2.0 * math.pi))


@njit(cache=True, nogil=True)
def normal_equations(ch, st, ws, slot, q0, mu):
    """ws.H = A^T A + lambda I and ws.g = A^T e + the null-space pull, at state ``slot``."""
    A, e, H, g = ws.A[slot], ws.e[slot], ws.H, ws.g
    n = A.shape[1]
    lam = mu * DAMPING_GAIN * 0.5 * ws.val[slot, 2] + LAMBDA_MIN
    for i in range(n):
        s = 0.0
        for k in range(6):
            s += A[k, i] * e[k]
        g[i] = s
        for j in range(i + 1):
            s = 0.0
            for k in range(6):
                s += A[k, i] * A[k, j]
            H[i, j] = s
            H[j, i] = s
        H[i, i] += lam
    if st.null_gain > 0.0:
        # lam k (q0 - q) only acts where A has no say: a pull in the null space. k shrinks
        # with the error so that the pull fades out and convergence stays fast.
        k = st.null_gain * min(1.0, math.sqrt(2.0 * lam))
        q = ws.q[slot]
        for i in range(n):
            d = q0[i] - q[i]
            if ch.kind[i] == CONTINUOUS:
                d = wrapped(d)
            g[i] += lam * k * d


@njit(cache=True, nogil=True)
def bound_step(dq):
    n2 = 0.0
    for i in range(dq.shape[0]):
        n2 += dq[i] * dq[i]
    if n2 > MAX_STEP * MAX_STEP:
        f = MAX_STEP / math.sqrt(n2)
        for i in range(dq.shape[0]):
            dq[i] *= f


@njit(cache=True, nogil=True)
def dls_step(ch, ws, slot):
    """ws.dq: the damped least-squares step with joints on a limit held when pushed out."""
    H, g, dq, free = ws.H, ws.g, ws.dq, ws.free
    q = ws.q[slot]
    n = q.shape[0]
    free[:] = True
    solve_spd(H, g, free, ws.L, dq)
    blocked = False
    for i in range(n):
        if (q[i] <= ch.lower[i] + ON_LIMIT and dq[i] < 0.0) or (
            q[i] >= ch.upper[i] - ON_LIMIT and dq[i] > 0.0
        ):
            free[i] = False
            blocked = True
    if blocked:
        solve_spd(H, g, free, ws.L, dq)  # zero on the held joints
    bound_step(dq)


@njit(cache=True, nogil=True)
def inverse_spd(H, ws):
    """ws.G = H^-1 by Cholesky; False if H is not positive definite."""
    n = H.shape[0]
    free = ws.free
    free[:] = True
    for c in range(n):
        ws.unit[:] = 0.0
        ws.unit[c] = 1.0
        if not cholesky_solve(H, ws.unit, free, ws.L, ws.x):
            return False
        for r in range(n):
            ws.G[r, c] = ws.x[r]
    return True


@njit(cache=True, nogil=True)
def active_set(G, x_free, lb, ub, start, ws, x):
    """The box QP's exact solution x by a primal-dual active-set iteration (Hintermueller,
    Ito and Kunisch), starting from the bounds that ``start`` crosses. Returns False if no
    set is found in 2n rounds.

    G = H^-1 and x_free = G g, the unconstrained minimiser. Holding the joints of a set B
    at their bounds b with multipliers m (H x - g = m on B, 0 elsewhere) gives
    x = x_free + G[:, B] m with G_BB m = b - x_free_B. The set is optimal when every free
    joint stays in its box and every held joint's multiplier has the right sign (KKT).
    """
    n = x_free.shape[0]
    side, held, Hh, gap, mult = ws.side, ws.held, ws.Hh, ws.gap, ws.mult
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
                Hh[a, b] = G[i, held[b]]
        if h == 1:
            mult[0] = gap[0] / Hh[0, 0]
        elif h > 1:
            sub = ws.free
            sub[:] = False
            sub[:h] = True
            if not cholesky_solve(Hh, gap, sub, ws.L, mult):
                return False
        for i in range(n):
            s = x_free[i]
            for a in range(h):
                s += G[i, held[a]] * mult[a]
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


@njit(cache=True, nogil=True)
def qp_step(ch, st, ws, slot):
    """ws.dq: the box-constrained step (limits as bounds on dq), scaled to MAX_STEP."""
    H, g, dq, x_free, lb, ub = ws.H, ws.g, ws.dq, ws.xf, ws.lb, ws.ub
    q = ws.q[slot]
    n = q.shape[0]
    ws.free[:] = True
    solve_spd(H, g, ws.free, ws.L, dq)
    x_free[:] = dq
    bound_step(dq)
    inside = True
    for i in range(n):
        lb[i] = ch.lower[i] - q[i]
        ub[i] = ch.upper[i] - q[i]
        if dq[i] < lb[i] or dq[i] > ub[i]:
            inside = False
    if inside:
        return
    found = False
    if inverse_spd(H, ws):
        found = active_set(ws.G, x_free, lb, ub, dq, ws, ws.x)
        if not found:  # cycled: start again from the joints resting on a bound
            ws.unit[:] = 0.0
            found = active_set(ws.G, x_free, lb, ub, ws.unit, ws, ws.x)
    if found:
        dq[:] = ws.x
    else:
        Hc, gc, lbc, ubc = H.copy(), g.copy(), lb.copy(), ub.copy()
        which = st.backend
        with objmode(sol="float64[:]"):
            sol = solve_box_qp(Hc, gc, lbc, ubc, which)
        if not np.isnan(sol[0]):
            dq[:] = sol
        for i in range(n):  # backends meet bounds only to their tolerance
            dq[i] = min(max(dq[i], lb[i]), ub[i])
    bound_step(dq)


@njit(cache=True, nogil=True)
def step(ch, st, ws, slot, q0, mu):
    """ws.dq: the step of the solver ``st.step`` from state ``slot``."""
    normal_equations(ch, st, ws, slot, q0, mu)
    if st.step == STEP_DLS:
        dls_step(ch, ws, slot)
    else:
        qp_step(ch, st, ws, slot)
