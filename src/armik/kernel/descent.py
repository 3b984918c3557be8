"""One attempt of the descent, and a whole solve: the first attempt, then restarts.

Steps are taken without an acceptance test at first: the overshoots help to leave poor
basins (measured: accepting only improving steps from the start lowered the success rate on
the UR5, Z1 and Panda). When the error stops falling by ``PROGRESS`` within
``STALL_WINDOW`` iterations while already small, the attempt turns careful:
Levenberg-Marquardt acceptance, where a step that does not lower |e|^2 is rejected and the
damping multiplier mu raised, which ends the cycling between two poses seen near singular
boundaries. A careful attempt that stalls too gives way to a restart, and so does one that,
with a small error, comes within ``KNOWN_MINIMUM_RADIUS`` of a configuration where an
earlier attempt of the same solve got stuck.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.chain import CONTINUOUS, PRISMATIC, lower, reach, upper
from armik.kernel.clock import thread_cpu_ns
from armik.kernel.error import _evaluate
from armik.kernel.fk import forward, jacobian_local
from armik.kernel.linalg import copy_to
from armik.kernel.problem import BEST, DQ, NO_LIMIT, SHIFT, U
from armik.kernel.region import rows_at
from armik.kernel.restarts import _pick, seed_shift
from armik.kernel.step import dls, qp, wrapped
from armik.status import Status
from armik.tolerances import LIMIT_TOL

STALL_WINDOW = 4  # iterations without enough progress (PROGRESS) before a restart
MU_UP, MU_DOWN = 4.0, 0.5  # damping multiplier after a rejected / accepted step
# |e|^2 must fall below this fraction of its best within STALL_WINDOW iterations. Measured
# with the benchmark protocol: 0.7 rather than 0.98 ends attempts caught in a local minimum
# sooner, leaves time for more restarts, and took qp on the Z1 from 99.80 to 99.90 % and dls
# on the Panda from 99.90 to 100 %.
PROGRESS = 0.7
CAREFUL_BELOW = 1e-2  # |e|^2 under which a stalled attempt turns careful, not restarts
# An attempt that comes this close (max over joints, rad or m; continuous joints by their
# wrapped angle) to a local minimum an earlier attempt of the same solve ended in stops
# there: it would only end in it again.
KNOWN_MINIMUM_RADIUS = 0.05
DUPLICATE_TOL = 1e-4  # rad or m: answers closer than this are one solution
CLOCK_EVERY = 16  # iterations between two reads of the CPU clock (a read costs ~0.5 us)
TWO_PI = 2.0 * math.pi
# A typed zero for counters passed to compiled callees: a literal 0 would type them with
# Literal[int](0) first and compile a second version of each callee.
ZERO = np.int64(0)

CONVERGED = Status.CONVERGED.code
UNREACHABLE = Status.UNREACHABLE.code
NOT_CONVERGED = Status.NOT_CONVERGED.code


# Step-independent helpers are compiled once and called (not inlined): both entries share
# them, and each inlined copy would be compiled again.
@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def _near_known_minimum(ch, q, minima, count):
    n = q.shape[0]
    for m in range(count):
        far = 0.0
        for i in range(n):
            d = q[i] - minima[m, i]
            if ch.kind[i] == CONTINUOUS:
                d = wrapped(d)
            far = max(far, abs(d))
        if far < KNOWN_MINIMUM_RADIUS:
            return True
    return False


# Passed to ``descend`` as its ``measure``. Inlined: a call between the descent and the
# exact error cost a plain target 2-4 % of its solve; inlined, the branch costs nothing
# measurable, and one entry a step serves targets with and without a region.
@njit(cache=True, nogil=True, inline="always")
def _measure(ch, st, R_t, p_t, ws, slot):
    """The error, its Jacobian and the measures at ws.q[slot]: of the exact target, or of
    its region when the target has bounds. The region's is ``region._evaluate_region``'s
    body (its FK and Jacobian, then its rows called): one call from the descent, no more."""
    if st.region:
        forward(ch, ws.q[slot], ws.m3[0], ws.v3[0], ws.geo[0], ws.geo[1])
        jacobian_local(ch, ws.m3[0], ws.v3[0], ws.geo[0], ws.geo[1], ws.J)
        rows_at(st.bounds, st.w, st.cone, st.cone_axis, st.look, st.look_point, R_t, p_t, ws, slot)
    else:
        _evaluate(ch, st, R_t, p_t, ws, slot)


@njit(cache=True, nogil=True, inline="always")
def descend(ch, st, R_t, p_t, q0, ws, limit, deadline_ns, n_minima, step, measure):
    """Iterate from ws.q[0] with ``step`` (``step.dls`` or ``step.qp``), measuring with
    ``measure`` (``_measure``), for at most ``limit`` iterations (and, if ``deadline_ns`` is
    not NO_LIMIT, until the thread's CPU clock passes it). Returns (iterations, converged,
    slot of the last state)."""
    cur = ZERO
    measure(ch, st, R_t, p_t, ws, cur)
    best_sq = ws.val[cur, 2]
    mu = 1.0
    careful = False
    since_best = 0
    n = q0.shape[0]
    lo, hi = lower(ch), upper(ch)
    it = 0
    while True:
        if ws.val[cur, 0] <= st.tol_pos and ws.val[cur, 1] <= st.tol_rot:
            return it, True, cur
        if it >= limit:
            break
        if deadline_ns != NO_LIMIT and it > 0 and it % CLOCK_EVERY == 0:
            if thread_cpu_ns() > deadline_ns:
                break
        step(ch, st, ws, cur, q0, mu)
        trial = 1 - cur
        q, qn, dq = ws.q[cur], ws.q[trial], ws.vec[DQ]
        for i in range(n):
            qn[i] = min(max(q[i] + dq[i], lo[i]), hi[i])
        measure(ch, st, R_t, p_t, ws, trial)
        it += 1
        if not careful or ws.val[trial, 2] < ws.val[cur, 2]:
            cur = trial
            mu = max(1.0, mu * MU_DOWN)
        else:
            mu *= MU_UP
        sq = ws.val[cur, 2]
        if (
            n_minima > 0
            and sq < CAREFUL_BELOW
            and _near_known_minimum(ch, ws.q[cur], ws.minima, n_minima)
        ):
            break
        if sq < PROGRESS * best_sq:
            best_sq = sq
            since_best = 0
        else:
            since_best += 1
            if since_best >= STALL_WINDOW:
                if careful or sq > CAREFUL_BELOW:
                    break
                careful = True
                since_best = 0
    return it, False, cur


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def normalise(ch, q, q_ref, out):
    """out: q with continuous angles in (-pi, pi], then every angle shifted by a multiple
    of 2 pi to the value nearest q_ref that stays within the limits (as
    ``ArmModel.nearest_equivalent``)."""
    lows, highs = lower(ch), upper(ch)
    for i in range(q.shape[0]):
        qi = q[i]
        if ch.kind[i] == CONTINUOUS:
            qi = math.atan2(math.sin(qi), math.cos(qi))
        ri, lo, hi = q_ref[i], lows[i], highs[i]
        if ch.kind[i] != PRISMATIC and not (-math.pi <= qi - ri <= math.pi and lo <= qi <= hi):
            # np.rint: np.round's numbers (round half to even) without compiling numba's
            # round-to-decimals helper (~0.25 s per process)
            near = qi + TWO_PI * np.rint((ri - qi) / TWO_PI)
            best = np.nan
            for c in (near, near - TWO_PI, near + TWO_PI, qi):
                if lo - LIMIT_TOL <= c <= hi + LIMIT_TOL and (
                    np.isnan(best) or abs(c - ri) < abs(best - ri)
                ):
                    best = c
            if not np.isnan(best):
                qi = min(max(best, lo), hi)
        out[i] = qi


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def _add_solution(ch, q, q0, u, out_q, found):
    """Append q (normalised near q0, in scratch u) to out_q[:found] unless it is there
    already; returns the new count."""
    normalise(ch, q, q0, u)
    n = q.shape[0]
    for f in range(found):
        far = 0.0
        for i in range(n):
            far = max(far, abs(u[i] - out_q[f, i]))
        if far < DUPLICATE_TOL:
            return found
    copy_to(out_q[found], u)
    return found + 1


@njit(cache=True, nogil=True, inline="always")
def solve_one(ch, st, R_t, p_t, q0, seed, ws, out_q, info, err, step, measure):
    """A whole solve of one target: descend from q0, then from restart seeds, until
    ``st.max_found`` distinct solutions, the restart limit or the budget.

    out_q (S, n): the solutions found (normalised near q0), else row 0 holds the best
    unconverged configuration (or q0 for a target beyond reach). info (5,): claim (a
    ``Status`` code), solutions found, iterations, restarts, 1 if the budget (time or
    iterations) ended the solve. err (2,): position and orientation error of the best
    unconverged attempt (m, rad; the iteration's measure, not the verification's).
    ``step`` and ``measure`` as ``descend``'s.
    """
    start = thread_cpu_ns()
    deadline = NO_LIMIT
    if st.iteration_budget == NO_LIMIT and st.timeout_ns != NO_LIMIT:
        deadline = start + st.timeout_ns
    info[:] = 0
    err[:] = np.nan
    if st.check_reach:
        origin, bound = reach(ch)
        d0, d1, d2 = p_t[0] - origin[0], p_t[1] - origin[1], p_t[2] - origin[2]
        if math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) > bound + st.reach_slack:
            copy_to(out_q[0], q0)
            info[0] = UNREACHABLE
            return
    seed_shift(seed, ws.vec[SHIFT])
    copy_to(ws.q[0], q0)
    best = ws.vec[BEST]
    copy_to(best, q0)
    found = ZERO
    n_minima = ZERO
    stuck = 0
    capacity = ws.minima.shape[0]
    best_sq = np.inf
    iterations = 0
    restarts = 0
    k = ZERO  # next restart point
    out_of_budget = False
    while True:
        limit = st.max_iterations
        if st.iteration_budget != NO_LIMIT:
            limit = min(limit, st.iteration_budget - iterations)
        its, ok, cur = descend(ch, st, R_t, p_t, q0, ws, limit, deadline, n_minima, step, measure)
        iterations += its
        sq = ws.val[cur, 2]
        if not ok and sq < CAREFUL_BELOW:  # a local minimum near the target
            copy_to(ws.minima[stuck % capacity], ws.q[cur])  # the oldest go first when full
            stuck += 1
            n_minima = min(stuck, capacity)
        if ok:
            found = _add_solution(ch, ws.q[cur], q0, ws.vec[U], out_q, found)
            if found >= st.max_found:
                break
        elif not sq >= best_sq:
            best_sq = sq
            copy_to(best, ws.q[cur])
            err[0], err[1] = ws.val[cur, 0], ws.val[cur, 1]
        if restarts >= st.max_restarts:
            break
        if deadline != NO_LIMIT and thread_cpu_ns() > deadline:
            out_of_budget = True
            break
        if st.iteration_budget != NO_LIMIT and iterations >= st.iteration_budget:
            out_of_budget = True
            break
        restarts += 1
        k = _pick(ch, st, R_t, p_t, ws, k, ws.q[0])
    if found:
        info[0] = CONVERGED
    else:
        info[0] = NOT_CONVERGED
        normalise(ch, best, q0, out_q[0])
    info[1] = found
    info[2] = iterations
    info[3] = restarts
    info[4] = 1 if out_of_budget else 0


# The whole solve compiled once per step, for both entries (``entry``, ``single``), and
# without numba's reference counting (``_nrt=False``, as its callees in the loop): every view
# the loop takes of the workspace (ws.q[cur], ws.vec[DQ], ...) and every tuple it passes on
# (the workspace's 15 arrays) was an atomic increment and decrement of a reference count,
# half the time of an iteration (measured with perf on the UR5). The entries own the arrays
# and keep them alive across the call; nothing here allocates.
@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def solve_one_dls(ch, st, R_t, p_t, q0, seed, ws, out_q, info, err):
    """``solve_one`` with the dls step."""
    solve_one(ch, st, R_t, p_t, q0, seed, ws, out_q, info, err, dls, _measure)


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def solve_one_qp(ch, st, R_t, p_t, q0, seed, ws, out_q, info, err):
    """``solve_one`` with the qp step."""
    solve_one(ch, st, R_t, p_t, q0, seed, ws, out_q, info, err, qp, _measure)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def descend_dls(ch, st, R_t, p_t, q0, ws, limit, deadline_ns, n_minima):
    """``descend`` with the dls step (an entry for Python callers)."""
    return descend(ch, st, R_t, p_t, q0, ws, limit, deadline_ns, n_minima, dls, _measure)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def descend_qp(ch, st, R_t, p_t, q0, ws, limit, deadline_ns, n_minima):
    """``descend`` with the qp step (an entry for Python callers)."""
    return descend(ch, st, R_t, p_t, q0, ws, limit, deadline_ns, n_minima, qp, _measure)
