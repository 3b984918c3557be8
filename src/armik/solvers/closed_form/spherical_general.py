"""Closed-form IK of 6R arms with a spherical wrist and no further structure (IK-Geo's
``IK_spherical``): axes 4, 5, 6 meet in the wrist centre, the first three axes are
arbitrary lines (axes 1 and 3 parallel, a skewed shoulder, an offset elbow).

With the chain in product-of-exponentials form (``sixr.Chain6R``; the points on axes 4, 5,
6 all at the wrist centre W), for the target (R, p):

    R_06 = R R_tip0^T,   p_16 = p - R_06 p_6T - p_01
    -p_12 + rot(-h1, q1) p_16 = rot(h2, q2) (p_23 + rot(h3, q3) p_34)   -> SP5: q1, q2, q3
    rot(h4, q4)^T R_36 h6 = rot(h5, q5) h6                             -> SP2: q4, q5
    rot(h6, q6) = (R_03 R_4 R_5)^T R_06                                -> SP1: q6

Up to 4 x 2 = 8 solutions. Singular cases keep the free angle at q0 (``singular``): the
wrist (axes 4 and 6 aligned: q4 free) and a continuum of SP5 (the wrist centre on axis 1).
The two spherical-wrist layouts of ``spherical_wrist`` (axes 2, 3 parallel; axes 1, 2
meeting) are special cases; ``auto`` keeps choosing that file's solver for them.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from armik.kernel.single import plain_pose, plain_seed
from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes, angle_between, axis_lines, fmt, meeting_point
from armik.solvers.closed_form import sixr
from armik.solvers.closed_form.family import Family
from armik.solvers.closed_form.sixr import LS, MISSED, SINGULAR
from armik.solvers.closed_form.sixr_judged import GENERAL, UNLABELLED, judged, split
from armik.solvers.closed_form.spherical_wrist import _wrist
from armik.solvers.closed_form.subproblems import (
    add,
    mat,
    mm,
    mmt,
    mv,
    neg,
    norm,
    rot,
    sub,
    vec,
)
from armik.solvers.closed_form.subproblems_56 import sp5
from armik.tolerances import ANGLE_TOL, DISTANCE_TOL

CLOSED_FORM = "closed form (general spherical wrist)"
FAMILY = "spherical_general"


def classify(arm: ArmModel, ax: Axes | None = None) -> sixr.Chain6R | str:
    """The geometry of a 6R arm whose last three axes meet (the wrist centre), whatever
    its first three axes, or the reason it is not one."""
    why = sixr.not_6r(arm)
    if why:
        return why
    ax = ax or axis_lines(arm)
    P, H = ax.points, ax.directions
    for i, j in ((3, 4), (4, 5)):
        ang = angle_between(H[i], H[j])
        if ang < ANGLE_TOL:
            return f"axes {i + 1} and {j + 1} are parallel, so the last three do not form a wrist"
    w, miss = meeting_point(P[3:], H[3:])
    if miss > DISTANCE_TOL:
        return (
            f"the last three axes do not meet in one point: they miss by {fmt(miss)} m "
            f"(tolerance {DISTANCE_TOL:g} m)"
        )
    text = f"spherical wrist at {np.round(w, 6).tolist()} m, first three axes general"
    return sixr.chain_6r(FAMILY, "", ax, [P[0], P[1], P[2], w, w, w], text)


@njit(cache=True, no_cfunc_wrapper=True)
def kernel(h, p, R_tip0, R, pos, q0, lower, upper, variant, labelled, out):
    """All closed-form solutions for the target rotation ``R`` (9-tuple, row-major) and
    position ``pos`` (3-tuple), packed nearest-first into ``out`` (8, 11), the first
    ``labelled`` with their branch; returns (n, first reached) (see ``sixr.pack``).
    ``variant`` is unused: the arguments every family's kernel takes (``family``)."""
    W = np.empty((8, 11))
    h1, h2, h3, h4 = vec(h[0]), vec(h[1]), vec(h[2]), vec(h[3])
    h5, h6 = vec(h[4]), vec(h[5])
    p0, p1, p2, p3, p6 = vec(p[0]), vec(p[1]), vec(p[2]), vec(p[3]), vec(p[6])
    R06 = mmt(R, mat(R_tip0))
    p16 = sub(sub(pos, mv(R06, p6)), p0)
    t1, t2, t3, m, ls = sp5(neg(p1), p16, p2, p3, neg(h1), h2, h3)
    flag, cd, v0 = 0, 0, 0.0
    if m == -1:  # a continuum: one of it, q1 free
        m = 1
        flag |= SINGULAR
    n = np.int64(0)  # not a literal 0: numba would compile the callees for it too
    for i in range(m):
        q1, q2, q3 = t1[i], t2[i], t3[i]
        R03 = mm(mm(rot(h1, q1), rot(h2, q2)), rot(h3, q3))
        f = flag
        if ls:  # how far the closest wrist centre is from the target's
            f |= LS
            cd = MISSED
            got = add(add(mv(rot(h1, q1), p1), mv(mm(rot(h1, q1), rot(h2, q2)), p2)), mv(R03, p3))
            v0 = norm(sub(got, p16))
        n = _wrist(R03, R06, h4, h5, h6, q0, lower, upper, q1, q2, q3, f, cd, v0, 0.0, W, n)
    sixr.nearest_equivalents(W, n, q0, lower, upper)
    return n, sixr.pack(W, n, q0, lower, upper, h, p, labelled, out)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def solve_into(chain, H, q0, every, out):
    """``kernel`` for one 4x4 pose ``H``, its rows packed into ``out`` (8, 11); returns
    ``sixr.hand_over``'s (n, head), or n = -1 and nothing solved when ``H`` or ``q0`` is
    not plain (``kernel.single``). ``chain``: ``sixr.flat``."""
    h, p, R_tip0, lower, upper, variant = sixr.unflatten(chain)
    if not plain_pose(H) or not plain_seed(q0, lower, upper):
        return -1, 0
    labelled = 8 if every else 1
    n, reached = kernel(
        h, p, R_tip0, mat(H), sixr.column(H), q0, lower, upper, variant, labelled, out
    )
    return sixr.hand_over(n, reached, labelled, h, p, out)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def solve_all_into(ctx, H, q0, rows):
    """``kernel``'s every row for ``H`` in ``rows`` (8, ``sixr_judged.WIDTH``), unlabelled,
    measured and judged in the same call: ``sixr_judged.judged``'s (n, verdict), n = -1 and
    nothing solved when ``H`` or ``q0`` is not plain. ``ctx``: ``sixr_judged.context``."""
    chain, judge, frame, packed, kind, halton = split(ctx)
    h, p, R_tip0, lower, upper, variant = sixr.unflatten(chain)
    if not plain_pose(H) or not plain_seed(q0, lower, upper):
        return -1, GENERAL
    n, _ = kernel(h, p, R_tip0, mat(H), sixr.column(H), q0, lower, upper, variant, UNLABELLED, rows)
    return judged(n, chain, packed, kind, halton, frame, judge, H, rows)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def kernel_many(chain, Rs, ps, q0s):
    """``kernel`` for N targets: the row nearest q0 of each, and its claim code."""
    h, p, R_tip0, lower, upper, variant = sixr.unflatten(chain)
    N = ps.shape[0]
    Q = np.empty((N, 6))
    claim = np.empty(N, np.int8)
    out = np.empty((8, 11))  # one for every target
    unlabelled = np.int64(0)  # no branch labels (not a literal 0: one compile of kernel)
    for i in range(N):
        kernel(h, p, R_tip0, mat(Rs[i]), vec(ps[i]), q0s[i], lower, upper, variant, unlabelled, out)
        for j in range(6):  # a loop: a slice copy compiles numba's shape-error path
            Q[i, j] = out[0, j]
        claim[i] = sixr.UNREACHABLE_CODE if int(out[0, 6]) & LS else sixr.CONVERGED_CODE
    return Q, claim


def _classify(arm: ArmModel):
    return classify(arm)


SPEC = Family(
    FAMILY, _classify, CLOSED_FORM, kernel, solve_into, kernel_many, solve_all_into=solve_all_into
).register(
    "spherical_general",
    75,
    "closed form for 6R arms with any spherical wrist (SP5): up to 8 solutions",
)
