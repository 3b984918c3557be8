"""From the eigenvalues of ``elimination``'s companion matrix to the answers: each real
root x3 gives u = (x4^i x5^j) by inverse iteration on M(x3) (singular there), q4 and q5
from u's ratios, q1 and q2 from the eliminated products (their least-squares solution),
q6 from the rotation left; Newton steps on the 6-D pose error (``general_6r.polish``) take
it to full precision, and the answers are deduplicated.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.solvers.closed_form import sixr
from armik.solvers.closed_form.elimination import SIZE, lu, lu_solve
from armik.solvers.closed_form.general_6r import is_new, polish
from armik.solvers.closed_form.subproblems import cross, dot, mat, mm, mmt, mtm, mv, rot, vec

REAL = 1e-7  # rad: an eigenvalue whose angle is this close to real is a solution's
NEAR = 1e-3  # rad: ... this close, polished too (rounding can split a double root)
ROWS = 16  # a 6R arm has at most 16 solutions
ITERATIONS = 60  # Newton steps at most (general_6r's)
EXACT = 1e-11  # m and rad: a polished configuration this close to the target is an answer


@njit(cache=True, no_cfunc_wrapper=True)
def _angle(u, i0, i1):
    """2 atan2(u[i1], u[i0]): the angle whose half-angle tangent is u[i1] / u[i0]."""
    return 2.0 * math.atan2(u[i1], u[i0])


@njit(cache=True, no_cfunc_wrapper=True)
def _back(state, x, Mx, piv, u, z, q):
    """The loop's joint values (place order) of the root x3 = ``x`` into ``q``."""
    o_M = 14 * 27 + 8 * 14
    for r in range(12):
        for c in range(12):
            Mx[r, c] = (state[o_M + 288 + 12 * r + c] * x + state[o_M + 144 + 12 * r + c]) * x \
                + state[o_M + 12 * r + c]  # fmt: skip
    lu(Mx, piv)
    for r in range(12):
        z[r] = 1.0
    for _ in range(2):  # inverse iteration: M(x3) is singular at a root
        lu_solve(Mx, piv, z, u)
        big = 0.0
        for r in range(12):
            big = max(big, abs(u[r]))
        if not big > 0.0 or not math.isfinite(big):
            break
        for r in range(12):
            z[r] = u[r] / big
    # u[3 i + j] = x4^i x5^j: q4 from the column, q5 from the row of largest entries
    bj, bv = 0, -1.0
    for j in range(3):
        v = abs(z[j]) + abs(z[3 + j]) + abs(z[6 + j]) + abs(z[9 + j])
        if v > bv:
            bj, bv = j, v
    bi, bv = 0, -1.0
    for i in range(3):
        v = abs(z[3 * i + bj]) + abs(z[3 * (i + 1) + bj])
        if v > bv:
            bi, bv = i, v
    q[3] = _angle(z, 3 * bi + bj, 3 * (bi + 1) + bj)
    bi, bv = 0, -1.0
    for i in range(4):
        v = abs(z[3 * i]) + abs(z[3 * i + 1]) + abs(z[3 * i + 2])
        if v > bv:
            bi, bv = i, v
    bj, bv = 0, -1.0
    for j in range(2):
        v = abs(z[3 * bi + j]) + abs(z[3 * bi + j + 1])
        if v > bv:
            bj, bv = j, v
    q[4] = _angle(z, 3 * bi + bj, 3 * bi + bj + 1)
    q[2] = state[SIZE - 2] + 2.0 * math.atan(x)
    # q1, q2 from the eliminated products: (Lc . m345) = Q m12
    b3, b4 = (math.sin(q[2]), math.cos(q[2]), 1.0), (math.sin(q[3]), math.cos(q[3]), 1.0)
    b5 = (math.sin(q[4]), math.cos(q[4]), 1.0)
    lhs = np.empty(14)
    for n in range(14):
        v = 0.0
        for i in range(27):
            v += state[27 * n + i] * b3[i // 9] * b4[(i // 3) % 3] * b5[i % 3]
        lhs[n] = v
    m = np.zeros(8)
    for c in range(8):
        for n in range(14):
            m[c] += state[14 * 27 + 14 * c + n] * lhs[n]
    q[0], q[1] = math.atan2(m[2], m[5]), math.atan2(m[6], m[7])
    # q6: Y J6 L6 = J1 L1 J2 L2 inverted, rotations only
    o_L = o_M + 3 * 144
    o_H = o_L + 72
    Y = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    W = Y
    for k in range(2, 5):
        Y = mm(mm(Y, rot(_h(state, o_H, k), q[k])), _r(state, o_L, k))
    for k in range(2):
        W = mm(mm(W, rot(_h(state, o_H, k), q[k])), _r(state, o_L, k))
    last = np.int64(5)  # typed, not a literal: one compile of _r and _h
    R6 = mmt(mtm(Y, (W[0], W[3], W[6], W[1], W[4], W[7], W[2], W[5], W[8])), _r(state, o_L, last))
    h6 = _h(state, o_H, last)
    e = (1.0, 0.0, 0.0) if abs(h6[0]) < 0.9 else (0.0, 1.0, 0.0)
    a = cross(h6, e)
    y = mv(R6, a)
    q[5] = math.atan2(dot(h6, cross(a, y)), dot(a, y))


@njit(cache=True, no_cfunc_wrapper=True)
def _h(state, at, k):
    return (state[at + 3 * k], state[at + 3 * k + 1], state[at + 3 * k + 2])


@njit(cache=True, no_cfunc_wrapper=True)
def _r(state, at, k):
    b = at + 12 * k
    return (state[b], state[b + 1], state[b + 2], state[b + 3], state[b + 4], state[b + 5],
            state[b + 6], state[b + 7], state[b + 8])  # fmt: skip


@njit(cache=True, no_cfunc_wrapper=True)
def solutions(h, p, R_tip0, R, pos, state, roots, places, sign, q0, lower, upper, out):
    """Every root of ``roots`` (the companion's eigenvalues, complex) back-substituted,
    polished and deduplicated, packed nearest-first into ``out`` (``ROWS``, 11;
    ``sixr.pack``, every row labelled); ``places``/``sign``: the arm's joint at each place
    of the cut's loop and its sense. Returns (n, sure): sure unless a real root gave no
    new answer (two roots too close to tell apart, or one Newton could not polish)."""
    R9, P3 = mat(R), vec(pos)
    W = np.empty((ROWS, 11))
    Mx, piv = np.empty((12, 12)), np.empty(12, np.int64)
    u, z, t, q = np.empty(12), np.empty(12), np.empty(6), np.empty(6)
    n = np.int64(0)
    sure = True
    for k in range(len(roots)):
        x = roots[k]
        a, b = x.real, abs(x.imag)
        off = 2.0 * b / (1.0 + a * a)  # |Im 2 atan(x)| to first order
        if off > NEAR or not math.isfinite(a):
            continue
        _back(state, a, Mx, piv, u, z, t)
        for j in range(6):
            q[places[j]] = sign * t[j]
        r = polish(h, p, R_tip0, R9, P3, q, ITERATIONS)
        fresh = r <= EXACT and n < ROWS and is_new(W, n, q)
        if fresh:
            zero = np.int64(0)  # typed: literal 0s compile put_row once more
            n = sixr.put_row(W, n, q[0], q[1], q[2], q[3], q[4], q[5], zero, zero, 0.0, 0.0)
        elif off <= REAL:
            sure = False
    sixr.nearest_equivalents(W, n, q0, lower, upper)
    sixr.onto_limits(W, n, lower, upper)  # a polished double root a hair past a limit
    sixr.pack(W, n, q0, lower, upper, h, p, np.int64(ROWS), out)
    return n, sure
