"""The servo's damped step within every limit, compiled: what one tick does once its rows
are stacked, shared by a chain's tick (``armik.servo.tick``) and the tick over chains that
share joints (``armik.servo.union_tick``).

From the stacked rows E, A at q (this tick's target) and E1, A1 (the last tick's target at
the same q, its motion since): the smallest singular value (``armik.servo.singular``) and
the damping; the whole correction x toward this target and x_old toward the last one; the
desired step, the target's motion (x - x_old) plus the last correction slowed so that
every joint can stop on it; the nearest step to it within the velocity box of
``armik.servo.box`` (``kernel.step.active_set``, else ``armik.servo.box_qp``) and the
collision rows (``armik.servo.rows``); q and v advanced. ``code`` says what held the tick
back.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.linalg import cholesky_factor, cholesky_substitute
from armik.kernel.step import active_set
from armik.servo.box import ACCELERATION, BRAKING, POSITION, VELOCITY, velocity_box
from armik.servo.box_qp import nearest_in_box
from armik.servo.layout import (
    ACC,
    AMAX,
    CODE,
    CONFLICT,
    CURVE,
    DT,
    GAIN,
    GRAM,
    HI,
    JOINT,
    LAM_ERR,
    LAM_MAX,
    LAM_MIN,
    LO,
    MAX_ROWS,
    PULL,
    REST,
    SIGMA,
    SIGMA_EPS,
    TOL_P,
    TOL_R,
    VMAX,
    Q,
    V,
)
from armik.servo.rows import with_rows
from armik.servo.singular import smallest_singular

# what limited a tick (``armik.servo.result.ServoStatus`` in this order)
ON_TARGET, TRACKING, JOINT_LIMIT, VELOCITY_LIMIT, ACCELERATION_LIMIT = range(5)
SINGULARITY, OUT_OF_REACH, OBSTACLE, STALLED = 5, 6, 7, 8
BRAKED = 10.0  # tolerances: slowing to stop on a target farther than this is reported
SLOWING = 0.5  # a brake below this: the step slowed to stop on the target (``status_code``)
# The Gauss-Newton step leaves out the error times the rows' second derivatives, about
# the curvature length (``servo.curvature``) times the error. Where the joints cannot
# remove the error, these terms outweigh A^T A and the step overshoots a minimum the
# limits hold it off from (a TALOS arm wandered at 1 rad/s 9 mm from it): the damping
# grows by the curvature length times the error left after a step damped by UNREMOVED of
# the curvature length times the error, times that error's share of the error squared
# (none while tracking a target the joints reach: the step as before)
UNREMOVED = 1e-2
RESIDUAL = 1e-3  # of the plain damping: below it none (the plain step to the last bit)
WEAK = 1e2  # (``_weak``)
UNSEEN = 1e-12  # of the normal matrix's trace: the pull's damping (``_unseen``)


@njit(cache=True, nogil=True, inline="always")
def take(buf, o, size):
    return buf[o : o + size], o + size


@njit(cache=True, nogil=True, inline="always")
def scratch(buf, o, n, m):
    """The step's arrays on ``buf`` from ``o`` for n joint values and m rows a target:
    (E (2 m), A (2, m, n), mats (8, n, n), vecs (19, n), act (2 ``MAX_ROWS``: each pair's
    damper and braking, ``armik.servo.rows``), scale (2, m):
    each row's scale in the singular value, ``tick.stack``'s, the end)."""
    E, o = take(buf, o, 2 * m)
    Ab, o = take(buf, o, 2 * m * n)
    mats, o = take(buf, o, 8 * n * n)
    vecs, o = take(buf, o, 19 * n)
    act, o = take(buf, o, 2 * MAX_ROWS)
    sc, o = take(buf, o, 2 * m)
    mats3, vecs2 = mats.reshape((8, n, n)), vecs.reshape((19, n))
    return E, Ab.reshape((2, m, n)), mats3, vecs2, act, sc.reshape((2, m)), o


def scratch_size(n: int, m: int) -> int:
    """The floats ``scratch`` takes for n joint values and m rows a target."""
    return 4 * m + 2 * m * n + 8 * n * n + 19 * n + 2 * MAX_ROWS


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def _factor(H, lam, Hl, L, free):
    """L: the Cholesky factor of Hl = H + lam I (``kernel.linalg``'s form); the damping is
    raised tenfold at a time should rounding leave Hl not positive definite."""
    for i in range(H.shape[0]):
        free[i] = 1
    _damped_factor(H, lam, Hl, L, free)


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def _damped_factor(H, lam, Hl, L, free):
    """Whether L is the Cholesky factor of Hl = H + lam I over the ``free`` joints, the
    damping raised tenfold at a time (40 times at most) should rounding leave Hl not
    positive definite."""
    n = H.shape[0]
    for _ in range(40):
        for i in range(n):
            for j in range(n):
                Hl[i, j] = H[i, j]
            Hl[i, i] += lam
        if cholesky_factor(Hl, free, L):
            return True
        lam *= 10.0
    return False


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
def _gradient(E, A, m, g, lam, pull, z):
    """g = A^T E + lam pull z: the minimiser of |A x - E|^2 + lam |x - pull z|^2 is (A^T A +
    lam I)^-1 (A^T E + lam pull z), with z the way to the rest posture that no row sees
    (``_unseen``), which thus acts only along the directions the damping gives up and the
    task leaves free, so that the arm leaves a stretched, limit-held posture."""
    n = A.shape[1]
    for i in range(n):
        s = 0.0
        for r in range(m):
            s += A[r, i] * E[r]
        g[i] = s + lam * pull * z[i]


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def _unseen(Hm, state, Hl, L, every, t, z):
    """z: the way to the rest posture, rest - q, projected onto the directions in which
    the rows do not move, ``mu (A^T A + mu I)^-1`` (mu a share ``UNSEEN`` of the trace: 1
    along a null direction of A, mu / s^2 along one of singular value s): a redundant
    arm's self-motion, a stretched arm's fold. Along a direction the rows see, however
    weakly, the pull balanced the gradient near a singularity and the arm came to rest
    short of a target it reaches (a Kinova 0.9 mm off for good, saying ``singularity``).
    ``Hl``, ``L`` (n x n) and ``t`` (n) are scratch."""
    n = Hm.shape[0]
    trace = 0.0
    for i in range(n):
        trace += Hm[i, i]
    mu = UNSEEN * (trace + 1.0)
    for i in range(n):
        t[i] = mu * (state[REST, i] - state[Q, i])
    if _damped_factor(Hm, mu, Hl, L, every):
        cholesky_substitute(L, t, every, z)
    else:
        for i in range(n):
            z[i] = 0.0


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def _unremoved(E, A, m, scale, h, Hm, mu, Hl, L, free, z):
    """(|E - A z|^2, |E|^2) over the rows the task asks for (``scale`` not 0; a row along
    a direction the tip never moves has no second derivative either), z = (A^T A + mu
    I)^-1 h over the ``free`` joints (ints), h = A^T E: the error a step over them damped
    by mu (of the curvature length times the error) leaves. None where they remove the
    error; all of it at a least-squares minimum (A^T E = 0), and wherever only directions
    whose squared singular value is below mu could remove it: there the terms the
    Gauss-Newton step leaves out outweigh the ones it keeps. ``Hl``, ``L`` (n x n) and
    ``z`` (n) are scratch."""
    n = Hm.shape[0]
    trace = 0.0
    for i in range(n):
        trace += Hm[i, i]
    mu = max(mu, 1e-15 * (trace + 1.0))  # (raised tenfold should rounding need it)
    if not _damped_factor(Hm, mu, Hl, L, free):
        return 0.0, 0.0
    cholesky_substitute(L, h, free, z)
    left = whole = 0.0
    for k in range(m):
        if scale[k] == 0.0:
            continue
        e = E[k]
        whole += e * e
        for i in range(n):
            e -= A[k, i] * z[i]
        left += e * e
    return left, whole


@njit(cache=True, nogil=True, inline="always")
def _weak(sigma, scale, rows, active, rank, free, mu):
    """Whether some direction of the task may have a squared singular value within
    ``WEAK`` of mu (``_unremoved`` then measured; else it would add under 1e-6 of the
    curvature length times the error, the step as good as the plain one, and a tick
    tracking a target saves a second factorisation): a joint pinned at a limit, more rows
    than can be independent (than joints, or than the tip's structural ranks allow), or
    the smallest singular value of the weighted rows (at least sigma over the largest row
    scale) that small."""
    if active > rank:
        return True
    for i in range(free.shape[0]):
        if free[i] == 0:
            return True
    top = 0.0
    for r in range(rows):
        top = max(top, scale[r])
    if top == 0.0:
        return False
    weak = sigma / top
    return weak * weak < WEAK * mu


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def _within_limits(x, q, state, Hl, t, lb, ub, side, free, L, r, p):
    """x (in place): the correction within the position limits nearest x in the metric of
    the damped normal matrix ``Hl`` (``box_qp``), where x crosses one: a joint at its
    limit that x pushes past it stays there and the others make up for it as far as
    they can. Else the braking toward x is read off a motion no joint can make, and the
    step that the box leaves the others, slowed for it, crawls (a saddle the arm would
    leave at once is left in seconds). ``t``, ``lb``, ``ub``, ``r``, ``p`` (n), ``side``,
    ``free`` (n ints) and ``L`` (n x n) are scratch. Returns the joint held back most at
    its limit (-1: none)."""
    n = x.shape[0]
    crosses = False
    for i in range(n):
        lb[i] = state[LO, i] - q[i]
        ub[i] = state[HI, i] - q[i]
        t[i] = x[i]
        crosses = crosses or x[i] < lb[i] or x[i] > ub[i]
    if not crosses:
        return -1
    nearest_in_box(Hl, t, lb, ub, x, side, free, L, r, p)
    worst, most = -1, 0.0
    for i in range(n):
        if (x[i] <= lb[i] or x[i] >= ub[i]) and abs(t[i] - x[i]) > most:
            worst, most = i, abs(t[i] - x[i])
    return worst


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def step_within(E0, A0, E1, A1, rows, active, rank, scale, moved, whole, rows_cb, state, cfg,
                M6, W, iv, every, act, stalled, saddle):  # fmt: skip
    """state's q and v advanced by one step toward E0, A0 (``rows`` rows, ``active`` of
    them counted in the singular value, each at its ``scale``: ``tick.stack``'s, at most
    ``rank`` of them independent at any q: ``tick.rank_bound``'s), from
    E1, A1 where the target ``moved`` since the last tick, within every limit and the
    collision rows ``rows_cb`` (K, 2 n + 1: C, then b, for C dq >= b, then each pair's
    levers, ``armik.servo.rows``).
    With ``whole`` a desired step beyond a joint's velocity limit is scaled as a whole
    (the tip keeps its line), else the box QP leaves the others to make up for it (a
    slow lift under two arms). ``stalled``: q is a local minimum of the error within the
    position limits (``armik.servo.minimum``), where the step holds still; ``saddle``: the
    gradient vanishes there but the error falls at second order. ``iv[2]``: the joints
    free to move (``minimum.first_order``'s). Returns (sigma, brake, scale, slowest,
    joint, bound, blocked, conflict, stalled) for ``status_code``."""
    n = A0.shape[1]
    Hm, Hl, Lc, Gi, Hh, Lm = M6[0], M6[1], M6[2], M6[3], M6[4], M6[5]
    S, Ls = M6[6], M6[7]  # the Gram matrix of ``singular`` and its factor
    u, tmp, g, y, x, x_old, xf, lb, ub, dq, gap, mult, xo = (
        W[0], W[1], W[2], W[3], W[4], W[5], W[6], W[7], W[8], W[9], W[10], W[11], W[12]
    )  # fmt: skip
    # (u: the Gram matrix's smallest eigenvector, kept between ticks)
    lk, uk = W[13], W[14]
    side, held, sub = iv[0], iv[1], iv[2]
    q, v_prev = state[Q], state[V]
    dt = cfg[DT]
    # the normal matrix, the smallest singular value, the damping
    for i in range(n):
        for j in range(i + 1):
            s = 0.0
            for r in range(rows):
                s += A0[r, i] * A0[r, j]
            Hm[i, j] = s
            Hm[j, i] = s
    last_k = np.int64(cfg[GRAM])
    rank = min(n, rank)  # (W[16] is scratch until the collision rows)
    sigma, k = smallest_singular(A0, rows, active, rank, scale, S, u, last_k, Ls, tmp, side, W[16])
    cfg[GRAM] = k
    eps = cfg[SIGMA_EPS]
    lam, err2 = cfg[LAM_MIN], 0.0
    for r in range(rows):  # and with the error (Levenberg-Marquardt): far, a gradient step
        lam += cfg[LAM_ERR] * E0[r] * E0[r]
        err2 += E0[r] * E0[r]
    if sigma < eps:
        lam += cfg[LAM_MAX] * (1.0 - (sigma / eps) ** 2)
    pull = cfg[PULL] * dt * (lam - cfg[LAM_MIN]) / lam  # none on a plain step
    lam_g = lam
    z = W[17]  # the pull's way, along what no row sees (W[16:19] scratch until the rows)
    _unseen(Hm, state, Hl, Lm, every, tmp, z)
    _gradient(E0, A0, rows, g, lam, pull, z)
    for i in range(n):  # y = A^T E: the pull taken back out of g
        y[i] = g[i] - lam * pull * z[i]
    # damped for the terms the Gauss-Newton step leaves out (``UNREMOVED``); at a saddle
    # (``minimum``), the plain step, which leaves it at once
    mu = UNREMOVED * cfg[CURVE] * math.sqrt(err2)
    if err2 > 0.0 and not saddle and _weak(sigma, scale, rows, active, rank, sub, mu):
        left2, whole2 = _unremoved(E0, A0, rows, scale, y, Hm, mu, Hl, Lm, sub, tmp)
        extra = cfg[CURVE] * left2 * math.sqrt(left2) / whole2 if whole2 > 0.0 else 0.0
        if extra > RESIDUAL * lam:  # (else the plain step, to the last bit)
            lam += extra  # (in the normal matrix only: the pull keeps lam_g)
    _factor(Hm, lam, Hl, Lc, every)
    cholesky_substitute(Lc, g, every, x)  # the whole correction to this tick's target
    at_limit = _within_limits(x, q, state, Hl, xf, lb, ub, side, sub, Lm, gap, mult)
    if stalled:  # a local minimum within the limits (``minimum``): held still there
        for i in range(n):
            x[i] = 0.0
    for i in range(n):
        x_old[i] = x[i]
    if moved and not stalled:  # the whole correction to the last tick's target, at this q
        _gradient(E1, A1, rows, y, lam_g, pull, z)
        cholesky_substitute(Lc, y, every, x_old)
        _within_limits(x_old, q, state, Hl, xf, lb, ub, side, sub, Lm, gap, mult)
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
        if whole and vi * scale > state[VMAX, i]:
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
            # cycled: the primal method, which cannot (clipping xf need not lower the error)
            nearest_in_box(Hl, xf, lb, ub, xo, side, sub, Lm, gap, mult)
        for i in range(n):  # within the box whatever the rounding
            dq[i] = min(max(xo[i], lb[i]), ub[i])
    blocked = False
    if rows_cb.shape[0] > 0:
        C, b, L = rows_cb[:, :n], rows_cb[:, n], rows_cb[:, n + 1 :]
        blocked = with_rows(C, b, L, v_prev, state[AMAX], dt, Hl, xf, lb, ub, dq, act, Hm, Gi, g, x,
                            tmp, iv, M6[4:6], W[16:19])  # fmt: skip
    # which bound held the step back most
    worst, joint, bound = 0.0, -1, 0
    for i in range(n):
        gap_i = abs(xf[i] - dq[i])
        if gap_i > worst and (dq[i] <= lb[i] or dq[i] >= ub[i]):
            worst, joint = gap_i, i
            bound = np.int64(lk[i]) if dq[i] <= lb[i] else np.int64(uk[i])
    if joint < 0 and at_limit >= 0:  # no box held it back: the limits held the correction
        joint, bound = at_limit, np.int64(POSITION)
    # advance: the velocity is the difference of the joint values actually commanded
    for i in range(n):
        qn = min(max(q[i] + dq[i], state[LO, i]), state[HI, i])
        v = (qn - q[i]) / dt
        state[ACC, i] = (v - v_prev[i]) / dt
        state[V, i] = v
        q[i] = qn
    return sigma, brake, scale, slowest, joint, bound, blocked, conflict, stalled


@njit(cache=True, nogil=True, inline="always")
def status_code(within, far, held, cfg, out, measured_p, measured_r):
    """out[CODE], out[JOINT], out[SIGMA], out[CONFLICT]: what limited the tick, from
    ``step_within``'s answer ``held`` and what the tasks measure where the command is
    (``measured_p`` m, ``measured_r`` rad: a region's distance outside it, the weighted
    rows', as the on-target decision reads them; read where the step slowed, SLOWING)."""
    sigma, brake, scale, slowest, joint, bound, blocked, conflict, stalled = held
    code, who = TRACKING, joint
    if within:
        code, who = ON_TARGET, -1
    elif far:
        code, who = OUT_OF_REACH, -1
    elif blocked:
        code, who = OBSTACLE, -1
    elif joint >= 0 and (bound == POSITION or bound == BRAKING):
        # at a limit no other motion gets past: the nearest the arm gets, within them
        code, who = (STALLED, -1) if stalled else (JOINT_LIMIT, joint)
    elif joint >= 0 and bound == VELOCITY:
        code = VELOCITY_LIMIT
    elif joint >= 0 and bound == ACCELERATION:
        code = ACCELERATION_LIMIT
    elif scale < 1.0:
        code, who = VELOCITY_LIMIT, slowest
    elif sigma < cfg[SIGMA_EPS]:
        code, who = SINGULARITY, -1
    elif brake < SLOWING and (measured_p > BRAKED * cfg[TOL_P] or measured_r > BRAKED * cfg[TOL_R]):
        code, who = ACCELERATION_LIMIT, -1
    elif stalled:
        code, who = STALLED, -1
    out[CODE], out[JOINT], out[SIGMA] = code, who, sigma
    out[CONFLICT] = 1.0 if conflict else 0.0
