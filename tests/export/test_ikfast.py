"""The IKFast 61 file: compiled against a header declaring IKFast's interface, included and
called as MoveIt's ikfast_kinematics_plugin does, it gives N_ik's solutions and N_fk's pose."""

from __future__ import annotations

import ctypes

import numpy as np
import pytest

import armik
from tests.export.build import Solver

_P = ctypes.POINTER(ctypes.c_double)


@pytest.mark.parametrize("name", ["ur5", "abb_irb120"])
def test_ikfast_gives_n_iks_solutions(name, tmp_path):
    arm = armik.load(name)
    solver = Solver(arm, name, tmp_path, ikfast=True)
    assert f"{name}_ikfast.cpp" in solver.files
    solve = solver.lib.ikfast_solve
    solve.restype = ctypes.c_int
    rng = np.random.default_rng(2)
    found = 0
    for _ in range(20):
        q = arm.random_q(rng)
        T = np.ascontiguousarray(arm.fk(q).homogeneous).reshape(16)
        Q = np.full((8, 6), np.nan)
        n = solve(T.ctypes.data_as(_P), Q.ctypes.data_as(_P))
        expected = solver.ik(T)
        assert n == len(expected) and np.array_equal(Q[:n], expected)
        found += n
        trans, rot = np.empty(3), np.empty(9)
        solver.lib.ikfast_fk(q.ctypes.data_as(_P), trans.ctypes.data_as(_P), rot.ctypes.data_as(_P))
        H = solver.fk(q)
        assert np.array_equal(trans, H[:3, 3]) and np.array_equal(rot, H[:3, :3].ravel())
    assert found >= 20
    far = np.eye(4)
    far[2, 3] = 100.0
    assert solve(far.reshape(16).ctypes.data_as(_P), np.empty((8, 6)).ctypes.data_as(_P)) == 0
