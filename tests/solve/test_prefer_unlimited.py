"""``prefer="limits"`` on an arm with continuous joints (the Kinova's, no middle to their
range): no numpy warning on any route, and the answers of the score's own ranking."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from tests.conftest import arm as bundled


@pytest.mark.parametrize("route", ["solve", "solve_all", "solve_batch", "solve_path"])
def test_limits_on_continuous_joints_warns_of_nothing(route):
    kinova = bundled("kinova")
    assert np.isinf(kinova.lower).any()
    rng = np.random.default_rng(1)
    qs = [kinova.random_q(rng) for _ in range(3)]
    T = [kinova.fk(q) for q in qs]
    calls = {
        "solve": lambda: [kinova.solve(T[0], prefer="limits")],
        "solve_all": lambda: kinova.solve_all(T[0], prefer="limits"),
        "solve_batch": lambda: kinova.solve_batch(T, prefer="limits"),
        "solve_path": lambda: kinova.solve_path(T, qs[0], prefer="limits"),
    }
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        got = list(calls[route]())
    assert got[0].success and np.isfinite(got[0].extra["score"])
