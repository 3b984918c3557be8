"""Three parallel axes (2, 3, 4) with a general wrist: classified, solved completely on
random arms with random fixed transforms before joint 1 and after joint 6, near misses
refused with their number."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers.closed_form import three_parallel_general

from .random_arms import check_round_trips, load_arm, random_arm


@pytest.mark.parametrize("kind", ["three_parallel_free", "three_parallel"])
def test_random_arms_are_solved_completely(kind):
    rng = np.random.default_rng({"three_parallel_free": 21, "three_parallel": 22}[kind])
    for _ in range(4 if kind == "three_parallel_free" else 2):
        a = load_arm(kind, rng)
        geo = three_parallel_general.classify(a.kinematics)
        assert not isinstance(geo, str), geo
        assert check_round_trips(a, "three_parallel_general", rng, 10) >= 7


def test_the_ur5_is_solved_completely_and_auto_keeps_its_closed_form():
    a = armik.load("ur5")
    rng = np.random.default_rng(23)
    assert check_round_trips(a, "three_parallel_general", rng, 10) >= 7
    assert a.solve(a.fk(a.random_q(rng))).solver == "three_parallel"
    b = load_arm("three_parallel_free", rng)
    assert b.solve(b.fk(b.random_q(rng))).solver == "three_parallel_general"


def test_near_miss_parallel_axes_are_refused_with_their_number():
    rng = np.random.default_rng(24)
    c, h = random_arm("three_parallel_free", rng)
    tilt = pin.exp3(
        2e-6 * np.cross(h[3], [1.0, 0.0, 0.0]) / np.linalg.norm(np.cross(h[3], [1, 0, 0]))
    )
    h[3] = tilt @ h[3]
    a = load_arm("three_parallel_free", rng, c, h)
    why = three_parallel_general.classify(a.kinematics)
    assert isinstance(why, str) and "axes 2 and 4 are 2e-06 rad apart" in why, why
    assert "tolerance 1e-09 rad" in why
    with pytest.raises(armik.SolverError, match="2e-06 rad apart"):
        a.solve(a.fk(np.zeros(6)), solver="three_parallel_general")


def test_other_families_are_refused():
    rng = np.random.default_rng(25)
    why = three_parallel_general.classify(load_arm("two_parallel", rng).kinematics)
    assert isinstance(why, str) and "axes 2, 3, 4 are not parallel" in why
    assert "7 joints" in three_parallel_general.classify(armik.load("panda").kinematics)


def test_out_of_reach_is_not_a_success():
    rng = np.random.default_rng(26)
    a = load_arm("three_parallel_free", rng)
    far = pin.SE3(a.fk(a.random_q(rng)).rotation, np.array([50.0, 0.0, 0.0]))
    for r in a.solve_all(far, solver="three_parallel_general"):
        assert not r.success and np.isfinite(r.q).all()


def test_batch_equals_solve():
    rng = np.random.default_rng(27)
    a = load_arm("three_parallel_free", rng)
    poses = np.array([a.fk(a.random_q(rng)).homogeneous for _ in range(5)])
    b = a.solve_batch(poses, solver="three_parallel_general", workers=1, progress=False)
    for i, H in enumerate(poses):
        r = a.solve(H, solver="three_parallel_general")
        assert b.success[i] == r.success
        np.testing.assert_allclose(b.q[i], r.q, atol=1e-12)
