"""Closed-form IK of 6R arms with axes 2, 3, 4 parallel and nothing else (IK-Geo's
``IK_3_parallel``): axes 5 and 6 need not meet, axis 1 and axes 5, 6 are arbitrary lines
(not parallel to axes 2, 3, 4).

With the chain in product-of-exponentials form (``sixr.Chain6R``, the points on the axes
as the URDF puts them), rot(h2, .) fixes h2 and so does R_14 = rot(h2, q2 + s3 q3 + s4 q4)
(s3, s4 = +-1: axes 3 and 4 along or against axis 2). For the target (R, p):

    R_06 = R R_tip0^T,   p_16 = p - R_06 p_6T - p_01
    h2 . rot(-h1, q1) p_16 - h2 . rot(h5, q5) p_56 = h2 . (p_12 + p_23 + p_34 + p_45)
    h2 . rot(-h1, q1) R_06 h6 - h2 . rot(h5, q5) h6 = 0                  -> SP6: q1, q5
    rot(-h6, q6) rot(h5, q5)^T h2 = R_06^T rot(h1, q1) h2                 -> SP1: q6
    R_14 = rot(h1, q1)^T R_06 rot(h6, q6)^T rot(h5, q5)^T                 -> SP1: q2 + s3 q3 + s4 q4
    |p_23 + rot(h3, q3) p_34| = |rot(h1, q1)^T p_16 - p_12 - R_14 (p_45 + R_5 p_56)| -> SP3: q3
    rot(h2, q2) (p_23 + rot(h3, q3) p_34) = ...                          -> SP1: q2, then q4

Up to 4 x 2 = 8 solutions. Singular cases keep the free angle at q0 (``singular``): the
wrist (rot(h5, q5) h6 along h2: q6 and q2 + s3 q3 + s4 q4 trade off, q6 kept), a
continuum of SP6, the elbow stretched or folded (one elbow root).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from armik.kernel.single import plain_pose, plain_seed
from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes, angle_between, axis_lines, fmt
from armik.solvers.closed_form import elbow_pair, sixr
from armik.solvers.closed_form.family import Family
from armik.solvers.closed_form.sixr import LS, SINGULAR
from armik.solvers.closed_form.sixr_judged import GENERAL, UNLABELLED, judged, split
from armik.solvers.closed_form.subproblems import (
    SINGLE,
    add,
    cross,
    dot,
    mat,
    mmt,
    mtm,
    mtv,
    mv,
    neg,
    norm,
    rot,
    scale,
    sp1,
    sub,
    vec,
)
from armik.solvers.closed_form.subproblems_56 import sp6
from armik.tolerances import ANGLE_TOL

CLOSED_FORM = "closed form (three parallel axes, general wrist)"
FAMILY = "three_parallel_general"


def classify(arm: ArmModel, ax: Axes | None = None) -> sixr.Chain6R | str:
    """The geometry of a 6R arm with axes 2, 3, 4 parallel, whatever its other axes, or
    the reason it is not one."""
    why = sixr.not_6r(arm)
    if why:
        return why
    ax = ax or axis_lines(arm)
    P, H = ax.points, ax.directions
    for i, j in ((1, 2), (1, 3)):
        ang = angle_between(H[i], H[j])
        if ang > ANGLE_TOL:
            return (
                f"axes 2, 3, 4 are not parallel: axes {i + 1} and {j + 1} are "
                f"{fmt(ang)} rad apart (tolerance {ANGLE_TOL:g} rad)"
            )
    for i in (0, 4):
        if angle_between(H[i], H[1]) < ANGLE_TOL:
            return f"axis {i + 1} is parallel to axes 2, 3, 4"
    text = f"axes 2, 3, 4 parallel along {np.round(H[1], 6).tolist()}, the wrist general"
    return sixr.chain_6r(FAMILY, "", ax, [P[0], P[1], P[2], P[3], P[4], P[5]], text)


@njit(cache=True, no_cfunc_wrapper=True)
def kernel(h, p, R_tip0, R, pos, q0, lower, upper, variant, labelled, out):
    """All closed-form solutions for the target rotation ``R`` (9-tuple, row-major) and
    position ``pos`` (3-tuple), packed nearest-first into ``out`` (8, 11), the first
    ``labelled`` with their branch; returns (n, first reached) (see ``sixr.pack``).
    ``variant`` is unused: the arguments every family's kernel takes (``family``)."""
    W = np.empty((8, 11))
    h1, h2, h3, h4 = vec(h[0]), vec(h[1]), vec(h[2]), vec(h[3])
    h5, h6 = vec(h[4]), vec(h[5])
    p0, p1, p2, p3 = vec(p[0]), vec(p[1]), vec(p[2]), vec(p[3])
    p4, p5, p6 = vec(p[4]), vec(p[5]), vec(p[6])
    s3, s4 = dot(h3, h2), dot(h4, h2)
    x = cross(h2, h1)
    x = scale(x, 1.0 / norm(x))  # a direction across the parallel axes
    R06 = mmt(R, mat(R_tip0))
    p16 = sub(sub(pos, mv(R06, p6)), p0)
    H6, K6, P6 = np.empty((4, 3)), np.empty((4, 3)), np.empty((4, 3))
    g = mv(R06, h6)
    for c in range(3):
        H6[0, c] = H6[1, c] = H6[2, c] = H6[3, c] = h2[c]
        K6[0, c] = K6[2, c] = -h1[c]
        K6[1, c] = K6[3, c] = h5[c]
        P6[0, c], P6[1, c], P6[2, c], P6[3, c] = p16[c], -p5[c], g[c], -h6[c]
    d1 = dot(h2, add(add(p1, p2), add(p3, p4)))
    t1, t5, m, ls = sp6(H6, K6, P6, d1, 0.0)
    flag = 0
    if m == -1:  # a continuum: one of it
        m = 1
        flag |= SINGULAR
    if ls:
        flag |= LS
    n = np.int64(0)  # not a literal 0: numba would compile the callees for it too
    for i in range(m):
        q1, q5 = t1[i], t5[i]
        R1, R5 = rot(h1, q1), rot(h5, q5)
        M = mtm(R1, R06)
        a = mtv(R5, h2)
        f6 = flag
        if norm(cross(a, h6)) < SINGLE:  # wrist singular: q6 kept at q0
            q6 = q0[5]
            f6 |= SINGULAR
        else:
            q6, _ = sp1(a, mtv(M, h2), neg(h6))
        R14 = mmt(mmt(M, rot(h6, q6)), R5)
        q14, _ = sp1(x, mv(R14, x), h2)
        v = sub(sub(mtv(R1, p16), p1), mv(R14, add(p4, mv(R5, p5))))
        nv = norm(v)
        c0, c1, n3, ls3, roots = elbow_pair.elbow_roots(p3, neg(p2), h3, nv, q0[2])
        f3, cd3, w0, w1 = f6, 0, 0.0, 0.0
        if n3 == -1 or (n3 == 1 and not ls3):
            f3 |= SINGULAR  # every turn spans it, or stretched or folded
        if ls3:
            f3 |= LS
            cd3, w1 = sixr.elbow_code(p2, p3, h3, c0, nv)
            w0 = nv
        start = n
        for i3 in range(roots):
            q3 = c0 if i3 == 0 else c1
            q2, _ = sp1(add(p2, mv(rot(h3, q3), p3)), v, h2)
            q4 = s4 * (q14 - q2 - s3 * q3)
            n = sixr.put_row(W, n, q1, q2, q3, q4, q5, q6, f3, cd3, w0, w1)
        if n3 == 1 and roots == 2:  # a merged root and its mirror: the better kept
            n = elbow_pair.keep_nearer(W, start, start + 1, n, q0, lower, upper)
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
    "three_parallel_general",
    70,
    "closed form for 6R arms with axes 2, 3, 4 parallel (SP6): up to 8 solutions",
)
