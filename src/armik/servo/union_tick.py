"""The servo over shared joints' tick, compiled: each tip's rows by its chain's kernel FK,
stacked over the union's joints, and the damped step within the velocity box.

``armik.servo.union`` calls ``union_tick`` once a tick. The chains are given as their
kernel arrays one after the other (``packed`` and ``kinds`` cut at ``pack_at`` and
``kind_at``) and ``maps``, each chain's joints' columns in the union (cut at ``map_at``).
A tip's row block is its position error (base axes, m), then, where its goal has a
rotation, its rotation error ``log3(R_goal R^T)`` (rad); its Jacobian's columns are each
joint's ``w x (p - o)`` and ``w`` (``w`` zero and ``v`` the axis for a prismatic joint),
in the base frame, scattered into the union's columns.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.chain import PRISMATIC, Flat
from armik.kernel.fk import forward
from armik.kernel.se3 import log3
from armik.kernel.step import active_set
from armik.servo.box import velocity_box

# what limited a tick, as ``armik.servo.result.ServoStatus`` orders them
ON_TARGET, TRACKING, JOINT_LIMIT, VELOCITY_LIMIT, ACCELERATION_LIMIT = range(5)
SINGULARITY, OUT_OF_REACH = 5, 6
_BY_BOX = (TRACKING, JOINT_LIMIT, VELOCITY_LIMIT, ACCELERATION_LIMIT, JOINT_LIMIT)  # box.FREE..


@njit(cache=True, nogil=True, inline="always")
def _errors(goal_R, goal_p, t, rotated, R, p, M, w, E, m):
    """Tip t's rows of E at the placement (R, p): its goal's position error, then, where
    its goal has a rotation, the rotation error ``log3(R_goal R^T)`` (M: R_goal R^T)."""
    for r in range(3):
        E[m + r] = goal_p[t, r] - p[r]
    if not rotated:
        return
    G = goal_R[t]
    for a in range(3):
        for b in range(3):
            M[a, b] = G[a, 0] * R[b, 0] + G[a, 1] * R[b, 1] + G[a, 2] * R[b, 2]
    log3(M, w)
    E[m + 3], E[m + 4], E[m + 5] = w[0], w[1], w[2]


@njit(cache=True, nogil=True)
def task_rows(packed, pack_at, kinds, kind_at, maps, map_at, q, goal_R, goal_p, last_R,
              last_p, rotated, E, E_last, A, jacobian,
              R, p, origins, axes, qc, w, M, flat0):  # fmt: skip
    """The stacked errors at the union's joint values q, from one FK of each chain: E
    toward the goals, E_last toward the last tick's (of the same kinds), and with
    ``jacobian`` E's Jacobian A over the union's joints; returns the rows written. ``R``,
    ``p``, ``origins``, ``axes``, ``qc``, ``w``, ``M``: scratch; ``flat0`` (0, n): a chain's
    empty restart table, cut to its joints."""
    m = 0
    n = q.shape[0]
    for t in range(pack_at.shape[0] - 1):
        cols = maps[map_at[t] : map_at[t + 1]]
        nt = cols.shape[0]
        for j in range(nt):
            qc[j] = q[cols[j]]
        ch = Flat(packed[pack_at[t] : pack_at[t + 1]], kinds[kind_at[t] : kind_at[t + 1]],
                  flat0[:, :nt])  # fmt: skip
        forward(ch, qc[:nt], R, p, origins, axes)
        _errors(goal_R, goal_p, t, rotated[t], R, p, M, w, E, m)
        _errors(last_R, last_p, t, rotated[t], R, p, M, w, E_last, m)
        rows = 6 if rotated[t] else 3
        if jacobian:
            for r in range(rows):
                for c in range(n):
                    A[m + r, c] = 0.0
            for j in range(nt):
                c = cols[j]
                wx, wy, wz = axes[j, 0], axes[j, 1], axes[j, 2]
                if kinds[kind_at[t] + nt + j] == PRISMATIC:
                    A[m, c], A[m + 1, c], A[m + 2, c] = wx, wy, wz
                    continue
                dx, dy, dz = p[0] - origins[j, 0], p[1] - origins[j, 1], p[2] - origins[j, 2]
                A[m, c] = wy * dz - wz * dy
                A[m + 1, c] = wz * dx - wx * dz
                A[m + 2, c] = wx * dy - wy * dx
                if rows == 6:
                    A[m + 3, c], A[m + 4, c], A[m + 5, c] = wx, wy, wz
        m += rows
    return m


@njit(cache=True, nogil=True)
def damped_step(A, E, E_last, q, v_prev, rest, lo, hi, vmax, amax, dt, gain, settings,
                lb, ub, v, ints, Hh, gap, mult, Lm, x):  # fmt: skip
    """The step v (rad/s) toward E (the error now) from E_last (toward the last tick's
    goals), within every joint's velocity box: the last correction slowed so that each
    joint can stop on it, the goals' motion followed at once, the free joints pulled to
    ``rest``; damped by ``settings`` (sigma_eps, lam_max, lam_err, lam_min, pull). Returns
    (sigma, slowed, code, joint, conflict): ``code`` what a box held back (``_BY_BOX``),
    ``joint`` which (-1: none)."""
    sigma_eps, lam_max, lam_err, lam_min, pull = (
        settings[0], settings[1], settings[2], settings[3], settings[4]
    )  # fmt: skip
    n = q.shape[0]
    # the smallest of A's min(rows, n) largest singular values, from the smaller Gram matrix
    gram = A @ A.T if A.shape[0] < n else A.T @ A
    sigma = math.sqrt(max(np.linalg.eigvalsh(gram)[0], 0.0)) if gram.shape[0] else math.inf
    lam = lam_min + lam_err * np.dot(E, E)
    if sigma < sigma_eps:
        lam += lam_max * (1.0 - (sigma / sigma_eps) ** 2)
    H = A.T @ A
    for i in range(n):
        H[i, i] += lam
    G = np.linalg.inv(H)
    fix = G @ (A.T @ E_last)
    slowed = 1.0
    for i in range(n):
        want = abs(gain * fix[i] / dt)
        if want > 0.0:
            slowed = min(slowed, math.sqrt(2.0 * amax[i] * abs(fix[i])) / want)
    free = (G @ (A.T @ (E - E_last))) / dt + slowed * gain * fix / dt
    free += lam * (G @ (pull * (rest - q)))
    lk = ints[0]
    uk = ints[1]
    conflict = False
    for i in range(n):
        lb[i], ub[i], lk[i], uk[i], c = velocity_box(
            q[i], v_prev[i], lo[i], hi[i], vmax[i], amax[i], dt
        )
        conflict = conflict or c
    if not active_set(G, free, lb, ub, free, ints[2], ints[3], ints[4], Hh, gap, mult, Lm, x):
        x[:] = free
    code, joint, most = TRACKING, -1, 0.0
    for i in range(n):
        v[i] = min(max(x[i], lb[i]), ub[i])
        over = 0.0
        box = 0
        if v[i] >= ub[i] - 1e-12 and free[i] > ub[i]:
            over, box = free[i] - ub[i], uk[i]
        elif v[i] <= lb[i] + 1e-12 and free[i] < lb[i]:
            over, box = lb[i] - free[i], lk[i]
        if over > most:
            code, joint, most = _BY_BOX[box], i, over
    return sigma, slowed, code, joint, conflict
