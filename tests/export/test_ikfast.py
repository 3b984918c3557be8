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
