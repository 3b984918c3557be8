"""Closed-form IK of 6R arms with a spherical wrist (Pieper): the last three axes meet in
the wrist centre, so the first three joints place the wrist centre and the last three
turn the tool. Covers axes 2 and 3 parallel (the ortho-parallel industrial arms: ABB,
KUKA, Fanuc, Staubli, the Kinova j2s6s, with any offsets) and axes 1 and 2 meeting.

With the chain in product-of-exponentials form (``sixr.Chain6R``; the points on
axes 4, 5, 6 all at the wrist centre W), for the target (R, p):

    R_06 = R R_tip0^T,   W = p - R_06 p_6T,   p_16 = W - p_01
    axes 2, 3 parallel:  h2 . rot(h1, q1)^T p_16 = h2 . (p_12 + p_23 + p_34)  -> SP4: q1
                         |p_23 + rot(h3, q3) p_34| = |rot(h1, q1)^T p_16 - p_12| -> SP3: q3
                         rot(h2, q2) (p_23 + rot(h3, q3) p_34) = ...            -> SP1: q2
    axes 1, 2 meeting:   |p_23 + rot(h3, q3) p_34| = |p_16|                     -> SP3: q3
                         rot(h1, q1) rot(h2, q2) (p_23 + rot(h3, q3) p_34) = p_16 -> SP2
    wrist:               rot(h4, q4)^T R_36 h6 = rot(h5, q5) h6                -> SP2: q4, q5
                         rot(h6, q6) = (R_03 R_4 R_5)^T R_06                    -> SP1: q6

Up to 2 x 2 x 2 = 8 solutions. Singular cases keep the free angle at q0 (``singular``):
the wrist (axes 4 and 6 aligned: q4 free), the shoulder (wrist centre on axis 1: q1 free),
the elbow stretched or folded (the two elbow roots merge into one; where axes 1 and 2
meet and the span then lies along axis 2, q2 free).
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
from armik.solvers.closed_form.line_split import split_at
from armik.solvers.closed_form.sixr import LS, SHOULDER_OFFSET, SINGULAR, WRIST_ORIENTATION
from armik.solvers.closed_form.sixr_judged import GENERAL, UNLABELLED, judged, split
from armik.solvers.closed_form.subproblems import (
    add,
    cross,
    dot,
    elbow_extreme,
    mat,
    mm,
    mmt,
    mtm,
    mtv,
    mv,
    neg,
    norm,
    rot,
    scale,
    sp1,
    sp2,
    sp4,
    sub,
    vec,
)
from armik.tolerances import ANGLE_TOL, DISTANCE_TOL

CLOSED_FORM = "closed form (spherical wrist)"
# m: a stretched or folded elbow whose span lies this near axis 2, with joint 2 at q0's
# value placing the wrist centre this near the target's, leaves joint 2 free (axes 1 and 2
# meeting); that costs no more than this, where SP2 at two nearly tangent circles loses more
STRAIGHT = 1e-11
FAMILY = "spherical_wrist"
# joints 4 and 6 (0-based) for ``split_at``, typed: literals compiled it a second time
J4, J6 = np.int64(3), np.int64(5)


def classify(arm: ArmModel, ax: Axes | None = None) -> sixr.Chain6R | str:
    """The 6R spherical-wrist geometry of ``arm``, or the reason it is not one."""
    why = sixr.not_6r(arm)
    if why:
        return why
    return classify_axes(ax or axis_lines(arm))


def classify_axes(ax: Axes) -> sixr.Chain6R | str:
    """The spherical-wrist geometry of six revolute axis lines (``classify`` without
    the arm: for chains built from part of an arm), or the reason it is not one."""
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
    a23 = angle_between(H[1], H[2])
    a12 = angle_between(H[0], H[1])
    if a12 < ANGLE_TOL:
        return "axes 1 and 2 are parallel; the closed form needs them to cross"
    if a23 < ANGLE_TOL:
        text = f"spherical wrist at {np.round(w, 6).tolist()} m, axes 2 and 3 parallel"
        pts = [P[0], P[1], P[2], w, w, w]
        return sixr.chain_6r("spherical_wrist", "parallel_23", ax, pts, text)
    c12, d12 = meeting_point(P[:2], H[:2])
    if d12 <= DISTANCE_TOL:
        text = f"spherical wrist at {np.round(w, 6).tolist()} m, axes 1 and 2 meet"
        pts = [c12, c12, P[2], w, w, w]
        return sixr.chain_6r("spherical_wrist", "meeting_12", ax, pts, text)
    return (
        "the last three axes meet in a point, but axes 2 and 3 are not parallel (angle "
        f"{fmt(a23)} rad) and axes 1 and 2 do not meet (they miss by {fmt(d12)} m): "
        "no closed form here for that case"
    )


@njit(cache=True, no_cfunc_wrapper=True)
def _wrist(R03, R06, h4, h5, h6, q0, lower, upper, q1, q2, q3, flag, cd, v0, v1, W, n):
    """Append the (up to 2) wrist solutions for a placed wrist centre to the kernel's rows
    ``W`` (``sixr``'s layout); returns the count."""
    return _wrist_free(R03, R06, h4, h5, h6, q0, lower, upper, q1, q2, q3, flag, cd, v0, v1, W, n)[
        0
    ]


@njit(cache=True, no_cfunc_wrapper=True)
def _wrist_free(R03, R06, h4, h5, h6, q0, lower, upper, q1, q2, q3, flag, cd, v0, v1, W, n):
    """``_wrist``: (the count, whether q4 was free: axes 4 and 6 in line). A free q4 is at
    q0's value, or the value nearest it that keeps q6 within its limits."""
    R36 = mtm(R03, R06)
    a0, a1, b0, b1, nw, lsw = sp2(mv(R36, h6), h6, neg(h4), h5, q0[3])
    sing = False
    if nw == -1:
        nw, sing = 1, True
    for iw in range(nw):
        q4 = a0 if iw == 0 else a1
        q5 = b0 if iw == 0 else b1
        R45 = mm(rot(h4, q4), rot(h5, q5))
        q6, _ = sp1(h5, mv(mtm(R45, R36), h5), h6)
        if sing:  # only q4 + q6 (q4 - q6 with the axes opposed) turns the tool
            s = 1.0 if dot(h4, mv(R45, h6)) > 0.0 else -1.0
            t = split_at(q4, q6, s, q0[3], lower, upper, J4, J6)
            q4, q6 = t, q6 + s * (q4 - t)
        f = flag
        c = cd
        if lsw:
            f |= LS
            if c == 0:
                c = WRIST_ORIENTATION
        if sing:
            f |= SINGULAR
        n = sixr.put_row(W, n, q1, q2, q3, q4, q5, q6, f, c, v0, v1)
    return n, sing


@njit(cache=True, no_cfunc_wrapper=True)
def kernel(h, p, R_tip0, R, pos, q0, lower, upper, variant, labelled, out):
    """All closed-form solutions for the target rotation ``R`` (9-tuple, row-major) and
    position ``pos`` (3-tuple), packed nearest-first into ``out`` (8, 11), the first
    ``labelled`` with their branch; returns (n, first reached) (see ``sixr.pack``).

    A free joint (the wrist centre on axis 1: joint 1; axes 4 and 6 in line: joint 4; an
    elbow whose turn leaves the span unchanged: joint 3; axes 1 and 2 meeting, the elbow
    stretched or folded along axis 2: joint 2) is kept at q0's value; where that
    leaves no row reached within the limits, the joint's other values are tried, nearest
    q0's first (``sixr.FREE_SWEEP`` of them over a turn within its limits), and the first
    that gives one is kept."""
    n, first, free = _kernel(h, p, R_tip0, R, pos, q0, lower, upper, variant, labelled, out)
    if first or free == 0 or n == 0:
        return n, first
    j = 0 if free & 1 else (2 if free & 4 else (1 if free & 8 else 3))
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
    free, bit 2 joint 4, bit 4 joint 3, bit 8 joint 2)."""
    free = 0
    W = np.empty((8, 11))
    h1, h2, h3, h4 = vec(h[0]), vec(h[1]), vec(h[2]), vec(h[3])
    h5, h6 = vec(h[4]), vec(h[5])
    p0, p1, p2, p3, p6 = vec(p[0]), vec(p[1]), vec(p[2]), vec(p[3]), vec(p[6])
    R06 = mmt(R, mat(R_tip0))
    p16 = sub(sub(pos, mv(R06, p6)), p0)
    n = np.int64(0)  # not a literal 0: numba would compile the callees for it too
    if variant == 0:  # axes 2 and 3 parallel
        d = dot(h2, add(add(p1, p2), p3))
        a0, a1, n1, ls1 = sp4(h2, p16, neg(h1), d)
        flag1, cd1, v0, v1 = 0, 0, 0.0, 0.0
        if n1 == -1:  # wrist centre on axis 1
            n1, a0 = 1, q0[0]
            flag1 |= SINGULAR
            free |= 1
        if ls1:
            flag1 |= LS
            cd1 = SHOULDER_OFFSET
            v0 = norm(sub(p16, scale(h1, dot(h1, p16))))
            v1 = abs(d - dot(h2, h1) * dot(h1, p16))
        for i1 in range(n1):
            q1 = a0 if i1 == 0 else a1
            R1 = rot(h1, q1)
            v = sub(mtv(R1, p16), p1)
            nv = norm(v)
            c0, c1, n3, ls3, roots = elbow_pair.elbow_roots(p3, neg(p2), h3, nv, q0[2])
            flag3, cd3, w0, w1 = flag1, cd1, v0, v1
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
            start = mid = n
            for i3 in range(roots):
                q3 = c0 if i3 == 0 else c1
                mid = n if i3 == 1 else mid
                R3 = rot(h3, q3)
                u = add(p2, mv(R3, p3))
                q2, _ = sp1(u, v, h2)
                R03 = mm(mm(R1, rot(h2, q2)), R3)
                n, sing = _wrist_free(
                    R03, R06, h4, h5, h6, q0, lower, upper, q1, q2, q3, flag3, cd3, w0, w1,
                    W, n,
                )  # fmt: skip
                free |= 2 if sing else 0
            if n3 == 1 and roots == 2:  # a merged root and its mirror: the better kept
                n = elbow_pair.keep_nearer(W, start, mid, n, q0, lower, upper)
    else:  # axes 1 and 2 meet (p_12 = 0)
        n16 = norm(p16)
        c0, c1, n3, ls3, roots = elbow_pair.elbow_roots(p3, neg(p2), h3, n16, q0[2])
        flag3, cd3, w0, w1 = 0, 0, 0.0, 0.0
        if n3 == -1:
            flag3 |= SINGULAR
            free |= 4
        elif n3 == 1 and not ls3:
            flag3 |= SINGULAR  # stretched or folded
        single = n3 != 2
        if ls3:
            flag3 |= LS
            cd3, w1 = sixr.elbow_code(p2, p3, h3, c0, n16)
            w0 = n16
        start = mid = n
        for i3 in range(roots):
            q3 = c0 if i3 == 0 else c1
            mid = n if i3 == 1 else mid
            if single:  # stretched or folded: a span along axis 2 leaves joint 2 free
                e = elbow_extreme(p3, neg(p2), h3, q3)
                u = add(p2, mv(rot(h3, e), p3))
                q2 = q0[1]
                R2 = rot(h2, q2)
                q1, _ = sp1(mv(R2, u), p16, h1)
                R12 = mm(rot(h1, q1), R2)
                miss = norm(sub(mv(R12, u), p16))  # where q2 = q0's puts the wrist centre
                if norm(cross(h2, u)) <= STRAIGHT and miss <= STRAIGHT:
                    R03 = mm(R12, rot(h3, e))
                    n, sing = _wrist_free(
                        R03, R06, h4, h5, h6, q0, lower, upper, q1, q2, e, flag3 | SINGULAR,
                        cd3, w0, w1, W, n,
                    )  # fmt: skip
                    free |= 8 | (2 if sing else 0)
                    continue
            R3 = rot(h3, q3)
            u = add(p2, mv(R3, p3))
            a0, a1, b0, b1, n12, ls12 = sp2(p16, u, neg(h1), h2, q0[0])
            flag = flag3
            if n12 == -1:  # wrist centre on axis 1
                n12 = 1
                flag |= SINGULAR
                free |= 1
            if ls12 and not ls3:
                flag |= LS
            for i12 in range(n12):
                q1 = a0 if i12 == 0 else a1
                q2 = b0 if i12 == 0 else b1
                R03 = mm(mm(rot(h1, q1), rot(h2, q2)), R3)
                n, sing = _wrist_free(
                    R03, R06, h4, h5, h6, q0, lower, upper, q1, q2, q3, flag, cd3, w0, w1,
                    W, n,
                )  # fmt: skip
                free |= 2 if sing else 0
        if n3 == 1 and roots == 2:  # a merged root and its mirror: the better kept
            n = elbow_pair.keep_nearer(W, start, mid, n, q0, lower, upper)
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
    R, pos = mat(H), sixr.column(H)
    n, reached = kernel(h, p, R_tip0, R, pos, q0, lower, upper, variant, labelled, out)
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
        R, pos = mat(Rs[i]), vec(ps[i])
        kernel(h, p, R_tip0, R, pos, q0s[i], lower, upper, variant, unlabelled, out)
        for j in range(6):  # a loop: a slice copy compiles numba's shape-error path
            Q[i, j] = out[0, j]
        claim[i] = sixr.UNREACHABLE_CODE if int(out[0, 6]) & LS else sixr.CONVERGED_CODE
    return Q, claim


def _classify(arm: ArmModel):
    return classify(arm)


SPEC = Family(
    FAMILY, _classify, CLOSED_FORM, kernel, solve_into, kernel_many, solve_all_into=solve_all_into
).register("spherical", 90, "closed form for 6R arms with a spherical wrist: up to 8 solutions")
