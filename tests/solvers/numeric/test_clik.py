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


def test_clik_from_a_singular_pose_with_heavy_weights_is_a_result():
    """The UR5's zeros are singular: the damping 1e-12 beside rows weighted 1e3 fell below
    rounding and the step's system was singular (LinAlgError)."""
    arm = armik.load("ur5")
    target = arm.fk(arm.random_q(0))
    for w in ((1, 1, 1, 1e6, 1e6, 1e6), (1e-6, 1e-6, 1e-6, 1, 1, 1)):
        r = arm.solve(target, q0=np.zeros(6), solver="clik", weights=w, max_iterations=1000)
        assert r.success or r.reason.startswith("CLIK did not converge"), r.reason
