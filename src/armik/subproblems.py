"""The Paden-Kahan subproblems: rotations about known axes that move known vectors.

Every function is compiled with numba (``@njit(cache=True)``) so that the closed-form
solvers built from them run in microseconds; they are also plain callables from Python.
``rot(k, theta)`` is the rotation by ``theta`` about the unit axis ``k`` (right hand).
Each subproblem returns all its solutions, their count ``n`` and a flag ``ls``: True when
no exact solution exists and the returned angle(s) solve it in the least-squares sense.

- SP1 ``sp1(p1, p2, k)``: theta with rot(k, theta) p1 = p2.
  LS: minimises |rot(k, theta) p1 - p2|.
- SP2 ``sp2(p1, p2, k1, k2)``: (theta1, theta2) with rot(k1, theta1) p1 = rot(k2, theta2) p2,
  k1 not parallel to k2; up to 2 pairs. LS: p1, p2 of different lengths are normalised;
  where the two circles miss, the pair nearest to meeting. ``n = -1``: p1 lies on k1, so
  theta1 is free (returned as the angle given in ``free``).
- SP3 ``sp3(p1, p2, k, d)``: theta with |rot(k, theta) p1 - p2| = d; up to 2.
  LS: minimises | |rot(k, theta) p1 - p2| - d |.
- SP4 ``sp4(h, p, k, d)``: theta with h . rot(k, theta) p = d (h unit); up to 2.
  LS: the theta nearest to satisfying it. ``n = -1``: h . rot(k, theta) p does not depend
  on theta (p along k, or h along k); every theta solves it if d matches.

Tolerance ``EPS`` (1e-12, relative) decides exact versus least squares and double roots.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

EPS = 1e-12
# Two roots of SP3/SP4 closer than 2 SINGLE (rad) merge into one: the equation moves by
# O(SINGLE^2) there. The same bound says when p1 lies on k1 in SP2 (a free angle).
SINGLE = 1e-7
DEGENERATE = 1e-9  # SP4's h . rot(k, theta) p varies by less than this (m): theta is free


@njit(cache=True)
def wrap(a):
    """The angle in (-pi, pi]."""
    return math.atan2(math.sin(a), math.cos(a))


@njit(cache=True)
def cross(a, b):
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


@njit(cache=True)
def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True)
def norm(a):
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


@njit(cache=True)
def rot(k, theta):
    """Rotation matrix about unit axis ``k`` by ``theta`` (Rodrigues)."""
    c, s = math.cos(theta), math.sin(theta)
    v = 1.0 - c
    x, y, z = k[0], k[1], k[2]
    R = np.empty((3, 3))
    R[0, 0] = c + x * x * v
    R[0, 1] = x * y * v - z * s
    R[0, 2] = x * z * v + y * s
    R[1, 0] = y * x * v + z * s
    R[1, 1] = c + y * y * v
    R[1, 2] = y * z * v - x * s
    R[2, 0] = z * x * v - y * s
    R[2, 1] = z * y * v + x * s
    R[2, 2] = c + z * z * v
    return R


@njit(cache=True)
def sp1(p1, p2, k):
    """theta with rot(k, theta) p1 = p2; returns (theta, ls)."""
    kxp = cross(k, p1)
    a = dot(kxp, p2)
    b = -dot(cross(k, kxp), p2)
    theta = math.atan2(a, b)
    scale = max(norm(p1), norm(p2), 1.0)
    ls = abs(norm(p1) - norm(p2)) > EPS * scale or abs(dot(k, p1) - dot(k, p2)) > EPS * scale
    return theta, ls


@njit(cache=True)
def sp4(h, p, k, d):
    """theta with h . rot(k, theta) p = d; returns (thetas (2,), n, ls)."""
    out = np.zeros(2)
    kxp = cross(k, p)
    a = dot(h, kxp)  # coefficient of sin
    b = -dot(h, cross(k, kxp))  # coefficient of cos
    c = d - dot(h, k) * dot(k, p)
    rho = math.hypot(a, b)
    scale = max(norm(p), abs(d), 1.0)
    if rho <= DEGENERATE * scale:
        return out, -1, abs(c) > DEGENERATE * scale
    phi = math.atan2(a, b)
    x = c / rho
    if abs(x) >= 1.0:
        out[0] = wrap(phi if x > 0 else phi + math.pi)
        return out, 1, abs(x) > 1.0 + EPS
    t = math.acos(x)
    if t < SINGLE or t > math.pi - SINGLE:  # a double root: merging moves f by O(t^2)
        out[0] = wrap(phi if t < SINGLE else phi + math.pi)
        return out, 1, False
    out[0] = wrap(phi + t)
    out[1] = wrap(phi - t)
    return out, 2, False


@njit(cache=True)
def sp3(p1, p2, k, d):
    """theta with |rot(k, theta) p1 - p2| = d; returns (thetas (2,), n, ls)."""
    n2 = norm(p2)
    if n2 <= EPS:  # |rot p1| = |p1| whatever theta: exact only if |p1| = d
        return np.zeros(2), -1, abs(norm(p1) - d) > EPS * max(d, 1.0)
    h = p2 / n2
    target = (dot(p1, p1) + n2 * n2 - d * d) / (2.0 * n2)
    return sp4(h, p1, k, target)


@njit(cache=True)
def sp2(p1, p2, k1, k2, free):
    """(theta1, theta2) with rot(k1, theta1) p1 = rot(k2, theta2) p2.

    Returns (theta1 (2,), theta2 (2,), n, ls). n = -1: p1 lies along k1, theta1 is free and
    set to ``free``, theta2 follows.
    """
    t1 = np.zeros(2)
    t2 = np.zeros(2)
    n1, n2 = norm(p1), norm(p2)
    ls = abs(n1 - n2) > EPS * max(n1, n2, 1.0)
    u1 = p1 / n1
    u2 = p2 / n2
    if norm(cross(k1, u1)) <= SINGLE:  # p1 on k1: any theta1 keeps it (nearly) still
        t1[0] = free
        target = mv(rot(k1, free), u1)
        th, _ = sp1(u2, target, k2)
        t2[0] = th
        # p1 lies within SINGLE of k1, so an exact solution misses by less than that.
        miss = norm(mv(rot(k2, th), u2) - target)
        return t1, t2, -1, ls or miss > 10.0 * SINGLE
    k12 = dot(k1, k2)
    den = 1.0 - k12 * k12
    a1 = dot(k1, u1)
    a2 = dot(k2, u2)
    alpha = (a1 - k12 * a2) / den
    beta = (a2 - k12 * a1) / den
    k1xk2 = cross(k1, k2)
    g2 = (1.0 - alpha * alpha - beta * beta - 2.0 * alpha * beta * k12) / den
    n = 2
    if g2 < 0.0:
        if g2 < -EPS:
            ls = True
        g2 = 0.0
    g = math.sqrt(g2)
    if g < 1e-9:
        n = 1
    base = alpha * k1 + beta * k2
    for i in range(n):
        sign = 1.0 if i == 0 else -1.0
        c = base + sign * g * k1xk2
        # A least-squares c lies off the unit sphere; SP1 projects it.
        t1[i], _ = sp1(u1, c, k1)
        t2[i], _ = sp1(u2, c, k2)
    return t1, t2, n, ls


# 3x3 products written out: numba sends ``@`` to BLAS, which costs a microsecond a call.


@njit(cache=True)
def mv(A, x):
    """A x."""
    return np.array(
        [
            A[0, 0] * x[0] + A[0, 1] * x[1] + A[0, 2] * x[2],
            A[1, 0] * x[0] + A[1, 1] * x[1] + A[1, 2] * x[2],
            A[2, 0] * x[0] + A[2, 1] * x[1] + A[2, 2] * x[2],
        ]
    )


@njit(cache=True)
def mtv(A, x):
    """A^T x."""
    return np.array(
        [
            A[0, 0] * x[0] + A[1, 0] * x[1] + A[2, 0] * x[2],
            A[0, 1] * x[0] + A[1, 1] * x[1] + A[2, 1] * x[2],
            A[0, 2] * x[0] + A[1, 2] * x[1] + A[2, 2] * x[2],
        ]
    )


@njit(cache=True)
def mm(A, B):
    """A B."""
    C = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            C[i, j] = A[i, 0] * B[0, j] + A[i, 1] * B[1, j] + A[i, 2] * B[2, j]
    return C


@njit(cache=True)
def mtm(A, B):
    """A^T B."""
    C = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            C[i, j] = A[0, i] * B[0, j] + A[1, i] * B[1, j] + A[2, i] * B[2, j]
    return C


@njit(cache=True)
def mmt(A, B):
    """A B^T."""
    C = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            C[i, j] = A[i, 0] * B[j, 0] + A[i, 1] * B[j, 1] + A[i, 2] * B[j, 2]
    return C
