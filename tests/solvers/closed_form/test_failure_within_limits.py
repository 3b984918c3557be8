"""A closed form's failure out of reach returns its closest configuration within the joint
limits: a q a user may command (the IRB 120's wrist and the iiwa's last joints came back
past their limits by a few mrad to 50 mrad). A failure over the limits themselves
(``joint_limits``, the configuration that reaches the target outside them, or the iiwa's
elbow outside its limits at every swivel angle) shows them."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from armik.status import Status

from ...conftest import arm


@pytest.mark.parametrize("name", ["abb_irb120", "kuka_iiwa14", "ur5"])
def test_a_failed_answer_lies_within_the_limits(name):
    a = arm(name)
    rng = np.random.default_rng(0)
    failures = 0
    for _ in range(40):
        T = pin.SE3(pin.exp3(rng.normal(size=3)), rng.normal(size=3) * 1.2)
        r = a.solve(T)
        over = r.status is Status.JOINT_LIMITS or "outside its limits" in r.reason
        if not r.success and not over:
            failures += 1
            assert np.all(r.q >= a.lower) and np.all(r.q <= a.upper), (r.q, r.reason)
    assert failures >= 10  # the route under test was taken


def test_the_irb120s_far_target():
    a = arm("abb_irb120")
    r = a.solve(pin.SE3(pin.exp3(np.array([0.3, 0.2, 0.1])), np.array([0.9, 0.3, 0.6])))
    assert not r.success and np.all(r.q >= a.lower) and np.all(r.q <= a.upper)
