"""The general spherical wrist (axes 4, 5, 6 meet, nothing else): classified, solved
completely on random arms with random fixed transforms before joint 1 and after joint 6,
near misses refused with their number."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers.closed_form import spherical_general
from armik.status import Status

from .random_arms import check_round_trips, load_arm, random_arm


@pytest.mark.parametrize("kind", ["spherical", "parallel_23", "meeting_12"])
def test_random_arms_are_solved_completely(kind):
    rng = np.random.default_rng({"spherical": 11, "parallel_23": 12, "meeting_12": 13}[kind])
    for _ in range(4 if kind == "spherical" else 2):
        a = load_arm(kind, rng)
        geo = spherical_general.classify(a.kinematics)
        assert not isinstance(geo, str), geo
        assert check_round_trips(a, "spherical_general", rng, 10) >= 7


def test_auto_keeps_the_special_layouts_and_takes_the_general_one():
    rng = np.random.default_rng(14)
    general = load_arm("spherical", rng)
    T = general.fk(general.random_q(rng))
    assert general.solve(T).solver == "spherical_general"
    special = load_arm("parallel_23", rng)
    assert special.solve(special.fk(special.random_q(rng))).solver == "spherical"
    assert armik.load("abb_irb120").solve(armik.load("abb_irb120").fk(np.zeros(6))).solver == (
        "spherical"
    )


def test_near_miss_wrist_is_refused_with_its_number():
    rng = np.random.default_rng(15)
    c, h = random_arm("spherical", rng)
    shift = np.cross(h[5], h[4])
    c[5] = c[5] + 3e-7 * shift / np.linalg.norm(shift)
    a = load_arm("spherical", rng, c, h)
    why = spherical_general.classify(a.kinematics)
    assert isinstance(why, str)
    assert "tolerance 1e-09 m" in why
    miss = float(why.split("miss by ")[1].split(" m")[0])
    assert 5e-8 < miss <= 3e-7  # axis 6 moved 3e-7 m off the other two's point
    with pytest.raises(armik.SolverError, match="miss by"):
        a.solve(a.fk(np.zeros(6)), solver="spherical_general")


def test_other_families_are_refused():
    rng = np.random.default_rng(16)
    why = spherical_general.classify(load_arm("two_parallel", rng).kinematics)
    assert isinstance(why, str) and "do not meet" in why
    assert "7 joints" in spherical_general.classify(armik.load("panda").kinematics)


def test_out_of_reach_is_unreachable_with_the_distance():
    rng = np.random.default_rng(17)
    a = load_arm("spherical", rng)
    T = a.fk(a.random_q(rng))
    far = pin.SE3(T.rotation, np.array([50.0, 0.0, 0.0]))
    r = a.solve(far, solver="spherical_general")
    assert not r.success and r.status is Status.UNREACHABLE
    assert "misses its wrist point by" in r.reason
    missed = float(r.reason.split("point by ")[1].split(" m")[0])
    # the wrist point's miss: the tip's, give or take the tool offset when a random
    # (non-orthogonal) wrist cannot take the target's orientation there
    assert abs(missed - np.linalg.norm(a.fk(r.q).translation - far.translation)) < 0.5
    assert missed > 45.0


def test_batch_equals_solve():
    rng = np.random.default_rng(18)
    a = load_arm("spherical", rng)
    poses = np.array([a.fk(a.random_q(rng)).homogeneous for _ in range(5)])
    b = a.solve_batch(poses, solver="spherical_general", workers=1, progress=False)
    for i, H in enumerate(poses):
        r = a.solve(H, solver="spherical_general")
        assert b.success[i] == r.success
        np.testing.assert_allclose(b.q[i], r.q, atol=1e-12)
