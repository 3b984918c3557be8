"""The task solver's descent, compiled: Levenberg-Marquardt on the stacked rows of a table of
tasks, each on a frame of its own (``armik.kernel.frame_chains``).

A task's six rows are ``region._evaluate_region``'s for its frame's chain: a pose within
bounds (weights, free axes), a position within a box (the target's rotation the identity,
the rotation rows free), an axis within a cone of a direction or of the line to a point.
The table (``armik.solve.task_table``) holds per task the target ``(R_t, p_t)``, its
parameters and (chain, look) as ints. The step is the Python descent's
(``armik.solve.tasks._descend``): damped normal equations, a joint a step would push
through its limit held for that step, the trial clipped into the box, kept only where the
cost falls. It stops when every task is within half the tolerances on the compiled FK;
Pinocchio's measure of each task decides afterwards.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from armik.kernel.chain import Flat
from armik.kernel.linalg import solve_spd
from armik.kernel.problem import _workspace
from armik.kernel.region import _evaluate_region

# columns of the table's float parameters (one row per task)
BOUNDS, WEIGHTS, CONE, AXIS, POINT = slice(0, 6), slice(6, 12), 12, slice(13, 16), slice(16, 19)
PARAMS = 19
CHAIN, LOOK = 0, 1  # columns of its ints
LAMBDA_MIN, LAMBDA_MAX = 1e-12, 1e12


@njit(cache=True, nogil=True, inline="always")
def _most_joints(fo, ko, n):
    """The most physical joints of a chain of the table (the workspace's rows of them)."""
    nj = 1
    for c in range(fo.shape[0] - 1):
        nj = max(nj, (ko[c + 1] - ko[c] - n) // 2)
    return nj


@njit(cache=True, nogil=True)
def _stack(fp, fo, ki, ko, halton, R_t, p_t, par, ti, q, tol_p, tol_r, ws, e, A):
    """e (6T,) and A (6T, n) at q, each task's rows after the other; returns (|e|^2, every
    task within (tol_p, tol_r))."""
    n = q.shape[0]
    ws.q[0, :] = q
    cost = 0.0
    done = True
    for t in range(ti.shape[0]):
        c = ti[t, 0]
        ch = Flat(fp[fo[c] : fo[c + 1]], ki[ko[c] : ko[c + 1]], halton)
        p = par[t]
        _evaluate_region(
            ch, p[0:6], p[6:12], p[12], p[13:16], ti[t, 1], p[16:19], R_t[t], p_t[t], ws, 0
        )
        done = done and ws.val[0, 0] <= tol_p and ws.val[0, 1] <= tol_r
        cost += ws.val[0, 2]
        for k in range(6):
            e[6 * t + k] = ws.e[0, k]
            for col in range(n):
                A[6 * t + k, col] = ws.A[0, k, col]
    return cost, done


@njit(cache=True, nogil=True)
def descend(fp, fo, ki, ko, halton, R_t, p_t, par, ti, q, lo, hi, iterations, tol_p, tol_r, lam0):
    """Levenberg-Marquardt from q (overwritten with the end) within [lo, hi]; returns
    (iterations used, every task within half the tolerances)."""
    n, m = q.shape[0], 6 * ti.shape[0]
    ws = _workspace(n, 1, _most_joints(fo, ko, n))
    e, A = np.empty((2, m)), np.empty((2, m, n))
    H, L = np.empty((n, n)), np.empty((n, n))
    g, dq, trial = np.empty(n), np.empty(n), np.empty(n)
    free = np.ones(n, dtype=np.int64)
    tp, tr = 0.5 * tol_p, 0.5 * tol_r
    now = 0
    cost, done = _stack(fp, fo, ki, ko, halton, R_t, p_t, par, ti, q, tp, tr, ws, e[0], A[0])
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
            fp, fo, ki, ko, halton, R_t, p_t, par, ti, trial, tp, tr, ws, e[other], A[other]
        )
        if cost2 < cost:
            q[:] = trial
            now, cost = other, cost2
            lam = max(lam / 3.0, LAMBDA_MIN)
            if done:
                return k + 1, True
        else:
            lam *= 4.0
            if lam > LAMBDA_MAX:
                return k + 1, False
    return iterations, False


@njit(cache=True, nogil=True)
def stacked(fp, fo, ki, ko, halton, R_t, p_t, par, ti, q):
    """(e, A) at q, minus the residual and its Jacobian: ``_stack`` for the tests."""
    n, m = q.shape[0], 6 * ti.shape[0]
    ws = _workspace(n, 1, _most_joints(fo, ko, n))
    e, A = np.empty(m), np.empty((m, n))
    _stack(fp, fo, ki, ko, halton, R_t, p_t, par, ti, q, 0.0, 0.0, ws, e, A)
    return e, A
