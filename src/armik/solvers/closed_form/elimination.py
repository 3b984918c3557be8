"""Every solution of a 6R arm by elimination (Raghavan and Roth 1993, in the form of Manocha
and Canny 1994): the compiled algebra. ``elimination_6r`` is the family around it.

The chain's closure is a loop of six joints J_k (rotations about axes through the origins
of their frames) and six links L_k between them, L_6 holding the target. A *cut* (``CUTS``:
the loop read forwards or backwards, from any joint) numbers the loop so that joint 6 is
dropped: with Y = J3 L3 J4 L4 J5 L5 and Z = L2^-1 J2^-1 L1^-1 J1^-1 L6^-1, Y J6 = Z, so
axis 6's line (point o, direction h6, which J6 leaves in place) gives

    p = Y o = Z o,   l = Y h6 = Z h6,

and with them p.p, p.l, p x l and (p.p) l - 2 (p.l) p: 14 equations, each side of degree
at most one in the sine and cosine of each of its joints (Raghavan and Roth's result; the
coefficients are read here by sampling each side at three angles a joint, which is exact
for that degree). The right side's 8 products of (q1, q2) are eliminated by the 6 rows
that annihilate their 14 x 8 matrix, leaving 6 equations in (s3, c3, 1) x (s4, c4, 1) x
(s5, c5, 1). With x_k = tan(q_k / 2) (q3 shifted by ``PHASES``' first value that keeps
the leading matrix regular) and the 6 rows again times x4, a 12 x 12 matrix polynomial
M(x3) = A x3^2 + B x3 + C, M(x3) u = 0 with u = (x4^i x5^j): its 24 eigenvalues (a
companion matrix, ``numpy.linalg.eigvals``) are x3 at every solution and 8 at +-i.
``elimination_roots`` takes each real one back to the joints.

A cut on which M(x3) is singular for every x3 (special geometry: parallel or meeting axes)
cannot be used; ``elimination_6r`` picks a regular cut per arm.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.solvers.closed_form.subproblems import (
    add,
    cross,
    dot,
    mat,
    mm,
    mmt,
    mtm,
    mtv,
    mv,
    rot,
    scale,
    sub,
    vec,
)

CUTS = 12  # cut c: the loop from joint c % 6 + 2, backwards when c >= 6
PHASES = np.array([0.0, 0.9, 2.1, -1.3])  # rad: shifts of q3 tried for a regular A
REGULAR = 1e-9  # smallest |pivot| / largest of A's LU below which a phase is not used
SIZE = 14 * 27 + 8 * 14 + 3 * 144 + 6 * 12 + 6 * 3 + 2  # the state ``companion`` keeps

_ANGLES = (0.0, 2.0 * math.pi / 3.0, 4.0 * math.pi / 3.0)
# (s, c, 1) at the three angles, inverted: sampled values to coefficients
_BASIS = np.linalg.inv(np.array([[math.sin(a), math.cos(a), 1.0] for a in _ANGLES]))
# (s, c, 1) times 1 + x^2 as polynomials in x = tan(q / 2): rows s, c, 1; columns 1, x, x^2
_HALF = np.array([[0.0, 2.0, 0.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0]])
# typed indices, not literals: one compile each of row9, at9, _line and _reflect
K0, K1, K2, K3, K4, K5 = (np.int64(k) for k in range(6))


def cut_joints(cut: int) -> tuple[np.ndarray, int]:
    """(the arm's joint at each place of cut ``cut``'s loop, +1 forwards or -1 backwards)."""
    d, back = cut % 6, cut >= 6
    base = [(d + 1 + k) % 6 for k in range(6)]
    return np.array([5 - b if back else b for b in base], dtype=np.int64), (-1 if back else 1)


@njit(cache=True, no_cfunc_wrapper=True)
def _loop(h, p, R_tip0, R9, P3, cut, LH, LR, LT):
    """Cut ``cut``'s loop for the target (R9, P3): axes ``LH`` (6, 3), links' rotations
    ``LR`` (6, 9) and translations ``LT`` (6, 3), joint 6 the dropped one."""
    d, back = cut % 6, cut >= 6
    GR = mmt(mat(R_tip0), R9)  # L6 = Tr(p6) R_tip0 T^-1 Tr(p0)
    Gt = add(vec(p[6]), mv(GR, sub(vec(p[0]), P3)))
    I9 = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    for k in range(6):
        b = (d + 1 + k) % 6
        j = 5 - b if back else b
        link = (4 - b) % 6 if back else b
        Rl, tl = (GR, Gt) if link == 5 else (I9, vec(p[link + 1]))
        if back:  # the inverse link
            tl = scale(mtv(Rl, tl), -1.0)
            Rl = mtm(Rl, I9)  # its transpose
        for c in range(3):
            LH[k, c], LT[k, c] = h[j, c], tl[c]
        for c in range(9):
            LR[k, c] = Rl[c]


@njit(cache=True, no_cfunc_wrapper=True)
def _fourteen(pv, lv, out, n0):
    """The 14 quantities of point ``pv`` and direction ``lv`` into ``out[n0:n0 + 14]``."""
    pp, pl = dot(pv, pv), dot(pv, lv)
    x = cross(pv, lv)
    for c in range(3):
        out[n0 + c] = pv[c]
        out[n0 + 3 + c] = lv[c]
        out[n0 + 8 + c] = x[c]
        out[n0 + 11 + c] = pp * lv[c] - 2.0 * pl * pv[c]
    out[n0 + 6], out[n0 + 7] = pp, pl


@njit(cache=True, no_cfunc_wrapper=True)
def _sides(LH, LR, LT, Lc, Rc):
    """The coefficients of both sides: ``Lc`` (14, 3, 3, 3) over (s, c, 1) of joints 3, 4,
    5 and ``Rc`` (14, 3, 3) of joints 1, 2, each side sampled at three angles a joint."""
    Rs = np.empty((5, 3, 9))
    for k in range(5):
        for a in range(3):
            r = rot(vec(LH[k]), _ANGLES[a])
            for c in range(9):
                Rs[k, a, c] = r[c]
    S = np.empty(14 * 27)
    h6 = vec(LH[5])
    for a in range(3):
        for b in range(3):
            for c in range(3):
                R3, R4, R5 = at9(Rs, K2, a), at9(Rs, K3, b), at9(Rs, K4, c)
                inner = add(mv(row9(LR, K3), mv(R5, vec(LT[4]))), vec(LT[3]))
                pv = mv(R3, add(mv(row9(LR, K2), mv(R4, inner)), vec(LT[2])))
                Y = mm(mm(mm(R3, row9(LR, K2)), mm(R4, row9(LR, K3))),
                       mm(R5, row9(LR, K4)))  # fmt: skip
                _fourteen(pv, mv(Y, h6), S, 14 * (9 * a + 3 * b + c))
    _fit3(S, Lc)
    T = np.empty(14 * 9)
    o6 = scale(mtv(row9(LR, K5), vec(LT[5])), -1.0)  # L6^-1 o
    d6 = mtv(row9(LR, K5), h6)
    for a in range(3):
        for b in range(3):
            R1, R2 = at9(Rs, K0, a), at9(Rs, K1, b)
            v = sub(mtv(row9(LR, K0), mtv(R1, o6)), mtv(row9(LR, K0), vec(LT[0])))
            pv = sub(mtv(row9(LR, K1), mtv(R2, v)), mtv(row9(LR, K1), vec(LT[1])))
            lv = mtv(row9(LR, K1), mtv(R2, mtv(row9(LR, K0), mtv(R1, d6))))
            _fourteen(pv, lv, T, 14 * (3 * a + b))
    for n in range(14):
        for i in range(3):
            for j in range(3):
                s = 0.0
                for a in range(3):
                    for b in range(3):
                        s += _BASIS[i, a] * _BASIS[j, b] * T[14 * (3 * a + b) + n]
                Rc[n, i, j] = s


@njit(cache=True, no_cfunc_wrapper=True)
def row9(A, k):
    """Row ``k`` of an array of 9-vectors, a 9-tuple (a rotation)."""
    return (A[k, 0], A[k, 1], A[k, 2], A[k, 3], A[k, 4], A[k, 5], A[k, 6], A[k, 7], A[k, 8])


@njit(cache=True, no_cfunc_wrapper=True)
def at9(A, k, a):
    """``A[k, a]`` of an array of 9-vectors, a 9-tuple (a rotation)."""
    return (A[k, a, 0], A[k, a, 1], A[k, a, 2], A[k, a, 3], A[k, a, 4], A[k, a, 5],
            A[k, a, 6], A[k, a, 7], A[k, a, 8])  # fmt: skip


@njit(cache=True, no_cfunc_wrapper=True)
def _fit3(S, Lc):
    """Samples S[14 (9a + 3b + c) + n] to coefficients Lc[n, i, j, k], one joint at a time."""
    W = np.empty((14, 3, 3, 3))
    for n in range(14):
        for a in range(3):
            for b in range(3):
                for c in range(3):
                    W[n, a, b, c] = S[14 * (9 * a + 3 * b + c) + n]
    for axis in range(3):
        for n in range(14):
            for u in range(3):
                for v in range(3):
                    y0, y1, y2 = _line(W, n, u, v, axis, K0), _line(W, n, u, v, axis, K1), \
                        _line(W, n, u, v, axis, K2)  # fmt: skip
                    for i in range(3):
                        x = _BASIS[i, 0] * y0 + _BASIS[i, 1] * y1 + _BASIS[i, 2] * y2
                        if axis == 0:
                            W[n, i, u, v] = x
                        elif axis == 1:
                            W[n, u, i, v] = x
                        else:
                            W[n, u, v, i] = x
    for n in range(14):
        for a in range(3):
            for b in range(3):
                for c in range(3):
                    Lc[n, a, b, c] = W[n, a, b, c]


@njit(cache=True, no_cfunc_wrapper=True)
def _reflect(M, v, v2, k, m, c0, c1):
    """Columns ``c0`` to ``c1`` of ``M`` reflected by the Householder vector ``v`` (rows
    ``k`` to ``m``, squared norm ``v2``): M <- (I - 2 v v^T / v2) M."""
    for c in range(c0, c1):
        f = 0.0
        for r in range(k, m):
            f += v[r] * M[r, c]
        f *= 2.0 / v2
        for r in range(k, m):
            M[r, c] -= f * v[r]


@njit(cache=True, no_cfunc_wrapper=True)
def _householder(A, P):
    """Householder QR of ``A`` (14, 8) in place (R in its upper triangle) with ``P`` = Q^T
    (14, 14): its last 6 rows annihilate A's columns. Returns min |R_kk| / max |R_kk|."""
    m, k_n = A.shape
    for r in range(m):
        for c in range(m):
            P[r, c] = 1.0 if r == c else 0.0
    v = np.empty(m)
    big, small = 0.0, math.inf
    for k in range(k_n):
        x2 = 0.0
        for r in range(k, m):
            x2 += A[r, k] * A[r, k]
        alpha = -math.copysign(math.sqrt(x2), A[k, k])
        v2 = 0.0
        for r in range(k, m):
            v[r] = A[r, k] - (alpha if r == k else 0.0)
            v2 += v[r] * v[r]
        if v2 > 0.0:
            _reflect(A, v, v2, k, m, k, k_n)
            _reflect(P, v, v2, k, m, K0, m)
        big, small = max(big, abs(A[k, k])), min(small, abs(A[k, k]))
    return small / big if big > 0.0 else 0.0


@njit(cache=True, no_cfunc_wrapper=True)
def _line(W, n, u, v, axis, a):
    if axis == 0:
        return W[n, a, u, v]
    if axis == 1:
        return W[n, u, a, v]
    return W[n, u, v, a]


@njit(cache=True, no_cfunc_wrapper=True)
def lu(A, piv):
    """LU of the square ``A`` in place with partial pivoting (``piv`` the row order);
    returns the smallest |pivot| over the largest."""
    m = A.shape[0]
    big, small = 0.0, math.inf
    for k in range(m):
        piv[k] = k
    for k in range(m):
        r = k
        for i in range(k + 1, m):
            if abs(A[i, k]) > abs(A[r, k]):
                r = i
        if r != k:
            piv[k], piv[r] = piv[r], piv[k]
            for c in range(m):
                A[k, c], A[r, c] = A[r, c], A[k, c]
        a = abs(A[k, k])
        big, small = max(big, a), min(small, a)
        if A[k, k] == 0.0:
            A[k, k] = 1e-300  # singular: inverse iteration wants it finite
        for i in range(k + 1, m):
            f = A[i, k] / A[k, k]
            A[i, k] = f
            for c in range(k + 1, m):
                A[i, c] -= f * A[k, c]
    return small / big if big > 0.0 else 0.0


@njit(cache=True, no_cfunc_wrapper=True)
def lu_solve(A, piv, b, x):
    """x = A^-1 b for ``A`` factored by ``lu``."""
    m = A.shape[0]
    for i in range(m):
        s = b[piv[i]]
        for c in range(i):
            s -= A[i, c] * x[c]
        x[i] = s
    for i in range(m - 1, -1, -1):
        s = x[i]
        for c in range(i + 1, m):
            s -= A[i, c] * x[c]
        x[i] = s / A[i, i]


@njit(cache=True, no_cfunc_wrapper=True)
def _matrices(E, phase, M):
    """M[0], M[1], M[2] (C, B, A: 12 x 12) of the 6 equations ``E`` (6, 3, 3, 3) over
    (s, c, 1) of joints 3, 4, 5, with q3 = phase + 2 atan(x3)."""
    cp, sp = math.cos(phase), math.sin(phase)
    for a in range(3):
        for r in range(12):
            for c in range(12):
                M[a, r, c] = 0.0
    for r in range(6):
        for j in range(3):
            for k in range(3):
                ks, kc, k1 = E[r, 0, j, k], E[r, 1, j, k], E[r, 2, j, k]
                e3 = (ks * cp - kc * sp, ks * sp + kc * cp, k1)  # over (s, c, 1) of q3 - phase
                for a in range(3):
                    f3 = e3[0] * _HALF[0, a] + e3[1] * _HALF[1, a] + e3[2] * _HALF[2, a]
                    for b in range(3):
                        for c in range(3):
                            v = f3 * _HALF[j, b] * _HALF[k, c]
                            M[a, r, 3 * b + c] += v
                            M[a, 6 + r, 3 * (b + 1) + c] += v


@njit(cache=True, no_cfunc_wrapper=True)
def companion(h, p, R_tip0, R, pos, cut, K, state):
    """The 24 x 24 companion matrix ``K`` of cut ``cut``'s M(x3) for the target (rotation
    ``R`` 3 x 3, position ``pos``), and in ``state`` (``SIZE``) what ``solutions`` reads;
    returns (regular, rank): whether a phase made A regular, and the smallest singular
    value of the eliminated products' matrix over its largest."""
    R9, P3 = mat(R), vec(pos)
    LH, LR, LT = np.empty((6, 3)), np.empty((6, 9)), np.empty((6, 3))
    _loop(h, p, R_tip0, R9, P3, cut, LH, LR, LT)
    Lc, Rc = np.empty((14, 3, 3, 3)), np.empty((14, 3, 3))
    _sides(LH, LR, LT, Lc, Rc)
    for n in range(14):  # the right side's constant moves left (a loop: no shape error)
        Lc[n, 2, 2, 2] -= Rc[n, 2, 2]
    Q = np.empty((14, 8))
    for n in range(14):
        for c in range(8):
            Q[n, c] = Rc[n, c // 3, c % 3]
    P = np.empty((14, 14))
    rank = _householder(Q, P)
    E = np.zeros((6, 3, 3, 3))
    for r in range(6):
        for n in range(14):
            w = P[8 + r, n]
            for i in range(3):
                for j in range(3):
                    for k in range(3):
                        E[r, i, j, k] += w * Lc[n, i, j, k]
    M = np.empty((3, 12, 12))
    F = np.empty((12, 12))
    piv = np.empty(12, np.int64)
    best, phase = -1.0, 0.0
    for t in range(len(PHASES)):
        _matrices(E, PHASES[t], M)
        for r in range(12):
            for c in range(12):
                F[r, c] = M[2, r, c]
        g = lu(F, piv)
        if g > best:
            best, phase = g, PHASES[t]
        if g >= REGULAR:
            break
    _matrices(E, phase, M)
    for r in range(12):
        for c in range(12):
            F[r, c] = M[2, r, c]
    lu(F, piv)
    b, x = np.empty(12), np.empty(12)
    for r in range(24):
        for c in range(24):
            K[r, c] = 0.0
    for r in range(12):
        K[r, 12 + r] = 1.0
    for c in range(24):  # the lower rows: -A^-1 [C B]
        for r in range(12):
            b[r] = M[0, r, c] if c < 12 else M[1, r, c - 12]
        lu_solve(F, piv, b, x)
        for r in range(12):
            K[12 + r, c] = -x[r]
    # the state: Lc, the products' pseudo-inverse, M, the loop, phase and cut
    at = 0
    for n in range(14):
        for i in range(27):
            state[at] = Lc[n, i // 9, (i // 3) % 3, i % 3]
            at += 1
    for n in range(14):  # R^-1 P[:8]: the products' least-squares solution, column by column
        for c in range(7, -1, -1):
            v = P[c, n]
            for k in range(c + 1, 8):
                v -= Q[c, k] * state[at + 14 * k + n]
            state[at + 14 * c + n] = v / Q[c, c] if Q[c, c] != 0.0 else 0.0  # rank: the caller
    at += 8 * 14
    for a in range(3):
        for r in range(12):
            for c in range(12):
                state[at] = M[a, r, c]
                at += 1
    for k in range(6):
        for c in range(9):
            state[at + c] = LR[k, c]
        for c in range(3):
            state[at + 9 + c] = LT[k, c]
        at += 12
    for k in range(6):
        for c in range(3):
            state[at] = LH[k, c]
            at += 1
    state[at], state[at + 1] = phase, cut
    return best >= REGULAR, rank
