"""The branches of the search over q4 for 6R arms whose axes 5 and 6 meet (IK-Geo's
``IK_2_intersecting``; ``two_intersecting`` classifies the arms, ``search_zeros`` finds the
zeros).

With the chain in product-of-exponentials form (``sixr.Chain6R``; the points on axes 5 and
6 at their meeting point, so p_56 = 0), for the target (R, p) and a trial q4:

    -p_12 + rot(-h1, q1) p_16 = rot(h2, q2) (p_23 + rot(h3, q3) (p_34 + rot(h4, q4) p_45))
                                                                       -> SP5: q1, q2, q3
    error h5 . R_04^T R_06 h6 - h5 . h6 (axis 6 must keep its angle to axis 5)

The error vanishes at the solutions' q4 (up to 4 branches, one per SP5 solution), then
rot(h5, q5) h6 = R_04^T R_06 h6 and rot(-h6, q6) h5 = R_06^T R_04 h5 (SP1: q5, q6).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from armik.solvers.closed_form.search_1d import BRANCHES, sp5_roots
from armik.solvers.closed_form.subproblems import add, dot, mm, mtv, mv, neg, rot, sp1, vec


@njit(cache=True, no_cfunc_wrapper=True)
def _R04(h, q1, q2, q3, q4):
    R = mm(rot(vec(h[0]), q1), rot(vec(h[1]), q2))
    return mm(mm(R, rot(vec(h[2]), q3)), rot(vec(h[3]), q4))


@njit(cache=True, no_cfunc_wrapper=True)
def branches(x, h, p, R06, p16, e, s):
    """The branches at the trial angle ``x`` (``search_1d``, ``search_zeros``)."""
    h5, h6 = vec(h[4]), vec(h[5])
    p35 = add(vec(p[3]), mv(rot(vec(h[3]), x), vec(p[4])))
    h1, h2, h3 = vec(h[0]), vec(h[1]), vec(h[2])
    T = np.empty((8, 3))
    m = min(max(sp5_roots(neg(vec(p[1])), p16, vec(p[2]), p35, neg(h1), h2, h3, T), 0), BRANCHES)
    g = mv(R06, h6)
    c56 = dot(h5, h6)
    for i in range(m):
        e[i] = dot(h5, mtv(_R04(h, T[i, 0], T[i, 1], T[i, 2], x), g)) - c56
        s[i, 0], s[i, 1], s[i, 2] = T[i, 0], T[i, 1], T[i, 2]
    return m


@njit(cache=True, no_cfunc_wrapper=True)
def configuration(h, p, R06, p16, x, state, q):
    """The configuration of the zero at q4 = ``x`` on the branch ``state`` (q1, q2, q3)."""
    h5, h6 = vec(h[4]), vec(h[5])
    R04 = _R04(h, state[0], state[1], state[2], x)
    q5, _ = sp1(h6, mtv(R04, mv(R06, h6)), h5)
    q6, _ = sp1(h5, mtv(R06, mv(R04, h5)), neg(h6))
    q[0], q[1], q[2], q[3], q[4], q[5] = state[0], state[1], state[2], x, q5, q6
