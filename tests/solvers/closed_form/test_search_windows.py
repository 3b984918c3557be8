"""The windows of q1 where ``two_parallel``'s SP6 can have solutions (``search_q1``): they
hold every solution, and the search's parameter covers the turn once, in order."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

import armik
from armik.solvers.closed_form import search_q1, sixr, two_parallel
from armik.solvers.closed_form.subproblems import mat, mmt, mv, sub, vec

RTB = os.path.join(
    os.path.dirname(__file__), "..", "..", "data", "rtb"
)  # rtb-data's (README there)
IRB140 = os.path.join(RTB, "abb_irb140_description", "urdf", "irb140.urdf")


@pytest.fixture(scope="module")
def chain():
    return two_parallel.classify(armik.load(IRB140, tip="tool0").kinematics)


def _pieces(g, q):
    R, pos = sixr.forward(g.h, g.p, g.R_tip0, q)
    R06 = mmt(R, mat(g.R_tip0))
    return R06, sub(sub(pos, mv(R06, vec(g.p[6]))), vec(g.p[0]))


def _inside(q1, phi0, ua, ub):
    u = abs(math.remainder(q1 - phi0, 2.0 * math.pi))
    return ua - 1e-12 <= u <= ub + 1e-12


def test_every_solution_lies_in_a_window_and_the_windows_are_narrow(chain):
    """Each window holds its q1; on the IRB 140 (axes 5 and 6 0.02 m apart) many are
    narrower than the old uniform grid's step, which is why that grid missed solutions."""
    rng = np.random.default_rng(3)
    widths = []
    for _ in range(200):
        q = rng.uniform(-math.pi, math.pi, 6)
        _, p16 = _pieces(chain, q)
        phi0, ua, ub, empty = search_q1._window(chain.h, chain.p, p16)
        assert not empty and _inside(q[0], phi0, ua, ub)
        widths.append(ub - ua)
    assert np.mean(np.array(widths) < 2.0 * math.pi / 200) > 0.2


@pytest.mark.parametrize("windows", [(0.3, 0.1, 0.12), (-2.0, 0.0, 0.5), (1.0, 2.9, math.pi)])
def test_the_parameter_covers_the_turn_once_in_order(windows):
    """q1_of is continuous and increasing over one turn of t, and lands in the windows
    for nine tenths of it."""
    phi0, ua, ub = windows
    t = np.linspace(-math.pi, math.pi, 20001)
    q1 = np.array([search_q1.q1_of(x, phi0, ua, ub) for x in t])
    steps = np.remainder(np.diff(q1), 2.0 * math.pi)
    assert steps.max() < 0.05 and abs(steps.sum() - 2.0 * math.pi) < 1e-9
    share = np.mean([_inside(x, phi0, ua, ub) for x in q1])
    assert share >= search_q1.IN_WINDOWS - 0.01
    assert search_q1.q1_of(0.7, 0.0, 0.0, math.pi) == 0.7  # no window: the identity


@pytest.mark.parametrize("q4", [0.0, math.pi, -math.pi + 1e-3])
def test_the_wrist_pose_where_the_rotation_does_not_split_q23_from_q5(q4):
    """The IRB 140 with q4 = 0 or pi (axes 2, 3, 5 parallel; the arm is not singular):
    solve_all finds the configuration that made the target, every time."""
    arm = armik.load(IRB140, tip="tool0")
    rng = np.random.default_rng(4)
    for _ in range(25):
        q = arm.random_q(rng)
        q[3] = q4
        assert np.linalg.svd(arm.jacobian(q), compute_uv=False)[-1] > 1e-3
        found = [r.q for r in arm.solve_all(arm.fk(q), solver="two_parallel") if r.success]
        wrapped = [np.remainder(x - q + math.pi, 2.0 * math.pi) - math.pi for x in found]
        assert any(np.abs(d).max() < 1e-6 for d in wrapped), q
