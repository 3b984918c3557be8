"""The Paden-Kahan subproblems on random instances, checked against their definitions."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from armik.solvers.closed_form import subproblems as sp

N = 200
GRID = np.linspace(-math.pi, math.pi, 20001)


def unit(v):
    return v / np.linalg.norm(v)


def angdiff(a, b):
    return abs(math.remainder(a - b, 2 * math.pi))


@pytest.fixture
def rng():
    return np.random.default_rng(7)


def rot(k, t):
    return sp.matrix(sp.rot(k, t))


def test_rot_is_pinocchio_exp(rng):
    for _ in range(20):
        k, t = unit(rng.normal(size=3)), rng.uniform(-4, 4)
        assert np.abs(rot(k, t) - pin.exp3(k * t)).max() < 1e-14


def test_products(rng):
    A, B, x = rng.normal(size=(3, 3)), rng.normal(size=(3, 3)), rng.normal(size=3)
    a, b = sp.mat(A), sp.mat(B)
    assert np.allclose(sp.mv(a, x), A @ x) and np.allclose(sp.mtv(a, x), A.T @ x)
    assert np.allclose(sp.matrix(sp.mm(a, b)), A @ B)
    assert np.allclose(sp.matrix(sp.mtm(a, b)), A.T @ B)
    assert np.allclose(sp.matrix(sp.mmt(a, b)), A @ B.T)
    assert np.allclose(sp.cross(x, A[0]), np.cross(x, A[0])) and sp.vec(x) == tuple(x)


def test_sp1_exact(rng):
    for _ in range(N):
        k, p1, t = unit(rng.normal(size=3)), rng.normal(size=3), rng.uniform(-3, 3)
        theta, ls = sp.sp1(p1, rot(k, t) @ p1, k)
        assert not ls and angdiff(theta, t) < 1e-9


def test_sp1_least_squares_minimises(rng):
    for _ in range(20):
        k, p1, p2 = unit(rng.normal(size=3)), rng.normal(size=3), rng.normal(size=3)
        theta, ls = sp.sp1(p1, p2, k)
        assert ls
        err = np.linalg.norm(rot(k, theta) @ p1 - p2)
        grid = min(np.linalg.norm(pin.exp3(k * t) @ p1 - p2) for t in GRID[::20])
        assert err <= grid + 1e-9


def test_sp4_all_solutions(rng):
    for _ in range(N):
        h, k, p = unit(rng.normal(size=3)), unit(rng.normal(size=3)), rng.normal(size=3)
        t = rng.uniform(-3, 3)
        d = h @ rot(k, t) @ p
        *thetas, n, ls = sp.sp4(h, p, k, d)
        assert n == 2 and not ls
        for theta in thetas[:n]:
            assert abs(h @ rot(k, theta) @ p - d) < 1e-9
        assert min(angdiff(x, t) for x in thetas[:n]) < 1e-7
        # no other root: the function h.R(theta)p - d changes sign at most twice
        f = np.array([h @ pin.exp3(k * x) @ p - d for x in GRID[::50]])
        assert np.count_nonzero(np.diff(np.sign(f))) <= 2


def test_sp4_least_squares_and_degenerate(rng):
    h, k, p = np.array([1.0, 0, 0]), np.array([0, 0, 1.0]), np.array([1.0, 0, 0])
    *thetas, n, ls = sp.sp4(h, p, k, 2.0)  # h.R p is at most 1
    assert n == 1 and ls and angdiff(thetas[0], 0.0) < 1e-12
    *thetas, n, ls = sp.sp4(h, p, k, -3.0)
    assert n == 1 and ls and angdiff(thetas[0], math.pi) < 1e-12
    *thetas, n, ls = sp.sp4(h, p, k, 1.0)  # double root
    assert n == 1 and not ls
    *_, n, ls = sp.sp4(h, np.array([0, 0, 2.0]), k, 0.0)  # p along k: any theta
    assert n == -1 and not ls
    *_, n, ls = sp.sp4(h, np.array([0, 0, 2.0]), k, 0.5)
    assert n == -1 and ls


def test_sp3_all_solutions(rng):
    for _ in range(N):
        k, p1, p2 = unit(rng.normal(size=3)), rng.normal(size=3), rng.normal(size=3)
        t = rng.uniform(-3, 3)
        d = np.linalg.norm(rot(k, t) @ p1 - p2)
        *thetas, n, ls = sp.sp3(p1, p2, k, d)
        assert n == 2 and not ls
        for theta in thetas[:n]:
            assert abs(np.linalg.norm(rot(k, theta) @ p1 - p2) - d) < 1e-9
        assert min(angdiff(x, t) for x in thetas[:n]) < 1e-7


def test_sp3_least_squares(rng):
    for _ in range(20):
        k, p1, p2 = unit(rng.normal(size=3)), rng.normal(size=3), rng.normal(size=3)
        far = np.linalg.norm(p1) + np.linalg.norm(p2) + 1.0
        *thetas, n, ls = sp.sp3(p1, p2, k, far)
        assert n == 1 and ls
        got = np.linalg.norm(rot(k, thetas[0]) @ p1 - p2)
        best = max(np.linalg.norm(pin.exp3(k * t) @ p1 - p2) for t in GRID[::20])
        assert got >= best - 1e-9  # the farthest the rotation can take p1 from p2


def test_sp2_all_solutions(rng):
    for _ in range(N):
        k1, k2 = unit(rng.normal(size=3)), unit(rng.normal(size=3))
        p1, t1, t2 = rng.normal(size=3), rng.uniform(-3, 3), rng.uniform(-3, 3)
        p2 = rot(k2, t2).T @ rot(k1, t1) @ p1
        a0, a1, b0, b1, n, ls = sp.sp2(p1, p2, k1, k2, 0.0)
        a, b = np.array([a0, a1]), np.array([b0, b1])
        assert n == 2 and not ls
        for i in range(n):
            assert np.linalg.norm(rot(k1, a[i]) @ p1 - rot(k2, b[i]) @ p2) < 1e-8
        assert min(angdiff(a[i], t1) + angdiff(b[i], t2) for i in range(n)) < 1e-6


def test_sp2_least_squares_and_free_angle():
    k1, k2 = np.array([0, 0, 1.0]), np.array([1.0, 0, 0])
    # rot(z) keeps p1's z = 1; rot(x) of p2 = (1, 0, 0) never leaves z = 0
    a0, a1, b0, b1, n, ls = sp.sp2(np.array([0.0, 0.6, 0.8]), np.array([1.0, 0, 0]), k1, k2, 0.0)
    a, b = np.array([a0, a1]), np.array([b0, b1])
    assert ls and n >= 1 and np.isfinite(a[:n]).all() and np.isfinite(b[:n]).all()
    # p1 along k1: theta1 is free and set to the given value, theta2 still solves it
    p2 = np.array([0.0, 1.0, 0.0])
    a0, a1, b0, b1, n, ls = sp.sp2(np.array([0, 0, 1.0]), p2, k1, k2, 0.3)
    a, b = np.array([a0, a1]), np.array([b0, b1])
    assert n == -1 and not ls and a[0] == 0.3
    assert np.linalg.norm(rot(k2, b[0]) @ p2 - np.array([0, 0, 1.0])) < 1e-12


def test_elbow_merges_a_double_root_split_by_rounding_only(rng):
    """Within ELBOW (m) of its full stretch an elbow has one root, exact, where SP3 gives two
    a few 1e-6 rad apart; 1e-8 m short of it, both roots, as SP3's."""
    for _ in range(N):
        k, p1, p2 = unit(rng.normal(size=3)), rng.normal(size=3), rng.normal(size=3)
        # |rot(k, t) p1 - p2| at its largest: the parts across k opposite
        across = np.linalg.norm(np.cross(k, p1)) * np.linalg.norm(np.cross(k, p2))
        stretch = math.sqrt(p1 @ p1 + p2 @ p2 - 2.0 * ((k @ p1) * (k @ p2) - across))
        for short, merged in ((1e-12, True), (1e-8, False)):
            d = stretch - short
            *split, n3, _ = sp.sp3(p1, p2, k, d)
            *thetas, n, ls = sp.elbow(p1, p2, k, d)
            assert not ls
            if merged:
                assert n == 1 and min(angdiff(thetas[0], t) for t in split[:n3]) == 0.0
            else:
                assert n == n3 == 2 and thetas == split
            for t in thetas[:n]:
                assert abs(np.linalg.norm(rot(k, t) @ p1 - p2) - d) < 1e-12
