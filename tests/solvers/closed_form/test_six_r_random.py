"""Random arms of each closed-form class, written as URDFs: classified, then every target
of a random configuration solved completely (the configuration is among solve_all's
answers modulo 2 pi) and exactly."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers.closed_form import spherical_wrist, three_parallel
from armik.status import Status

from ...analytic_urdfs import six_r
from ...conftest import write_urdf
from .random_arms import load_arm


@pytest.mark.parametrize("kind", ["parallel_23", "meeting_12", "three_parallel"])
def test_random_arms_are_solved_completely(kind, tmp_path):
    rng = np.random.default_rng({"parallel_23": 1, "meeting_12": 2, "three_parallel": 3}[kind])
    solver = "three_parallel" if kind == "three_parallel" else "spherical"
    for k in range(6):
        a = load_arm(kind, rng)
        family = spherical_wrist if solver == "spherical" else three_parallel
        geo = family.classify(a.kinematics)
        assert not isinstance(geo, str), geo
        if solver == "spherical":
            assert geo.variant == kind
        checked = 0
        for _ in range(12):
            q = a.random_q(rng)
            T = a.fk(q)
            results = a.solve_all(T)
            assert results[0].solver == solver
            for r in results:
                if r.success:
                    err = pin.log6(a.fk(r.q).inverse() * T).vector
                    assert np.linalg.norm(err) < 1e-9
            if any(r.singular for r in results):
                continue
            wrapped = [np.abs(np.angle(np.exp(1j * (r.q - q)))).max() for r in results]
            assert min(wrapped) < 1e-6, (kind, k, q)
            checked += 1
        assert checked >= 8


def test_compiled_equivalents_match_arm_nearest_equivalent():
    from armik.solvers.closed_form.sixr import nearest_equivalents

    rng = np.random.default_rng(5)
    a = armik.load("abb_irb120")  # limits narrower than 2 pi and wider (axis 6: 800 deg)
    for _ in range(300):
        Q = rng.uniform(-7, 7, size=(3, 6))
        q0 = a.random_q(rng)
        expected = [a.kinematics.nearest_equivalent(row, q0) for row in Q]
        nearest_equivalents(Q, 3, q0, a.lower, a.upper)
        assert np.array_equal(Q, np.array(expected))


def test_orientation_a_skew_wrist_cannot_take(tmp_path):
    """A wrist whose axes 5 and 6 meet at 60 degrees cannot turn axis 6 within 30 degrees
    of axis 4: a branch that would need it is refused with that reason and a finite
    configuration (other branches, with axis 4 elsewhere, may still reach the target)."""
    s = np.sin(np.pi / 3)
    joints = [
        ("0 0 0", "0 0 0", "0 0 1"),
        ("0 0 0.3", "0 0 0", "0 1 0"),
        ("0 0 0.4", "0 0 0", "0 1 0"),
        ("0.3 0 0.05", "0 0 0", "1 0 0"),
        ("0 0 0", "0 0 0", "0 1 0"),
        ("0 0 0", "0 0 0", f"0 0.5 {s}"),
    ]
    a = armik.load(
        write_urdf(tmp_path, six_r(joints, tool_xyz="0.1 0 0")), base="world", tip="tool"
    )
    assert spherical_wrist.classify(a.kinematics).variant == "parallel_23"
    rng = np.random.default_rng(9)
    refused = 0
    for _ in range(40):
        R = pin.exp3(rng.normal(size=3))
        for r in a.solve_all(pin.SE3(R, np.array([0.35, 0.1, 0.5]))):
            assert np.isfinite(r.q).all()
            if not r.success and "orientation" in r.reason:
                assert r.status is Status.UNREACHABLE
                refused += 1
    assert refused > 0
