"""The IKFast 61 file: compiled against a header declaring IKFast's interface, included and
called as MoveIt's ikfast_kinematics_plugin does, it gives N_ik's solutions and N_fk's pose;
a 7R arm's held joint is IKFast's one free parameter."""

from __future__ import annotations

import ctypes

import numpy as np
import pytest

import armik
from tests.export.build import Solver

_P = ctypes.POINTER(ctypes.c_double)


@pytest.mark.parametrize("name", ["ur5", "abb_irb120", "panda"])
def test_ikfast_gives_n_iks_solutions(name, tmp_path):
    arm = armik.load(name)
    solver = Solver(arm, name, tmp_path, ikfast=True)
    assert f"{name}_ikfast.cpp" in solver.files
    solve = solver.lib.ikfast_solve
    solve.restype = ctypes.c_int
    held = solver.held  # the Panda's joint 7, None for the 6R arms
    assert solver.lib.ikfast_free_index() == (-1 if held is None else held)
    rng = np.random.default_rng(2)
    found = 0
    for _ in range(20):
        q = arm.random_q(rng)
        T = np.ascontiguousarray(arm.fk(q).homogeneous).reshape(16)
        free = np.array([0.0 if held is None else q[held]])
        Q = np.full((8, arm.dof), np.nan)
        n = solve(T.ctypes.data_as(_P), free.ctypes.data_as(_P), Q.ctypes.data_as(_P))
        expected = solver.ik(T, None if held is None else q[held])
        assert n == len(expected) and np.array_equal(Q[:n], expected)
        if held is not None:
            assert np.all(Q[:n, held] == q[held])
        found += n
        trans, rot = np.empty(3), np.empty(9)
        solver.lib.ikfast_fk(q.ctypes.data_as(_P), trans.ctypes.data_as(_P), rot.ctypes.data_as(_P))
        H = solver.fk(q)
        assert np.array_equal(trans, H[:3, 3]) and np.array_equal(rot, H[:3, :3].ravel())
    assert found >= 20
    far = np.eye(4)
    far[2, 3] = 100.0
    free = np.zeros(1)
    none = np.empty((8, arm.dof))
    args = (far.reshape(16).ctypes.data_as(_P), free.ctypes.data_as(_P), none.ctypes.data_as(_P))
    assert solve(*args) == 0
    reflected = arm.fk(arm.random_q(rng)).homogeneous  # what N_ik refuses (-1): no solution
    reflected[:3, 0] *= -1
    T = np.ascontiguousarray(reflected).reshape(16)
    free = np.array([0.0 if held is None else arm.middle[held]])
    assert solve(T.ctypes.data_as(_P), free.ctypes.data_as(_P), none.ctypes.data_as(_P)) == 0


def test_a_free_value_moveit_takes_as_within_the_limits_is_on_them(tmp_path):
    """MoveIt's plugin seeds the free parameter with the robot's joint 7, which it takes up
    to its LIMIT_TOLERANCE (1e-7 rad) outside a limit: ComputeIk solves such a value as the
    limit itself, where N_ik (as solve_all's hold=) takes 1e-12 and refuses it; further
    out, no solution."""
    arm = armik.load("panda")
    solver = Solver(arm, "panda", tmp_path, ikfast=True)
    solve = solver.lib.ikfast_solve
    solve.restype = ctypes.c_int
    held = solver.held
    rng = np.random.default_rng(4)
    for limit, outward in ((arm.upper[held], 1.0), (arm.lower[held], -1.0)):
        q = arm.random_q(rng)
        q[held] = limit
        T = np.ascontiguousarray(arm.fk(q).homogeneous).reshape(16)
        expected = solver.ik(T, limit)
        assert len(expected) >= 1
        for past, n_wanted in ((1e-9, len(expected)), (9e-8, len(expected)), (1e-6, 0)):
            free = np.array([limit + outward * past])
            Q = np.full((8, arm.dof), np.nan)
            n = solve(T.ctypes.data_as(_P), free.ctypes.data_as(_P), Q.ctypes.data_as(_P))
            assert n == n_wanted, (limit, past, n)
            assert np.array_equal(Q[:n], expected[:n]) and np.all(Q[:n, held] == limit)
            assert solver.ik_count(T, free[0])[0] == -1  # N_ik itself keeps 1e-12
