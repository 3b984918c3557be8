"""The Paden-Kahan subproblems: rotations about known axes that move known vectors.

Every function is compiled with numba (``@njit(cache=True)``) so that the closed-form
solvers built from them run in microseconds; they are also plain callables from Python.
Vectors are 3-tuples and rotation matrices 9-tuples (row-major): numba keeps tuples in
registers, where small arrays would each cost a heap allocation. Inputs may also be numpy
arrays of the same length. ``rot(k, theta)`` is the rotation by ``theta`` about the unit
axis ``k`` (right hand); ``matrix(R)`` turns a 9-tuple into a 3x3 array.

Each subproblem returns all its solutions, their count ``n`` and a flag ``ls``: True when
no exact solution exists and the returned angle(s) solve it in the least-squares sense.

- SP1 ``sp1(p1, p2, k) -> (theta, ls)``: rot(k, theta) p1 = p2.
  LS: minimises |rot(k, theta) p1 - p2|.
- SP2 ``sp2(p1, p2, k1, k2, free) -> (a0, a1, b0, b1, n, ls)``: (theta1, theta2) = (a_i, b_i)
  with rot(k1, theta1) p1 = rot(k2, theta2) p2, k1 not parallel to k2; up to 2 pairs.
  LS: p1, p2 of different lengths are normalised; where the two circles miss, the pair
  nearest to meeting. ``n = -1``: p1 lies on k1 (within ``SINGLE``), so theta1 is free and
  set to ``free``; theta2 follows.
- SP3 ``sp3(p1, p2, k, d) -> (t0, t1, n, ls)``: |rot(k, theta) p1 - p2| = d; up to 2.
  LS: minimises | |rot(k, theta) p1 - p2| - d |.
- Elbow ``elbow(p1, p2, k, d) -> (t0, t1, n, ls)``: SP3 at an elbow, whose two roots are one
  (stretched or folded) when a change of d by ``ELBOW`` (m) or less makes them a double
  root: the model's own rounding (1e-12 m on the Kinova, 1e-10 m on the UR5) splits them
  by 1e-6 rad and more.
  The exact root t0 is kept, so merging costs no accuracy.
- SP4 ``sp4(h, p, k, d) -> (t0, t1, n, ls)``: h . rot(k, theta) p = d (h unit); up to 2.
  LS: the theta nearest to satisfying it. ``n = -1``: h . rot(k, theta) p does not depend
  on theta (p along k, or h along k); every theta solves it if d matches.

Tolerances: ``EPS`` (1e-12, relative) decides exact versus least squares; two roots closer
than ``2 SINGLE`` (rad) merge into one, which moves the equation by O(SINGLE^2) only.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.tolerances import DISTANCE_TOL

EPS = 1e-12
SINGLE = 1e-7
DEGENERATE = 1e-9  # SP4's h . rot(k, theta) p varies by less than this (m): theta is free
# m: an elbow whose span this small a change makes a double root is stretched or folded:
# the closed forms take axis lines within DISTANCE_TOL as meeting, so they cannot tell it
ELBOW = DISTANCE_TOL


@njit(cache=True, no_cfunc_wrapper=True)
def wrap(a):
    """The angle in (-pi, pi] (arithmetic: no trigonometric call)."""
    if -math.pi < a <= math.pi:
        return a
    a -= 2.0 * math.pi * math.floor(a / (2.0 * math.pi))  # [0, 2 pi)
    return a - 2.0 * math.pi if a > math.pi else a


# -- vectors (3-tuples) and rotations (9-tuples, row-major) ---------------------------------


@njit(cache=True, no_cfunc_wrapper=True)
def vec(a):
    return (a[0], a[1], a[2])


@njit(cache=True, no_cfunc_wrapper=True)
def mat(A):
    """A 3x3 array as a 9-tuple."""
    return (A[0, 0], A[0, 1], A[0, 2], A[1, 0], A[1, 1], A[1, 2], A[2, 0], A[2, 1], A[2, 2])


def matrix(R) -> np.ndarray:
    """A 9-tuple as a 3x3 array."""
    return np.array(R, dtype=float).reshape(3, 3)


@njit(cache=True, no_cfunc_wrapper=True)
def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@njit(cache=True, no_cfunc_wrapper=True)
def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@njit(cache=True, no_cfunc_wrapper=True)
def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


@njit(cache=True, no_cfunc_wrapper=True)
def neg(a):
    return (-a[0], -a[1], -a[2])


@njit(cache=True, no_cfunc_wrapper=True)
def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@njit(cache=True, no_cfunc_wrapper=True)
def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True, no_cfunc_wrapper=True)
def norm(a):
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


@njit(cache=True, no_cfunc_wrapper=True)
def rot(k, theta):
    """Rotation about unit axis ``k`` by ``theta`` (Rodrigues), a 9-tuple."""
    c, s = math.cos(theta), math.sin(theta)
    v = 1.0 - c
    x, y, z = k[0], k[1], k[2]
    return (
        c + x * x * v,
        x * y * v - z * s,
        x * z * v + y * s,
        y * x * v + z * s,
        c + y * y * v,
        y * z * v - x * s,
        z * x * v - y * s,
        z * y * v + x * s,
        c + z * z * v,
    )


@njit(cache=True, no_cfunc_wrapper=True)
def mv(A, x):
    """A x."""
    return (
        A[0] * x[0] + A[1] * x[1] + A[2] * x[2],
        A[3] * x[0] + A[4] * x[1] + A[5] * x[2],
        A[6] * x[0] + A[7] * x[1] + A[8] * x[2],
    )


@njit(cache=True, no_cfunc_wrapper=True)
def mtv(A, x):
    """A^T x."""
    return (
        A[0] * x[0] + A[3] * x[1] + A[6] * x[2],
        A[1] * x[0] + A[4] * x[1] + A[7] * x[2],
        A[2] * x[0] + A[5] * x[1] + A[8] * x[2],
    )


@njit(cache=True, no_cfunc_wrapper=True)
def mm(A, B):
    """A B."""
    return (
        A[0] * B[0] + A[1] * B[3] + A[2] * B[6],
        A[0] * B[1] + A[1] * B[4] + A[2] * B[7],
        A[0] * B[2] + A[1] * B[5] + A[2] * B[8],
        A[3] * B[0] + A[4] * B[3] + A[5] * B[6],
        A[3] * B[1] + A[4] * B[4] + A[5] * B[7],
        A[3] * B[2] + A[4] * B[5] + A[5] * B[8],
        A[6] * B[0] + A[7] * B[3] + A[8] * B[6],
        A[6] * B[1] + A[7] * B[4] + A[8] * B[7],
        A[6] * B[2] + A[7] * B[5] + A[8] * B[8],
    )


@njit(cache=True, no_cfunc_wrapper=True)
def mtm(A, B):
    """A^T B."""
    return (
        A[0] * B[0] + A[3] * B[3] + A[6] * B[6],
        A[0] * B[1] + A[3] * B[4] + A[6] * B[7],
        A[0] * B[2] + A[3] * B[5] + A[6] * B[8],
        A[1] * B[0] + A[4] * B[3] + A[7] * B[6],
        A[1] * B[1] + A[4] * B[4] + A[7] * B[7],
        A[1] * B[2] + A[4] * B[5] + A[7] * B[8],
        A[2] * B[0] + A[5] * B[3] + A[8] * B[6],
        A[2] * B[1] + A[5] * B[4] + A[8] * B[7],
        A[2] * B[2] + A[5] * B[5] + A[8] * B[8],
    )


@njit(cache=True, no_cfunc_wrapper=True)
def mmt(A, B):
    """A B^T."""
    return (
        A[0] * B[0] + A[1] * B[1] + A[2] * B[2],
        A[0] * B[3] + A[1] * B[4] + A[2] * B[5],
        A[0] * B[6] + A[1] * B[7] + A[2] * B[8],
        A[3] * B[0] + A[4] * B[1] + A[5] * B[2],
        A[3] * B[3] + A[4] * B[4] + A[5] * B[5],
        A[3] * B[6] + A[4] * B[7] + A[5] * B[8],
        A[6] * B[0] + A[7] * B[1] + A[8] * B[2],
        A[6] * B[3] + A[7] * B[4] + A[8] * B[5],
        A[6] * B[6] + A[7] * B[7] + A[8] * B[8],
    )


# -- the subproblems ------------------------------------------------------------------------


@njit(cache=True, no_cfunc_wrapper=True)
def sp1(p1, p2, k):
    """theta with rot(k, theta) p1 = p2; returns (theta, ls)."""
    kxp = cross(k, p1)
    a = dot(kxp, p2)
    b = -dot(cross(k, kxp), p2)
    theta = math.atan2(a, b)
    n1, n2 = norm(p1), norm(p2)
    tol = EPS * max(n1, n2, 1.0)
    ls = abs(n1 - n2) > tol or abs(dot(k, p1) - dot(k, p2)) > tol
    return theta, ls


@njit(cache=True, no_cfunc_wrapper=True)
def sp4(h, p, k, d):
    """theta with h . rot(k, theta) p = d; returns (t0, t1, n, ls)."""
    return _sp4(h, p, k, d, 0.0)


@njit(cache=True, no_cfunc_wrapper=True)
def _sp4(h, p, k, d, merge):
    """``sp4``; two roots that a change of d by ``merge`` (m) or less makes one are one, the
    root phi + t kept (0: only roots within ``SINGLE`` rad of each other merge)."""
    kxp = cross(k, p)
    a = dot(h, kxp)  # coefficient of sin
    b = -dot(h, cross(k, kxp))  # coefficient of cos
    c = d - dot(h, k) * dot(k, p)
    rho = math.hypot(a, b)
    tol = DEGENERATE * max(norm(p), abs(d), 1.0)
    if rho <= tol:
        return 0.0, 0.0, -1, abs(c) > tol
    phi = math.atan2(a, b)
    x = c / rho
    if abs(x) >= 1.0:
        return wrap(phi if x > 0 else phi + math.pi), 0.0, 1, abs(x) > 1.0 + EPS
    t = math.acos(x)
    if t < SINGLE:  # a double root: merging moves the equation by O(t^2)
        return wrap(phi), 0.0, 1, False
    if t > math.pi - SINGLE:
        return wrap(phi + math.pi), 0.0, 1, False
    if rho * (1.0 - abs(x)) <= merge:  # a double root but for rounding: keep an exact one
        return wrap(phi + t), 0.0, 1, False
    return wrap(phi + t), wrap(phi - t), 2, False


@njit(cache=True, no_cfunc_wrapper=True)
def sp3(p1, p2, k, d):
    """theta with |rot(k, theta) p1 - p2| = d; returns (t0, t1, n, ls)."""
    return _sp3(p1, p2, k, d, 0.0)


@njit(cache=True, no_cfunc_wrapper=True)
def elbow(p1, p2, k, d):
    """``sp3`` at an elbow: roots a change of d by ``ELBOW`` or less makes one are one."""
    return _sp3(p1, p2, k, d, ELBOW)


@njit(cache=True, no_cfunc_wrapper=True)
def elbow_extreme(p1, p2, k, theta):
    """The angle nearest ``theta`` where |rot(k, .) p1 - p2| is at its largest or smallest
    (the elbow stretched or folded)."""
    kxp = cross(k, p1)
    phi = math.atan2(dot(p2, kxp), -dot(p2, cross(k, kxp)))  # p2 . rot p1 largest
    return phi if math.cos(theta - phi) >= 0.0 else wrap(phi + math.pi)


@njit(cache=True, no_cfunc_wrapper=True)
def _sp3(p1, p2, k, d, merge):
    n2 = norm(p2)
    if n2 <= EPS:  # |rot p1 - 0| = |p1| whatever theta: exact only if |p1| = d
        return 0.0, 0.0, -1, abs(norm(p1) - d) > EPS * max(d, 1.0)
    target = (dot(p1, p1) + n2 * n2 - d * d) / (2.0 * n2)
    # d^2 = |p1|^2 + n2^2 - 2 n2 (h . rot p1): SP4's d moves by n2 / d times d's change
    return _sp4(scale(p2, 1.0 / n2), p1, k, target, merge * d / n2)


@njit(cache=True, no_cfunc_wrapper=True)
def sp2(p1, p2, k1, k2, free):
    """(theta1, theta2) with rot(k1, theta1) p1 = rot(k2, theta2) p2.

    Returns (a0, a1, b0, b1, n, ls): the pairs (a0, b0) and (a1, b1). n = -1: p1 lies along
    k1, theta1 is free and set to ``free``, theta2 follows.
    """
    n1, n2 = norm(p1), norm(p2)
    ls = abs(n1 - n2) > EPS * max(n1, n2, 1.0)
    u1 = scale(p1, 1.0 / n1)
    u2 = scale(p2, 1.0 / n2)
    if norm(cross(k1, u1)) <= SINGLE:  # p1 on k1: any theta1 keeps it (nearly) still
        target = mv(rot(k1, free), u1)
        th, _ = sp1(u2, target, k2)
        # p1 lies within SINGLE of k1, so an exact solution misses by less than that.
        miss = norm(sub(mv(rot(k2, th), u2), target))
        return free, 0.0, th, 0.0, -1, ls or miss > 10.0 * SINGLE
    k12 = dot(k1, k2)
    den = 1.0 - k12 * k12
    c1 = dot(k1, u1)
    c2 = dot(k2, u2)
    alpha = (c1 - k12 * c2) / den
    beta = (c2 - k12 * c1) / den
    g2 = (1.0 - alpha * alpha - beta * beta - 2.0 * alpha * beta * k12) / den
    if g2 < 0.0:
        if g2 < -EPS:
            ls = True
        g2 = 0.0
    g = math.sqrt(g2)
    base = add(scale(k1, alpha), scale(k2, beta))
    k1xk2 = cross(k1, k2)
    # A least-squares c lies off the unit sphere; SP1 projects it.
    c = add(base, scale(k1xk2, g))
    a0, _ = sp1(u1, c, k1)
    b0, _ = sp1(u2, c, k2)
    if g < 1e-9:
        return a0, 0.0, b0, 0.0, 1, ls
    c = sub(base, scale(k1xk2, g))
    a1, _ = sp1(u1, c, k1)
    b1, _ = sp1(u2, c, k2)
    return a0, a1, b0, b1, 2, ls
