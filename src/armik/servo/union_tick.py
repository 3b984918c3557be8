"""The servo over shared joints' tick, compiled: each tip's rows by its chain's kernel FK,
stacked over the union's joints, and the damped step within every limit.

``armik.servo.union`` calls ``tick`` once a tick. The chains are given as their kernel
arrays one after the other (``packed`` and ``kinds`` cut at ``at[0]`` and ``at[1]``) and
``maps``, each chain's joints' columns in the union (cut at ``at[2]``). Each tip's target
is a table of tasks (``armik.servo.table``, at most ``MAX_TASKS`` rows, tip t's from row
``t MAX_TASKS`` of ``tables``), or with ``counts[t] == 0`` the plain 4x4 pose ``H[t]``,
its row written here. A tip's rows are those of a chain's own servo (``armik.servo.tick``'s
``stack``: ``kernel.region``'s six rows a task, a pose, a position, a region, an axis in a
cone, a look-at), their columns scattered into the union's; the step is a chain's own
(``armik.servo.step``) over the union's joints.

The memory (``allocate``): floats, the union's state, cfg and out as ``armik.servo.layout``
lays them for one chain, then each tip's last table, a chain's scratch and the step's; ints,
each tip's last task count, then the scratch.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.chain import Flat, dof, joints, reach
from armik.kernel.fk import forward, jacobian_local
from armik.kernel.problem import NVEC
from armik.kernel.single import plain_pose
from armik.servo.distances import distances
from armik.servo.layout import (
    CFG,
    COLUMNS,
    CONE,
    LOOK,
    MAX_TASKS,
    ORI_ERR,
    OUT,
    POS_ERR,
    REACH_SLACK,
    STATE_ROWS,
    TOL_P,
    TOL_R,
    Q,
)
from armik.servo.minimum import PROBE, curvature_column, first_order, no_descent
from armik.servo.step import SLOWING, scratch, scratch_size, status_code, step_within
from armik.servo.tick import equal, pose_row, rank_bound, regions, stack, views

# ints: n, tips, the most joint values and the most joints of a chain, the lengths of
# the chains' packed floats, kinds and maps
HEADER = 7


def chain_size(n: int, N: int) -> int:
    """The floats a chain's scratch takes (``views``' ``Workspace`` and its own rows) for
    n joint values and N joints."""
    ws = 2 * n + 12 + 12 * n + 6 + NVEC * n + 4 * n * n + 6 * N + 6 * n + 18 + 9 + 36 + n
    return ws + 36 + 12 + 6 * MAX_TASKS * (2 + n) + n


def allocate(
    n: int, packed: np.ndarray, kinds: np.ndarray, at: np.ndarray, maps: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(mem, imem) for n joint values over the chains of ``packed``, ``kinds`` (cut at
    ``at[0]``, ``at[1]``) and ``maps`` (cut at ``at[2]``), zero but for them."""
    tips = at.shape[1] - 1
    most = int(np.diff(at[2]).max())
    most_joints = int(((np.diff(at[1]) - np.diff(at[2])) // 2).max())
    P, K, M = packed.shape[0], kinds.shape[0], maps.shape[0]
    head = np.array([n, tips, most, most_joints, P, K, M], dtype=np.int64)
    f, i = offsets(head)
    m = 6 * MAX_TASKS * tips
    mem = np.zeros(f[-1] + chain_size(most, most_joints) + scratch_size(n, m) + 3 * m + 2 * m * n)
    imem = np.zeros(i[-1] + 3 * most + 5 * n, dtype=np.int64)
    imem[:HEADER] = head
    mem[f[7] : f[8]] = packed
    imem[i[2] : i[3]] = at.ravel()
    imem[i[3] : i[4]] = kinds
    imem[i[4] : i[5]] = maps
    return mem, imem


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def offsets(head):
    """Where each part starts in mem (state, cfg, out, out2, the last tables, the tables,
    the poses, each tip's ``fixed`` projectors (``tick.stack``'s) and its structural
    ranks (``tick.rank_bound``'s), the packed floats, the rest) and in imem (the last
    counts, the counts, ``at``, the kinds, the maps, the rest), from imem's header."""
    n, tips, P, K, M = head[0], head[1], head[4], head[5], head[6]
    table = tips * MAX_TASKS * COLUMNS
    f0 = STATE_ROWS * n
    f = (0, f0, f0 + CFG, f0 + CFG + OUT, f0 + CFG + 2 * OUT)
    f = f + (f[4] + table, f[4] + 2 * table, f[4] + 2 * table + 37 * tips)
    f = f + (f[7] + P,)
    i = (HEADER, HEADER + tips, HEADER + 2 * tips)
    i = i + (i[2] + 3 * (tips + 1),)
    i = i + (i[3] + K, i[3] + K + M)
    return f, i


def python_views(mem: np.ndarray, imem: np.ndarray) -> tuple[np.ndarray, ...]:
    """(state, cfg, out, tables, poses, counts, fixed, ranks): the views the
    ``UnionServo`` reads and sets."""
    f, i = offsets(imem[:HEADER])
    n, tips = int(imem[0]), int(imem[1])
    return (
        mem[f[0] : f[1]].reshape((STATE_ROWS, n)),
        mem[f[1] : f[2]],
        mem[f[2] : f[3]],
        mem[f[5] : f[6]].reshape((tips * MAX_TASKS, COLUMNS)),
        mem[f[6] : f[6] + 16 * tips].reshape((tips, 4, 4)),
        imem[i[1] : i[2]],
        mem[f[6] + 16 * tips : f[6] + 34 * tips].reshape((tips, 2, 3, 3)),
        mem[f[6] + 34 * tips : f[7]].reshape((tips, 3)),
    )


def stacked(mem: np.ndarray, imem: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(E, A): the rows ``rows_at`` wrote, this tick's target's (2 x 6 ``MAX_TASKS`` tips)
    and their Jacobian (rows x n)."""
    f, _ = offsets(imem[:HEADER])
    n, tips, most, most_joints = imem[:4].tolist()
    m = 6 * MAX_TASKS * tips
    o = f[8] + chain_size(most, most_joints)
    return mem[o : o + m], mem[o + 2 * m : o + 2 * m + m * n].reshape((m, n))


@njit(cache=True, nogil=True, inline="always")
def _carve(mem, imem):
    """The parts of ``offsets``: (state, cfg, out, out2, lasts, tables, poses, fixed,
    ranks, packed, the floats' rest), (last counts, counts, at, kinds, maps, the ints' rest)."""
    n, tips = imem[0], imem[1]
    f, i = offsets(imem[:HEADER])
    rows = tips * MAX_TASKS
    floats = (
        mem[f[0] : f[1]].reshape((STATE_ROWS, n)),
        mem[f[1] : f[2]],
        mem[f[2] : f[3]],
        mem[f[3] : f[4]],
        mem[f[4] : f[5]].reshape((rows, COLUMNS)),
        mem[f[5] : f[6]].reshape((rows, COLUMNS)),
        mem[f[6] : f[6] + 16 * tips].reshape((tips, 4, 4)),
        mem[f[6] + 16 * tips : f[6] + 34 * tips].reshape((tips, 2, 3, 3)),
        mem[f[6] + 34 * tips : f[7]].reshape((tips, 3)),
        mem[f[7] : f[8]],
        mem[f[8] :],
    )
    ints = (
        imem[i[0] : i[1]],
        imem[i[1] : i[2]],
        imem[i[2] : i[3]].reshape((3, tips + 1)),
        imem[i[3] : i[4]],
        imem[i[4] : i[5]],
        imem[i[5] :],
    )
    return floats, ints


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def _rows(tables, counts, lasts, last_counts, packed, kinds, at, maps, q, buf, ibuf, E, A,
          fixed, ranks, scale):  # fmt: skip
    """E[0], A[0]: every tip's rows toward its target at the union's joint values q, the
    chains' columns scattered into the union's, and their ``scale`` in the singular value
    (``tick.stack``'s, tip t's with the projectors ``fixed[t]``); E[1], A[1] toward the
    last tick's target where a tip's moved (of the same form), else this tick's. ``buf``,
    ``ibuf``: a chain's scratch. Returns (largest position and rotation distances from the
    regions, rows, counted rows, at most how many of them are independent (the tips'
    ``tick.rank_bound`` with their ``ranks[t]``), whether a target moved)."""
    n = q.shape[0]
    most = ibuf.shape[0] // 3
    reg_p = reg_r = 0.0
    rows = active = bound = 0
    moved = False
    for t in range(counts.shape[0]):
        cols = maps[at[2, t] : at[2, t + 1]]
        nt = cols.shape[0]
        hal = buf[buf.shape[0] - most : buf.shape[0] - most + nt].reshape((1, nt))
        ch = Flat(packed[at[0, t] : at[0, t + 1]], kinds[at[1, t] : at[1, t + 1]], hal)
        ws, o = views(buf, ibuf, nt, joints(ch))
        Ec = buf[o : o + 6 * MAX_TASKS]
        Ac = buf[o + 6 * MAX_TASKS : o + 6 * MAX_TASKS * (1 + nt)].reshape((6 * MAX_TASKS, nt))
        Sc = buf[o + 6 * MAX_TASKS * (1 + nt) : o + 6 * MAX_TASKS * (2 + nt)]
        qc = ws.q[0]
        for j in range(nt):
            qc[j] = q[cols[j]]
        R, p = ws.m3[0], ws.v3[0]
        forward(ch, qc, R, p, ws.geo[0], ws.geo[1])
        jacobian_local(ch, R, p, ws.geo[0], ws.geo[1], ws.J)
        k = counts[t]
        table = tables[t * MAX_TASKS : t * MAX_TASKS + k]
        rp, rr, act = stack(table, k, ws, Ec, Ac, fixed[t], Sc)
        reg_p, reg_r, active = max(reg_p, rp), max(reg_r, rr), active + act
        bound += rank_bound(table, k, Sc, ranks[t])
        _scatter(Ec, Ac, cols, rows, 6 * k, n, E[0], A[0])
        for r in range(6 * k):
            scale[rows + r] = Sc[r]
        last = lasts[t * MAX_TASKS : t * MAX_TASKS + k]
        turned = last_counts[t] == k and not equal(last, table, k)
        if turned:
            for r in range(k):  # of the same form: its rows' count and meaning
                turned = turned and last[r, LOOK] == table[r, LOOK]
                turned = turned and last[r, CONE] == table[r, CONE]
        if turned:
            stack(last, k, ws, Ec, Ac, fixed[t], Sc)
        moved = moved or turned
        _scatter(Ec, Ac, cols, rows, 6 * k, n, E[1], A[1])
        rows += 6 * k
    return reg_p, reg_r, rows, active, bound, moved


@njit(cache=True, nogil=True, inline="always")
def _scatter(Ec, Ac, cols, r0, rows, n, E, A):
    """E[r0:r0 + rows], A's rows there: a chain's rows, its columns at ``cols``."""
    for r in range(rows):
        E[r0 + r] = Ec[r]
        for c in range(n):
            A[r0 + r, c] = 0.0
        for j in range(cols.shape[0]):
            A[r0 + r, cols[j]] = Ac[r, j]


@njit(cache=True, nogil=True, inline="always")
def _poses(tables, counts, H):
    """Each pose tip's row (``counts[t] == 0``: H[t]) in its table, its count then 1;
    returns the first tip whose pose is not plain (-1: none)."""
    for t in range(counts.shape[0]):
        if counts[t] == 0:
            if not plain_pose(H[t]):
                return t
            pose_row(H[t], tables[t * MAX_TASKS])
            counts[t] = 1
    return -1


@njit(cache=True, nogil=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def rows_at(q, mem, imem):
    """``_rows`` at q (the test's view of them): the rows written, in the step's scratch
    (``stacked``); -1 for a pose that is not plain."""
    n, tips = imem[0], imem[1]
    (state, cfg, out, out2, lasts, tables, H, fixed, ranks, packed, buf), ints = _carve(mem, imem)
    last_counts, counts, at, kinds, maps, ib = ints
    if _poses(tables, counts, H) >= 0:
        return -1
    cw = chain_floats(imem[2], imem[3])
    E, A2, M6, W, act, sc, o = scratch(buf, cw, n, 6 * MAX_TASKS * tips)
    m = E.shape[0] // 2
    res = _rows(tables, counts, lasts, last_counts, packed, kinds, at, maps, q, buf[:cw],
                ib[: 3 * imem[2]], E.reshape((2, m)), A2, fixed, ranks, sc[0])  # fmt: skip
    return res[2]


@njit(cache=True, nogil=True, inline="always")
def chain_floats(n, N):
    """``chain_size`` in compiled code."""
    ws = 2 * n + 12 + 12 * n + 6 + NVEC * n + 4 * n * n + 6 * N + 6 * n + 18 + 9 + 36 + n
    return ws + 36 + 12 + 6 * MAX_TASKS * (2 + n) + n


@njit(cache=True, nogil=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def tick(mem, imem, rows_cb):
    """One tick of the union's state in ``mem`` toward every tip's target, within the
    collision rows ``rows_cb`` (K, 2 n + 1: C, then b, then the levers L, for C dq >= b).
    Returns -1, or, having done nothing, the first tip whose pose H[t] is not one the target
    parser keeps as given (the caller parses it)."""
    n, tips, most = imem[0], imem[1], imem[2]
    (state, cfg, out, out2, lasts, tables, H, fixed, ranks, packed, buf), ints = _carve(mem, imem)
    last_counts, counts, at, kinds, maps, ib = ints
    bad = _poses(tables, counts, H)
    if bad >= 0:
        return bad
    cw = chain_floats(most, imem[3])
    m = 6 * MAX_TASKS * tips
    E, A2, M6, W, act, sc, o = scratch(buf, cw, n, m)
    cbuf, cibuf = buf[:cw], ib[: 3 * most]
    iv = ib[3 * most : 3 * most + 4 * n].reshape((4, n))
    every = ib[3 * most + 4 * n : 3 * most + 5 * n]
    q = state[Q]
    E2 = E.reshape((2, m))
    reg_p, reg_r, rows, active, rank, moved = _rows(
        tables, counts, lasts, last_counts, packed, kinds, at, maps, q, cbuf, cibuf, E2, A2,
        fixed, ranks, sc[0],
    )  # fmt: skip
    within = reg_p <= cfg[TOL_P] and reg_r <= cfg[TOL_R]
    free = iv[2]
    saddle = first_order(E2[0], A2[0], rows, state, cfg, W[15], free)
    stalled = False
    if saddle:  # and no way on at second order (the rows at q moved, past the scratch)
        Ep = buf[o : o + 2 * m].reshape((2, m))
        Ap = buf[o + 2 * m : o + 2 * m + 2 * m * n].reshape((2, m, n))
        scp = buf[o + 2 * m + 2 * m * n : o + 3 * m + 2 * m * n]
        for j in range(n):
            if free[j] == 0:
                continue
            qj = q[j]
            step = PROBE * max(1.0, abs(qj))
            q[j] = qj + step
            _rows(tables, counts, lasts, last_counts, packed, kinds, at, maps, q, cbuf, cibuf,
                  Ep, Ap, fixed, ranks, scp)  # fmt: skip
            q[j] = qj
            curvature_column(E2[0], A2[0], Ap[0], rows, step, j, M6[0])
        stalled = no_descent(E2[0], A2[0], rows, M6[0], free, cfg, M6[1], M6[2])
        saddle = not stalled
    # a bool, not the literal False: one compiled step_within with the chain's tick (True)
    whole = bool(False)  # noqa: UP018
    held = step_within(
        E2[0], A2[0], E2[1], A2[1], rows, active, rank, sc[0], moved, whole, rows_cb, state,
        cfg, M6, W, iv, every, act, stalled, saddle,
    )  # fmt: skip
    # the true distances the command leaves (each chain's FK at the new joint values)
    far = False
    pos = ori = -1.0
    slowing = held[1] < SLOWING
    reg_p = reg_r = 0.0  # what the tasks measure where the command is (``tick.tick``)
    for t in range(tips):
        cols = maps[at[2, t] : at[2, t + 1]]
        nt = cols.shape[0]
        hal = cbuf[cw - most : cw - most + nt].reshape((1, nt))
        ch = Flat(packed[at[0, t] : at[0, t + 1]], kinds[at[1, t] : at[1, t + 1]], hal)
        ws, _ = views(cbuf, cibuf, nt, joints(ch))
        qc = ws.q[0]
        for j in range(dof(ch)):
            qc[j] = q[cols[j]]
        R, p = ws.m3[0], ws.v3[0]
        forward(ch, qc, R, p, ws.geo[0], ws.geo[1])
        origin, reach_ = reach(ch)
        k = counts[t]
        table = tables[t * MAX_TASKS : t * MAX_TASKS + k]
        far = distances(table, R, p, origin, reach_, cfg[REACH_SLACK], out2) or far
        if within or slowing:  # and where the command is (``tick.tick``)
            rp, rr = regions(table, k, ws)
            within = within and rp <= cfg[TOL_P] and rr <= cfg[TOL_R]
            reg_p, reg_r = max(reg_p, rp), max(reg_r, rr)
        if not math.isnan(out2[POS_ERR]):
            pos = max(pos, out2[POS_ERR])
        if not math.isnan(out2[ORI_ERR]):
            ori = max(ori, out2[ORI_ERR])
        for r in range(k):  # this target, the next tick's last
            for c in range(COLUMNS):
                lasts[t * MAX_TASKS + r, c] = table[r, c]
        last_counts[t] = k
    out[POS_ERR] = pos if pos >= 0.0 else math.nan
    out[ORI_ERR] = ori if ori >= 0.0 else math.nan
    status_code(within, far, held, cfg, out, reg_p, reg_r)
    return -1
