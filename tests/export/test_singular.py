"""Singular and unreachable targets: ``N_ik`` gives what ``solve_all`` verifies there (a free
joint at the middle of its limits, merged branches once), never more solutions than at a
regular target next to it, 0 beyond reach, and never a NaN."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from tests.export.build import Solver
from tests.export.test_export_c import check_solutions, reached
from tests.solvers.closed_form.random_arms import load_arm, wrapped_distance

SINGULAR = {  # joint values at a singularity of each arm's family, and the free joint
    "ur5": [([0.3, -1.0, 1.2, -0.4, 0.0, 0.7], 5), ([0.3, -1.0, 0.0, -0.4, 1.1, 0.7], None)],
    "abb_irb120": [([0.3, 0.4, 0.2, 0.5, 0.0, -0.6], 3), ([0.0, 0.3, 0.2, 0.4, 0.9, 0.1], None)],
    # the elbow stretched (its wrist's singularity is beyond its limits)
    "z1": [([0.3, 1.0, 0.0, 0.4, 0.5, 0.7], None)],
    # joint 2 at 0: axes 1 and 3 aligned, the reversed chain's wrist singular (joint 3 free)
    "panda": [
        ([0.3, 0.0, 0.2, -1.5, 0.4, 1.8, 0.6], 2),
        ([0.3, 0.5, 0.2, -1.5, 0.0, 1.8, 0.6], None),
    ],
}


def held_of(arm: armik.Arm, q: np.ndarray) -> float | None:
    return float(q[6]) if arm.dof == 7 else None


def verified_answers(arm: armik.Arm, T: np.ndarray, held: float | None) -> list[np.ndarray]:
    hold = {} if held is None else {"hold": {arm.joint_names[6]: held}}
    return [r.q for r in arm.solve_all(T, **hold) if r.success]


@pytest.mark.parametrize("name", sorted(SINGULAR))
def test_singular_targets(name, tmp_path):
    """No NaN, every row verified and solve_all's, each merged branch once, no more rows
    than at a regular target 1e-3 rad away; a free joint at the middle of its limits."""
    arm = armik.load(name)
    solver = Solver(arm, "s", tmp_path)
    for q, free in SINGULAR[name]:
        q = np.array(q)
        held = held_of(arm, q)
        T = arm.fk(q).homogeneous
        n, Q = solver.ik_count(T, held)
        assert 0 < n <= solver.max
        Q = Q[:n]
        check_solutions(arm, Q, T)
        expected = verified_answers(arm, T, held)
        assert len(Q) == len(expected)
        assert all(wrapped_distance(a, b) < 1e-7 for a, b in zip(Q, expected))
        for i in range(n):
            for j in range(i):
                assert wrapped_distance(Q[i], Q[j]) > 1e-6  # a merged branch once
        regular = solver.ik(arm.fk(q - 1e-3).homogeneous, None if held is None else held - 1e-3)
        assert n <= len(regular)
        if free is not None:
            assert np.any(np.abs(Q[:, free] - arm.kinematics.middle[free]) < 1e-12)


ARMS = ["ur5", "abb_irb120", "z1", "panda", ("spherical", 5), ("three_parallel_free", 6)]


@pytest.mark.parametrize("case", ARMS, ids=str)
def test_through_the_edge_of_reach(case, tmp_path):
    """Targets on a ray from a reached one out through the boundary of the workspace (the
    elbow stretched, least-squares branches): never a NaN, every row within the limits and
    the tolerances and solve_all's; nothing far beyond."""
    arm = (
        armik.load(case)
        if isinstance(case, str)
        else load_arm(*case[:1], np.random.default_rng(case[1]))
    )
    solver = Solver(arm, "edge", tmp_path)
    rng = np.random.default_rng(3)
    origin = arm.kinematics.first_joint_origin
    for _ in range(3):
        q = arm.random_q(rng)
        held = held_of(arm, q)
        T0 = arm.fk(q).homogeneous
        counts = []
        for scale in np.linspace(1.0, 3.0, 41):
            T = T0.copy()
            T[:3, 3] = origin + scale * (T0[:3, 3] - origin)
            n, Q = solver.ik_count(T, held)
            assert n >= 0 and np.isfinite(Q[:n]).all()
            for row in Q[:n]:
                position, orientation = reached(arm, row, T)
                assert position <= 1e-6 and orientation <= 1e-6
                assert np.all(row >= arm.lower - 1e-12) and np.all(row <= arm.upper + 1e-12)
            assert n == len(verified_answers(arm, T, held))
            counts.append(n)
        assert counts[0] >= 1
    far = T0.copy()
    far[:3, 3] = origin + [0.0, 0.0, 10.0 + arm.kinematics.reach]
    assert solver.ik_count(far, held)[0] == 0


def test_a_stretched_elbow_is_one_branch_as_in_solve_all(tmp_path):
    """The Kinova's stretched elbow: its double root, split ~5e-6 rad by the model's
    rounding, is one root in C as in solve_all (4 rows, not 4 pairs)."""
    arm = armik.load("kinova")
    solver = Solver(arm, "s", tmp_path)
    for q in ([1.2, 2.6, np.pi, 1.4, 3.3, -1.2], [-0.1, 4.9, np.pi, -0.9, 3.5, -1.1]):
        T = arm.fk(np.array(q)).homogeneous
        Q = solver.ik(T)
        check_solutions(arm, Q, T)
        expected = verified_answers(arm, T, None)
        assert len(Q) == len(expected) == 4
        assert all(wrapped_distance(a, b) < 1e-7 for a, b in zip(Q, expected))
        assert all(wrapped_distance(Q[i], Q[j]) > 1e-3 for i in range(4) for j in range(i))


def test_a_span_along_the_free_axis_as_in_solve_all(tmp_path):
    """The iiwa with joint 7 held and its elbow stretched: joints 6 to 1 read from the tip
    are a spherical wrist whose span lies along joint 5's axis, free at the middle of its
    limits in C as in solve_all, every row to 1e-12 m."""
    arm = armik.load("kuka_iiwa14")
    solver = Solver(arm, "s", tmp_path)
    rng = np.random.default_rng(1)
    at_middle = 0
    for _ in range(10):
        q = arm.random_q(rng)
        q[3] = 0.0
        T = arm.fk(q).homogeneous
        Q = solver.ik(T, float(q[6]))
        expected = verified_answers(arm, T, float(q[6]))
        assert 0 < len(Q) == len(expected)
        assert all(wrapped_distance(a, b) < 1e-7 for a, b in zip(Q, expected))
        for row in Q:
            assert max(reached(arm, row, T)) < 1e-12
        assert np.all(Q[:, 4] == Q[0, 4])  # one value of the free joint (swept if need be)
        at_middle += Q[0, 4] == arm.kinematics.middle[4]
    assert at_middle >= 8


def test_both_roots_of_an_elbow_almost_stretched_come_back(tmp_path):
    """An elbow bent 6e-5 to 9e-5 rad, which the merge of a double root takes for
    stretched: the root and its mirror lie 1e-4 rad or more apart, two solutions, both
    returned as ``solve_all`` returns them (``keep_nearer`` kept one)."""
    arm = armik.load("ur5")
    solver = Solver(arm, "elbow", tmp_path)
    rng = np.random.default_rng(9)
    for k in range(8):
        q = arm.random_q(rng)
        q[2] = (-1) ** k * rng.uniform(6e-5, 9e-5)
        T = arm.fk(q).homogeneous
        n, Q = solver.ik_count(T, None)
        Q = Q[:n]
        check_solutions(arm, Q, T)
        assert min(wrapped_distance(row, q) for row in Q) < 1e-6
        expected = verified_answers(arm, T, None)
        assert len(Q) == len(expected)
        assert all(wrapped_distance(a, b) < 1e-7 for a, b in zip(Q, expected))
