"""The error of a pose target with a region around it (TRAC-IK's bounds), for the step.

The twist of the tip relative to the target, in the target frame, ``E = (R_t^T (p - p_t),
log3(R_t^T R))``, is shrunk towards zero by each component's bound (``inf`` frees it): the
residual ``r`` is zero inside the box and grows outside it. The step solves ``A dq = e``
with ``e = -w r`` and ``A = w dE/dq`` on the rows outside the box (``w``: the weights),
``dE/dq = (R_t^T R J_v, Jlog3(R_t^T R) J_w)`` from the LOCAL Jacobian. ``val`` holds the
distance from the box (position m, orientation rad) and ``|e|^2``, as ``error._evaluate``
does for an exact target. ``armik.problem.Pose`` is the same task in Python: the tests hold
the two equal.

With a cone (``cone >= 0``), the rotation rows are instead those of ``armik.Axis``: the tip
axis ``a`` (tip frame) within ``cone`` rad of the target's image of it, ``w = R^T R_t a``
in the tip frame; the residual is ``(a x w) (theta - cone) / |a x w|`` outside the cone
(``armik.problem.tasks.cone``, the same floats up to rounding), zero inside. With ``look``
(``LOOK_POINT``) the cone's direction is the line from the tip to the point ``x``
(``armik.LookAt``): ``w = R^T (x - p) / |x - p|``, which moves with the tip's position too
(``_look_rows``); with ``LOOK_TOWARD``, the base-frame direction ``x`` (an ``armik.Axis``
whose position rows are a box in the base frame: the target's rotation the identity).
"""

from __future__ import annotations

import math

from numba import njit

from armik.kernel.error import to_target
from armik.kernel.fk import forward, jacobian_local
from armik.kernel.problem import LOOK_TOWARD, NO_LOOK
from armik.kernel.se3 import jlog3, log3
from armik.tolerances import SIGHT


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def _evaluate_region(ch, bounds, w, cone, a, look, x, R_t, p_t, ws, slot):
    """ws.e[slot], ws.A[slot] and ws.val[slot] at ws.q[slot] for the target (R_t, p_t)
    within ``bounds`` (6,), weighted by ``w`` (6,); with ``cone >= 0`` the tip axis ``a``
    (3,) within that cone instead of the rotation bounds, around the target's image of it
    or, with ``look``, around the line from the tip to the point ``x`` (3,)
    (``LOOK_POINT``) or the direction ``x`` (``LOOK_TOWARD``)."""
    forward(ch, ws.q[slot], ws.m3[0], ws.v3[0], ws.geo[0], ws.geo[1])
    jacobian_local(ch, ws.m3[0], ws.v3[0], ws.geo[0], ws.geo[1], ws.J)
    # the rows called, not inlined: one compiled copy of them for the descent, the task
    # solver and the servo alike
    rows_at(bounds, w, cone, a, look, x, R_t, p_t, ws, slot)


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def rows_at(bounds, w, cone, a, look, x, R_t, p_t, ws, slot):
    """``_evaluate_region``'s rows for a placement already in ws.m3[0], ws.v3[0] with its
    LOCAL Jacobian in ws.J (a frame's pose in another's, ``task_rows``)."""
    to_target(ws.m3[0], ws.v3[0], R_t, p_t, ws.m3[1], ws.v3[1])
    _rows(bounds, w, cone, a, look, x, ws, slot)


# Called from ``rows_at`` rather than inlined there: copying a callee this size into its
# caller cost more compile time than compiling it once.
@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def _rows(bounds, w, cone, a, look, x, ws, slot):
    """ws.e[slot], ws.A[slot], ws.val[slot] from the placement (ws.m3[0], ws.v3[0]), its
    LOCAL Jacobian ws.J and the target seen from it (ws.m3[1], ws.v3[1])."""
    J = ws.J
    M, t, v = ws.m3[1], ws.v3[1], ws.v3[2]
    e, A, Jl = ws.e[slot], ws.A[slot], ws.Jlog
    for i in range(3):
        e[i] = -(M[0, i] * t[0] + M[1, i] * t[1] + M[2, i] * t[2])  # R_t^T (p - p_t)
    n = J.shape[1]
    pos2 = rot2 = sq = 0.0
    if cone >= 0.0 and look != NO_LOOK:
        h = _look_rows(ws.m3[0], ws.v3[0], x, look == LOOK_TOWARD, J, a, cone, e, A, n)
        rot2 = h * h
        sq = e[3] * e[3] + e[4] * e[4] + e[5] * e[5]
    elif cone >= 0.0:  # the cone's rows: no log3 of the rotation, no Jlog3
        h = _cone_rows(M, J, a, cone, e, A, n)
        rot2 = h * h
        sq = e[3] * e[3] + e[4] * e[4] + e[5] * e[5]
    else:
        theta = log3(M, v)
        for i in range(3):
            v[i] = -v[i]  # log3(M^T) = -log3(M)
            e[3 + i] = v[i]
        jlog3(theta, v, Jl)  # of M^T, into Jl's upper-left block
    for k in range(3 if cone >= 0.0 else 6):
        b = bounds[k]
        E = e[k]
        if not abs(E) > b:  # inside (or free): no residual, no derivative
            e[k] = 0.0
            for c in range(n):
                A[k, c] = 0.0
            continue
        r = E - math.copysign(b, E)
        if w[k] > 0.0:
            if k < 3:
                pos2 += r * r
            else:
                rot2 += r * r
        e[k] = -w[k] * r
        sq += e[k] * e[k]
        for c in range(n):
            if k < 3:
                d = M[0, k] * J[0, c] + M[1, k] * J[1, c] + M[2, k] * J[2, c]
            else:
                i = k - 3
                d = Jl[i, 0] * J[3, c] + Jl[i, 1] * J[4, c] + Jl[i, 2] * J[5, c]
            A[k, c] = w[k] * d
    val = ws.val[slot]
    val[0], val[1], val[2] = math.sqrt(pos2), math.sqrt(rot2), sq


@njit(cache=True, nogil=True, inline="always")
def _beyond(a, w0, w1, w2, cone):
    """(c = a x w, s = |c|, k = a . w, the angle of a from w beyond ``cone``)."""
    c0, c1, c2 = a[1] * w2 - a[2] * w1, a[2] * w0 - a[0] * w2, a[0] * w1 - a[1] * w0
    s = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
    k = a[0] * w0 + a[1] * w1 + a[2] * w2
    return c0, c1, c2, s, k, math.atan2(s, k) - cone


@njit(cache=True, nogil=True, inline="always")
def _inside(e, A, n):
    """Rows 3-5 of e and A zero (the axis within its cone); the angle beyond it, 0."""
    for i in range(3, 6):
        e[i] = 0.0
        for col in range(n):
            A[i, col] = 0.0
    return 0.0


@njit(cache=True, nogil=True, inline="always")
def _cone_rows(M, J, a, cone, e, A, n):
    """Rows 3-5 of e and A for the axis ``a`` within ``cone`` of ``w = M a`` (M = R^T R_t);
    returns the angle beyond the cone. With ``c = a x w``, ``s = |c|``, ``k = a . w`` and
    J's angular rows ``j``: dw = w x j, so ds = -k (c . j) / s and dtheta = -(c . j) / s."""
    w0 = M[0, 0] * a[0] + M[0, 1] * a[1] + M[0, 2] * a[2]
    w1 = M[1, 0] * a[0] + M[1, 1] * a[1] + M[1, 2] * a[2]
    w2 = M[2, 0] * a[0] + M[2, 1] * a[1] + M[2, 2] * a[2]
    c0, c1, c2, s, k, h = _beyond(a, w0, w1, w2, cone)
    if h <= 0.0:
        return _inside(e, A, n)
    if s < _SMALL:  # the axis (anti)parallel to w: at the axis (cone 0) r = a x w itself
        f = 1.0 if k > 0.0 else 0.0  # opposite: no useful derivative (a restart's to leave)
        e[3], e[4], e[5] = -c0, -c1, -c2
        for col in range(n):
            j0, j1, j2 = J[3, col], J[4, col], J[5, col]
            aj = a[0] * j0 + a[1] * j1 + a[2] * j2
            A[3, col] = f * (w0 * aj - k * j0)
            A[4, col] = f * (w1 * aj - k * j1)
            A[5, col] = f * (w2 * aj - k * j2)
        return h
    f = h / s
    e[3], e[4], e[5] = -c0 * f, -c1 * f, -c2 * f
    for col in range(n):
        j0, j1, j2 = J[3, col], J[4, col], J[5, col]
        aj = a[0] * j0 + a[1] * j1 + a[2] * j2
        cj = c0 * j0 + c1 * j1 + c2 * j2
        ds = -k * cj / s
        df = (-cj - h * ds) / (s * s)  # (dtheta s - h ds) / s^2
        A[3, col] = (w0 * aj - k * j0) * f + c0 * df  # d(a x w) = w (a . j) - k j
        A[4, col] = (w1 * aj - k * j1) * f + c1 * df
        A[5, col] = (w2 * aj - k * j2) * f + c2 * df
    return h


_SMALL = 1e-12  # |a x w| below this: a and w (anti)parallel, as ``tasks.cone`` reads it


@njit(cache=True, nogil=True, inline="always")
def _look_rows(R, p, x, toward, J, a, cone, e, A, n):
    """``_cone_rows`` around the line of sight: ``w = R^T (x - p) / L``, ``L = |x - p|``,
    whose derivative has the position's part too: ``dw = w x j - (v - w (w . v)) / L``
    (``j``, ``v``: J's angular and linear rows); with ``toward``, around the unit direction
    ``x``: ``w = R^T x``, no position's part (L infinite in dw). With ``c = a x w``,
    ``s = |c|``, ``k = a . w``: ``dc = a x dw``, ``ds = c . dc / s``,
    ``dtheta = k ds - s (a . dw)``. No rows where the tip is at the point (within
    ``SIGHT``), and the angle there is pi, as the verdict measures it: no axis looks at a
    point from itself."""
    if toward:
        d0, d1, d2, L, far = x[0], x[1], x[2], 1.0, math.inf
    else:
        d0, d1, d2 = x[0] - p[0], x[1] - p[1], x[2] - p[2]
        L = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        far = L
    h = w0 = w1 = w2 = c0 = c1 = c2 = s = k = 0.0
    if L > SIGHT:
        w0 = (R[0, 0] * d0 + R[1, 0] * d1 + R[2, 0] * d2) / L
        w1 = (R[0, 1] * d0 + R[1, 1] * d1 + R[2, 1] * d2) / L
        w2 = (R[0, 2] * d0 + R[1, 2] * d1 + R[2, 2] * d2) / L
        c0, c1, c2, s, k, h = _beyond(a, w0, w1, w2, cone)
    if h <= 0.0:
        _inside(e, A, n)
        # on the point: no line of sight, no axis aimed (the verdict's pi), no rows to leave
        return math.pi if L <= SIGHT else 0.0
    near = s < _SMALL  # (anti)parallel: at the axis r = a x w itself, as ``_cone_rows``
    f = (1.0 if k > 0.0 else 0.0) if near else h / s
    e[3], e[4], e[5] = -c0 * f, -c1 * f, -c2 * f
    for col in range(n):
        v0, v1, v2 = J[0, col], J[1, col], J[2, col]
        j0, j1, j2 = J[3, col], J[4, col], J[5, col]
        wv = w0 * v0 + w1 * v1 + w2 * v2
        dw0 = w1 * j2 - w2 * j1 - (v0 - w0 * wv) / far
        dw1 = w2 * j0 - w0 * j2 - (v1 - w1 * wv) / far
        dw2 = w0 * j1 - w1 * j0 - (v2 - w2 * wv) / far
        dc0 = a[1] * dw2 - a[2] * dw1
        dc1 = a[2] * dw0 - a[0] * dw2
        dc2 = a[0] * dw1 - a[1] * dw0
        if near:
            A[3, col], A[4, col], A[5, col] = f * dc0, f * dc1, f * dc2
            continue
        ds = (c0 * dc0 + c1 * dc1 + c2 * dc2) / s
        dtheta = k * ds - s * (a[0] * dw0 + a[1] * dw1 + a[2] * dw2)
        df = (dtheta * s - h * ds) / (s * s)
        A[3, col] = dc0 * f + c0 * df
        A[4, col] = dc1 * f + c1 * df
        A[5, col] = dc2 * f + c2 * df
    return h


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def evaluate_region(ch, bounds, w, cone, a, look, x, R_t, p_t, ws, slot):
    """``_evaluate_region`` for Python callers (the tests)."""
    _evaluate_region(ch, bounds, w, cone, a, look, x, R_t, p_t, ws, slot)
