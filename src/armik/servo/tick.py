"""One tick of the servo, compiled: FK, the task rows, the damped step within every limit.

The target is a table of tasks on the tip (``armik.servo.table``), each row the six rows of
``kernel.region`` (a pose, a position, a region with bounds, an axis in a cone, a look-at).
A tick, from the joint values q and the last velocity v_prev (``state``):

1. the stacked error E and its Jacobian A at q, for this tick's target and for the last
   tick's (its motion since);
2. the smallest of A's ``min(rows, n)`` largest singular values (``armik.servo.singular``)
   says how close the arm is to a singularity, and the damping grows as it falls below
   ``SIGMA`` (so that the arm keeps moving along the directions it still has); the damped
   normal matrix ``A^T A + lam I`` is factored by Cholesky;
3. the desired step: the target's motion in joint space (feed-forward), plus the last
   tick's remaining correction slowed so that the arm can stop on it at its acceleration
   limits, scaled as a whole within the velocity limits;
4. the nearest step to it in the metric of the damped normal matrix within the velocity
   box of ``armik.servo.box`` (a box QP, ``kernel.step.active_set``).

Nothing is allocated and nothing reference-counted (``_nrt=False``): the tick works in the
servo's memory (``armik.servo.layout``), which also keeps the last tick's target.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.chain import dof, joints, reach
from armik.kernel.fk import forward, jacobian_local
from armik.kernel.linalg import cholesky_factor, cholesky_substitute
from armik.kernel.problem import NO_CONE, NO_LOOK, NVEC, Workspace
from armik.kernel.region import rows_at
from armik.kernel.single import plain_pose
from armik.kernel.step import active_set
from armik.servo.box import ACCELERATION, BRAKING, POSITION, VELOCITY, velocity_box
from armik.servo.distances import distances
from armik.servo.layout import (
    ACC,
    AMAX,
    AXIS,
    BOUNDS,
    CODE,
    COLUMNS,
    CONE,
    CONFLICT,
    DT,
    EXACT,
    GAIN,
    GRAM,
    HI,
    JOINT,
    LAM_ERR,
    LAM_MAX,
    LAM_MIN,
    LAST,
    LO,
    LOOK,
    MAX_ROWS,
    MAX_TASKS,
    ORI_ERR,
    POS,
    POS_ERR,
    PULL,
    REACH_SLACK,
    REST,
    ROT,
    SIGHT,
    SIGMA,
    SIGMA_EPS,
    TOL_P,
    TOL_R,
    VMAX,
    WEIGHTS,
    Q,
    V,
    carve,
)
from armik.servo.rows import with_rows
from armik.servo.singular import smallest_singular

# what limited a tick (``armik.servo.result.ServoStatus`` in this order)
ON_TARGET, TRACKING, JOINT_LIMIT, VELOCITY_LIMIT, ACCELERATION_LIMIT = range(5)
SINGULARITY, OUT_OF_REACH, OBSTACLE = 5, 6, 7
BRAKED = 10.0  # tolerances: slowing to stop on a target farther than this is reported
# (m, rad) a row's error below this is met, its correction none: the FK's rounding is a
# hundred times smaller, and an exact row's residual (``EXACT``) is far below it, so that
# a servo settled on a held target commands exactly zero motion, not rounding noise
MET = 1e-14


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


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def _stack(table, tasks, ws, E, A):
    """E, A: the six rows of each of the first ``tasks`` tasks at the placement in ws
    (``forward``'s); returns the largest distances from the tasks' regions (m, rad) and how
    many rows are active."""
    n = A.shape[1]
    slot = np.int64(0)
    reg_p = reg_r = 0.0
    for t in range(tasks):
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
            e = ws.e[0, k]
            E[6 * t + k] = e if abs(e) > MET else 0.0
            for c in range(n):
                A[6 * t + k, c] = ws.A[0, k, c]
    active = 0
    for r in range(6 * tasks):
        for c in range(n):
            if A[r, c] != 0.0:
                active += 1
                break
    return reg_p, reg_r, active


@njit(cache=True, nogil=True, inline="always")
def _equal(last, table, tasks):
    """Whether the first ``tasks`` rows of ``last`` and ``table`` are the same numbers (a
    held target: its correction at this q is this tick's, no second evaluation)."""
    for t in range(tasks):
        for c in range(COLUMNS):
            if last[t, c] != table[t, c]:
                return False
    return True


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def _factor(H, lam, Hl, L, free):
    """L: the Cholesky factor of Hl = H + lam I (``kernel.linalg``'s form); the damping is
    raised tenfold at a time should rounding leave Hl not positive definite."""
    n = H.shape[0]
    for i in range(n):
        free[i] = 1
    for _ in range(40):
        for i in range(n):
            for j in range(n):
                Hl[i, j] = H[i, j]
            Hl[i, i] += lam
        if cholesky_factor(Hl, free, L):
            return
        lam *= 10.0


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def _inverse(L, free, unit, col, Gi):
    """Gi = (L L^T)^-1, a column at a time."""
    n = L.shape[0]
    for c in range(n):
        for i in range(n):
            unit[i] = 1.0 if i == c else 0.0
        cholesky_substitute(L, unit, free, col)
        for i in range(n):
            Gi[i, c] = col[i]


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
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


@njit(cache=True, nogil=True, _nrt=False)  # type: ignore[call-overload]
def tick(table, mem, imem, rows_cb):
    """One tick toward the target ``table`` (tasks, ``COLUMNS``) on the servo's memory
    (``armik.servo.layout``), within the collision rows ``rows_cb`` (K, n + 1: C, then b,
    for C dq >= b)."""
    ch, state, cfg, out, last, _, buf, ibuf = carve(mem, imem)
    _tick(ch, table, rows_cb, state, cfg, out, last, buf, ibuf)


@njit(cache=True, nogil=True, _nrt=False)  # type: ignore[call-overload]
def tick_pose(H, mem, imem, rows_cb):
    """``tick`` toward the 4x4 pose H, where it is one the target parser keeps exactly as
    given (``kernel.single.plain_pose``): its table written here, not in Python. Returns
    False, having done nothing, for any other H (the parser then reads it)."""
    if not plain_pose(H):
        return False
    ch, state, cfg, out, last, pose, buf, ibuf = carve(mem, imem)
    row = pose[0]
    for c in range(COLUMNS):
        row[c] = 0.0
    for a in range(3):
        for b in range(3):
            row[ROT + 3 * a + b] = H[a, b]
        row[POS + a] = H[a, 3]
    for c in range(6):
        row[BOUNDS + c] = -EXACT
        row[WEIGHTS + c] = 1.0
    row[CONE], row[AXIS + 2], row[LOOK] = NO_CONE, 1.0, NO_LOOK
    _tick(ch, pose, rows_cb, state, cfg, out, last, buf, ibuf)
    return True


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def _tick(ch, table, rows_cb, state, cfg, out, last, buf, ibuf):
    """The tick: ``state``'s joint values and velocity advanced by one step toward
    ``table`` (``last``: the last tick's, its ``cfg[LAST]`` rows); ``out`` says what limited
    it."""
    n, N = dof(ch), joints(ch)
    ws, o = _views(buf, ibuf, n, N)
    m = 6 * MAX_TASKS
    E, o = _take(buf, o, 2 * m)
    Ab, o = _take(buf, o, 2 * m * n)
    mats, o = _take(buf, o, 8 * n * n)
    vecs, o = _take(buf, o, 19 * n)
    act, o = _take(buf, o, MAX_ROWS)
    A2 = Ab.reshape((2, m, n))
    M6 = mats.reshape((8, n, n))
    Hm, Hl, Lc, Gi, Hh, Lm = M6[0], M6[1], M6[2], M6[3], M6[4], M6[5]
    S, Ls = M6[6], M6[7]  # the Gram matrix of ``singular`` and its factor
    W = vecs.reshape((19, n))
    u, tmp, g, y, x, x_old, xf, lb, ub, dq, gap, mult, xo = (
        W[0], W[1], W[2], W[3], W[4], W[5], W[6], W[7], W[8], W[9], W[10], W[11], W[12]
    )  # fmt: skip
    # (u: the Gram matrix's smallest eigenvector, kept between ticks)
    lk, uk = W[13], W[14]
    iv = ibuf[3 * n : 7 * n].reshape((4, n))
    side, held, sub = iv[0], iv[1], iv[2]
    every = ibuf[7 * n : 8 * n]  # every joint free: the Cholesky factor's mask
    q, v_prev = state[Q], state[V]
    dt = cfg[DT]
    R, p = ws.m3[0], ws.v3[0]
    forward(ch, q, R, p, ws.geo[0], ws.geo[1])
    jacobian_local(ch, R, p, ws.geo[0], ws.geo[1], ws.J)
    tasks = table.shape[0]
    rows = 6 * tasks
    E0, A0 = E[0:m], A2[0]
    reg_p, reg_r, active = _stack(table, tasks, ws, E0, A0)
    within = reg_p <= cfg[TOL_P] and reg_r <= cfg[TOL_R]
    # the normal matrix, the smallest singular value, the damping
    for i in range(n):
        for j in range(i + 1):
            s = 0.0
            for r in range(rows):
                s += A0[r, i] * A0[r, j]
            Hm[i, j] = s
            Hm[j, i] = s
    last_k = np.int64(cfg[GRAM])
    sigma, k = smallest_singular(A0, rows, active, Hm, S, u, last_k, Ls, tmp, side)
    cfg[GRAM] = k
    eps = cfg[SIGMA_EPS]
    lam = cfg[LAM_MIN]
    for r in range(rows):  # and with the error (Levenberg-Marquardt): far, a gradient step
        lam += cfg[LAM_ERR] * E0[r] * E0[r]
    if sigma < eps:
        lam += cfg[LAM_MAX] * (1.0 - (sigma / eps) ** 2)
    pull = cfg[PULL] * dt * (lam - cfg[LAM_MIN]) / lam  # none on a plain step
    _gradient(E0, A0, rows, g, lam, pull, state)
    _factor(Hm, lam, Hl, Lc, every)
    cholesky_substitute(Lc, g, every, x)  # the whole correction to this tick's target
    for i in range(n):
        x_old[i] = x[i]
    if cfg[LAST] == tasks and not _equal(last, table, tasks):  # the last tick's target
        same = True
        for t in range(tasks):
            same = same and last[t, LOOK] == table[t, LOOK] and last[t, CONE] == table[t, CONE]
        if same:
            E1, A1 = E[m : 2 * m], A2[1]
            _stack(last, tasks, ws, E1, A1)
            _gradient(E1, A1, rows, y, lam, pull, state)
            cholesky_substitute(Lc, y, every, x_old)
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
        _inverse(Lc, every, y, tmp, Gi)
        if not active_set(Gi, xf, lb, ub, xf, side, held, sub, Hh, gap, mult, Lm, xo):
            for i in range(n):
                xo[i] = xf[i]
        for i in range(n):  # within the box whatever the rounding
            dq[i] = min(max(xo[i], lb[i]), ub[i])
    blocked = False
    if rows_cb.shape[0] > 0:
        C, b = rows_cb[:, :n], rows_cb[:, n]
        blocked = with_rows(C, b, Hl, xf, lb, ub, dq, act, Hm, Gi, g, x, tmp, iv, M6[4:6], W[16:19])
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
    far = distances(table, R, p, origin, reach_, cfg[REACH_SLACK], out)
    for t in range(tasks):  # this target, the next tick's last
        for c in range(COLUMNS):
            last[t, c] = table[t, c]
    cfg[LAST] = tasks
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
