import numpy as np

import armik


def test_clik_stops_at_max_iterations_and_iteration_budget():
    arm = armik.load("panda")
    target = arm.fk(arm.random_q(4))
    few = arm.solve(target, solver="clik", max_iterations=3, timeout=10.0)
    assert not few.success and few.iterations == 3
    capped = arm.solve(target, solver="clik", max_iterations=1000, iteration_budget=5)
    assert capped.iterations == 5


def test_clik_converges_given_its_example_cap():
    arm = armik.load("ur5")
    q = arm.random_q(2)
    r = arm.solve(
        arm.fk(q), q0=np.clip(q + 0.05, arm.lower, arm.upper), solver="clik", max_iterations=1000
    )
    assert r.success and 0 < r.iterations < 1000
