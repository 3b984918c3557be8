"""The branches of the search over q1 for 6R arms with axes 2 and 3 parallel (IK-Geo's
``IK_2_parallel``; ``two_parallel`` classifies the arms, ``search_zeros`` finds the zeros).

With the chain in product-of-exponentials form (``sixr.Chain6R``, the points on the axes
as the URDF puts them), R_13 = rot(h2, q2 + s3 q3) fixes h2 (s3 = +-1: axis 3 along or
against axis 2). For the target (R, p) and a trial q1, with a = R_06^T rot(h1, q1) h2:

    a . rot(-h6, q6) p_56 + h2 . rot(h4, q4) p_45 = h2 . (R_01^T p_16 - p_12 - p_23 - p_34)
    a . rot(-h6, q6) h5 - h2 . rot(h4, q4) h5 = 0                       -> SP6: q6, q4
    rot(h2, q2 + s3 q3) rot(h4, q4) h5 = R_01^T R_06 rot(h6, q6)^T h5  -> SP1: q2 + s3 q3
    v = R_01^T p_16 - p_12 - R_13 (p_34 + R_34 p_45) - R_01^T R_05 p_56, error |v| - |p_23|

The error vanishes at the solutions' q1 (up to 4 branches, one per SP6 solution), then
rot(h2, q2) p_23 = v (SP1: q2) and rot(-h5, q5) R_34^T h2 = R_56 R_06^T R_01 h2 (SP1: q5).

Where SP6 has solutions at all: its first equation's q6 term is at most |p_56| and its q4
term varies by at most |h2 x h4| |p_45 - (h4 . p_45) h4|, while its right-hand side is a
sinusoid in q1 of the wrist's reach. On an arm whose wrist is nearly spherical (the IRB
140's 0.02 m between axes 5 and 6) that holds on two windows of q1 narrower than a grid
step, which a uniform grid steps over. So the search runs over a parameter t whose turn
is mapped onto q1 piecewise linearly (``_window``, ``q1_of``), nine tenths of its samples
in the windows; outside them SP6 has no solution, so nothing is lost there.

Where rot(h4, q4) h5 is parallel to h2 (the IRB 140 at q4 = 0 or pi: axes 2, 3 and 5
parallel, a pose the arm reaches without being singular), the rotation fixes only
q2 + s3 q3 + q5 and SP1's q2 + s3 q3 is noise, so e(q1) spikes there and its zeros are
missed. The search then also polishes, from the grid sample where a branch comes nearest
that pose (``coupling``), the configurations whose q2 + s3 q3 the position fixes instead
(SP3, its two solutions: state[2] = 1 or 2).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.solvers.closed_form.search_1d import BRANCHES, sp6_roots
from armik.solvers.closed_form.subproblems import (
    add,
    cross,
    dot,
    mmt,
    mtm,
    mtv,
    mv,
    neg,
    norm,
    rot,
    scale,
    sp1,
    sp3,
    sub,
    vec,
    wrap,
)

IN_WINDOWS = 0.9  # of the search's samples, where SP6 can have solutions
MARGIN = 1e-6  # relative widening of the windows: rounding never shuts a solution out
DEGENERATE = 0.05  # ``coupling`` below this: q2 + s3 q3 from the rotation is ill-conditioned


@njit(cache=True, no_cfunc_wrapper=True)
def _window(h, p, p16):
    """The windows of q1 where SP6 can have solutions, as (phi0, ua, ub, empty): q1 - phi0
    within [ua, ub] or [-ub, -ua] (ua = 0, ub = pi: the whole turn)."""
    h1, h2, h4 = vec(h[0]), vec(h[1]), vec(h[3])
    p4 = vec(p[4])
    k = cross(h1, h2)  # (R1 h2) . p16 = e + alpha sin q1 + beta cos q1
    e = dot(h1, h2) * dot(h1, p16)
    alpha, beta = dot(p16, k), dot(p16, h2) - e
    c = e - dot(h2, add(add(vec(p[1]), vec(p[2])), vec(p[3]))) - dot(h2, h4) * dot(h4, p4)
    off = sub(p4, scale(h4, dot(h4, p4)))
    rho = norm(vec(p[5])) + norm(cross(h2, h4)) * norm(off)
    amp = math.hypot(alpha, beta)
    rho += MARGIN * (rho + amp + abs(c)) + 1e-12
    if amp <= 1e-12:  # the wrist centre on axis 1: every q1 or none, by c alone
        return 0.0, 0.0, math.pi, abs(c) > rho
    lo, hi = (-rho - c) / amp, (rho - c) / amp  # cos(q1 - phi0) within [lo, hi]
    if lo > 1.0 or hi < -1.0:
        return 0.0, 0.0, math.pi, True
    return math.atan2(alpha, beta), math.acos(min(hi, 1.0)), math.acos(max(lo, -1.0)), False


@njit(cache=True, no_cfunc_wrapper=True)
def q1_of(t, phi0, ua, ub):
    """q1 at the search's parameter ``t`` (rad, any turn): the turn t in [-pi, pi) runs
    over the window [ua, ub], the gap through pi, the window [-ub, -ua], the gap through
    0, with ``IN_WINDOWS`` of it in the windows (or their share, if larger)."""
    if ua <= 0.0 and ub >= math.pi:
        return t
    L = (ub - ua, 2.0 * (math.pi - ub), ub - ua, 2.0 * ua)
    inside, outside = 2.0 * (ub - ua), 2.0 * math.pi - 2.0 * (ub - ua)
    dense = max(1.0, IN_WINDOWS / (1.0 - IN_WINDOWS) * outside / max(inside, 1e-300))
    total = inside * dense + outside
    tt = (t + math.pi) % (2.0 * math.pi)
    start = ua
    for i in range(4):
        tau = L[i] * (dense if i % 2 == 0 else 1.0) * 2.0 * math.pi / total
        if tt < tau or i == 3:
            u = start + (tt / tau * L[i] if tau > 0.0 else 0.0)
            return wrap(u + phi0)
        tt -= tau
        start += L[i]
    return t


@njit(cache=True, no_cfunc_wrapper=True)
def _sp6_at(h, p, R06, p16, q1):
    """SP6's (q6, q4) solutions at the trial ``q1`` and the pieces that follow."""
    h1, h2, h4, h5, h6 = vec(h[0]), vec(h[1]), vec(h[3]), vec(h[4]), vec(h[5])
    R1 = rot(h1, q1)
    a = mtv(R06, mv(R1, h2))
    H6, K6, P6 = np.empty((4, 3)), np.empty((4, 3)), np.empty((4, 3))
    p4, p5 = vec(p[4]), vec(p[5])
    for c in range(3):
        H6[0, c], H6[1, c], H6[2, c], H6[3, c] = a[c], h2[c], a[c], h2[c]
        K6[0, c], K6[1, c], K6[2, c], K6[3, c] = -h6[c], h4[c], -h6[c], h4[c]
        P6[0, c], P6[1, c], P6[2, c], P6[3, c] = p5[c], p4[c], h5[c], -h5[c]
    u = sub(sub(sub(mtv(R1, p16), vec(p[1])), vec(p[2])), vec(p[3]))
    T = np.empty((8, 2))
    m = sp6_roots(H6, K6, P6, dot(h2, u), 0.0, T)
    return R1, T, max(m, 0)


@njit(cache=True, no_cfunc_wrapper=True)
def _rest(h, p, R06, R1, q4, q6):
    """(v, q23, M) for a trial: v the vector rot(h2, q2) p_23 must equal, q23 = q2 + s3 q3,
    M = R_01^T R_06 rot(h6, q6)^T."""
    h2, h4, h5, h6 = vec(h[1]), vec(h[3]), vec(h[4]), vec(h[5])
    R4 = rot(h4, q4)
    M = mmt(mtm(R1, R06), rot(h6, q6))
    q23, _ = sp1(mv(R4, h5), mv(M, h5), h2)
    R13 = rot(h2, q23)
    return R4, M, q23, R13


@njit(cache=True, no_cfunc_wrapper=True)
def _v(p, R1, p16, R13, R4, M):
    w = mv(R13, add(vec(p[3]), mv(R4, vec(p[4]))))
    return sub(sub(sub(mtv(R1, p16), vec(p[1])), w), mv(M, vec(p[5])))


@njit(cache=True, no_cfunc_wrapper=True)
def branches(x, h, p, R06, p16, e, s):
    """The branches at the search's parameter ``x`` (``search_1d``, ``search_zeros``):
    q1 = ``q1_of(x, ...)``."""
    phi0, ua, ub, empty = _window(h, p, p16)
    if empty:
        return 0
    R1, T, m = _sp6_at(h, p, R06, p16, q1_of(x, phi0, ua, ub))
    n23 = norm(vec(p[2]))
    m = min(m, BRANCHES)
    for i in range(m):
        R4, M, q23, R13 = _rest(h, p, R06, R1, T[i, 1], T[i, 0])
        e[i] = norm(_v(p, R1, p16, R13, R4, M)) - n23
        s[i, 0], s[i, 1], s[i, 2] = T[i, 0], T[i, 1], 0.0
    return m


@njit(cache=True, no_cfunc_wrapper=True)
def coupling(h, state):
    """How well the rotation alone fixes q2 + s3 q3 on the branch ``state``: the part of
    rot(h4, q4) h5 across h2 (0 where axes 2, 3 and 5 are parallel), and which of the two
    such poses it is near (0: h5 along h2, 1: against it)."""
    h2, u = vec(h[1]), mv(rot(vec(h[3]), state[1]), vec(h[4]))
    return norm(cross(h2, u)), 0 if dot(h2, u) >= 0.0 else 1


@njit(cache=True, no_cfunc_wrapper=True)
def _split_by_position(h, p, R06, p16, x, state, q):
    """The configuration at q1 = ``x`` whose q2 + s3 q3 the position fixes (SP3's
    solution ``state[2]``: 1 or 2) and q5 the rest of the rotation."""
    h1, h2, h3, h4, h5, h6 = vec(h[0]), vec(h[1]), vec(h[2]), vec(h[3]), vec(h[4]), vec(h[5])
    q6, q4 = state[0], state[1]
    R1, R4 = rot(h1, x), rot(h4, q4)
    M = mmt(mtm(R1, R06), rot(h6, q6))
    w0 = add(vec(p[3]), mv(R4, vec(p[4])))
    c = sub(sub(mtv(R1, p16), vec(p[1])), mv(M, vec(p[5])))
    t0, t1, _, _ = sp3(w0, c, h2, norm(vec(p[2])))
    q23 = t0 if state[2] < 1.5 else t1
    R13 = rot(h2, q23)
    q2, _ = sp1(vec(p[2]), sub(c, mv(R13, w0)), h2)
    y = cross(h5, (1.0, 0.0, 0.0)) if abs(h5[0]) < 0.9 else cross(h5, (0.0, 1.0, 0.0))
    q5, _ = sp1(y, mtv(R4, mtv(R13, mv(M, y))), h5)
    q[0], q[1], q[2], q[3], q[4], q[5] = x, q2, dot(h3, h2) * (q23 - q2), q4, q5, q6


@njit(cache=True, no_cfunc_wrapper=True)
def configuration(h, p, R06, p16, x, state, q):
    """The configuration of the zero at the parameter ``x`` on the branch ``state``
    (q6, q4)."""
    h1, h2, h3, h5 = vec(h[0]), vec(h[1]), vec(h[2]), vec(h[4])
    q6, q4 = state[0], state[1]
    phi0, ua, ub, _ = _window(h, p, p16)
    x = q1_of(x, phi0, ua, ub)
    if state[2] > 0.5:
        _split_by_position(h, p, R06, p16, x, state, q)
        return
    R1 = rot(h1, x)
    R4, M, q23, R13 = _rest(h, p, R06, R1, q4, q6)
    v = _v(p, R1, p16, R13, R4, M)
    q2, _ = sp1(vec(p[2]), v, h2)
    q5, _ = sp1(mtv(R4, h2), mtv(M, h2), neg(h5))
    q[0], q[1], q[2], q[3], q[4], q[5] = x, q2, dot(h3, h2) * (q23 - q2), q4, q5, q6
