"""A 7R arm with joint 7 held (the Panda): ``N_ik(T, held, q)`` against Pinocchio and
``solve_all(T, hold={joint 7: held})``, the held value checked as ``hold=`` checks it."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from tests.export.build import Solver
from tests.export.test_export_c import check_solutions
from tests.solvers.closed_form.random_arms import wrapped_distance

TARGETS = 50


@pytest.fixture(scope="module")
def panda(tmp_path_factory):
    arm = armik.load("panda")
    return arm, Solver(arm, "panda", tmp_path_factory.mktemp("held"))


def same_as_held_solve_all(arm, Q, T, value):
    name = arm.joint_names[6]
    expected = [r.q for r in arm.solve_all(T, hold={name: value}) if r.success]
    assert len(Q) == len(expected), (Q.tolist(), [q.tolist() for q in expected])
    for got, want in zip(Q, expected):
        assert wrapped_distance(got, want) < 1e-7, (got.tolist(), want.tolist())


def test_header_takes_the_held_joint(panda):
    arm, solver = panda
    header = solver.files["panda_ik.h"]
    assert "#define PANDA_IK_DOF 7" in header and "#define PANDA_IK_HELD_JOINT 6" in header
    assert "int panda_ik(const double T[16], double held, double q[][PANDA_IK_DOF]);" in header
    assert solver.held == 6
    words = " ".join(header.split())  # the header's comment, its lines joined
    held = "(up to 1e-12 outside one it is taken as on it; else, or when it is not finite, -1)"
    assert held in words
    assert "a singular target gives no more solutions than a regular one next to it" in words


def test_fk_is_pinocchios(panda):
    arm, solver = panda
    rng = np.random.default_rng(8)
    for _ in range(TARGETS):
        q = arm.random_q(rng)
        assert np.abs(solver.fk(q) - arm.fk(q).homogeneous).max() < 1e-12


def test_every_solution_as_solve_all_holds_it(panda):
    """At the joint 7 a target was made with and at another value of it: every row has
    joint 7 there, reaches the target within 1e-9 by Pinocchio, and is solve_all's."""
    arm, solver = panda
    rng = np.random.default_rng(12)
    found = 0
    for k in range(TARGETS):
        q = arm.random_q(rng)
        T = arm.fk(q).homogeneous
        value = q[6] if k % 2 == 0 else float(rng.uniform(arm.lower[6], arm.upper[6]))
        Q = solver.ik(T, value)
        assert np.all(Q[:, 6] == value)
        check_solutions(arm, Q, T)
        same_as_held_solve_all(arm, Q, T, value)
        found += len(Q) if k % 2 == 0 else 0
    assert found >= TARGETS // 2  # at its own joint 7, a target of joints within limits is reached


def test_held_value_outside_its_limits_or_not_finite(panda):
    """-1, as hold= refuses it (a JointError); within LIMIT_TOL of a limit it is clipped."""
    arm, solver = panda
    q = arm.random_q(np.random.default_rng(1))
    T = arm.fk(q).homogeneous
    lo, hi = float(arm.lower[6]), float(arm.upper[6])
    for bad in (hi + 1e-3, lo - 1e-3, np.nan, np.inf):
        assert solver.ik_count(T, bad)[0] == -1
    with pytest.raises(armik.JointError):
        arm.solve_all(T, hold={arm.joint_names[6]: hi + 1e-3})
    n, Q = solver.ik_count(T, hi + 1e-12)
    assert n >= 0 and np.all(Q[:n, 6] == hi)


def test_out_of_reach_gives_nothing(panda):
    arm, solver = panda
    far = np.eye(4)
    far[:3, 3] = [0.0, 0.0, 10.0]
    n, Q = solver.ik_count(far, 0.5)
    assert n == 0
