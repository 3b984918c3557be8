"""The ladder's dynamic programming, compiled (``armik.solve.ladder``).

A state is a rung (one solution of a waypoint, a row of ``B``) with a turn per joint: the
joint's value is ``B[rung, j] + 2 pi turn[j]``. From a state, each rung of the next
waypoint is taken with every joint turned to its value within the limits nearest the
state's; the child is kept where no joint moves more than its ``step`` and costs the
parent's cost plus the step's Euclidean norm. Children that are the same rung with the
same turns are one state (the cheapest parent kept), found in a table indexed by the rung
and the turns, so a layer costs its candidates, not their square. Where no child is kept,
every path breaks at that waypoint: it is flagged with the smallest jump's joint and size,
and its children are taken without the step bound, and every rung at every turn within the
limits too, from the cheapest state before (one loop in ``plan``): the turn that leaves room
for the rest of the path need not be the one nearest the answer before. An edge in
``forbidden`` (a pair of rungs a jump hides between: ``armik.solve.ladder``) counts as a
jump too. Without q0 the
first waypoint's states are every turn within the limits of every rung.

A joint without limits on either side (a continuous joint, or one given infinite limits)
is free: every turn of it is within its limits and no step's size depends on which one the
state holds, so its turn is no part of a state (states that differ only in it are one, the
cheapest parent's turn kept), it starts at its rung's own value, and it takes the turn
nearest the state before however many turns the path has made.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

TWO_PI = 2.0 * math.pi
TURNS = 5  # turns a joint can take in a state: -2 .. 2 around its rung's own value
EDGE = 1e-12  # rad or m: a value this far outside a limit is on it


@njit(cache=True, no_cfunc_wrapper=True)
def _child(B, r, q, lo, hi, periodic, out, turn):
    """The rung ``r`` with each joint turned to its value within the limits nearest ``q``,
    into ``out`` (the turns into ``turn``); False where a joint has none (or a limited one
    would take a turn beyond -2 .. 2; a free joint takes any)."""
    for j in range(q.shape[0]):
        b = B[r, j]
        if not periodic[j]:
            if b < lo[j] - EDGE or b > hi[j] + EDGE:
                return False
            out[j], turn[j] = b, 0
            continue
        k0 = math.floor((q[j] - b) / TWO_PI + 0.5)
        best, bk = math.inf, 0
        for k in (k0, k0 - 1, k0 + 1):
            v = b + TWO_PI * k
            if lo[j] - EDGE <= v <= hi[j] + EDGE and abs(v - q[j]) < abs(best - q[j]):
                best, bk = v, k
        if best == math.inf or (bk < -2 or bk > 2) and not _free(lo[j], hi[j]):
            return False
        out[j], turn[j] = best, bk
    return True


@njit(cache=True, no_cfunc_wrapper=True)
def _grow(a, n):
    """``a``, or a copy twice its length when row ``n`` does not fit."""
    if n < a.shape[0]:
        return a
    b = np.empty((2 * a.shape[0],) + a.shape[1:], a.dtype)
    # a loop over the flat arrays, not a slice copy: no shape-mismatch error to compile
    flat_a, flat_b = a.reshape(a.size), b.reshape(b.size)
    for i in range(flat_a.shape[0]):
        flat_b[i] = flat_a[i]
    return b


@njit(cache=True, no_cfunc_wrapper=True)
def _free(lo, hi):
    """Whether a joint has no limit on either side: its turn is no part of a state."""
    return lo == -math.inf and hi == math.inf


@njit(cache=True, no_cfunc_wrapper=True)
def _turn_range(b, lo, hi, periodic):
    """(first, last) turn of a joint's value ``b`` within its limits (last < first: none),
    -2 .. 2 at most; a free joint's only turn is 0, its rung's own value."""
    if not periodic:
        return (0, 0) if lo - EDGE <= b <= hi + EDGE else (1, 0)
    if _free(lo, hi):
        return 0, 0
    # clipped before rounding: an infinite limit on one side is no integer (numba's
    # floor of inf is INT64_MIN)
    first = math.ceil(max(-2.0, min(3.0, (lo - EDGE - b) / TWO_PI)))
    last = math.floor(min(2.0, max(-3.0, (hi + EDGE - b) / TWO_PI)))
    return first, last


@njit(cache=True, no_cfunc_wrapper=True)
def edge_code(a, b, n_rungs):
    """The code of the edge from rung ``a`` (-1: q0) to rung ``b`` in ``forbidden``."""
    return (a + 1) * n_rungs + b


@njit(cache=True, no_cfunc_wrapper=True)
def plan(B, offs, q0, has_q0, lo, hi, periodic, step, forbidden, node, weight):
    """The least-cost path over the rungs ``B`` (rows ``offs[i]:offs[i + 1]`` for
    waypoint i) from ``q0`` (``has_q0`` False: from any turn of any first rung), without
    the edges ``forbidden`` (sorted ``edge_code``s) unless every path breaks. A path's cost:
    ``weight`` times its total motion plus ``node[r]`` for each rung r it passes (a
    preference's score; zeros and 1 for the least motion). Returns (rung
    per waypoint, -1 where it has none; q per waypoint; broken per waypoint; hidden: broken
    where some step within the bound was forbidden; the smallest other jump's joint, -1
    where none, and size)."""
    n, d = offs.shape[0] - 1, B.shape[1]
    m_max = 1
    for i in range(n):
        m_max = max(m_max, offs[i + 1] - offs[i])
    base = np.ones(d, np.int64)  # a joint without a period takes one turn, 0
    size = m_max
    keyed = np.zeros(d, np.bool_)  # the joints whose turn is part of a state
    for j in range(d):
        if periodic[j] and not _free(lo[j], hi[j]):
            keyed[j] = True
            base[j] = TURNS
            size *= TURNS
    table = np.full(size, -1, np.int64)
    touched = np.empty(table.shape[0], np.int64)
    cap = 256
    s_rung, s_parent = np.empty(cap, np.int64), np.empty(cap, np.int64)
    s_turn, s_cost = np.empty((cap, d), np.int64), np.empty(cap)
    layer = np.full(n, -1, np.int64)
    broken, hidden = np.zeros(n, np.bool_), np.zeros(n, np.bool_)
    jump_joint, jump_size = np.full(n, -1, np.int64), np.zeros(n)
    count, prev_lo, prev_hi = np.int64(0), 0, 0  # count typed: _grow compiles once
    started = False
    Q, child = np.empty(d), np.empty(d)
    turn, first, last = np.zeros(d, np.int64), np.zeros(d, np.int64), np.zeros(d, np.int64)
    for i in range(n):
        if offs[i + 1] == offs[i]:
            continue  # no solution: the path goes on from the states before
        start, n_touched = count, 0
        initial = not started and not has_q0  # every turn within the limits, at no cost
        for bounded in (True, False):
            best_ratio, best_joint, best_size, seen = math.inf, -1, 0.0, False
            sources = 0 if initial else (1 if not started else prev_hi - prev_lo)
            for s in range(sources):
                src = -1 if not started else prev_lo + s
                for j in range(d):
                    Q[j] = q0[j] if src < 0 else B[s_rung[src], j] + TWO_PI * s_turn[src, j]
                for r in range(offs[i], offs[i + 1]):
                    if not _child(B, r, Q, lo, hi, periodic, child, turn):
                        continue
                    ratio, joint, size, norm2 = 0.0, 0, 0.0, 0.0
                    for j in range(d):
                        dq = abs(child[j] - Q[j])
                        norm2 += dq * dq
                        if dq / step[j] > ratio:
                            ratio, joint, size = dq / step[j], j, dq
                    if bounded and ratio <= 1.0 and forbidden.shape[0] > 0:
                        a = -1 if src < 0 else s_rung[src]
                        e = edge_code(a, r, B.shape[0])
                        k = np.searchsorted(forbidden, e)
                        if k < forbidden.shape[0] and forbidden[k] == e:
                            seen = True
                            continue
                    if ratio < best_ratio:
                        best_ratio, best_joint, best_size = ratio, joint, size
                    if bounded and ratio > 1.0:
                        continue
                    cost = (0.0 if src < 0 else s_cost[src]) + weight * math.sqrt(norm2) + node[r]
                    code = r - offs[i]
                    for j in range(d):
                        code = code * base[j] + (turn[j] + 2 if keyed[j] else 0)
                    at = table[code]
                    if at >= 0:
                        if cost < s_cost[at]:  # a free joint's turn is the new parent's
                            s_cost[at], s_parent[at] = cost, src
                            for j in range(d):
                                s_turn[at, j] = turn[j]
                        continue
                    s_rung, s_parent = _grow(s_rung, count), _grow(s_parent, count)
                    s_turn, s_cost = _grow(s_turn, count), _grow(s_cost, count)
                    s_rung[count], s_parent[count], s_cost[count] = r, src, cost
                    for j in range(d):
                        s_turn[count, j] = turn[j]
                    table[code] = count
                    touched[n_touched] = code
                    n_touched += 1
                    count += 1
            if initial or not bounded:  # every rung at every turn within the limits:
                # the first states, or after a jump from the cheapest state before (the
                # turn that leaves room for the rest of the path, a wrist spun on past its
                # limit, may be none nearest the answer before; a free joint's: nearest)
                src = -1
                for t in range(prev_lo, prev_hi if started else prev_lo):
                    if src < 0 or s_cost[t] < s_cost[src]:
                        src = t
                for j in range(d):
                    Q[j] = q0[j] if src < 0 else B[s_rung[src], j] + TWO_PI * s_turn[src, j]
                cost0 = 0.0 if src < 0 else s_cost[src]
                for r in range(offs[i], offs[i + 1]):
                    ok = True
                    for j in range(d):
                        if not initial and periodic[j] and _free(lo[j], hi[j]):
                            first[j] = last[j] = math.floor((Q[j] - B[r, j]) / TWO_PI + 0.5)
                        else:
                            first[j], last[j] = _turn_range(B[r, j], lo[j], hi[j], periodic[j])
                        ok = ok and last[j] >= first[j]
                        turn[j] = first[j]
                    while ok:
                        norm2, code = 0.0, r - offs[i]
                        for j in range(d):
                            dq = B[r, j] + TWO_PI * turn[j] - Q[j]
                            norm2 += dq * dq
                            code = code * base[j] + (turn[j] + 2 if keyed[j] else 0)
                        cost = node[r] if initial else cost0 + weight * math.sqrt(norm2) + node[r]
                        at = table[code]
                        if at >= 0:
                            if cost < s_cost[at]:
                                s_cost[at], s_parent[at] = cost, src
                                for j in range(d):
                                    s_turn[at, j] = turn[j]
                        else:
                            s_rung, s_parent = _grow(s_rung, count), _grow(s_parent, count)
                            s_turn, s_cost = _grow(s_turn, count), _grow(s_cost, count)
                            s_rung[count], s_parent[count], s_cost[count] = r, src, cost
                            for j in range(d):
                                s_turn[count, j] = turn[j]
                            table[code] = count
                            touched[n_touched] = code
                            n_touched += 1
                            count += 1
                        j = d - 1  # the next combination of turns, as an odometer
                        while j >= 0 and turn[j] == last[j]:
                            turn[j] = first[j]
                            j -= 1
                        if j < 0:
                            break
                        turn[j] += 1
            if count > start or not bounded or initial:
                break
            broken[i], hidden[i] = True, seen
            jump_joint[i], jump_size[i] = best_joint, best_size
        for t in range(n_touched):
            table[touched[t]] = -1
        if count > start:
            layer[i], prev_lo, prev_hi, started = start, start, count, True
    rung_out, q_out = np.full(n, -1, np.int64), np.full((n, d), np.nan)
    if not started:
        return rung_out, q_out, broken, hidden, jump_joint, jump_size
    state = prev_lo
    for s in range(prev_lo, prev_hi):
        if s_cost[s] < s_cost[state]:
            state = s
    for i in range(n - 1, -1, -1):
        if layer[i] < 0 or state < 0:
            continue
        rung_out[i] = s_rung[state]
        for j in range(d):  # on a limit to rounding: onto it
            v = B[s_rung[state], j] + TWO_PI * s_turn[state, j]
            q_out[i, j] = min(max(v, lo[j]), hi[j])
        state = s_parent[state]
    return rung_out, q_out, broken, hidden, jump_joint, jump_size
