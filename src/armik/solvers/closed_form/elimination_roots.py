"""From the eigenvalues of ``elimination``'s companion matrix to the answers: each real
root x3 gives u = (x4^i x5^j) by inverse iteration on M(x3) (singular there), q4 and q5
from u's ratios, q1 and q2 from the eliminated products (their least-squares solution),
q6 from the rotation left; Newton steps on the 6-D pose error (``general_6r.polish``) take
it to full precision, and the answers are deduplicated. Where roots gave no new answer, a
multiple root's solutions are read off M(x3)'s null space (``seeds``) and polished too.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.solvers.closed_form import sixr
from armik.solvers.closed_form.elimination import SIZE, lu, lu_solve
from armik.solvers.closed_form.general_6r import is_new, onto_limits, polish
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
def _back(state, x, Mx, piv, u, z, q, null):
    """The loop's joint values (place order) of the root x3 = ``x`` into ``q``; with
    ``null`` False, of the q3, q4 and q5 already in ``q``."""
    o_M = 14 * 27 + 8 * 14
    if null:  # q3 and q4, q5 from the null vector
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
def solutions(h, p, R_tip0, R, pos, state, roots, seeds, places, sign, q0, lower, upper, out):
    """Every root of ``roots`` (the companion's eigenvalues, complex) back-substituted,
    polished and deduplicated, then each of ``seeds`` (rows of q3, q4, q5, from ``seeds``),
    packed nearest-first into ``out`` (``ROWS``, 11; ``sixr.pack``, every row labelled);
    ``places``/``sign``: the arm's joint at each place of the cut's loop and its sense.
    Returns (n, sure, lost): sure unless a real root gave no new answer (two roots too close
    to tell apart, or one Newton could not polish); lost, how many roots it polishes did
    (a multiple root split by rounding into complex ones too)."""
    R9, P3 = mat(R), vec(pos)
    W = np.empty((ROWS, 11))
    Mx, piv = np.empty((12, 12)), np.empty(12, np.int64)
    u, z, t, q = np.empty(12), np.empty(12), np.empty(6), np.empty(6)
    n, lost = np.int64(0), np.int64(0)
    sure = True
    m = len(roots)
    for k in range(m + len(seeds)):
        a, off = 0.0, 0.0
        if k < m:
            a, b = roots[k].real, abs(roots[k].imag)
            off = 2.0 * b / (1.0 + a * a)  # |Im 2 atan(x)| to first order
            if off > NEAR or not math.isfinite(a):
                continue
        else:  # a seed's q3, q4, q5
            t[2], t[3], t[4] = seeds[k - m, 0], seeds[k - m, 1], seeds[k - m, 2]
        _back(state, a, Mx, piv, u, z, t, k < m)
        for j in range(6):
            q[places[j]] = sign * t[j]
        r = polish(h, p, R_tip0, R9, P3, q, ITERATIONS)
        fresh = r <= EXACT and n < ROWS and is_new(W, n, q)
        if fresh:
            zero = np.int64(0)  # typed: literal 0s compile put_row once more
            n = sixr.put_row(W, n, q[0], q[1], q[2], q[3], q[4], q[5], zero, zero, 0.0, 0.0)
        elif k < m:
            lost += 1
            sure = sure and off > REAL
    sixr.nearest_equivalents(W, n, q0, lower, upper)
    onto_limits(h, p, R_tip0, R9, P3, W, n, lower, upper)  # a double root a hair past one
    sixr.pack(W, n, q0, lower, upper, h, p, np.int64(ROWS), out)
    return n, sure, lost


CLUSTER = 0.02  # rad: roots this close in q3 (and to real) are read as one multiple root
NO_SEEDS = np.empty((0, 3))
# the half-angle tangents of q4 and q5 read from these shifts (no solution's at infinity),
# and the weight that tells two solutions sharing one of them apart
_SHIFT4, _SHIFT5, _MIX = 0.7, -1.1, 0.618


def seeds(state: np.ndarray, roots: np.ndarray) -> np.ndarray:
    """(q3, q4, q5) of every solution at a multiple root of ``roots`` (k roots within
    ``CLUSTER`` of q3 and of real, one of them real to ``NEAR``; rounding splits a k-fold
    root by about 1e-16^(1/k)), read off M(x3)'s k-dimensional null space there: its vectors
    u = (x4^i x5^j) are the only ones shifting a power of x4 or of x5 maps to multiples of
    themselves, the eigenvectors of those maps. Inverse iteration there gives a mixture,
    which Newton can take to the same solution from each root (two solutions with the same
    q3, say joint 1 turned by pi with a near-spherical shoulder, lost)."""
    a, b = roots.real, np.abs(roots.imag)
    off = np.where(np.isfinite(a), 2.0 * b / (1.0 + a * a), np.inf)  # as ``solutions``'
    near = off <= CLUSTER
    t, off = 2.0 * np.arctan(a[near]), off[near]
    out = []
    for at in _clusters(t):
        if len(at) < 2 or not np.any(off[at] <= NEAR):  # a real root's, complex ones too
            continue
        group = np.unwrap(t[at])
        c = group[0] + 2.0 * np.arctan(np.mean(np.tan((group - group[0]) / 2.0)))
        s, k = np.sin(c / 2.0), np.cos(c / 2.0)  # M(x3) times cos^2 of the half angle
        o_M = 14 * 27 + 8 * 14
        M = state[o_M : o_M + 3 * 144].reshape(3, 12, 12)
        N = np.linalg.svd(M[2] * s * s + M[1] * s * k + M[0] * k * k)[2][-len(group) :].T
        for q4, q5 in _pairs(N):
            out.append((state[SIZE - 2] + c, q4, q5))
    return np.array(out, dtype=float).reshape(-1, 3)


def _clusters(t: np.ndarray) -> list[np.ndarray]:
    """The indices of angles ``t`` (in (-pi, pi]) in runs ``CLUSTER`` apart at most, on the
    circle, each run in increasing order."""
    if len(t) == 0:
        return []
    order = np.argsort(t)
    s = t[order]
    gaps = np.diff(np.r_[s, s[0] + 2.0 * np.pi])
    start = (int(np.argmax(gaps)) + 1) % len(s)  # the circle cut at its widest gap
    order = np.r_[order[start:], order[:start]]
    s = np.r_[s[start:], s[:start] + 2.0 * np.pi]
    return np.split(order, np.flatnonzero(np.diff(s) > CLUSTER) + 1)


def _pairs(N: np.ndarray) -> list[tuple[float, float]]:
    """(q4, q5) of the solutions whose vectors u = (x4^i x5^j), u[3 i + j], span ``N``
    (12 x k): in y = tan((q - shift) / 2), the rows with one more power of y4 (of y5) are
    Y4 (Y5) times those with one fewer for each of them, so their common eigenvectors."""
    k = N.shape[1]
    V = np.linalg.solve(np.kron(_binomial(3, _SHIFT4), _binomial(2, _SHIFT5)), N).reshape(4, 3, k)
    Y4 = np.linalg.lstsq(V[:3].reshape(9, k), V[1:].reshape(9, k), rcond=None)[0]
    Y5 = np.linalg.lstsq(V[:, :2].reshape(8, k), V[:, 1:].reshape(8, k), rcond=None)[0]
    if not (np.all(np.isfinite(Y4)) and np.all(np.isfinite(Y5))):
        return []
    _, C = np.linalg.eig(Y4 + _MIX * Y5)
    if abs(np.linalg.det(C)) < 1e-12:
        return []
    Ci = np.linalg.inv(C)
    y4, y5 = np.diag(Ci @ Y4 @ C).real, np.diag(Ci @ Y5 @ C).real
    return [(_SHIFT4 + 2.0 * np.arctan(a), _SHIFT5 + 2.0 * np.arctan(b)) for a, b in zip(y4, y5)]


def _binomial(degree: int, shift: float) -> np.ndarray:
    """T: the homogeneous powers W^(d - i) X^i of x = X / W = tan(q / 2) as T times those
    of y = tan((q - shift) / 2) (X = Y + t V, W = V - t Y, t = tan(shift / 2))."""
    t = math.tan(shift / 2.0)
    T = np.empty((degree + 1, degree + 1))
    for i in range(degree + 1):
        row = np.array([1.0])
        for _ in range(degree - i):
            row = np.convolve(row, [1.0, -t])
        for _ in range(i):
            row = np.convolve(row, [t, 1.0])
        T[i] = row
    return T
