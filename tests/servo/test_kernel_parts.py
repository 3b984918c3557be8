"""The servo's compiled parts against plain references: the smallest singular value
against numpy's SVD, the velocity box's braking against a simulation of braking."""

from __future__ import annotations

import numpy as np
import pytest

from armik.servo.box import velocity_box
from armik.servo.singular import smallest_singular


def _sigma(A, rows, last_k=-1, u=None, scale=None, rank=1000):
    """The servo's sigma of A's first ``rows`` rows, each at its ``scale`` (default: 1 for
    a nonzero row, 0 for a zero one), at most ``rank`` of them independent."""
    n = A.shape[1]
    if scale is None:
        scale = (np.abs(A).sum(axis=1) > 0).astype(float)
    active = int((scale[:rows] != 0).sum())
    u = np.zeros(n) if u is None else u
    work = np.zeros((3, n, n))
    sigma, k = smallest_singular(
        A, rows, active, rank, scale, work[0], u, last_k, work[1], np.zeros(n),
        np.zeros(n, dtype=np.int64), np.zeros(n),
    )  # fmt: skip
    return sigma, k, u


@pytest.mark.parametrize("n", [3, 5, 7])
def test_a_counted_zero_row_is_a_singularity_and_scales_unweight(n, rng):
    """A row that counts is in the measure even where it is zero (sigma 0 then); each row
    is measured at its scale (1 over its weight), so that sigma is the unweighted rows'."""
    A = np.zeros((24, n))
    A[:2] = rng.normal(size=(2, n))
    A[2] = 0.0  # asked for, zero at this q
    scale = np.zeros(24)
    scale[:3] = 1.0
    sigma, k, _ = _sigma(A, 6, scale=scale)
    assert k == min(3, n) and sigma < 1e-12
    B = np.zeros((24, n))
    B[:6] = rng.normal(size=(6, n))
    w = np.array([1.0, 1.0, 1.0, 0.01, 0.01, 0.01])
    Bw = B.copy()
    Bw[:6] *= w[:, None]
    scale = np.zeros(24)
    scale[:6] = 1.0 / w
    expected = np.linalg.svd(B[:6], compute_uv=False)[min(6, n) - 1]
    assert abs(_sigma(Bw, 6, scale=scale)[0] - expected) <= 1e-10 * max(1.0, expected)


@pytest.mark.parametrize("n", [1, 5, 6, 7, 9])
@pytest.mark.parametrize("rows", [3, 6, 12])
def test_smallest_singular_value_matches_numpy(n, rows, rng):
    """The r-th largest singular value (r = min(nonzero rows, n)), from a cold start."""
    A = np.zeros((24, n))
    A[:rows] = rng.normal(size=(rows, n))
    A[1] = 0.0  # a row inside its bound: not counted
    sigma, k, _ = _sigma(A, rows)
    r = min(rows - 1, n)
    assert k == r
    expected = np.linalg.svd(A, compute_uv=False)[r - 1]
    assert abs(sigma - expected) <= 1e-12 * max(1.0, expected)


def test_smallest_singular_value_warm_and_singular(rng):
    """From the last call's vector on a slowly turning matrix, with two singular values a
    few per cent apart (slow for a plain inverse iteration); and on a singular one."""
    base = rng.normal(size=(6, 7))
    U, _, Vt = np.linalg.svd(base, full_matrices=False)
    u, k = None, -1
    for t in range(50):
        R = np.linalg.qr(np.eye(6) + 1e-3 * t * rng.normal(size=(6, 6)))[0]
        A = np.zeros((24, 7))
        A[:6] = R @ U @ np.diag([2.0, 1.8, 0.7, 0.3, 0.2, 0.19]) @ Vt
        sigma, k, u = _sigma(A, 6, k, u)
        assert abs(sigma - np.linalg.svd(A, compute_uv=False)[5]) <= 1e-12
    A[:6, :] = 0.0
    A[:6, 0] = rng.normal(size=6)  # rank one: five singular values of zero
    A[:6, 1] = 2.0 * A[:6, 0]
    sigma, _, _ = _sigma(A, 6, k, u)
    assert 0.0 <= sigma < 1e-6


@pytest.mark.parametrize(("n", "rows", "rank"), [(4, 3, 2), (7, 6, 5), (5, 9, 3), (7, 3, 1)])
def test_the_rank_th_singular_value_of_rows_of_lower_rank(n, rows, rank, rng):
    """Rows of rank ``rank`` at every q (a tip on a joint's axis): sigma is the rank-th
    largest singular value, the smaller ones (zero) lifted out of the way, from a cold
    start and from the last call's vector on a turning matrix."""
    u, k = None, -1
    base = rng.normal(size=(rows, rank)) @ rng.normal(size=(rank, n))
    for t in range(20):
        A = np.zeros((24, n))
        turn = np.linalg.qr(np.eye(rows) + 1e-2 * t * rng.normal(size=(rows, rows)))[0]
        A[:rows] = turn @ base
        sigma, k, u = _sigma(A, rows, k, u, rank=rank)
        expected = np.linalg.svd(A, compute_uv=False)[rank - 1]
        assert abs(sigma - expected) <= 1e-10 * max(1.0, expected)
        assert expected > 1e-3  # (a value the plain smallest would read as 0)


def test_box_never_empty_and_braking_stops_before_the_limit(rng):
    """Ticks that always take the box's fastest velocity toward the upper limit, then brake:
    the box is never empty, every tick keeps every limit, the joint stops before the limit."""
    dt, lo, hi, vmax, amax = 0.002, -1.0, 1.0, 3.0, 20.0
    for _ in range(20):
        q, v = rng.uniform(-0.9, 0.5), 0.0
        for _ in range(3000):
            lb, ub, _, _, conflict = velocity_box(q, v, lo, hi, vmax, amax, dt)
            assert lb <= ub and not conflict
            w = ub if rng.random() < 0.9 else lb
            assert abs(w) <= vmax and abs(w - v) <= amax * dt + 1e-12
            q, v = q + w * dt, w
            assert lo <= q <= hi
    # a joint at its limit has nowhere further to go
    lb, ub, _, _, _ = velocity_box(hi, 0.0, lo, hi, vmax, amax, dt)
    assert ub == 0.0 and lb < 0.0
