"""A success measured apart says what its distances are from: with weights on a region's
axes, the region's centre, its free components left out (``armik.verify.distances``)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik

from ..conftest import arm

# z free: the distances leave it out, so they are no distance to the target
BOUNDS = (0.01, 0.01, np.inf, 0.1, 0.1, 0.1)
WEIGHTS = (1, 1, 1, 1, 1, 0.5)


def _target(a) -> pin.SE3:
    T = a.fk(a.random_q(np.random.default_rng(1)))
    return pin.SE3(T.rotation, T.translation + T.rotation @ np.array([0.003, 0.0, 0.2]))


@pytest.mark.parametrize("solver", ["auto", "qp"])
def test_weights_with_bounds_say_the_regions_centre(solver):
    ur5 = arm("ur5")
    T = _target(ur5)
    r = ur5.solve(T, bounds=BOUNDS, weights=WEIGHTS, solver=solver)
    assert r.success, r.reason
    # 0.2 m along the free z: the tip is that far from the target, not what is reported
    assert np.linalg.norm(ur5.fk(r.q).translation - T.translation) > r.position_error + 0.1
    assert "from the target" not in r.reason, r.reason
    assert f"{r.position_error:.3g} m" in r.reason
    assert "from the region's centre, free components apart" in r.reason, r.reason
    assert "(on the weighted axes)" in r.reason


def test_weights_with_bounds_say_the_regions_centre_on_every_answer():
    ur5 = arm("ur5")
    rs = ur5.solve_all(_target(ur5), bounds=BOUNDS, weights=WEIGHTS)
    assert len(rs) and all(r.success for r in rs)
    for r in rs:
        assert "from the region's centre, free components apart" in r.reason, r.reason


def test_weights_alone_still_say_the_target():
    ur5 = arm("ur5")
    T = ur5.fk(ur5.random_q(np.random.default_rng(2)))
    r = ur5.solve(T, weights=(1, 1, 1, 1, 1, 0.5))
    assert r.success and r.reason.endswith("from the target"), r.reason


@pytest.mark.parametrize("region", [False, True])
def test_every_answer_with_obstacles_says_its_distances_before_its_closest_pair(region):
    """``solve_all`` with obstacles checks collisions before the distances are measured:
    its words say them in ``solve``'s order, what the verdict measured, the distances,
    then the closest pair."""
    ur5 = arm("ur5")
    far = armik.Sphere(0.05, (2.0, 0.0, 0.0))
    kw = dict(weights=WEIGHTS, obstacles=[far], **({"bounds": BOUNDS} if region else {}))
    T = _target(ur5) if region else ur5.fk(ur5.random_q(np.random.default_rng(2)))
    rs = ur5.solve_all(T, **kw)
    one = ur5.solve(T, **kw)
    assert len(rs) and one.success
    for r in [*rs, one]:
        said, clear, pair = r.reason.partition("; collision-free: closest ")
        assert clear and pair.endswith("(margin 0 m)"), r.reason
        assert said.endswith(
            f"{r.position_error:.3g} m, {r.orientation_error:.3g} rad from "
            + ("the region's centre, free components apart" if region else "the target")
        ), r.reason
