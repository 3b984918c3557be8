"""The task solver's descent, compiled: Levenberg-Marquardt on the stacked rows of a table of
tasks, each on a frame of its own (``armik.model.frame_chains``).

A task's six rows are ``region._evaluate_region``'s for its frame's chain: a pose within
bounds (weights, free axes), a position within a box (the target's rotation the identity,
the rotation rows free), an axis within a cone of a direction or of the line to a point.
The table (``armik.solve.task_table``) holds per task the target ``(R_t, p_t)``, its
parameters and (chain, look, reference chain) as ints; a task with a reference
(``armik.Relative``) has its rows on its frame's placement in the reference's. The step
is the Python descent's (``armik.solve.tasks._descend``): damped normal equations, a
joint a step would push through its limit held for that step, the trial clipped into the
box, kept only where the cost falls. It stops when every task is within half the
tolerances on the compiled FK; Pinocchio's measure of each task decides afterwards.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from armik.kernel.chain import Flat
from armik.kernel.fk import forward, jacobian_local
from armik.kernel.linalg import solve_spd
from armik.kernel.problem import _workspace
from armik.kernel.region import _evaluate_region, rows_at

# columns of the table's float parameters (one row per task)
BOUNDS, WEIGHTS, CONE, AXIS, POINT = slice(0, 6), slice(6, 12), 12, slice(13, 16), slice(16, 19)
PARAMS = 19
CHAIN, LOOK, REFERENCE = 0, 1, 2  # columns of its ints (REFERENCE: a Relative's, else -1)
LAMBDA_MIN, LAMBDA_MAX = 1e-12, 1e12
# the workspace slot, typed: a literal 0 would compile the region's rows a second time, for
# Literal[int](0), beside the int64 the descent and the servo pass
SLOT, ONE = np.int64(0), np.int64(1)


@njit(cache=True, nogil=True, inline="always")
def _most_joints(fo, ko, n):
    """The most physical joints of a chain of the table (the workspace's rows of them)."""
    nj = 1
    for c in range(fo.shape[0] - 1):
        nj = max(nj, (ko[c + 1] - ko[c] - n) // 2)
    return nj


# Called, not inlined: 2 s of the task solver's compile went to copying it into ``_stack``.
@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def _in_reference(ch, other, ws, kept):
    """ws.m3[0], ws.v3[0], ws.J: the placement of ``ch``'s frame in ``other``'s, ``T =
    T_other^-1 T_frame``, at ws.q[0], and its LOCAL Jacobian ``J_frame - Ad(T^-1)
    J_other`` (``armik.Relative``'s)."""
    n = ws.J.shape[1]
    q, geo = ws.q[0], ws.geo
    # R_f C-ordered (rows 0-2 of kept read as one 3x3): ``forward`` and ``jacobian_local``
    # compile once, for the C-ordered rotation every other caller passes
    R_f = kept[0:3].reshape(-1)[0:9].reshape((3, 3))
    p_f, J_f = kept[3, 0:3], kept[4:10]
    forward(ch, q, R_f, p_f, geo[0], geo[1])
    jacobian_local(ch, R_f, p_f, geo[0], geo[1], J_f)
    R, p, J = ws.m3[0], ws.v3[0], ws.J
    forward(other, q, R, p, geo[0], geo[1])
    jacobian_local(other, R, p, geo[0], geo[1], J)
    Rr, pr = ws.m3[1], ws.v3[1]  # T's rotation and translation
    d0, d1, d2 = p_f[0] - p[0], p_f[1] - p[1], p_f[2] - p[2]
    for i in range(3):
        pr[i] = R[0, i] * d0 + R[1, i] * d1 + R[2, i] * d2
        for j in range(3):
            Rr[i, j] = R[0, i] * R_f[0, j] + R[1, i] * R_f[1, j] + R[2, i] * R_f[2, j]
    for col in range(n):  # v' = Rr^T (v - pr x w), w' = Rr^T w: Ad(T^-1) on J_other
        v0, v1, v2 = J[0, col], J[1, col], J[2, col]
        w0, w1, w2 = J[3, col], J[4, col], J[5, col]
        u0 = v0 - (pr[1] * w2 - pr[2] * w1)
        u1 = v1 - (pr[2] * w0 - pr[0] * w2)
        u2 = v2 - (pr[0] * w1 - pr[1] * w0)
        for i in range(3):
            J[i, col] = J_f[i, col] - (Rr[0, i] * u0 + Rr[1, i] * u1 + Rr[2, i] * u2)
            J[3 + i, col] = J_f[3 + i, col] - (Rr[0, i] * w0 + Rr[1, i] * w1 + Rr[2, i] * w2)
    for i in range(3):
        p[i] = pr[i]
        for j in range(3):
            R[i, j] = Rr[i, j]


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _stack(fp, fo, ki, ko, halton, R_t, p_t, par, ti, q, tol_p, tol_r, ws, e, A, kept):
    """e (6T,) and A (6T, n) at q, each task's rows after the other; returns (|e|^2, every
    task within (tol_p, tol_r)). ``kept`` (10, n) is scratch for a frame's placement while
    its reference's is computed."""
    n = q.shape[0]
    for i in range(n):  # loops, not slice copies: no shape-mismatch error to compile
        ws.q[0, i] = q[i]
    cost = 0.0
    done = True
    for t in range(ti.shape[0]):
        c, ref = ti[t, CHAIN], ti[t, REFERENCE]
        ch = Flat(fp[fo[c] : fo[c + 1]], ki[ko[c] : ko[c + 1]], halton)
        p = par[t]
        if ref < 0:
            _evaluate_region(
                ch,
                p[0:6],
                p[6:12],
                p[12],
                p[13:16],
                ti[t, LOOK],
                p[16:19],
                R_t[t],
                p_t[t],
                ws,
                SLOT,
            )
        else:
            other = Flat(fp[fo[ref] : fo[ref + 1]], ki[ko[ref] : ko[ref + 1]], halton)
            _in_reference(ch, other, ws, kept)
            rows_at(
                p[0:6], p[6:12], p[12], p[13:16], ti[t, LOOK], p[16:19], R_t[t], p_t[t], ws, SLOT
            )
        done = done and ws.val[0, 0] <= tol_p and ws.val[0, 1] <= tol_r
        cost += ws.val[0, 2]
        for k in range(6):
            e[6 * t + k] = ws.e[0, k]
            for col in range(n):
                A[6 * t + k, col] = ws.A[0, k, col]
    return cost, done


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def descend(fp, fo, ki, ko, halton, R_t, p_t, par, ti, q, lo, hi, iterations, tol_p, tol_r, lam0):
    """Levenberg-Marquardt from q (overwritten with the end) within [lo, hi]; returns
    (iterations used, every task within half the tolerances)."""
    n, m = q.shape[0], 6 * ti.shape[0]
    ws = _workspace(n, ONE, np.int64(_most_joints(fo, ko, n)))  # typed, as the entries'
    kept = np.empty((10, max(n, 3)))
    e, A = np.empty((2, m)), np.empty((2, m, n))
    H, L = np.empty((n, n)), np.empty((n, n))
    g, dq, trial = np.empty(n), np.empty(n), np.empty(n)
    free = np.ones(n, dtype=np.int64)
    tp, tr = 0.5 * tol_p, 0.5 * tol_r
    now = 0
    cost, done = _stack(fp, fo, ki, ko, halton, R_t, p_t, par, ti, q, tp, tr, ws, e[0], A[0], kept)
    if done:
        return 0, True
    lam = -1.0
    for k in range(iterations):
        Ac, ec = A[now], e[now]
        for i in range(n):  # H = A^T A, g = A^T e (e is minus the residual)
            s = 0.0
            for r in range(m):
                s += Ac[r, i] * ec[r]
            g[i] = s
            for j in range(i + 1):
                s = 0.0
                for r in range(m):
                    s += Ac[r, i] * Ac[r, j]
                H[i, j] = s
                H[j, i] = s
        if lam < 0.0:
            top = 1e-12
            for i in range(n):
                top = max(top, H[i, i])
            lam = lam0 * top
        for i in range(n):
            H[i, i] += lam
            free[i] = 1
        solve_spd(H, g, free, L, dq)
        # a joint the step would push through its limit is held for it (an active set)
        held = False
        for i in range(n):
            if (q[i] <= lo[i] and dq[i] < 0.0) or (q[i] >= hi[i] and dq[i] > 0.0):
                free[i] = 0
                held = True
        if held:
            solve_spd(H, g, free, L, dq)
        for i in range(n):
            trial[i] = min(max(q[i] + dq[i], lo[i]), hi[i])
        other = 1 - now
        cost2, done = _stack(
            fp, fo, ki, ko, halton, R_t, p_t, par, ti, trial, tp, tr, ws, e[other], A[other], kept
        )
        if cost2 < cost:
            for i in range(n):
                q[i] = trial[i]
            now, cost = other, cost2
            lam = max(lam / 3.0, LAMBDA_MIN)
            if done:
                return k + 1, True
        else:
            lam *= 4.0
            if lam > LAMBDA_MAX:
                return k + 1, False
    return iterations, False


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def stacked(fp, fo, ki, ko, halton, R_t, p_t, par, ti, q):
    """(e, A) at q, minus the residual and its Jacobian: ``_stack`` for the tests."""
    n, m = q.shape[0], 6 * ti.shape[0]
    ws = _workspace(n, ONE, np.int64(_most_joints(fo, ko, n)))  # typed, as the entries'
    kept = np.empty((10, max(n, 3)))
    e, A = np.empty(m), np.empty((m, n))
    _stack(fp, fo, ki, ko, halton, R_t, p_t, par, ti, q, 0.0, 0.0, ws, e, A, kept)
    return e, A
