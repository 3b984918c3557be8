"""One tick of the servo, compiled: FK, the task rows, the damped step within every limit.

The target is a table of tasks on the tip (``armik.servo.table``), each row the six rows of
``kernel.region`` (a pose, a position, a region with bounds, an axis in a cone, a look-at).
A tick, from the joint values q and the last velocity v_prev (``state``):

1. the stacked error E and its Jacobian A at q, for this tick's target and for the last
   tick's (its motion since);
2. the damped normal matrix ``A^T A + lam I`` by its eigen-decomposition: the smallest of
   its ``min(rows, n)`` largest singular values says how close the arm is to a
   singularity, and the damping grows as it falls below ``SIGMA`` (so that the arm keeps
   moving along the directions it still has);
3. the desired step: the target's motion in joint space (feed-forward), plus the last
   tick's remaining correction slowed so that the arm can stop on it at its acceleration
   limits, scaled as a whole within the velocity limits;
4. the nearest step to it in the metric of the damped normal matrix within the velocity
   box of ``armik.servo.box`` (a box QP, ``kernel.step.active_set``).

Nothing is allocated: the caller's buffers hold the workspace (``layout``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.chain import Flat, joints, reach
from armik.kernel.fk import forward, jacobian_local
from armik.kernel.problem import LOOK_POINT, LOOK_TOWARD, NVEC, Workspace
from armik.kernel.region import rows_at
from armik.kernel.step import active_set
from armik.servo.box import ACCELERATION, BRAKING, POSITION, VELOCITY, velocity_box
from armik.servo.eigen import jacobi, kth_largest
from armik.servo.rows import with_rows

# columns of a task's row in the table
ROT, POS, BOUNDS, WEIGHTS, CONE, AXIS, LOOK, SIGHT = 0, 9, 12, 18, 24, 25, 28, 29
COLUMNS = 32
MAX_TASKS = 4
MAX_ROWS = 16  # collision rows a tick (``armik.servo.collisions``), the nearest pairs'
# rows of ``state`` (n columns): joint values, last velocity, limits; the tick's acceleration
Q, V, ACC, VMAX, AMAX, LO, HI, REST = range(8)  # Q, V, ACC first: the command
STATE_ROWS = 8
# entries of ``cfg``
DT, TOL_P, TOL_R, SIGMA_EPS, LAM_MAX, LAM_MIN, GAIN, REACH_SLACK, PULL, LAM_ERR, RESET = range(11)
CFG = 11  # RESET: 1 on the first tick (no eigenvectors kept yet)
# entries of ``out``
POS_ERR, ORI_ERR, CODE, JOINT, SIGMA, CONFLICT = range(6)
OUT = 6
# what limited a tick (``armik.servo.result.ServoStatus`` in this order)
ON_TARGET, TRACKING, JOINT_LIMIT, VELOCITY_LIMIT, ACCELERATION_LIMIT = range(5)
SINGULARITY, OUT_OF_REACH, OBSTACLE = 5, 6, 7
BRAKED = 10.0  # tolerances: slowing to stop on a target farther than this is reported


@njit(cache=True, nogil=True)
def layout(n, N):
    """(floats, ints): the buffer sizes ``tick`` needs for n joint values, N physical
    joints."""
    m = 6 * MAX_TASKS
    ws = 2 * n + 12 + 12 * n + 6 + NVEC * n + 4 * n * n + 6 * N + 6 * n + 18 + 9 + 36 + n
    ws += 36 + 12
    return ws + 2 * m + 2 * m * n + 8 * n * n + 19 * n + MAX_ROWS, 7 * n


@njit(cache=True, nogil=True, inline="always")
def _take(buf, o, size):
    return buf[o : o + size], o + size


@njit(cache=True, nogil=True, inline="always")
def _views(buf, ibuf, n, N):
    """A ``kernel.problem.Workspace`` on ``buf`` and ``ibuf`` (one slot's rows read), and
    where the rest of ``buf`` starts."""
    o = 0
    q, o = _take(buf, o, 2 * n)
    e, o = _take(buf, o, 12)
    A, o = _take(buf, o, 12 * n)
    val, o = _take(buf, o, 6)
    vec, o = _take(buf, o, NVEC * n)
    mat, o = _take(buf, o, 4 * n * n)
    geo, o = _take(buf, o, 6 * N)
    J, o = _take(buf, o, 6 * n)
    m3, o = _take(buf, o, 18)
    v3, o = _take(buf, o, 9)
    Jl, o = _take(buf, o, 36)
    mi, o = _take(buf, o, n)
    task, o = _take(buf, o, 36)
    tvec, o = _take(buf, o, 12)
    ws = Workspace(
        q.reshape((2, n)),
        e.reshape((2, 6)),
        A.reshape((2, 6, n)),
        val.reshape((2, 3)),
        vec.reshape((NVEC, n)),
        mat.reshape((4, n, n)),
        ibuf[0 : 3 * n].reshape((3, n)),
        geo.reshape((2, N, 3)),
        J.reshape((6, n)),
        m3.reshape((2, 3, 3)),
        v3.reshape((3, 3)),
        Jl.reshape((6, 6)),
        mi.reshape((1, n)),
        task.reshape((6, 6)),
        tvec.reshape((2, 6)),
    )
    return ws, o


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]
def _stack(table, ws, E, A):
    """E, A: every task's six rows at the placement in ws (``forward``'s); returns the
    largest distances from the tasks' regions (m, rad) and how many rows are active."""
    n = A.shape[1]
    slot = np.int64(0)
    reg_p = reg_r = 0.0
    for t in range(table.shape[0]):
        row = table[t]
        R_t = row[ROT : ROT + 9].reshape((3, 3))
        look = np.int64(row[LOOK])
        rows_at(
            row[BOUNDS : BOUNDS + 6],
            row[WEIGHTS : WEIGHTS + 6],
            row[CONE],
            row[AXIS : AXIS + 3],
            look,
            row[SIGHT : SIGHT + 3],
            R_t,
            row[POS : POS + 3],
            ws,
            slot,
        )
        reg_p = max(reg_p, ws.val[0, 0])
        reg_r = max(reg_r, ws.val[0, 1])
        for k in range(6):
            E[6 * t + k] = ws.e[0, k]
            for c in range(n):
                A[6 * t + k, c] = ws.A[0, k, c]
    active = 0
    for r in range(6 * table.shape[0]):
        for c in range(n):
            if A[r, c] != 0.0:
                active += 1
                break
    return reg_p, reg_r, active


@njit(cache=True, nogil=True, inline="always")
def _measured(row, k):
    """Whether the task's bounds measure position (k = 0) or rotation (k = 3) at all."""
    for i in range(k, k + 3):
        if row[BOUNDS + i] < math.inf:
            return True
    return False


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]
def _distances(table, R, p, origin, reach_, slack, out):
    """out[POS_ERR], out[ORI_ERR]: the largest true distances to the tasks' targets (NaN
    where none measures it); returns whether a position target is beyond the arm's reach."""
    pos = ori = -1.0
    far = False
    for t in range(table.shape[0]):
        row = table[t]
        cone = row[CONE]
        if _measured(row, 0):
            d0, d1, d2 = p[0] - row[POS], p[1] - row[POS + 1], p[2] - row[POS + 2]
            pos = max(pos, math.sqrt(d0 * d0 + d1 * d1 + d2 * d2))
            b = 0.0
            for i in range(3):
                b += row[BOUNDS + i] * row[BOUNDS + i]
            x0, x1, x2 = row[POS] - origin[0], row[POS + 1] - origin[1], row[POS + 2] - origin[2]
            if math.sqrt(x0 * x0 + x1 * x1 + x2 * x2) > reach_ + math.sqrt(b) + slack:
                far = True
        if cone < 0.0 and _measured(row, 3):  # the angle of R_t^T R
            tr = sx = sy = sz = 0.0
            for i in range(3):
                for k in range(3):
                    tr += row[ROT + 3 * k + i] * R[k, i]
            for k in range(3):  # M[2,1]-M[1,2], M[0,2]-M[2,0], M[1,0]-M[0,1], M = R_t^T R
                rk0, rk1, rk2 = row[ROT + 3 * k], row[ROT + 3 * k + 1], row[ROT + 3 * k + 2]
                sx += rk2 * R[k, 1] - rk1 * R[k, 2]
                sy += rk0 * R[k, 2] - rk2 * R[k, 0]
                sz += rk1 * R[k, 0] - rk0 * R[k, 1]
            s = 0.5 * math.sqrt(sx * sx + sy * sy + sz * sz)
            ori = max(ori, math.atan2(s, 0.5 * (tr - 1.0)))
        elif cone >= 0.0:  # the angle of the tip's axis from its direction
            look = np.int64(row[LOOK])
            x0, x1, x2 = row[SIGHT], row[SIGHT + 1], row[SIGHT + 2]
            if look == LOOK_POINT:
                x0, x1, x2 = x0 - p[0], x1 - p[1], x2 - p[2]
            elif look != LOOK_TOWARD:  # the target's image of the axis, in the base frame
                a0, a1, a2 = row[AXIS], row[AXIS + 1], row[AXIS + 2]
                x0 = row[ROT] * a0 + row[ROT + 1] * a1 + row[ROT + 2] * a2
                x1 = row[ROT + 3] * a0 + row[ROT + 4] * a1 + row[ROT + 5] * a2
                x2 = row[ROT + 6] * a0 + row[ROT + 7] * a1 + row[ROT + 8] * a2
            w0 = R[0, 0] * x0 + R[1, 0] * x1 + R[2, 0] * x2  # R^T x: in the tip frame
            w1 = R[0, 1] * x0 + R[1, 1] * x1 + R[2, 1] * x2
            w2 = R[0, 2] * x0 + R[1, 2] * x1 + R[2, 2] * x2
            a0, a1, a2 = row[AXIS], row[AXIS + 1], row[AXIS + 2]
            c0, c1, c2 = a1 * w2 - a2 * w1, a2 * w0 - a0 * w2, a0 * w1 - a1 * w0
            s = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
            k = a0 * w0 + a1 * w1 + a2 * w2
            ori = max(ori, math.atan2(s, k) if s > 0.0 or k != 0.0 else 0.0)
    out[POS_ERR] = pos if pos >= 0.0 else math.nan
    out[ORI_ERR] = ori if ori >= 0.0 else math.nan
    return far


@njit(cache=True, nogil=True, inline="always")
def _congruent(H, V, T, B):
    """B = V^T H V (T: scratch)."""
    n = H.shape[0]
    for i in range(n):
        for j in range(n):
            s = 0.0
            for k in range(n):
                s += H[i, k] * V[k, j]
            T[i, j] = s
    for i in range(n):
        for j in range(i + 1):
            s = 0.0
            for k in range(n):
                s += V[k, i] * T[k, j]
            B[i, j] = s
            B[j, i] = s


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]
def _solve(V, ev, lam, g, y, x):
    """x = V diag(1 / (ev + lam)) V^T g."""
    n = g.shape[0]
    for k in range(n):
        s = 0.0
        for i in range(n):
            s += V[i, k] * g[i]
        y[k] = s / (ev[k] + lam)
    for i in range(n):
        s = 0.0
        for k in range(n):
            s += V[i, k] * y[k]
        x[i] = s


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]
def _gradient(E, A, m, g, lam, pull, state):
    """g = A^T E + lam pull (rest - q): the minimiser of |A x - E|^2 + lam |x - z|^2 is
    (A^T A + lam I)^-1 (A^T E + lam z), with z a pull toward the rest posture, which thus
    acts only along the directions the damping gives up (near a singularity, far from
    the target), so that the arm leaves a stretched, limit-held posture."""
    n = A.shape[1]
    for i in range(n):
        s = 0.0
        for r in range(m):
            s += A[r, i] * E[r]
        g[i] = s + lam * pull * (state[REST, i] - state[Q, i])


@njit(cache=True, nogil=True)
def tick(packed, kind, halton, table, old, rows_cb, state, cfg, buf, ibuf, out):
    """One tick: ``state``'s joint values and velocity advanced by one step toward the
    target ``table`` (``old``: the last tick's, or no rows), within the collision rows
    ``rows_cb`` (K, n + 1: C, then b, for C dq >= b); ``out`` says what limited it."""
    ch = Flat(packed, kind, halton)
    n, N = halton.shape[1], joints(ch)
    ws, o = _views(buf, ibuf, n, N)
    m = 6 * MAX_TASKS
    E, o = _take(buf, o, 2 * m)
    Ab, o = _take(buf, o, 2 * m * n)
    mats, o = _take(buf, o, 8 * n * n)
    vecs, o = _take(buf, o, 19 * n)
    act, o = _take(buf, o, MAX_ROWS)
    A2 = Ab.reshape((2, m, n))
    M6 = mats.reshape((8, n, n))
    Hm, B, Vm, Gi, Hh, Lm = M6[0], M6[1], M6[2], M6[3], M6[4], M6[5]
    Vp, Vr = M6[6], M6[7]  # Vp: the last tick's eigenvectors (kept between ticks)
    W = vecs.reshape((19, n))
    ev, tmp, g, y, x, x_old, xf, lb, ub, dq, gap, mult, xo = (
        W[0], W[1], W[2], W[3], W[4], W[5], W[6], W[7], W[8], W[9], W[10], W[11], W[12]
    )  # fmt: skip
    lk, uk = W[13], W[14]
    iv = ibuf[3 * n : 7 * n].reshape((4, n))
    side, held, sub = iv[0], iv[1], iv[2]
    q, v_prev = state[Q], state[V]
    dt = cfg[DT]
    R, p = ws.m3[0], ws.v3[0]
    forward(ch, q, R, p, ws.geo[0], ws.geo[1])
    jacobian_local(ch, R, p, ws.geo[0], ws.geo[1], ws.J)
    rows = 6 * table.shape[0]
    E0, A0 = E[0:m], A2[0]
    reg_p, reg_r, active = _stack(table, ws, E0, A0)
    within = reg_p <= cfg[TOL_P] and reg_r <= cfg[TOL_R]
    # the normal matrix, its eigen-decomposition, the damping
    for i in range(n):
        for j in range(i + 1):
            s = 0.0
            for r in range(rows):
                s += A0[r, i] * A0[r, j]
            Hm[i, j] = s
            Hm[j, i] = s
    # Jacobi from the last tick's eigenvectors: B = Vp^T H Vp is nearly diagonal, one or
    # two sweeps instead of six to eight from scratch; then V = Vp Vr
    if cfg[RESET] != 0.0:
        cfg[RESET] = 0.0
        for i in range(n):
            for j in range(n):
                Vp[i, j] = 1.0 if i == j else 0.0
    _congruent(Hm, Vp, Gi, B)
    jacobi(B, Vr, ev)
    for i in range(n):
        for j in range(n):
            s = 0.0
            for k in range(n):
                s += Vp[i, k] * Vr[k, j]
            Vm[i, j] = s
    for i in range(n):
        for j in range(n):
            Vp[i, j] = Vm[i, j]
    r = min(active, n)
    sigma = math.inf if r == 0 else math.sqrt(max(kth_largest(ev, r, tmp), 0.0))
    eps = cfg[SIGMA_EPS]
    lam = cfg[LAM_MIN]
    for r in range(rows):  # and with the error (Levenberg-Marquardt): far, a gradient step
        lam += cfg[LAM_ERR] * E0[r] * E0[r]
    if sigma < eps:
        lam += cfg[LAM_MAX] * (1.0 - (sigma / eps) ** 2)
    pull = cfg[PULL] * dt * (lam - cfg[LAM_MIN]) / lam  # none on a plain step
    _gradient(E0, A0, rows, g, lam, pull, state)
    _solve(Vm, ev, lam, g, y, x)  # the whole correction to this tick's target
    for i in range(n):
        x_old[i] = x[i]
    if old.shape[0] == table.shape[0]:  # the last tick's target, at this q
        same = True
        for t in range(table.shape[0]):
            same = same and old[t, LOOK] == table[t, LOOK] and old[t, CONE] == table[t, CONE]
        if same:
            E1, A1 = E[m : 2 * m], A2[1]
            _stack(old, ws, E1, A1)
            _gradient(E1, A1, rows, y, lam, pull, state)
            for i in range(n):
                g[i] = y[i]
            _solve(Vm, ev, lam, g, y, x_old)
    # desired velocity: feed-forward of the target's motion, plus the last tick's remaining
    # correction slowed so that every joint can stop on it at its acceleration limit
    gain = cfg[GAIN]
    brake = 1.0
    for i in range(n):  # box.braking(a, dt, d) dt / d, for d = |x_old| gain
        d = abs(x_old[i]) * gain
        if d > 0.0:
            a = state[AMAX, i]
            brake = min(brake, 2.0 * a * dt / (a * dt + math.sqrt(a * a * dt * dt + 2.0 * a * d)))
    scale = 1.0
    slowest = -1
    for i in range(n):
        xf[i] = (x[i] - x_old[i]) + brake * gain * x_old[i]
        vi = abs(xf[i]) / dt
        if vi * scale > state[VMAX, i]:
            scale = state[VMAX, i] / vi
            slowest = i
    # the box of every limit, and the QP's step within it
    conflict = False
    inside = True
    for i in range(n):
        xf[i] *= scale
        lo_v, hi_v, kl, ku, c = velocity_box(
            q[i], v_prev[i], state[LO, i], state[HI, i], state[VMAX, i], state[AMAX, i], dt
        )
        conflict = conflict or c
        lb[i], ub[i] = lo_v * dt, hi_v * dt
        lk[i], uk[i] = kl, ku
        if xf[i] < lb[i] or xf[i] > ub[i]:
            inside = False
    if inside:
        for i in range(n):
            dq[i] = xf[i]
    else:
        for k in range(n):
            y[k] = 1.0 / (ev[k] + lam)
        for i in range(n):
            for j in range(n):
                s = 0.0
                for k in range(n):
                    s += Vm[i, k] * y[k] * Vm[j, k]
                Gi[i, j] = s
        if not active_set(Gi, xf, lb, ub, xf, side, held, sub, Hh, gap, mult, Lm, xo):
            for i in range(n):
                xo[i] = xf[i]
        for i in range(n):  # within the box whatever the rounding
            dq[i] = min(max(xo[i], lb[i]), ub[i])
    blocked = False
    if rows_cb.shape[0] > 0:
        C, b = rows_cb[:, :n], rows_cb[:, n]
        blocked = with_rows(
            C, b, Vm, ev, lam, xf, lb, ub, dq, act, B, Gi, g, x, tmp, iv, M6[4:6], W[16:19]
        )
    # which bound held the step back most
    worst, joint, bound = 0.0, -1, 0
    for i in range(n):
        gap_i = abs(xf[i] - dq[i])
        if gap_i > worst and (dq[i] <= lb[i] or dq[i] >= ub[i]):
            worst, joint = gap_i, i
            bound = np.int64(lk[i]) if dq[i] <= lb[i] else np.int64(uk[i])
    # advance: the velocity is the difference of the joint values actually commanded
    for i in range(n):
        qn = min(max(q[i] + dq[i], state[LO, i]), state[HI, i])
        v = (qn - q[i]) / dt
        state[ACC, i] = (v - v_prev[i]) / dt
        state[V, i] = v
        q[i] = qn
    # the true distances the command leaves (the FK at the new joint values)
    forward(ch, q, R, p, ws.geo[0], ws.geo[1])
    origin, reach_ = reach(ch)
    far = _distances(table, R, p, origin, reach_, cfg[REACH_SLACK], out)
    code, who = TRACKING, joint
    if within:
        code, who = ON_TARGET, -1
    elif far:
        code, who = OUT_OF_REACH, -1
    elif blocked:
        code, who = OBSTACLE, -1
    elif joint >= 0 and (bound == POSITION or bound == BRAKING):
        code = JOINT_LIMIT
    elif joint >= 0 and bound == VELOCITY:
        code = VELOCITY_LIMIT
    elif joint >= 0 and bound == ACCELERATION:
        code = ACCELERATION_LIMIT
    elif scale < 1.0:
        code, who = VELOCITY_LIMIT, slowest
    elif sigma < eps:
        code, who = SINGULARITY, -1
    elif brake < 0.5 and (  # (an error not measured is NaN: compares false)
        out[POS_ERR] > BRAKED * cfg[TOL_P] or out[ORI_ERR] > BRAKED * cfg[TOL_R]
    ):
        code, who = ACCELERATION_LIMIT, -1
    out[CODE], out[JOINT], out[SIGMA] = code, who, sigma
    out[CONFLICT] = 1.0 if conflict else 0.0
