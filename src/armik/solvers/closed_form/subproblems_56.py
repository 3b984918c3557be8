"""Subproblems 5 and 6 as IK-Geo (Elias and Wen) defines them: three circles, and four
circles in two angles. The conventions are ``subproblems``' (read it first): compiled with
numba, vectors as 3-tuples (or arrays of 3), ``rot(k, theta)`` the rotation by ``theta``
(rad) about the unit axis ``k``, every solution returned with its count ``n`` and a flag
``ls`` (True: no exact solution exists and the answer is a least-squares one). Lengths are
in any one unit (m in armik); tolerances are relative to the largest input length.

- SP5 ``sp5(p0, p1, p2, p3, k1, k2, k3) -> (t1, t2, t3, n, ls)``: angles with
  p0 + rot(k1, theta1) p1 = rot(k2, theta2) (p2 + rot(k3, theta3) p3), IK-Geo's ``sp_5``.
  Up to 4 solutions, solution i being ``(t1[i], t2[i], t3[i])`` (4-tuples; unused slots 0).
  The point v1 = p0 + rot(k1, theta1) p1 runs on a circle, v3 = p2 + rot(k3, theta3) p3 on
  another; rot(k2, theta2) v3 = v1 asks for the same height along k2 and the same length,
  two equations linear in (sin, cos) of theta1 and of theta3: SP6's form, solved as SP6
  is (a quartic), then theta2 by SP1. IK-Geo eliminates into a quartic in the height
  instead, which loses the roots when k1 or k3 is nearly parallel to k2 (its window of
  heights shrinks to nothing); this form has no such division.
  LS: the angles minimising |p0 + rot(k1, theta1) p1 - rot(k2, theta2) (p2 + ...)|.
- SP6 ``sp6(h, k, p, d1, d2) -> (t1, t2, n, ls)``: angles with
  h[0] . rot(k[0], theta1) p[0] + h[1] . rot(k[1], theta2) p[1] = d1 and
  h[2] . rot(k[2], theta1) p[2] + h[3] . rot(k[3], theta2) p[3] = d2, IK-Geo's ``sp_6``
  (``h``, ``k``, ``p``: four 3-vectors each, as rows; the ``h`` need not be unit). Up to 4
  solutions. The equations are linear in (sin, cos) of both angles; the better conditioned
  pair is eliminated and the other's unit circle meets an ellipse: a quartic in the tangent
  of a half angle, taken from a point where the curves are far apart so that no root goes
  to infinity. When both pairs are singular, one combination of the equations holds one
  angle only (SP4's form), and the other angle follows.
  LS: the angles minimising the sum of both equations' squared residuals.

``n = -1``: a continuum of solutions (an angle is free: p1 on k1, p3 on k3, every axis of
SP5 parallel, or SP6's equations dependent); one of them is returned, with ``ls`` telling
whether even it misses. Every root is refined by Newton steps on the defining equations
(damped Newton on the squared residual) and kept only if it then satisfies them to
``EXACT``; with none, the least-squares answer is the best of the local minima of a grid
over the two angles that matter, each refined the same way (the closest approximation
found; a search, not a proof). A solution that the roots missed (a tangency) is found by
that search and reported as exact.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.solvers.closed_form.roots import (
    grid_minima,
    keep_distinct,
    newton_step,
    trig1,
    trig2,
)
from armik.solvers.closed_form.subproblems import (
    add,
    cross,
    dot,
    mv,
    neg,
    norm,
    rot,
    scale,
    sp1,
    sub,
    vec,
)

EXACT = 1e-10  # a residual below this, relative to the largest length, is an exact solution
ROOT_GATE = 1e-4  # a root's residual (relative) below which Newton steps are tried on it
GRID = 32  # samples per angle of the least-squares search
STARTS = 6  # local minima of that grid refined
SINGULAR = 1e-10  # |det M| / |M|_F^2 below this: a 2 x 2 block M is taken as singular
# Typed numbers for the compiled callees: a literal (0, -1, 8, False) would compile each
# callee once more for its Literal type beside the int64 or bool it is called with elsewhere.
NONE, FREE, ONE = np.int64(0), np.int64(-1), np.int64(1)
FEW, MANY = np.int64(8), np.int64(60)  # Newton steps on a root, on a least-squares start
NOT_LS = np.bool_(False)


# -- shared pieces ----------------------------------------------------------------------------


@njit(cache=True, no_cfunc_wrapper=True)
def _circle(o, k, p):
    """v(theta) = o + rot(k, theta) p = c + sin(theta) a + cos(theta) b: (c, a, b)."""
    along = scale(k, dot(k, p))
    return add(o, along), cross(k, p), sub(p, along)


@njit(cache=True, no_cfunc_wrapper=True)
def _on(c, a, b, t):
    return add(c, add(scale(a, math.sin(t)), scale(b, math.cos(t))))


@njit(cache=True, no_cfunc_wrapper=True)
def _pairs(M, f, size, out):
    """Candidate angle pairs (ta, tb) of the two equations
    M[0] sa + M[1] ca + M[2] sb + M[3] cb = f[0] and M[4] sa + ... + M[7] cb = f[1]
    (sa = sin ta, ...), written into ``out``, unrefined. Returns (count, free): free when
    the solutions form a continuum (an angle absent, or the equations dependent)."""
    a0, b0, a1, b1, a2, b2, a3, b3 = M[0], M[1], M[2], M[3], M[4], M[5], M[6], M[7]
    n = 0
    det1, det2 = a0 * b2 - b0 * a2, a1 * b3 - b1 * a3
    small = (1e-12 * size) ** 2  # coefficients this small are rounding
    n1, n2 = a0 * a0 + b0 * b0 + a2 * a2 + b2 * b2, a1 * a1 + b1 * b1 + a3 * a3 + b3 * b3
    if n1 <= small or n2 <= small:
        return 0, True  # an angle appears in neither equation
    q1, q2 = abs(det1) / n1, abs(det2) / n2
    if max(q1, q2) >= SINGULAR:
        # Eliminate the better conditioned pair: y = g - B x, then |y| = 1 on x's circle,
        # a trigonometric polynomial of degree 2 in x's angle.
        if q2 >= q1:
            Ma, Mb, det = (a0, b0, a2, b2), (a1, b1, a3, b3), det2
        else:
            Ma, Mb, det = (a1, b1, a3, b3), (a0, b0, a2, b2), det1
        i00, i01, i10, i11 = Mb[3] / det, -Mb[1] / det, -Mb[2] / det, Mb[0] / det
        g0, g1 = i00 * f[0] + i01 * f[1], i10 * f[0] + i11 * f[1]
        B00, B01 = i00 * Ma[0] + i01 * Ma[2], i00 * Ma[1] + i01 * Ma[3]
        B10, B11 = i10 * Ma[0] + i11 * Ma[2], i10 * Ma[1] + i11 * Ma[3]
        S00, S01 = B00 * B00 + B10 * B10, B00 * B01 + B10 * B11
        S11 = B01 * B01 + B11 * B11
        A0 = g0 * g0 + g1 * g1 - 1.0 + 0.5 * (S00 + S11)
        A1, B1 = -2.0 * (B00 * g0 + B10 * g1), -2.0 * (B01 * g0 + B11 * g1)
        A2, B2 = S01, 0.5 * (S11 - S00)
        big = max(abs(A0), abs(A1), abs(B1), abs(A2), abs(B2))
        if big <= 1e-10 * (g0 * g0 + g1 * g1 + S00 + S11 + 1.0):
            return 0, True  # |g - B x| = 1 all round the circle: a continuum
        ts, m = trig2(A0, A1, B1, A2, B2)
        for i in range(m):
            sx, cx = math.sin(ts[i]), math.cos(ts[i])
            ty = math.atan2(g0 - B00 * sx - B01 * cx, g1 - B10 * sx - B11 * cx)
            out[i, 0], out[i, 1] = (ts[i], ty) if q2 >= q1 else (ty, ts[i])
        return m, False
    # Both pairs singular: w removes tb (w . Mb = 0, Mb's columns along v), leaving one
    # equation in ta, then v's row gives tb.
    if a1 * a1 + a3 * a3 >= b1 * b1 + b3 * b3:
        v0, v1 = a1, a3
    else:
        v0, v1 = b1, b3
    nv = math.hypot(v0, v1)
    v0, v1 = v0 / nv, v1 / nv
    w0, w1 = -v1, v0
    ra, rb = w0 * a0 + w1 * a2, w0 * b0 + w1 * b2
    if math.hypot(ra, rb) <= 1e-12 * size:
        return 0, True  # the equations are one: a continuum, or none
    u0, u1, m, ls = trig1(ra, rb, w0 * f[0] + w1 * f[1])
    for i in range(m if not ls else 0):
        ta = u0 if i == 0 else u1
        sa, ca = math.sin(ta), math.cos(ta)
        rest = v0 * (f[0] - a0 * sa - b0 * ca) + v1 * (f[1] - a2 * sa - b2 * ca)
        x0, x1, mb, lsb = trig1(v0 * a1 + v1 * a3, v0 * b1 + v1 * b3, rest)
        for j in range(mb if not lsb else 0):
            out[n, 0], out[n, 1] = ta, (x0 if j == 0 else x1)
            n += 1
    return n, False


# -- SP5 --------------------------------------------------------------------------------------


@njit(cache=True, no_cfunc_wrapper=True)
def _f5(q0, q1, q2, q3, e1, e2, e3, x):
    """|f|, the gradient and the Hessian (flat, row-major) of |f|^2 / 2 at the angles
    ``x``, for SP5's residual f = p0 + rot(k1, t1) p1 - rot(k2, t2) (p2 + rot(k3, t3) p3)."""
    R2 = rot(e2, x[1])
    u = mv(rot(e1, x[0]), q1)
    w3 = mv(rot(e3, x[2]), q3)
    w = mv(R2, add(q2, w3))
    f = sub(add(q0, u), w)
    js = (cross(e1, u), neg(cross(e2, w)), neg(mv(R2, cross(e3, w3))))
    # second derivatives of f: d11, d22, d33 and d23 (the others are zero)
    d11 = cross(e1, cross(e1, u))
    d22 = neg(cross(e2, cross(e2, w)))
    d33 = neg(mv(R2, cross(e3, cross(e3, w3))))
    d23 = cross(e2, js[2])
    g, H = np.empty(3), np.empty(9)
    for a in range(3):
        g[a] = dot(js[a], f)
        for b in range(3):
            H[3 * a + b] = dot(js[a], js[b])
    H[0] += dot(f, d11)
    H[4] += dot(f, d22)
    H[8] += dot(f, d33)
    H[5] += dot(f, d23)
    H[7] += dot(f, d23)
    return norm(f), g, H


@njit(cache=True, no_cfunc_wrapper=True)
def _refine5(q0, q1, q2, q3, e1, e2, e3, t, iters, floor):
    """Damped Newton steps on |f|^2 / 2 (SP5's residual) from the angles ``t`` (3 floats),
    a step taken only when it lowers |f|, none once |f| is below ``floor``. Returns (angles,
    |f|)."""
    x = np.array((t[0], t[1], t[2]))
    r, g, H = _f5(q0, q1, q2, q3, e1, e2, e3, x)
    mu = 0.0
    for _ in range(iters):
        if r <= floor:
            break
        step, ok = newton_step(H, g, np.int64(3), mu)
        if ok:
            y = x + step
            ry, gy, Hy = _f5(q0, q1, q2, q3, e1, e2, e3, y)
            if ry < r:
                x, r, g, H = y, ry, gy, Hy
                mu *= 0.1
                continue
        tr = abs(H[0]) + abs(H[4]) + abs(H[8]) + 1e-300
        mu = max(10.0 * mu, 1e-12 * tr)
        if mu > 1e12 * tr:
            break
    return x, r


@njit(cache=True, no_cfunc_wrapper=True)
def _profile(c, a, b, e2, t):
    """Height along k2 and distance from it of the circle point at angle t."""
    v = _on(c, a, b, t)
    h = dot(e2, v)
    return h, norm(sub(v, scale(e2, h)))


@njit(cache=True, no_cfunc_wrapper=True)
def _ls5(q0, q1, q2, q3, e1, e2, e3):
    """SP5's least-squares answer: rot(k2, t2) v3 is closest to v1 at distance
    sqrt((h1 - h3)^2 + (rho1 - rho3)^2) (heights along k2, distances from it), searched
    from the local minima of a grid over (t1, t3), t2 by SP1, each refined; the best.
    Returns (angles, |residual|)."""
    c1, a1, b1 = _circle(q0, e1, q1)
    c3, a3, b3 = _circle(q2, e3, q3)
    h1, r1, h3, r3 = np.empty(GRID), np.empty(GRID), np.empty(GRID), np.empty(GRID)
    for i in range(GRID):
        t = -math.pi + 2.0 * math.pi * i / GRID
        h1[i], r1[i] = _profile(c1, a1, b1, e2, t)
        h3[i], r3[i] = _profile(c3, a3, b3, e2, t)
    D = np.empty((GRID, GRID))
    for i in range(GRID):
        for j in range(GRID):
            D[i, j] = (h1[i] - h3[j]) ** 2 + (r1[i] - r3[j]) ** 2
    starts = np.zeros((STARTS, 2), np.int64)
    floor = 1e-16 * max(norm(q0), norm(q1), norm(q2), norm(q3))
    best, rbest = np.zeros(3), math.inf
    for s in range(grid_minima(D, starts)):
        t1 = -math.pi + 2.0 * math.pi * starts[s, 0] / GRID
        t3 = -math.pi + 2.0 * math.pi * starts[s, 1] / GRID
        t2, _ = sp1(_on(c3, a3, b3, t3), _on(c1, a1, b1, t1), e2)
        x, r = _refine5(q0, q1, q2, q3, e1, e2, e3, (t1, t2, t3), MANY, floor)
        if r < rbest:
            best, rbest = x, r
    return best, rbest


@njit(cache=True, no_cfunc_wrapper=True)
def _try5(q0, q1, q2, q3, e1, e2, e3, t1, t3, sol, res, n, size):
    """Complete (t1, t3) with t2 by SP1, refine, keep if exact; returns the count."""
    c1, a1, b1 = _circle(q0, e1, q1)
    c3, a3, b3 = _circle(q2, e3, q3)
    v1, v3 = _on(c1, a1, b1, t1), _on(c3, a3, b3, t3)
    t2, _ = sp1(v3, v1, e2)
    if norm(sub(v1, mv(rot(e2, t2), v3))) > ROOT_GATE * size:
        return n
    x, r = _refine5(q0, q1, q2, q3, e1, e2, e3, (t1, t2, t3), FEW, 1e-16 * size)
    if r <= EXACT * size:
        n = keep_distinct(sol, res, n, x, r)
    return n


@njit(cache=True, no_cfunc_wrapper=True)
def _pack5(sol, n, ls):
    t = np.zeros((4, 3))
    for i in range(abs(n)):
        for j in range(3):
            t[i, j] = sol[i, j]
    return (
        (t[0, 0], t[1, 0], t[2, 0], t[3, 0]),
        (t[0, 1], t[1, 1], t[2, 1], t[3, 1]),
        (t[0, 2], t[1, 2], t[2, 2], t[3, 2]),
        n,
        ls,
    )


@njit(cache=True, no_cfunc_wrapper=True)
def _system5(q0, q1, q2, q3, e1, e2, e3, size):
    """SP5's two equations in (sin, cos) of t1 and of t3 (``_pairs``' form): (M, f)."""
    c1, a1, b1 = _circle(q0, e1, q1)
    c3, a3, b3 = _circle(q2, e3, q3)
    # The same height along k2 (row 1) and the same |v| (row 2, over 2 size): linear in
    # (sin, cos) of t1 and of t3.
    M = np.array(
        (
            dot(e2, a1),
            dot(e2, b1),
            -dot(e2, a3),
            -dot(e2, b3),
            dot(c1, a1) / size,
            dot(c1, b1) / size,
            -dot(c3, a3) / size,
            -dot(c3, b3) / size,
        )
    )
    lengths = dot(c3, c3) + dot(a3, a3) - dot(c1, c1) - dot(a1, a1)
    f = np.array((dot(e2, c3) - dot(e2, c1), 0.5 * lengths / size))
    return M, f


@njit(cache=True, no_cfunc_wrapper=True)
def sp5(p0, p1, p2, p3, k1, k2, k3):
    """Angles with p0 + rot(k1, t1) p1 = rot(k2, t2) (p2 + rot(k3, t3) p3).

    Returns (t1, t2, t3, n, ls): 4-tuples of angles (rad), solution i being
    (t1[i], t2[i], t3[i]) for i < |n|; see the module docstring."""
    q0, q1, q2, q3 = vec(p0), vec(p1), vec(p2), vec(p3)
    e1, e2, e3 = vec(k1), vec(k2), vec(k3)
    size = max(norm(q0), norm(q1), norm(q2), norm(q3))
    sol = np.zeros((4, 3))
    res = np.full(4, math.inf)
    if size == 0.0:  # everything is zero: every angle solves it
        return _pack5(sol, FREE, NOT_LS)
    M, f = _system5(q0, q1, q2, q3, e1, e2, e3, size)
    pairs = np.zeros((8, 2))
    m, free = _pairs(M, f, size, pairs)
    n = NONE
    for i in range(m):
        n = _try5(q0, q1, q2, q3, e1, e2, e3, pairs[i, 0], pairs[i, 1], sol, res, n, size)
    if n > 0:
        return _pack5(sol, FREE if free else n, NOT_LS)
    x, r = _ls5(q0, q1, q2, q3, e1, e2, e3)
    keep_distinct(sol, res, NONE, x, r)
    return _pack5(sol, FREE if free else ONE, r > EXACT * size)


# -- SP6 --------------------------------------------------------------------------------------


@njit(cache=True, no_cfunc_wrapper=True)
def _term(h, k, p):
    """h . rot(k, theta) p = e + alpha sin(theta) + beta cos(theta): (e, alpha, beta)."""
    e = dot(h, k) * dot(k, p)
    return e, dot(h, cross(k, p)), dot(h, p) - e


@njit(cache=True, no_cfunc_wrapper=True)
def _f6(M, f, x):
    """|r|, the gradient and the Hessian (flat) of |r|^2 / 2 at the angles ``x`` for SP6's
    residuals r; ``M`` holds (alpha, beta) of the four terms, ``f`` the right-hand sides
    less the constants."""
    s1, c1, s2, c2 = math.sin(x[0]), math.cos(x[0]), math.sin(x[1]), math.cos(x[1])
    r1 = M[0] * s1 + M[1] * c1 + M[2] * s2 + M[3] * c2 - f[0]
    r2 = M[4] * s1 + M[5] * c1 + M[6] * s2 + M[7] * c2 - f[1]
    j0, j1 = M[0] * c1 - M[1] * s1, M[2] * c2 - M[3] * s2  # d r1 / d (t1, t2)
    j2, j3 = M[4] * c1 - M[5] * s1, M[6] * c2 - M[7] * s2  # d r2 / d (t1, t2)
    g = np.array((j0 * r1 + j2 * r2, j1 * r1 + j3 * r2))
    H = np.empty(4)
    H[0] = j0 * j0 + j2 * j2 - r1 * (M[0] * s1 + M[1] * c1) - r2 * (M[4] * s1 + M[5] * c1)
    H[1] = H[2] = j0 * j1 + j2 * j3
    H[3] = j1 * j1 + j3 * j3 - r1 * (M[2] * s2 + M[3] * c2) - r2 * (M[6] * s2 + M[7] * c2)
    return math.hypot(r1, r2), g, H


@njit(cache=True, no_cfunc_wrapper=True)
def _refine6(M, f, t1, t2, iters, floor):
    """Damped Newton steps on SP6's |r|^2 / 2 from (t1, t2), as ``_refine5``."""
    x = np.array((t1, t2))
    r, g, H = _f6(M, f, x)
    mu = 0.0
    for _ in range(iters):
        if r <= floor:
            break
        step, ok = newton_step(H, g, np.int64(2), mu)
        if ok:
            y = np.array((x[0] + step[0], x[1] + step[1]))
            ry, gy, Hy = _f6(M, f, y)
            if ry < r:
                x, r, g, H = y, ry, gy, Hy
                mu *= 0.1
                continue
        tr = abs(H[0]) + abs(H[3]) + 1e-300
        mu = max(10.0 * mu, 1e-12 * tr)
        if mu > 1e12 * tr:
            break
    return x, r


@njit(cache=True, no_cfunc_wrapper=True)
def _ls6(M, f, floor):
    """SP6's least-squares answer: the local minima of a grid over (t1, t2), refined; the
    best of them."""
    D = np.empty((GRID, GRID))
    for i in range(GRID):
        ta = -math.pi + 2.0 * math.pi * i / GRID
        sa, ca = math.sin(ta), math.cos(ta)
        for jj in range(GRID):
            tb = -math.pi + 2.0 * math.pi * jj / GRID
            sb, cb = math.sin(tb), math.cos(tb)
            r1 = M[0] * sa + M[1] * ca + M[2] * sb + M[3] * cb - f[0]
            r2 = M[4] * sa + M[5] * ca + M[6] * sb + M[7] * cb - f[1]
            D[i, jj] = r1 * r1 + r2 * r2
    starts = np.zeros((STARTS, 2), np.int64)
    best, rbest = np.zeros(2), math.inf
    for s in range(grid_minima(D, starts)):
        t1 = -math.pi + 2.0 * math.pi * starts[s, 0] / GRID
        t2 = -math.pi + 2.0 * math.pi * starts[s, 1] / GRID
        x, r = _refine6(M, f, t1, t2, MANY, floor)
        if r < rbest:
            best, rbest = x, r
    return best, rbest


@njit(cache=True, no_cfunc_wrapper=True)
def _try6(M, f, t1, t2, sol, res, n, size):
    r, _, _ = _f6(M, f, np.array((t1, t2)))
    if r > ROOT_GATE * size:
        return n
    x, r = _refine6(M, f, t1, t2, FEW, 1e-16 * size)
    if r <= EXACT * size:
        n = keep_distinct(sol, res, n, x, r)
    return n


@njit(cache=True, no_cfunc_wrapper=True)
def _pack6(sol, n, ls):
    t = np.zeros((4, 2))
    for i in range(abs(n)):
        t[i, 0], t[i, 1] = sol[i, 0], sol[i, 1]
    return (t[0, 0], t[1, 0], t[2, 0], t[3, 0]), (t[0, 1], t[1, 1], t[2, 1], t[3, 1]), n, ls


@njit(cache=True, no_cfunc_wrapper=True)
def _system6(h, k, p, d1, d2):
    """SP6's two equations in (sin, cos) of t1 and t2 (``_pairs``' form): (M, f, size)."""
    e0, a0, b0 = _term(vec(h[0]), vec(k[0]), vec(p[0]))
    e1, a1, b1 = _term(vec(h[1]), vec(k[1]), vec(p[1]))
    e2, a2, b2 = _term(vec(h[2]), vec(k[2]), vec(p[2]))
    e3, a3, b3 = _term(vec(h[3]), vec(k[3]), vec(p[3]))
    # M1 (sin t1, cos t1) + M2 (sin t2, cos t2) = f, M = (M1 row 1, M2 row 1, M1 row 2, ...)
    M = np.array((a0, b0, a1, b1, a2, b2, a3, b3))
    f = np.array((d1 - e0 - e1, d2 - e2 - e3))
    size = 0.0
    for i in range(4):
        size = max(size, norm(vec(h[i])) * norm(vec(p[i])))
    size = max(size, abs(d1), abs(d2))
    return M, f, size


@njit(cache=True, no_cfunc_wrapper=True)
def sp6(h, k, p, d1, d2):
    """Angles with h[0] . rot(k[0], t1) p[0] + h[1] . rot(k[1], t2) p[1] = d1 and
    h[2] . rot(k[2], t1) p[2] + h[3] . rot(k[3], t2) p[3] = d2.

    Returns (t1, t2, n, ls): 4-tuples of angles (rad), solution i being (t1[i], t2[i]) for
    i < |n|; see the module docstring."""
    M, f, size = _system6(h, k, p, d1, d2)
    sol = np.zeros((4, 2))
    res = np.full(4, math.inf)
    if size == 0.0:
        return _pack6(sol, FREE, NOT_LS)
    pairs = np.zeros((8, 2))
    m, free = _pairs(M, f, size, pairs)
    n = NONE
    for i in range(m):
        n = _try6(M, f, pairs[i, 0], pairs[i, 1], sol, res, n, size)
    if n > 0:
        return _pack6(sol, FREE if free else n, NOT_LS)
    x, r = _ls6(M, f, 1e-16 * size)
    keep_distinct(sol, res, NONE, x, r)
    return _pack6(sol, FREE if free else ONE, r > EXACT * size)
