"""SP5, SP6 and their root finders on random instances, checked against their definitions.

Instances are built from known angles, which must be among the solutions; every solution
returned as exact must satisfy the defining equation; least-squares answers must be no
worse than a dense grid; degenerate inputs must give an answer, not an exception.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from armik.solvers.closed_form import roots, subproblems_56
from armik.solvers.closed_form import subproblems as sp


def sp5(*args):
    """SP5 called as the library calls it (3-tuples of floats): compiled once, for the
    closed forms' own signature (an array signature would be compiled for the tests alone,
    a minute or more on a cold cache)."""
    return subproblems_56.sp5(*(tuple(float(x) for x in v) for v in args))


sp6 = subproblems_56.sp6  # the library calls it with (4, 3) arrays, as the tests do

N = 300
EXACT = 1e-9  # the defining equations, for answers not flagged least squares
KNOWN = 1e-9  # rad: the known angles among the solutions


@pytest.fixture
def rng():
    return np.random.default_rng(56)


def unit(v):
    return v / np.linalg.norm(v)


def rot(k, t):
    return pin.exp3(np.asarray(k) * t)  # Pinocchio's, not the module's own


def angdiff(a, b):
    return abs(math.remainder(a - b, 2 * math.pi))


def rotated(k, p, th):
    """rot(k, t) p for every t of the array ``th`` (Rodrigues' formula, vectorised): (n, 3)."""
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    return p * c + np.cross(k, p) * s + k * (k @ p) * (1 - c)


def tilted(k, angle, rng):
    """A unit vector ``angle`` rad away from ``k``."""
    side = unit(np.cross(k, rng.normal(size=3)))
    return math.cos(angle) * k + math.sin(angle) * side


# -- roots -----------------------------------------------------------------------------------


def test_quartic_finds_every_real_root(rng):
    for _ in range(N):
        r = np.sort(rng.uniform(-3, 3, 4))
        if np.diff(r).min() < 1e-3:
            continue
        c = np.poly(r) * rng.uniform(0.1, 10) * rng.choice([-1, 1])
        *found, n = roots.quartic(*c)
        assert n == 4
        np.testing.assert_allclose(found, r, atol=1e-10)


def test_quartic_with_complex_roots_and_double_roots(rng):
    for _ in range(N):
        r = rng.uniform(-3, 3, 2)
        z = complex(rng.normal(), 0.05 + abs(rng.normal()))
        *found, n = roots.quartic(*np.real(np.poly([r[0], r[1], z, z.conjugate()])))
        assert n == 2 and np.allclose(found[:2], np.sort(r), atol=1e-9)
        w = complex(rng.normal(), 0.05 + abs(rng.normal()))
        *found, n = roots.quartic(*np.real(np.poly([z, z.conjugate(), w, w.conjugate()])))
        assert n == 0
    # a double root the rounding of the coefficients lifts off the axis is still found
    for x in rng.uniform(-2, 2, 50):
        c = np.poly([x, x, x + 1.5, x - 1.7]) + [0, 0, 0, 0, 1e-13]
        *found, n = roots.quartic(*c)
        assert min(abs(f - x) for f in found[:n]) < 1e-5


def test_lower_degrees_and_zero():
    assert roots.quartic(0, 0, 0, 0, 0)[-1] == -1
    *found, n = roots.quartic(1e-20, 1, 0, -1, 0)  # a cubic: its root at infinity dropped
    assert n == 3 and np.allclose(found[:3], [-1, 0, 1])
    assert roots.quartic(0, 0, 1, -3, 2)[-1] == 2 and roots.quartic(0, 0, 1, 0, 1)[-1] == 0
    assert (
        roots.cubic(1, 0, 0, -8)[:1] == pytest.approx((2.0,)) and roots.cubic(1, 0, 0, -8)[-1] == 1
    )
    assert roots.quadratic(1, -2, 1) == pytest.approx((1.0, 0.0, 1))
    assert roots.quadratic(1, 0, 1)[-1] == 0


def test_roots_are_polished_to_full_precision(rng):
    for _ in range(N):
        c = rng.normal(size=5)
        *found, n = roots.quartic(*c)
        for x in found[:n]:
            assert abs(np.polyval(c, x)) <= 1e-13 * np.polyval(np.abs(c), abs(x))


def test_trig2_every_root(rng):
    grid = np.linspace(-math.pi, math.pi, 40001)
    for _ in range(N):
        A = rng.normal(size=5)
        ts, n = roots.trig2(*A)

        def f(t, A=A):
            return (
                A[0]
                + A[1] * np.sin(t)
                + A[2] * np.cos(t)
                + A[3] * np.sin(2 * t)
                + A[4] * np.cos(2 * t)
            )

        for t in ts[:n]:
            assert abs(f(t)) < 1e-12 * np.abs(A).sum()
        assert n == np.count_nonzero(np.diff(np.sign(f(grid))))  # each sign change, once
    assert roots.trig1(0.0, 0.0, 1.0)[2:] == (-1, True)


# -- SP5 -------------------------------------------------------------------------------------


def sp5_residual(p0, p1, p2, p3, k1, k2, k3, t1, t2, t3):
    return np.linalg.norm(p0 + rot(k1, t1) @ p1 - rot(k2, t2) @ (p2 + rot(k3, t3) @ p3))


def sp5_instance(rng, k1=None, k2=None, k3=None, p1=None, p3=None, t=None):
    k1 = unit(rng.normal(size=3)) if k1 is None else k1
    k2 = unit(rng.normal(size=3)) if k2 is None else k2
    k3 = unit(rng.normal(size=3)) if k3 is None else k3
    p1 = rng.normal(size=3) if p1 is None else p1
    p3 = rng.normal(size=3) if p3 is None else p3
    p2 = rng.normal(size=3)
    t = rng.uniform(-math.pi, math.pi, 3) if t is None else t
    p0 = rot(k2, t[1]) @ (p2 + rot(k3, t[2]) @ p3) - rot(k1, t[0]) @ p1
    return (p0, p1, p2, p3, k1, k2, k3), t


def check_sp5(args, t, known=KNOWN):
    t1, t2, t3, n, ls = sp5(*args)
    assert not ls and n != 0
    for i in range(abs(n)):
        assert sp5_residual(*args, t1[i], t2[i], t3[i]) < EXACT
    if n > 0:
        near = min(max(angdiff(a, b) for a, b in zip((t1[i], t2[i], t3[i]), t)) for i in range(n))
        assert near < known
    return n


def sp5_count(args, samples=20000):
    """An independent count of SP5's solutions: for each theta1, SP4 puts circle 3 at the
    height of v1 (two branches), and every sign change of the distance mismatch along
    theta1 is a solution (close pairs may hide: a lower bound)."""
    p0, p1, p2, p3, k1, k2, k3 = args
    th = np.linspace(-math.pi, math.pi, samples)
    v1 = p0 + rotated(k1, p1, th)
    h1 = v1 @ k2
    rho1 = np.linalg.norm(v1 - np.outer(h1, k2), axis=1)
    c3 = p2 + k3 * (k3 @ p3)
    a3, b3 = np.cross(k3, p3), p3 - k3 * (k3 @ p3)
    a, b = k2 @ a3, k2 @ b3
    x = (h1 - k2 @ c3) / math.hypot(a, b)
    ok = np.abs(x) < 1
    count = 0
    for sign in (1, -1):
        t3 = math.atan2(a, b) + sign * np.arccos(np.clip(x, -1, 1))
        v3 = c3 + np.outer(np.sin(t3), a3) + np.outer(np.cos(t3), b3)
        g = rho1 - np.linalg.norm(v3 - np.outer(v3 @ k2, k2), axis=1)
        change = (np.sign(g[1:]) != np.sign(g[:-1])) & ok[1:] & ok[:-1]
        count += np.count_nonzero(change)
    return count


def test_sp5_random_instances_contain_the_known_angles(rng):
    counts = set()
    for _ in range(N):
        args, t = sp5_instance(rng)
        counts.add(check_sp5(args, t))
    assert counts == {2, 4}  # both occur; every one of up to 4 is returned


def test_sp5_returns_every_solution(rng):
    for _ in range(40):
        args, t = sp5_instance(rng)
        n = check_sp5(args, t)
        assert n >= sp5_count(args)


def test_sp5_least_squares_is_no_worse_than_a_grid(rng):
    grid = np.linspace(-math.pi, math.pi, 121)
    for _ in range(15):
        args, _t = sp5_instance(rng)
        args = (args[0] + 4.0 * unit(rng.normal(size=3)), *args[1:])  # out of reach
        t1, t2, t3, n, ls = sp5(*args)
        if not ls:  # moved, yet still reachable: then it must be exact
            assert sp5_residual(*args, t1[0], t2[0], t3[0]) < EXACT
            continue
        assert n == 1
        err = sp5_residual(*args, t1[0], t2[0], t3[0])
        p0, p1, p2, p3, k1, k2, k3 = args
        # the distance of v1 to the circle of v3 about k2, minimised over a 121 x 121 grid
        v1, v3 = p0 + rotated(k1, p1, grid), p2 + rotated(k3, p3, grid)
        h1, h3 = v1 @ k2, v3 @ k2
        r1 = np.linalg.norm(v1 - np.outer(h1, k2), axis=1)
        r3 = np.linalg.norm(v3 - np.outer(h3, k2), axis=1)
        best = np.sqrt((h1[:, None] - h3[None]) ** 2 + (r1[:, None] - r3[None]) ** 2).min()
        assert err <= best + 1e-9 and err > EXACT


def test_sp5_parallel_axes(rng):
    for _ in range(60):
        k2 = unit(rng.normal(size=3))
        args, t = sp5_instance(rng, k1=k2, k2=k2)  # k1 along k2: circle 1 keeps its height
        check_sp5(args, t)
        args, t = sp5_instance(rng, k2=k2, k3=-k2)  # k3 along k2
        check_sp5(args, t)


@pytest.mark.parametrize("angle", [1e-9, 1e-7, 1e-5, 1e-3])
def test_sp5_nearly_parallel_axes(rng, angle):
    for _ in range(20):
        k2 = unit(rng.normal(size=3))
        args, t = sp5_instance(rng, k1=tilted(k2, angle, rng), k2=k2)
        check_sp5(args, t, known=1e-6)
        args, t = sp5_instance(rng, k2=k2, k3=tilted(k2, angle, rng))
        check_sp5(args, t, known=1e-6)


def test_sp5_continua(rng):
    k = unit(rng.normal(size=3))
    k1, k3 = unit(rng.normal(size=3)), unit(rng.normal(size=3))
    for args, _ in (
        sp5_instance(rng, k1=k, k2=k, k3=k),  # every axis parallel: an angle is free
        sp5_instance(rng, k1=k1, p1=0.7 * k1),  # p1 on k1: theta1 is free
        sp5_instance(rng, k3=k3, p3=0.4 * k3),  # p3 on k3: theta3 is free
    ):
        t1, t2, t3, n, ls = sp5(*args)
        assert n == -1 and not ls
        assert sp5_residual(*args, t1[0], t2[0], t3[0]) < EXACT


def test_sp5_degenerate_inputs_do_not_raise(rng):
    z = np.zeros(3)
    k = unit(rng.normal(size=3))
    assert sp5(z, z, z, z, k, k, k)[3] == -1
    t1, t2, t3, n, ls = sp5(z, rng.normal(size=3), z, rng.normal(size=3), k, k, k)
    assert n in (-1, 1) and np.isfinite(t1 + t2 + t3).all()
    # every axis parallel and the heights apart: a least-squares continuum
    args, _ = sp5_instance(rng, k1=k, k2=k, k3=k)
    t1, t2, t3, n, ls = sp5(args[0] + 2 * k, *args[1:])
    assert n == -1 and ls


# -- SP6 -------------------------------------------------------------------------------------


def sp6_residual(H, K, P, d1, d2, t1, t2):
    e1 = H[0] @ rot(K[0], t1) @ P[0] + H[1] @ rot(K[1], t2) @ P[1] - d1
    e2 = H[2] @ rot(K[2], t1) @ P[2] + H[3] @ rot(K[3], t2) @ P[3] - d2
    return math.hypot(e1, e2)


def sp6_instance(rng, H=None, K=None, P=None, t=None):
    H = np.array([unit(v) for v in rng.normal(size=(4, 3))]) if H is None else H
    K = np.array([unit(v) for v in rng.normal(size=(4, 3))]) if K is None else K
    P = rng.normal(size=(4, 3)) if P is None else P
    t = rng.uniform(-math.pi, math.pi, 2) if t is None else t
    d1 = H[0] @ rot(K[0], t[0]) @ P[0] + H[1] @ rot(K[1], t[1]) @ P[1]
    d2 = H[2] @ rot(K[2], t[0]) @ P[2] + H[3] @ rot(K[3], t[1]) @ P[3]
    return (H, K, P, d1, d2), t


def check_sp6(args, t, known=KNOWN):
    t1, t2, n, ls = sp6(*args)
    assert not ls and n != 0
    for i in range(abs(n)):
        assert sp6_residual(*args, t1[i], t2[i]) < EXACT
    if n > 0:
        near = min(max(angdiff(t1[i], t[0]), angdiff(t2[i], t[1])) for i in range(n))
        assert near < known
    return n


def sp6_count(args, samples=20000):
    """An independent count: for each theta1 the second equation gives theta2 (two
    branches, SP4 by hand), and each sign change of the first equation is a solution."""
    H, K, P, d1, d2 = args
    th = np.linspace(-math.pi, math.pi, samples)
    T1 = rotated(K[0], P[0], th) @ H[0]
    T3 = rotated(K[2], P[2], th) @ H[2]
    e = (H[3] @ K[3]) * (K[3] @ P[3])
    a, b = H[3] @ np.cross(K[3], P[3]), H[3] @ P[3] - e
    x = (d2 - T3 - e) / math.hypot(a, b)
    ok = np.abs(x) < 1
    count = 0
    for sign in (1, -1):
        t2 = math.atan2(a, b) + sign * np.arccos(np.clip(x, -1, 1))
        g = T1 + rotated(K[1], P[1], t2) @ H[1] - d1
        count += np.count_nonzero((np.sign(g[1:]) != np.sign(g[:-1])) & ok[1:] & ok[:-1])
    return count


def test_sp6_random_instances_contain_the_known_angles(rng):
    counts = set()
    for _ in range(N):
        args, t = sp6_instance(rng)
        counts.add(check_sp6(args, t))
    assert counts == {2, 4}


def test_sp6_returns_every_solution(rng):
    for _ in range(40):
        args, t = sp6_instance(rng)
        assert check_sp6(args, t) >= sp6_count(args)


def test_sp6_least_squares_is_no_worse_than_a_grid(rng):
    grid = np.linspace(-math.pi, math.pi, 241)
    seen = 0
    for _ in range(20):
        (H, K, P, d1, d2), _t = sp6_instance(rng)
        args = (H, K, P, d1 + 3.0, d2 - 3.0)
        t1, t2, n, ls = sp6(*args)
        if not ls:
            assert sp6_residual(*args, t1[0], t2[0]) < EXACT
            continue
        seen += 1
        assert n == 1
        T = [rotated(K[i], P[i], grid) @ H[i] for i in range(4)]
        e1 = T[0][:, None] + T[1][None] - d1 - 3.0
        e2 = T[2][:, None] + T[3][None] - d2 + 3.0
        best = np.sqrt(e1**2 + e2**2).min()
        assert sp6_residual(*args, t1[0], t2[0]) <= best + 1e-9
    assert seen > 10


def test_sp6_degenerate_terms(rng):
    for _ in range(60):
        K = np.array([unit(v) for v in rng.normal(size=(4, 3))])
        H = np.array([unit(v) for v in rng.normal(size=(4, 3))])
        H[1] = K[1]  # h2 along k2: the first equation's theta2 term is a constant
        args, t = sp6_instance(rng, H=H, K=K)
        check_sp6(args, t)
        H[2] = -K[2]  # ... and the second's theta1 term: both pairs singular
        args, t = sp6_instance(rng, H=H, K=K)
        assert check_sp6(args, t) in (1, 2, 3, 4)


def test_sp6_continua_and_no_angle(rng):
    K = np.array([unit(v) for v in rng.normal(size=(4, 3))])
    H = np.array([unit(v) for v in rng.normal(size=(4, 3))])
    H[1], H[3] = K[1], K[3]  # theta2 in neither equation: free
    args, t = sp6_instance(rng, H=H, K=K)
    t1, t2, n, ls = sp6(*args)
    assert n == -1 and not ls and sp6_residual(*args, t1[0], t2[0]) < EXACT
    # the same equation twice: a continuum
    (H, K, P, d1, _d2), t = sp6_instance(rng)
    H2, K2, P2 = np.vstack([H[:2], H[:2]]), np.vstack([K[:2], K[:2]]), np.vstack([P[:2], P[:2]])
    t1, t2, n, ls = sp6(H2, K2, P2, d1, d1)
    assert n == -1 and not ls and sp6_residual(H2, K2, P2, d1, d1, t1[0], t2[0]) < EXACT
    z = np.zeros((4, 3))
    assert sp6(z, K, z, 0.0, 0.0)[2] == -1
    assert sp6(z, K, z, 1.0, 0.0)[2:] == (-1, True)  # no angle, and 0 = 1: least squares


def test_sp6_parallel_axes(rng):
    for _ in range(60):
        K = np.array([unit(v) for v in rng.normal(size=(4, 3))])
        K[2] = K[0]
        K[3] = -K[1]  # each angle's two axes parallel
        args, t = sp6_instance(rng, K=K)
        check_sp6(args, t)


def test_module_rot_agrees_with_pinocchio(rng):
    k, a = unit(rng.normal(size=3)), rng.uniform(-4, 4)
    assert np.abs(sp.matrix(sp.rot(k, a)) - rot(k, a)).max() < 1e-14
