"""One tick of the servo, compiled: FK, the task rows, the damped step within every limit.

The target is a table of tasks on the tip (``armik.servo.table``), each row the six rows of
``kernel.region`` (a pose, a position, a region with bounds, an axis in a cone, a look-at).
A tick, from the joint values q and the last velocity v_prev (``state``):

1. the stacked error E and its Jacobian A at q, for this tick's target and for the last
   tick's (its motion since);
2. the smallest of A's ``min(rows, n, rank)`` largest singular values over the unweighted
   rows the task asks for (``stack``, ``rank_bound``, ``armik.servo.singular``) says how
   close the arm is to a singularity, and the damping grows as it falls below
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
from armik.kernel.problem import NO_CONE, NO_LOOK, NVEC, Workspace
from armik.kernel.region import rows_at
from armik.kernel.single import plain_pose
from armik.servo.distances import distances
from armik.servo.layout import (
    AXIS,
    BOUNDS,
    COLUMNS,
    CONE,
    EXACT,
    FIXED,
    LAST,
    LOOK,
    MAX_TASKS,
    PARTS,
    POS,
    RANKS,
    REACH_SLACK,
    ROT,
    SIGHT,
    TOL_P,
    TOL_R,
    WEIGHTS,
    Q,
    carve,
)
from armik.servo.minimum import PROBE, curvature_column, first_order, no_descent
from armik.servo.step import SLOWING, scratch, status_code, step_within
from armik.servo.step import take as _take

# (m, rad) a row's error below this is met, its correction none: the FK's rounding is a
# hundred times smaller, and an exact row's residual (``EXACT``) is far below it, so that
# a servo settled on a held target commands exactly zero motion, not rounding noise
MET = 1e-14
# an exact row whose direction lies within this (1 - its squared share along the
# directions the arm never moves) of them is one the arm can never follow
NEVER = 1e-12


# Called, not inlined at its three sites: 1.2 s less CPU to compile the servo.
@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def views(buf, ibuf, n, N):
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
def stack(table, tasks, ws, E, A, fixed, scale):
    """E, A: the six rows of each of the first ``tasks`` tasks at the placement in ws
    (``forward``'s), and each row's ``scale`` in the singular value (``_counted``; the
    base frame's directions the tip never moves and turns in ``fixed``, (2, 3, 3)
    projectors); returns the largest distances from the tasks' regions (m, rad) and how
    many rows count."""
    n = A.shape[1]
    slot = np.int64(0)
    reg_p = reg_r = 0.0
    active = 0
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
        if row[CONE] > 0.0:
            _one_row(ws.e[0], ws.A[0], n)
        for k in range(6):
            e = ws.e[0, k]
            E[6 * t + k] = e if abs(e) > MET else 0.0
            nonzero = False
            for c in range(n):
                A[6 * t + k, c] = ws.A[0, k, c]
                nonzero = nonzero or ws.A[0, k, c] != 0.0
            sc = _counted(row, k, R_t, nonzero, fixed)
            scale[6 * t + k] = sc
            if sc != 0.0:
                active += 1
    return reg_p, reg_r, active


@njit(cache=True, nogil=True, inline="always")
def rank_bound(table, tasks, scale, ranks):
    """How many of the rows counted in the singular value (``stack``'s ``scale``) can be
    independent at any q: the tip's structural ranks (``armik.servo.fixed``'s: its linear
    velocity's, its angular velocity's, its twist's) bound those of the position rows
    (each reads the linear velocity), of the rotation's and a cone's (the angular
    velocity) and of all; a line of sight's rows read both. The damping's sigma is the
    bound-th singular value: the smallest of more rows would be zero at every q."""
    lin = ang = both = 0
    for t in range(tasks):
        look = table[t, LOOK] != NO_LOOK
        for k in range(6):
            if scale[6 * t + k] != 0.0:
                if k < 3:
                    lin += 1
                elif look:
                    both += 1
                else:
                    ang += 1
    r_lin, r_ang, r_all = np.int64(ranks[0]), np.int64(ranks[1]), np.int64(ranks[2])
    return min(r_all, min(lin, r_lin) + min(ang, r_ang) + both)


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def regions(table, tasks, ws):
    """The largest distances (m, rad) of the placement in ws (ws.m3[0], ws.v3[0]) from the
    first ``tasks`` tasks' regions, as ``stack`` measures them: whether a command is on
    target. The rows go to ws's slot 1 and are not read (ws.J may be another placement's)."""
    slot = np.int64(1)
    reg_p = reg_r = 0.0
    for t in range(tasks):
        row = table[t]
        rows_at(
            row[BOUNDS : BOUNDS + 6],
            row[WEIGHTS : WEIGHTS + 6],
            row[CONE],
            row[AXIS : AXIS + 3],
            np.int64(row[LOOK]),
            row[SIGHT : SIGHT + 3],
            row[ROT : ROT + 9].reshape((3, 3)),
            row[POS : POS + 3],
            ws,
            slot,
        )
        reg_p = max(reg_p, ws.val[1, 0])
        reg_r = max(reg_r, ws.val[1, 1])
    return reg_p, reg_r


@njit(cache=True, nogil=True, inline="always")
def _counted(row, k, R_t, nonzero, fixed):
    """Row k's scale in the singular value (``armik.servo.singular``): 1 over its weight
    where the task asks for it, else 0. A cone's rows (unweighted) and a region's count
    where they are nonzero (outside it); a freed row (infinite bound, zero weight) never;
    an exact row always, zero or not at this q, unless it lies along a direction in
    which the arm never moves its tip (``fixed``: a planar arm's normal), where it is
    zero at every q."""
    if row[CONE] >= 0.0 and k >= 3:
        return 1.0 if nonzero else 0.0
    w, b = row[WEIGHTS + k], row[BOUNDS + k]
    if not (w > 0.0 and b < math.inf):
        return 0.0
    if nonzero:
        return 1.0 / w
    if b > 0.0:  # a region's row inside it
        return 0.0
    P = fixed[0] if k < 3 else fixed[1]
    a = k % 3  # the row's direction in the base frame: the target's axis R_t[:, a]
    along = 0.0
    for i in range(3):
        s = P[i, 0] * R_t[0, a] + P[i, 1] * R_t[1, a] + P[i, 2] * R_t[2, a]
        along += s * s
    return 1.0 / w if 1.0 - along > NEVER else 0.0


@njit(cache=True, nogil=True, inline="always")
def _one_row(e, A, n):
    """A cone's rows 3-5 outside it, ``e = u h`` (u a unit vector, h the angle beyond the
    cone), as the one row (h, u^T A) (``d(u h) = u dh + h du`` with ``u . du = 0``: the
    same gradient ``A^T e``): three rows of rank one near the cone's edge would read as a
    singularity and damp every other task's step."""
    h = math.sqrt(e[3] * e[3] + e[4] * e[4] + e[5] * e[5])
    if h == 0.0:
        return
    u0, u1, u2 = e[3] / h, e[4] / h, e[5] / h
    e[3], e[4], e[5] = h, 0.0, 0.0
    for c in range(n):
        A[3, c] = u0 * A[3, c] + u1 * A[4, c] + u2 * A[5, c]
        A[4, c] = 0.0
        A[5, c] = 0.0


@njit(cache=True, nogil=True, inline="always")
def equal(last, table, tasks):
    """Whether the first ``tasks`` rows of ``last`` and ``table`` are the same numbers (a
    held target: its correction at this q is this tick's, no second evaluation)."""
    for t in range(tasks):
        for c in range(COLUMNS):
            if last[t, c] != table[t, c]:
                return False
    return True


@njit(cache=True, nogil=True, inline="always")
def pose_row(H, row):
    """row: the table row of the plain 4x4 pose H (exact, every axis weighted)."""
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
    row[PARTS], row[PARTS + 1] = 1.0, 1.0


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def _at_minimum(ch, table, tasks, ws, q, E, A, rows, Ep, Ap, scp, fixed, free, M6, cfg):
    """Whether q, where the projected gradient vanishes, is a local minimum of the error
    over the ``free`` joints (``minimum.no_descent``): the rows' derivatives from the rows
    at q moved ``PROBE`` along each (into Ep, Ap, scp), ws's placement left at q again."""
    n = q.shape[0]
    R, p = ws.m3[0], ws.v3[0]
    for j in range(n):
        if free[j] == 0:
            continue
        qj = q[j]
        step = PROBE * max(1.0, abs(qj))
        q[j] = qj + step
        forward(ch, q, R, p, ws.geo[0], ws.geo[1])
        jacobian_local(ch, R, p, ws.geo[0], ws.geo[1], ws.J)
        stack(table, tasks, ws, Ep, Ap, fixed, scp)
        q[j] = qj
        curvature_column(E, A, Ap, rows, step, j, M6[0])
    forward(ch, q, R, p, ws.geo[0], ws.geo[1])
    jacobian_local(ch, R, p, ws.geo[0], ws.geo[1], ws.J)
    return no_descent(E, A, rows, M6[0], free, cfg, M6[1], M6[2])


@njit(cache=True, nogil=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def tick(target, mem, imem, rows_cb):
    """One tick on the servo's memory (``armik.servo.layout``) toward ``target``, within the
    collision rows ``rows_cb`` (K, 2 n + 1: C, then b, then the levers L, for C dq >= b):
    ``state``'s joint values and velocity advanced by one step, ``out`` saying what limited
    it. ``target``: a table (tasks, ``COLUMNS``), or a 4x4 pose H, its table written here
    where it is one the target parser keeps exactly as given (``kernel.single.plain_pose``).
    Returns False, having done nothing, for any other H (the parser then reads it).

    One compiled function for both: each entry would otherwise optimise and emit the
    whole tick's machine code again (numba links a callee's code into every caller)."""
    ch, state, cfg, out, last, pose, buf, ibuf = carve(mem, imem)
    table = target
    if target.shape[1] != COLUMNS:  # a 4x4 pose
        if not plain_pose(target):
            return False
        pose_row(target, pose[0])
        table = pose
    n, N = dof(ch), joints(ch)
    ws, o = views(buf, ibuf, n, N)
    m = 6 * MAX_TASKS
    E, A2, M6, W, act, sc, o = scratch(buf, o, n, m)
    fixed = cfg[FIXED : FIXED + 18].reshape((2, 3, 3))
    iv = ibuf[3 * n : 7 * n].reshape((4, n))
    every = ibuf[7 * n : 8 * n]  # every joint free: the Cholesky factor's mask
    q = state[Q]
    R, p = ws.m3[0], ws.v3[0]
    forward(ch, q, R, p, ws.geo[0], ws.geo[1])
    jacobian_local(ch, R, p, ws.geo[0], ws.geo[1], ws.J)
    tasks = table.shape[0]
    rows = 6 * tasks
    E0, A0, E1, A1 = E[0:m], A2[0], E[m : 2 * m], A2[1]
    reg_p, reg_r, active = stack(table, tasks, ws, E0, A0, fixed, sc[0])
    rank = rank_bound(table, tasks, sc[0], cfg[RANKS : RANKS + 3])
    within = reg_p <= cfg[TOL_P] and reg_r <= cfg[TOL_R]
    free = iv[2]
    saddle = first_order(E0, A0, rows, state, cfg, W[15], free)
    stalled = False
    if saddle:  # and no way on at second order (the rows at q moved: E1, A1 as scratch)
        stalled = _at_minimum(ch, table, tasks, ws, q, E0, A0, rows, E1, A1, sc[1], fixed,
                              free, M6, cfg)  # fmt: skip
        saddle = not stalled
    moved = cfg[LAST] == tasks and not equal(last, table, tasks)  # the last tick's target
    if moved:
        for t in range(tasks):
            moved = moved and last[t, LOOK] == table[t, LOOK] and last[t, CONE] == table[t, CONE]
        if moved:
            stack(last, tasks, ws, E1, A1, fixed, sc[1])
    # a bool, not the literal True: one compiled step_within with the union's tick (False)
    whole = bool(True)  # noqa: UP018
    held = step_within(
        E0, A0, E1, A1, rows, active, rank, sc[0], moved, whole, rows_cb, state, cfg, M6, W,
        iv, every, act, stalled, saddle,
    )  # fmt: skip
    # the true distances the command leaves (the FK at the new joint values)
    forward(ch, q, R, p, ws.geo[0], ws.geo[1])
    # on target where the arm was and where the command is: a moving arm told to stop
    # where it is passes through it, unable to stop within one tick; slowing to stop on
    # the target while what the tasks measure there is still far from it
    if within or held[1] < SLOWING:
        reg_p, reg_r = regions(table, tasks, ws)
        within = within and reg_p <= cfg[TOL_P] and reg_r <= cfg[TOL_R]
    origin, reach_ = reach(ch)
    far = distances(table, R, p, origin, reach_, cfg[REACH_SLACK], out)
    for t in range(tasks):  # this target, the next tick's last
        for c in range(COLUMNS):
            last[t, c] = table[t, c]
    cfg[LAST] = tasks
    status_code(within, far, held, cfg, out, reg_p, reg_r)
    return True
