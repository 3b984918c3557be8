"""The pose error of the iteration and its exact Jacobian.

e = log6(T_tip^-1 T_target): the twist from the tip to the target in the tip frame (LOCAL).
Its Jacobian is -Jlog6(T_target^-1 T_tip) J_local, so a step dq solving A dq = e with
A = Jlog6(T_target^-1 T_tip) J_local moves the tip onto the target. Weights scale the rows
of e and A; the position and orientation errors are measured on the unweighted twist. When
weights free position and rotation axes both, the linear rows are the tip-frame
translation to the target instead (see ``_evaluate``).
"""

from __future__ import annotations

import math

from numba import njit

from armik.kernel.fk import forward, jacobian_local
from armik.kernel.se3 import jlog6_ab, log3, log6_ab


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def relative(ch, q, R_t, p_t, ws):
    """FK at q, then ws.m3[1], ws.v3[1] = T_tip^-1 T_target (rotation, translation in the
    tip frame)."""
    forward(ch, q, ws.m3[0], ws.v3[0], ws.geo[0], ws.geo[1])
    to_target(ws.m3[0], ws.v3[0], R_t, p_t, ws.m3[1], ws.v3[1])


@njit(cache=True, nogil=True, inline="always")
def to_target(R, p, R_t, p_t, M, t):
    """M, t = T^-1 T_target (rotation, translation in the frame T = (R, p))."""
    d0, d1, d2 = p_t[0] - p[0], p_t[1] - p[1], p_t[2] - p[2]
    for i in range(3):
        t[i] = R[0, i] * d0 + R[1, i] * d1 + R[2, i] * d2
        for j in range(3):
            M[i, j] = R[0, i] * R_t[0, j] + R[1, i] * R_t[1, j] + R[2, i] * R_t[2, j]


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def _evaluate(ch, st, R_t, p_t, ws, slot):
    """Error (ws.e[slot]), Jacobian (ws.A[slot]) and ws.val[slot] = (position error,
    orientation error, |e|^2) at the joint values ws.q[slot]."""
    relative(ch, ws.q[slot], R_t, p_t, ws)
    J = ws.J
    jacobian_local(ch, ws.m3[0], ws.v3[0], ws.geo[0], ws.geo[1], J)
    M, t = ws.m3[1], ws.v3[1]
    e = ws.e[slot]
    theta, alpha, beta, sh = log6_ab(M, t, e)  # alpha, beta: also Jlog6's (same angle)
    # Jlog6 of the inverse (M^T, -M^T t), whose log3 is -log3(M) = -e[3:].
    ti, wi = ws.v3[0], ws.v3[2]
    for i in range(3):
        ti[i] = -(M[0, i] * t[0] + M[1, i] * t[1] + M[2, i] * t[2])
        wi[i] = -e[3 + i]
    Jl = ws.Jlog
    jlog6_ab(theta, alpha, beta, sh, wi, ti, Jl)
    A = ws.A[slot]
    n = J.shape[1]
    for c in range(n):  # A = Jlog6 J, with Jlog6's lower-left block zero
        j0, j1, j2, j3, j4, j5 = J[0, c], J[1, c], J[2, c], J[3, c], J[4, c], J[5, c]
        for r in range(3):
            A[r, c] = (
                Jl[r, 0] * j0
                + Jl[r, 1] * j1
                + Jl[r, 2] * j2
                + Jl[r, 3] * j3
                + Jl[r, 4] * j4
                + Jl[r, 5] * j5
            )
            A[3 + r, c] = Jl[3 + r, 3] * j3 + Jl[3 + r, 4] * j4 + Jl[3 + r, 5] * j5
    val = ws.val[slot]
    w = st.w
    if st.full_task:
        pos2 = t[0] * t[0] + t[1] * t[1] + t[2] * t[2]
        rot2 = e[3] * e[3] + e[4] * e[4] + e[5] * e[5]
        lin2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2]
        val[0], val[1], val[2] = math.sqrt(pos2), math.sqrt(rot2), lin2 + rot2
        return
    if st.translation_rows:
        # Free position and rotation axes both: log6's linear part V^-1 t mixes the axes
        # through the rotation left free, so driving its weighted rows to zero does not
        # zero those of t, which the check measures. Use t itself, the tip-frame
        # translation to the target: d t / dq = -(J_lin + J_ang x t).
        for r in range(3):
            e[r] = t[r]
        for c in range(n):
            j3, j4, j5 = J[3, c], J[4, c], J[5, c]
            A[0, c] = J[0, c] + j4 * t[2] - j5 * t[1]
            A[1, c] = J[1, c] + j5 * t[0] - j3 * t[2]
            A[2, c] = J[2, c] + j3 * t[1] - j4 * t[0]
    pos2 = rot2 = sq = 0.0
    for k in range(3):
        if w[k] > 0.0:
            pos2 += t[k] * t[k]
        if w[3 + k] > 0.0:
            rot2 += e[3 + k] * e[3 + k]
    for k in range(6):
        e[k] *= w[k]
        sq += e[k] * e[k]
        for c in range(n):
            A[k, c] *= w[k]
    val[0], val[1], val[2] = math.sqrt(pos2), math.sqrt(rot2), sq


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def evaluate(ch, st, R_t, p_t, ws, slot):
    """``_evaluate`` for Python callers: the kernel calls ``_evaluate``, compiled without the
    CPython wrapper (unboxing its tuple arguments cost compile time in every process)."""
    _evaluate(ch, st, R_t, p_t, ws, slot)


@njit(cache=True, nogil=True, inline="always")
def candidate_score(ch, st, q, R_t, p_t, ws):
    """How far q's tip lands from the target (one FK, no Jacobian): the weighted squared
    position error, or the orientation error when the task ignores position."""
    relative(ch, q, R_t, p_t, ws)
    w, t = st.w, ws.v3[1]
    s = 0.0
    if st.measure_position:
        for k in range(3):
            d = t[k] * w[k]
            s += d * d
        return s
    wv = ws.v3[2]
    log3(ws.m3[1], wv)
    for k in range(3):
        d = wv[k] * w[3 + k]
        s += d * d
    return s
