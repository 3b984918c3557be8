"""Closed-form IK of 6R arms with a spherical shoulder (Pieper's other case): the first three
axes meet in one point, so the chain read from the tip back to the base is a spherical
wrist (``spherical_wrist``). The Franka Panda or the KUKA iiwa with joint 7 locked
(``armik.load("panda", locked={"panda_joint7": v})``) are such arms.

Read from the tip, joints 6, 5, ..., 1 form a 6R chain (joint j becomes joint 7 - j, its
axis negated, its angle the same) that reaches T^-1 from the tip frame at q = 0; with the
chain in product-of-exponentials form (``sixr.Chain6R``: h, p, R_tip0) the reversed chain
is h'_k = -R_tip0^T h_(6-k), p'_i = -R_tip0^T p_(6-i), R'_tip0 = R_tip0^T, so the arm's own
chain (its points on axes 1 to 3 at the shoulder centre) is kept and reversed in the
kernel. When the reversed chain is in ``spherical_wrist``'s class (axes 5 and 4 parallel,
or axes 6 and 5 meeting), that family's kernel gives every branch exactly: up to 8
solutions, the same as ``swept_7r`` gives a 7R arm with joint 7 held at the locked value.

Branch labels are read from the arm's own chain (``sixr.branch_bits``): with the shoulder
centre on axes 1 to 3, the shoulder and wrist bits tell branches apart, the elbow bit (a
bend about axis 3) does not.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from armik.kernel.single import plain_pose, plain_seed
from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes, angle_between, axis_lines, fmt, meeting_point
from armik.solvers.closed_form import sixr
from armik.solvers.closed_form import spherical_wrist as spherical
from armik.solvers.closed_form.family import Family
from armik.solvers.closed_form.sixr import LS
from armik.solvers.closed_form.sixr_judged import GENERAL, UNLABELLED, judged, split
from armik.solvers.closed_form.subproblems import mat, mtv, neg, vec
from armik.tolerances import ANGLE_TOL, DISTANCE_TOL

CLOSED_FORM = "closed form (spherical shoulder: joints 6 to 1 as a spherical wrist)"
FAMILY = "spherical_shoulder"
FAR = 10.0  # of the arm's size: axes 6 and 5 meeting further away are refused (``_far_meeting``)


def classify(arm: ArmModel, ax: Axes | None = None) -> sixr.Chain6R | str:
    """The 6R spherical-shoulder geometry of ``arm`` (its own chain, joint 1 first), or the
    reason it is not one."""
    why = sixr.not_6r(arm)
    if why:
        return why
    return classify_axes(ax or axis_lines(arm))


def reversed_axes(ax: Axes) -> Axes:
    """Six axis lines read from the tip: joint j becomes joint 7 - j, in the tip frame at
    q = 0, its axis negated; the tip is the base frame."""
    Rt = ax.tip_rotation.T
    t = ax.tip_position
    order = (5, 4, 3, 2, 1, 0)
    return Axes(
        np.array([Rt @ (ax.points[j] - t) for j in order]),
        np.array([-(Rt @ ax.directions[j]) for j in order]),
        np.ones(6, dtype=bool),
        -(Rt @ t),
        Rt.copy(),
    )


def reversed_chain(geo: sixr.Chain6R) -> sixr.Chain6R:
    """The chain ``geo`` read from the tip (see the module): h'_k = -R_tip0^T h_(6-k),
    p'_i = -R_tip0^T p_(6-i), R'_tip0 = R_tip0^T. Its own inverse."""
    Rt = np.ascontiguousarray(geo.R_tip0.T)
    h = np.ascontiguousarray(-(geo.h[::-1] @ Rt.T))
    p = np.ascontiguousarray(-(geo.p[::-1] @ Rt.T))
    return sixr.Chain6R(geo.kind, geo.variant, h, p, Rt, geo.description)


def _far_meeting(ax: Axes, shoulder: np.ndarray) -> str:
    """Why axes 6 and 5 meet too far away for the closed form, or "". Nearly parallel, they
    meet ``FAR`` times the arm's size away or more, and the rows lose digits with the cube of
    that distance (the Panda with joint 6 held at 1e-3 rad: 88 m, rows 3e-7 m off)."""
    c, _ = meeting_point(ax.points[4:], ax.directions[4:])
    span = max(float(np.linalg.norm(x - shoulder)) for x in (*ax.points, ax.tip_position))
    away = float(np.linalg.norm(c - shoulder))
    if away <= FAR * max(span, DISTANCE_TOL):
        return ""
    return (
        f"axes 6 and 5 meet {fmt(away)} m from the shoulder, more than {FAR:g} times the "
        f"arm's size ({fmt(span)} m): nearly parallel, the closed form would lose digits there"
    )


def classify_axes(ax: Axes) -> sixr.Chain6R | str:
    """The spherical-shoulder geometry of six revolute axis lines, or why not."""
    P, H = ax.points, ax.directions
    for i, j in ((0, 1), (1, 2)):
        if angle_between(H[i], H[j]) < ANGLE_TOL:
            return (
                f"axes {i + 1} and {j + 1} are parallel, so the first three do not form a "
                "spherical shoulder"
            )
    s, miss = meeting_point(P[:3], H[:3])
    if miss > DISTANCE_TOL:
        return (
            f"the first three axes do not meet in one point: they miss by {fmt(miss)} m "
            f"(tolerance {DISTANCE_TOL:g} m)"
        )
    back = spherical.classify_axes(reversed_axes(ax))
    if isinstance(back, str):
        return (
            f"a spherical shoulder at {np.round(s, 6).tolist()} m, but joints 6 to 1 read "
            f"from the tip (axis 1 there is joint 6) are not a spherical wrist: {back}"
        )
    if back.variant == "meeting_12":
        far = _far_meeting(ax, s)
        if far:
            return far
    way = "axes 5 and 4 parallel" if back.variant == "parallel_23" else "axes 6 and 5 meet"
    text = f"spherical shoulder at {np.round(s, 6).tolist()} m, {way}"
    mine = reversed_chain(back)
    return sixr.Chain6R(FAMILY, back.variant, mine.h, mine.p, mine.R_tip0, text)


@njit(cache=True, no_cfunc_wrapper=True)
def kernel(h, p, R_tip0, R, pos, q0, lower, upper, variant, labelled, out):
    """All closed-form solutions for the target rotation ``R`` (9-tuple, row-major) and
    position ``pos`` (3-tuple), packed nearest-first into ``out`` (8, 11), the first
    ``labelled`` with their branch; returns (n, first reached) (see ``sixr.pack``). ``h``,
    ``p``, ``R_tip0``, ``q0``, ``lower``, ``upper``: the arm's, joint 1 first; the
    spherical-wrist kernel solves the chain read from the tip for T^-1."""
    Rr = np.empty((3, 3))
    for a in range(3):
        for b in range(3):
            Rr[a, b] = R_tip0[b, a]
    hr = np.empty((6, 3))
    pr = np.empty((7, 3))
    for k in range(6):
        for a in range(3):
            hr[k, a] = -(Rr[a, 0] * h[5 - k, 0] + Rr[a, 1] * h[5 - k, 1] + Rr[a, 2] * h[5 - k, 2])
    for k in range(7):
        for a in range(3):
            pr[k, a] = -(Rr[a, 0] * p[6 - k, 0] + Rr[a, 1] * p[6 - k, 1] + Rr[a, 2] * p[6 - k, 2])
    R_inv = (R[0], R[3], R[6], R[1], R[4], R[7], R[2], R[5], R[8])
    p_inv = neg(mtv(R, pos))
    q0r, lor, hir = np.empty(6), np.empty(6), np.empty(6)
    for j in range(6):
        q0r[j], lor[j], hir[j] = q0[5 - j], lower[5 - j], upper[5 - j]
    W = np.empty((8, 11))
    n, first = spherical.kernel(
        hr, pr, Rr, R_inv, p_inv, q0r, lor, hir, variant, np.int64(0), W
    )  # nearest q0r first: the same order as nearest q0 (a distance over the same joints)
    for r in range(n):
        for j in range(6):
            out[r, j] = W[r, 5 - j]  # joints 1 to 6 again
        for c in range(6, 11):
            out[r, c] = W[r, c]
        out[r, 7] = 0.0
    for k in range(min(n, labelled)):
        out[k, 7] = sixr.branch_bits(h, p, out[k, :6])
    return n, first


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
    FAMILY,
    68,
    "closed form for 6R arms with a spherical shoulder (axes 1 to 3 meeting), read from the "
    "tip as a spherical wrist: up to 8 solutions",
)
