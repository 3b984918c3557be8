"""The servo's compiled parts against plain references: the eigen-decomposition against
numpy's, the velocity box's braking against a simulation of braking."""

from __future__ import annotations

import numpy as np
import pytest

from armik.servo.box import velocity_box
from armik.servo.eigen import eigen


@pytest.mark.parametrize("n", [1, 5, 6, 7, 9])
def test_eigen_matches_numpy(n, rng):
    A = rng.normal(size=(6, n))
    B = A.T @ A
    V, ev = np.empty((n, n)), np.empty(n)
    work = B.copy()
    eigen(work, V, ev)
    np.testing.assert_allclose(np.sort(ev), np.linalg.eigvalsh(B), atol=1e-12)
    np.testing.assert_allclose(V @ np.diag(ev) @ V.T, B, atol=1e-12)
    np.testing.assert_allclose(V.T @ V, np.eye(n), atol=1e-12)


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
