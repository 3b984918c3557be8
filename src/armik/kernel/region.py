"""The error of a pose target with a region around it (TRAC-IK's bounds), for the step.

The twist of the tip relative to the target, in the target frame, ``E = (R_t^T (p - p_t),
log3(R_t^T R))``, is shrunk towards zero by each component's bound (``inf`` frees it): the
residual ``r`` is zero inside the box and grows outside it. The step solves ``A dq = e``
with ``e = -w r`` and ``A = w dE/dq`` on the rows outside the box (``w``: the weights),
``dE/dq = (R_t^T R J_v, Jlog3(R_t^T R) J_w)`` from the LOCAL Jacobian. ``val`` holds the
distance from the box (position m, orientation rad) and ``|e|^2``, as ``error._evaluate``
does for an exact target. ``armik.problem.Pose`` is the same task in Python: the tests hold
the two equal.
"""

from __future__ import annotations

import math

from numba import njit

from armik.kernel.error import relative
from armik.kernel.fk import jacobian_local
from armik.kernel.se3 import jlog3, log3


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def _evaluate_region(ch, bounds, w, R_t, p_t, ws, slot):
    """ws.e[slot], ws.A[slot] and ws.val[slot] at ws.q[slot] for the target (R_t, p_t)
    within ``bounds`` (6,), weighted by ``w`` (6,)."""
    relative(ch, ws.q[slot], R_t, p_t, ws)  # M = R^T R_t, t = R^T (p_t - p)
    J = ws.J
    jacobian_local(ch, ws.m3[0], ws.v3[0], ws.geo[0], ws.geo[1], J)
    M, t, v = ws.m3[1], ws.v3[1], ws.v3[2]
    e, A, Jl = ws.e[slot], ws.A[slot], ws.Jlog
    theta = log3(M, v)
    for i in range(3):
        e[i] = -(M[0, i] * t[0] + M[1, i] * t[1] + M[2, i] * t[2])  # R_t^T (p - p_t)
        v[i] = -v[i]  # log3(M^T) = -log3(M)
        e[3 + i] = v[i]
    jlog3(theta, v, Jl)  # of M^T, into Jl's upper-left block
    n = J.shape[1]
    pos2 = rot2 = sq = 0.0
    for k in range(6):
        b = bounds[k]
        E = e[k]
        if not abs(E) > b:  # inside (or free): no residual, no derivative
            e[k] = 0.0
            for c in range(n):
                A[k, c] = 0.0
            continue
        r = E - math.copysign(b, E)
        if w[k] > 0.0:
            if k < 3:
                pos2 += r * r
            else:
                rot2 += r * r
        e[k] = -w[k] * r
        sq += e[k] * e[k]
        for c in range(n):
            if k < 3:
                d = M[0, k] * J[0, c] + M[1, k] * J[1, c] + M[2, k] * J[2, c]
            else:
                i = k - 3
                d = Jl[i, 0] * J[3, c] + Jl[i, 1] * J[4, c] + Jl[i, 2] * J[5, c]
            A[k, c] = w[k] * d
    val = ws.val[slot]
    val[0], val[1], val[2] = math.sqrt(pos2), math.sqrt(rot2), sq


@njit(cache=True, nogil=True)
def evaluate_region(ch, bounds, w, R_t, p_t, ws, slot):
    """``_evaluate_region`` for Python callers (the tests)."""
    _evaluate_region(ch, bounds, w, R_t, p_t, ws, slot)
