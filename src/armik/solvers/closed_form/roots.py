"""Real roots of polynomials up to degree 4 and of trigonometric polynomials up to degree
2, for the subproblems SP5 and SP6 (``subproblems_56``).

Compiled with numba (``@njit(cache=True)``), plain callables from Python too. Coefficients
are given highest power first (``a x^4 + b x^3 + c x^2 + d x + e``, as ``numpy.roots``).

The roots are found by the derivative's: between two consecutive real critical points (and
beyond the outermost ones, up to Cauchy's bound) a polynomial is monotone, so each interval
holds at most one root, bracketed by a sign change and found by Newton's method safeguarded
by bisection, to full precision. A critical point where the polynomial is within
``TOUCH`` of zero (relative to the size of its terms there) is a double root, reported
once: a tangency that rounding lifts off the axis is not lost. No complex arithmetic, no
companion matrix; every root returned is real and polished.

``quartic(a, b, c, d, e) -> (r0, r1, r2, r3, n)``: the ``n`` distinct real roots in
ascending order (unused slots 0.0); ``n = -1`` when every coefficient is 0 (every x is a
root). A leading coefficient below ``LEAD`` times the largest makes it a cubic, and so on
down: its root at infinity is dropped. ``cubic`` and ``quadratic`` work the same way.

``trig1(a, b, c) -> (t0, t1, n, ls)``: theta with a sin(theta) + b cos(theta) = c, as SP4.
``trig2(A0, A1, B1, A2, B2) -> (angles, n)``: the real roots of
A0 + A1 sin t + B1 cos t + A2 sin 2t + B2 cos 2t, up to 4 (rad, in an array of 4).

For refining roots on the equations they came from: ``newton_step`` is a damped Newton
step on a 2x2 or 3x3 Hessian, ``keep_distinct`` keeps a list of at most 4 distinct
solutions (angles within ``SAME`` rad are one, the better kept), ``grid_minima`` lists the
local minima of a periodic grid, where least-squares searches start.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.solvers.closed_form.subproblems import wrap

LEAD = 1e-14  # a leading coefficient this small (relative) is taken for 0
TOUCH = 1e-10  # |p(x*)| at a critical point x*, relative to sum |c_i x*^i|: a double root
MERGE = 1e-12  # roots closer than this (relative to 1 + |x|) are one root
SAME = 1e-6  # rad: solutions closer than this in every angle are one solution


@njit(cache=True, no_cfunc_wrapper=True)
def _value(c, deg, x):
    """(p(x), p'(x)) by Horner's rule; ``c`` highest power first, ``deg + 1`` of them."""
    f = c[0]
    df = 0.0
    for i in range(1, deg + 1):
        df = df * x + f
        f = f * x + c[i]
    return f, df


@njit(cache=True, no_cfunc_wrapper=True)
def _size(c, deg, x):
    """sum |c_i| |x|^i: the size of p's terms at x (the scale of its rounding error)."""
    ax = abs(x)
    m = abs(c[0])
    for i in range(1, deg + 1):
        m = m * ax + abs(c[i])
    return m


@njit(cache=True, no_cfunc_wrapper=True)
def _bracketed(c, deg, lo, hi, flo):
    """The root of p in [lo, hi], where p(lo) = flo and p(hi) have opposite signs: Newton's
    method, with a bisection step whenever Newton would leave the bracket."""
    x = 0.5 * (lo + hi)
    for _ in range(200):
        f, df = _value(c, deg, x)
        if f == 0.0:
            return x
        if (f < 0.0) == (flo < 0.0):
            lo = x
        else:
            hi = x
        xn = x - f / df if df != 0.0 else 0.5 * (lo + hi)
        if not lo < xn < hi:
            xn = 0.5 * (lo + hi)
        if abs(xn - x) <= 4e-16 * max(1.0, abs(x)) or hi - lo <= 4e-16 * max(1.0, abs(x)):
            return xn
        x = xn
    return x


@njit(cache=True, no_cfunc_wrapper=True)
def _roots_between(c, deg, crit, ncrit, out):
    """The real roots of p (``c``, leading coefficient nonzero) given its derivative's real
    roots ``crit[:ncrit]`` (ascending) written into ``out``; returns their count."""
    lead = abs(c[0])
    bound = 0.0
    for i in range(1, deg + 1):
        bound = max(bound, abs(c[i]) / lead)
    bound += 1.0  # Cauchy: every root lies strictly within
    n = 0
    lo = -bound
    flo, _ = _value(c, deg, lo)
    for k in range(ncrit + 1):
        hi = crit[k] if k < ncrit else bound
        fhi, _ = _value(c, deg, hi)
        crossing = flo != 0.0 and fhi != 0.0 and (flo < 0.0) != (fhi < 0.0)
        if crossing and hi > lo:
            x = _bracketed(c, deg, lo, hi, flo)
            if n == 0 or x - out[n - 1] > MERGE * (1.0 + abs(x)):
                out[n] = x
                n += 1
        # An extremum that comes within TOUCH of 0 without crossing it: a double root that
        # rounding lifted off the axis (one that crosses gives two roots, bracketed).
        touch = k < ncrit and not crossing and abs(fhi) <= TOUCH * _size(c, deg, hi)
        if (touch or fhi == 0.0) and (n == 0 or hi - out[n - 1] > MERGE * (1.0 + abs(hi))):
            out[n] = hi
            n += 1
        lo, flo = hi, fhi
    return n


@njit(cache=True, no_cfunc_wrapper=True)
def _normalised(coef, deg):
    """The coefficients over the largest one, and the degree once leading ones below LEAD
    are dropped (-1: all zero)."""
    big = 0.0
    for i in range(deg + 1):
        big = max(big, abs(coef[i]))
    c = np.zeros(5)
    if big == 0.0 or not math.isfinite(big):
        return c, -1
    start = 0
    while start < deg and abs(coef[start]) <= LEAD * big:
        start += 1
    for i in range(start, deg + 1):
        c[i - start] = coef[i] / big
    return c, deg - start


@njit(cache=True, no_cfunc_wrapper=True)
def _real_roots(c, deg, out):
    """The real roots of the degree-``deg`` polynomial ``c`` (leading term nonzero) into
    ``out``, ascending; returns their count. The derivative's roots come first."""
    if deg == 0:
        return 0
    if deg == 1:
        out[0] = -c[1] / c[0]
        return 1
    if deg == 2:
        a, b, e = c[0], c[1], c[2]
        disc = b * b - 4.0 * a * e
        if disc < 0.0:
            if -disc > 4.0 * TOUCH * (b * b + 4.0 * abs(a * e)):
                return 0
            disc = 0.0  # a tangency lifted by rounding: a double root
        if disc == 0.0:
            out[0] = -b / (2.0 * a)
            return 1
        sq = math.sqrt(disc)
        q = -0.5 * (b + sq) if b >= 0.0 else -0.5 * (b - sq)  # no cancellation
        r0, r1 = q / a, (e / q if q != 0.0 else -q / a)
        out[0], out[1] = min(r0, r1), max(r0, r1)
        return 1 if out[0] == out[1] else 2
    dc = np.zeros(5)
    for i in range(deg):
        dc[i] = c[i] * (deg - i)
    crit = np.zeros(4)
    ncrit = _real_roots(dc, deg - 1, crit)
    return _roots_between(c, deg, crit, ncrit, out)


@njit(cache=True, no_cfunc_wrapper=True)
def _solve(coef, deg):
    c, d = _normalised(coef, deg)
    out = np.zeros(4)
    if d < 0:
        return 0.0, 0.0, 0.0, 0.0, -1
    n = _real_roots(c, d, out)
    return out[0], out[1], out[2], out[3], n


@njit(cache=True, no_cfunc_wrapper=True)
def quartic(a, b, c, d, e):
    """Real roots of a x^4 + b x^3 + c x^2 + d x + e: (r0, r1, r2, r3, n), ascending."""
    return _solve(np.array((a, b, c, d, e)), 4)


@njit(cache=True, no_cfunc_wrapper=True)
def cubic(a, b, c, d):
    """Real roots of a x^3 + b x^2 + c x + d: (r0, r1, r2, n), ascending."""
    r0, r1, r2, _, n = _solve(np.array((a, b, c, d)), 3)
    return r0, r1, r2, n


@njit(cache=True, no_cfunc_wrapper=True)
def quadratic(a, b, c):
    """Real roots of a x^2 + b x + c: (r0, r1, n), ascending."""
    r0, r1, _, _, n = _solve(np.array((a, b, c)), 2)
    return r0, r1, n


@njit(cache=True, no_cfunc_wrapper=True)
def trig1(a, b, c):
    """theta with a sin(theta) + b cos(theta) = c: (t0, t1, n, ls), as SP4; n = -1 when
    a = b = 0 (every theta, or none: ls)."""
    rho = math.hypot(a, b)
    if rho == 0.0:
        return 0.0, 0.0, -1, c != 0.0
    phi = math.atan2(a, b)
    x = c / rho
    if abs(x) >= 1.0:
        return wrap(phi if x > 0 else phi + math.pi), 0.0, 1, abs(x) > 1.0 + 1e-12
    t = math.acos(x)
    return wrap(phi + t), wrap(phi - t), 2, False


@njit(cache=True, no_cfunc_wrapper=True)
def trig2(A0, A1, B1, A2, B2):
    """Real roots of A0 + A1 sin t + B1 cos t + A2 sin 2t + B2 cos 2t (not all 0): up to 4
    angles and their count. In t = t0 + 2 atan(x) the equation is a quartic in x whose
    leading coefficient is the function's value at t0 + pi: t0 is taken where that value
    is largest among 8 samples, so that no root lies near x = infinity."""
    best, t0 = -1.0, 0.0
    for i in range(8):
        t = 2.0 * math.pi * i / 8.0
        v = A0 + A1 * math.sin(t) + B1 * math.cos(t)
        v = abs(v + A2 * math.sin(2.0 * t) + B2 * math.cos(2.0 * t))
        if v > best:
            best, t0 = v, t - math.pi
    c, s, c2, s2 = math.cos(t0), math.sin(t0), math.cos(2 * t0), math.sin(2 * t0)
    a1, b1 = A1 * c - B1 * s, A1 * s + B1 * c
    a2, b2 = A2 * c2 - B2 * s2, A2 * s2 + B2 * c2
    x0, x1, x2, x3, n = quartic(
        A0 - b1 + b2, 2.0 * a1 - 4.0 * a2, 2.0 * A0 - 6.0 * b2, 2.0 * a1 + 4.0 * a2, A0 + b1 + b2
    )
    n = max(n, 0)
    xs = (x0, x1, x2, x3)
    out = np.zeros(4)
    for i in range(n):
        out[i] = t0 + 2.0 * math.atan(xs[i])
    return out, n


# -- refining roots ------------------------------------------------------------------------


@njit(cache=True, no_cfunc_wrapper=True)
def keep_distinct(sol, res, n, t, r):
    """Add solution ``t`` (angles, as many as ``sol`` has columns) with residual ``r`` to
    the ``n`` kept in ``sol``/``res``: a repeat replaces its twin if better, and past 4 the
    worst goes. Returns the new count."""
    m = sol.shape[1]
    for i in range(n):
        same = True
        for j in range(m):
            if abs(wrap(sol[i, j] - t[j])) > SAME:
                same = False
        if same:
            if r < res[i]:
                for j in range(m):
                    sol[i, j] = t[j]
                res[i] = r
            return n
    slot = n
    if n == 4:
        slot = 0
        for i in range(1, 4):
            if res[i] > res[slot]:
                slot = i
        if r >= res[slot]:
            return n
    for j in range(m):
        sol[slot, j] = wrap(t[j])
    res[slot] = r
    return n + 1 if n < 4 else n


@njit(cache=True, no_cfunc_wrapper=True)
def newton_step(H, g, m, mu):
    """(step, ok): the step s with (H + mu I) s = -g for the symmetric m x m (m = 2 or 3)
    ``H`` (row-major, flat), by Cramer's rule; ok is False (and s zero) unless H + mu I is
    positive definite, so that s goes downhill."""
    s = np.zeros(3)
    if m == 2:
        a, b, d = H[0] + mu, H[1], H[3] + mu
        det = a * d - b * b
        if not (a > 0.0 and det > 0.0):
            return s, False
        s[0] = -(d * g[0] - b * g[1]) / det
        s[1] = -(a * g[1] - b * g[0]) / det
        return s, True
    a00, a01, a02 = H[0] + mu, H[1], H[2]
    a11, a12, a22 = H[4] + mu, H[5], H[8] + mu
    c00 = a11 * a22 - a12 * a12
    c01 = a02 * a12 - a01 * a22
    c02 = a01 * a12 - a02 * a11
    c11 = a00 * a22 - a02 * a02
    c12 = a01 * a02 - a00 * a12
    c22 = a00 * a11 - a01 * a01
    det = a00 * c00 + a01 * c01 + a02 * c02
    if not (a00 > 0.0 and c22 > 0.0 and det > 0.0):  # Sylvester's criterion
        return s, False
    s[0] = -(c00 * g[0] + c01 * g[1] + c02 * g[2]) / det
    s[1] = -(c01 * g[0] + c11 * g[1] + c12 * g[2]) / det
    s[2] = -(c02 * g[0] + c12 * g[1] + c22 * g[2]) / det
    return s, True


@njit(cache=True, no_cfunc_wrapper=True)
def grid_minima(D, out):
    """The local minima of the periodic grid ``D`` (each cell no higher than its 8
    neighbours, wrapping round), the lowest first: up to ``len(out)`` (i, j) rows written
    into ``out``; returns their count (at least 1: the lowest cell). A valley along a row
    or a column (an angle that does not matter) counts once: a minimum in the row or
    column of one already listed, of the same value to rounding, is left out."""
    g0, g1 = D.shape
    m = out.shape[0]
    vals = np.full(m, np.inf)
    top = 0.0
    for i in range(g0):
        for j in range(g1):
            top = max(top, D[i, j])
    n = 0
    for i in range(g0):
        for j in range(g1):
            d = D[i, j]
            low = True
            for di in range(-1, 2):
                for dj in range(-1, 2):
                    if (di != 0 or dj != 0) and D[(i + di) % g0, (j + dj) % g1] < d:
                        low = False
            if not low or (n == m and d >= vals[m - 1]):
                continue
            for a in range(n):
                if (out[a, 0] == i or out[a, 1] == j) and abs(
                    vals[a] - d
                ) <= 1e-9 * d + 1e-14 * top:
                    low = False
            if not low:
                continue
            k = min(n, m - 1)  # insertion into the sorted list, dropping the highest
            while k > 0 and vals[k - 1] > d:
                vals[k], out[k, 0], out[k, 1] = vals[k - 1], out[k - 1, 0], out[k - 1, 1]
                k -= 1
            vals[k], out[k, 0], out[k, 1] = d, i, j
            n = min(n + 1, m)
    return n
