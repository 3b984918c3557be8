"""Closed-form IK of 6R arms with axes 2, 3, 4 parallel and axes 5, 6 meeting: the
Universal Robots family (UR3/5/10/16, Unitree Z1, ...), by subproblem decomposition
(Hawkins' closed form and IK-Geo's reading of it).

With the chain in product-of-exponentials form (``sixr.Chain6R``; the points on axes
5 and 6 at their meeting point, so p_56 = 0), rot(h2, .) fixes h2 and so does the
combined turn R_234 = rot(h2, q2 + s3 q3 + s4 q4) of the three parallel joints:

    R_06 = R R_tip0^T,   p_16 = p - R_06 p_6T - p_01
    h2 . rot(h1, q1)^T p_16 = h2 . (p_12 + p_23 + p_34 + p_45)     -> SP4: q1 (shoulder)
    h2 . rot(h5, q5) h6 = h2 . rot(h1, q1)^T R_06 h6                -> SP4: q5 (wrist)
    rot(h6, q6) M^T h2 = rot(h5, q5)^T h2, M = rot(h1, q1)^T R_06   -> SP1: q6
    R_234 = M rot(h6, q6)^T rot(h5, q5)^T                           -> SP1: q2 + s3 q3 + s4 q4
    |p_23 + rot(h3, q3) p_34| = |rot(h1, q1)^T p_16 - p_12 - R_234 p_45|  -> SP3: q3 (elbow)
    rot(h2, q2) (p_23 + rot(h3, q3) p_34) = ...                     -> SP1: q2, then q4

Up to 2 x 2 x 2 = 8 solutions. Singular cases: the wrist (h6 along R_5^T h2: q6 free, kept
at q0 unless the wrist point, which q6 then turns about h2 with q2 + q3 + q4, is out of
the elbow's reach: then turned just far enough, ``reach_turn``), the elbow stretched or
folded (one elbow root).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.single import plain_pose, plain_seed
from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes, angle_between, axis_lines, fmt, meeting_point
from armik.solvers.closed_form import elbow_pair, sixr
from armik.solvers.closed_form.family import Family
from armik.solvers.closed_form.sixr import LS, ORIENTATION, SHOULDER_OFFSET, SINGULAR
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
    sp4,
    sub,
    vec,
    wrap,
)
from armik.tolerances import ANGLE_TOL, DISTANCE_TOL

CLOSED_FORM = "closed form (three parallel axes)"
HAIR = 1e-9  # of cos(theta - phi) in ``reach_turn``: ~1e-10 m inside the elbow's reach
FAMILY = "three_parallel"


def classify(arm: ArmModel, ax: Axes | None = None) -> sixr.Chain6R | str:
    """The geometry of a 6R arm with axes 2, 3, 4 parallel (the UR family), or the reason
    it is not one."""
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
    if angle_between(H[0], H[1]) < ANGLE_TOL:
        return "axis 1 is parallel to axes 2, 3, 4"
    if angle_between(H[4], H[1]) < ANGLE_TOL:
        return "axis 5 is parallel to axes 2, 3, 4"
    if angle_between(H[4], H[5]) < ANGLE_TOL:
        return "axes 5 and 6 are parallel"
    c56, d56 = meeting_point(P[4:], H[4:])
    if d56 > DISTANCE_TOL:
        return (
            f"axes 5 and 6 do not meet: they miss by {fmt(d56)} m (tolerance "
            f"{DISTANCE_TOL:g} m); the closed form needs them to"
        )
    text = f"axes 2, 3, 4 parallel along {np.round(H[1], 6).tolist()}, axes 5 and 6 meet"
    pts = [P[0], P[1], P[2], P[3], c56, c56]
    return sixr.chain_6r("three_parallel", "", ax, pts, text)


@njit(cache=True, no_cfunc_wrapper=True)
def elbow_span2(p2, p3, h3):
    """(min, max) of |p2 + rot(h3, q3) p3|^2 over q3: the squared distances the elbow spans."""
    a2, a3 = dot(p2, h3), dot(p3, h3)
    r2 = norm(sub(p2, scale(h3, a2)))
    r3 = norm(sub(p3, scale(h3, a3)))
    base = dot(p2, p2) + dot(p3, p3) + 2.0 * a2 * a3
    return base - 2.0 * r2 * r3, base + 2.0 * r2 * r3


@njit(cache=True, no_cfunc_wrapper=True)
def reach_turn(c, p4, h2, theta, span2):
    """At the wrist singularity: the turn t nearest 0 such that, with q2 + q3 + q4 =
    theta + t, the elbow reaches the wrist, |c - rot(h2, theta + t) p4|^2 within ``span2``
    (``elbow_span2``); 0 when theta already reaches or no turn does (then the elbow's
    least-squares answer tells).

    c . rot(h2, theta) p4 = (c . h2)(p4 . h2) + B cos(theta - phi), so the reach is an
    interval of cos(theta - phi); the nearest turn puts theta - phi on its edge, inside by
    a hair so that the elbow is solved exactly."""
    along = dot(p4, h2)
    u = sub(p4, scale(h2, along))
    w = cross(h2, u)
    cu, cw = dot(c, u), dot(c, w)
    B = math.sqrt(cu * cu + cw * cw)
    if B < 1e-12:
        return 0.0
    k = dot(c, c) + dot(p4, p4) - 2.0 * dot(c, h2) * along
    low = (k - span2[1]) / (2.0 * B)  # cos(theta - phi) at the longest reach
    high = (k - span2[0]) / (2.0 * B)  # ... at the shortest
    if low > high or low > 1.0 + HAIR or high < -1.0 - HAIR:
        return 0.0  # (a hair past +-1: the edge of the workspace, one turn reaches it)
    t = wrap(theta - math.atan2(cw, cu))
    ct = math.cos(t)
    if ct > high:  # too close: open the angle
        edge = math.acos(max(high - HAIR, -1.0))
    elif ct < low:  # too far: close it
        edge = math.acos(min(low + HAIR, 1.0))
    else:
        return 0.0
    return (edge if t >= 0.0 else -edge) - t


@njit(cache=True, no_cfunc_wrapper=True)
def kernel(h, p, R_tip0, R, pos, q0, lower, upper, variant, labelled, out):
    """All closed-form solutions for the target rotation ``R`` (9-tuple, row-major) and
    position ``pos`` (3-tuple), packed nearest-first into ``out`` (8, 11), the first
    ``labelled`` with their branch; returns (n, first reached) (see ``sixr.pack``).
    ``variant`` is unused: the arguments every family's kernel takes (``family``).

    A free joint (the wrist point on axis 1: joint 1; the wrist singular: joint 6; an elbow
    whose turn leaves the span unchanged: joint 3) is kept at q0's value; where that leaves
    no row reached within the limits, the joint's other values are tried, nearest q0's first
    (``sixr.FREE_SWEEP`` over a turn within its limits), and the first that gives one is
    kept."""
    n, first, free = _kernel(h, p, R_tip0, R, pos, q0, lower, upper, variant, labelled, out)
    if first or free == 0 or n == 0:
        return n, first
    j = 0 if free & 1 else (2 if free & 4 else 5)
    lo, hi = max(lower[j], q0[j] - math.pi), min(upper[j], q0[j] + math.pi)
    step = 2.0 * math.pi / sixr.FREE_SWEEP
    seed = q0.copy()
    rows = np.empty_like(out)
    for k in range(1, sixr.FREE_SWEEP + 1):
        value = q0[j] + (step * ((k + 1) // 2) if k % 2 else -step * (k // 2))
        if not lo <= value <= hi:
            continue
        seed[j] = value
        m, ok, _ = _kernel(h, p, R_tip0, R, pos, seed, lower, upper, variant, labelled, rows)
        if ok:
            for r in range(m):
                for c in range(out.shape[1]):
                    out[r, c] = rows[r, c]
            return m, True
    return n, first


@njit(cache=True, no_cfunc_wrapper=True)
def _kernel(h, p, R_tip0, R, pos, q0, lower, upper, variant, labelled, out):
    """``kernel`` with each free joint at q0's value: (n, first reached, free: bit 1 joint 1
    free, bit 2 joint 6, bit 4 joint 3)."""
    free = 0
    W = np.empty((8, 11))
    h1, h2, h3, h4 = vec(h[0]), vec(h[1]), vec(h[2]), vec(h[3])
    h5, h6 = vec(h[4]), vec(h[5])
    p0, p1, p2, p3, p4, p6 = vec(p[0]), vec(p[1]), vec(p[2]), vec(p[3]), vec(p[4]), vec(p[6])
    s3, s4 = dot(h3, h2), dot(h4, h2)
    span2 = elbow_span2(p2, p3, h3)
    x = cross(h2, h1)
    x = scale(x, 1.0 / norm(x))  # a direction across the parallel axes
    R06 = mmt(R, mat(R_tip0))
    p16 = sub(sub(pos, mv(R06, p6)), p0)
    d1 = dot(h2, add(add(p1, p2), add(p3, p4)))
    a0, a1, n1, ls1 = sp4(h2, p16, neg(h1), d1)
    flag1, cd1, v0, v1 = 0, 0, 0.0, 0.0
    if n1 == -1:
        n1, a0 = 1, q0[0]
        flag1 |= SINGULAR
        free |= 1
    if ls1:
        flag1 |= LS
        cd1 = SHOULDER_OFFSET
        v0 = norm(sub(p16, scale(h1, dot(h1, p16))))
        v1 = abs(d1 - dot(h2, h1) * dot(h1, p16))
    n = np.int64(0)  # not a literal 0: numba would compile the callees for it too
    for i1 in range(n1):
        q1 = a0 if i1 == 0 else a1
        R1 = rot(h1, q1)
        M = mtm(R1, R06)
        b0, b1, n5, ls5 = sp4(h2, h6, h5, dot(h2, mv(M, h6)))
        flag5, cd5 = flag1, cd1
        if n5 == -1:
            n5, b0 = 1, q0[4]
            flag5 |= SINGULAR
        if ls5:
            flag5 |= LS
            if cd5 == 0:
                cd5 = ORIENTATION
        for i5 in range(n5):
            q5 = b0 if i5 == 0 else b1
            R5 = rot(h5, q5)
            a = mtv(M, h2)
            b = mtv(R5, h2)
            flag6 = flag5
            if norm(cross(a, h6)) < SINGLE or norm(cross(b, h6)) < SINGLE:
                # wrist singular: q6 and q2 + q3 + q4 trade off; q6 stays at q0 unless the
                # wrist point is then out of the elbow's reach
                q6 = q0[5]
                flag6 |= SINGULAR
                free |= 2
                R234 = mmt(mmt(M, rot(h6, q6)), R5)
                q234, _ = sp1(x, mv(R234, x), h2)
                turn = reach_turn(sub(mtv(R1, p16), p1), p4, h2, q234, span2)
                # turning q6 by t turns q2 + q3 + q4 by -t about M h6 = +-h2
                q6 -= turn if dot(mv(M, h6), h2) > 0.0 else -turn
            else:
                q6, _ = sp1(a, b, h6)
            R234 = mmt(mmt(M, rot(h6, q6)), R5)
            q234, _ = sp1(x, mv(R234, x), h2)
            v = sub(sub(mtv(R1, p16), p1), mv(R234, p4))
            nv = norm(v)
            c0, c1, n3, ls3, roots = elbow_pair.elbow_roots(p3, neg(p2), h3, nv, q0[2])
            flag3, cd3, w0, w1 = flag6, cd5, v0, v1
            if n3 == -1:
                flag3 |= SINGULAR
                free |= 4
            elif n3 == 1 and not ls3:
                flag3 |= SINGULAR  # stretched or folded
            if ls3:
                flag3 |= LS
                if cd3 == 0:
                    cd3, w1 = sixr.elbow_code(p2, p3, h3, c0, nv)
                    w0 = nv
            start = n
            for i3 in range(roots):
                q3 = c0 if i3 == 0 else c1
                u = add(p2, mv(rot(h3, q3), p3))
                q2, _ = sp1(u, v, h2)
                q4 = s4 * (q234 - q2 - s3 * q3)
                n = sixr.put_row(W, n, q1, q2, q3, q4, q5, q6, flag3, cd3, w0, w1)
            if n3 == 1 and roots == 2:  # a merged root and its mirror: the better kept
                n = elbow_pair.keep_nearer(W, start, start + 1, n, q0, lower, upper)
    sixr.nearest_equivalents(W, n, q0, lower, upper)
    return n, sixr.pack(W, n, q0, lower, upper, h, p, labelled, out), free


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
    "three_parallel", 90, "closed form for 6R arms with axes 2, 3, 4 parallel (UR family): up to 8"
)
