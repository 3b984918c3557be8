"""The check of a region target equals ``armik.problem.Pose.measure``."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

import armik
from armik.problem import Pose
from armik.verify.region import region_errors


def test_region_errors_are_the_pose_task_measure():
    # a base frame that is not the world's
    a = armik.load("panda", base="panda_link1").kinematics
    assert not a.T_base_world.isIdentity()
    rng = np.random.default_rng(2)
    bounds = np.array([0.005, 0.0, math.inf, 0.05, 0.05, 0.0])
    weights = np.array([1.0, 1.0, 1.0, 0.0, 1.0, 1.0])
    Q = [a.random_q(rng) for _ in range(6)]
    Ts = [a.fk(q) for q in Q]
    targets = [T * pin.exp6(pin.Motion(rng.normal(scale=0.03, size=6))) for T in Ts]
    world = [a.T_base_world.inverse() * T for T in Ts]  # the tip in the world frame
    R_w = np.array([T.rotation for T in world])
    p_w = np.array([T.translation for T in world])
    R_t = np.array([T.rotation for T in targets])
    p_t = np.array([T.translation for T in targets])
    got = region_errors(a.T_base_world, R_w, p_w, R_t, p_t, bounds, weights)
    for i, (T, T_t) in enumerate(zip(Ts, targets)):
        m = Pose(T_t, bounds=bounds, weights=weights).measure(T, 0.0, 0.0)
        np.testing.assert_allclose(got[i], [m.position, m.orientation], rtol=0, atol=1e-12)
    R_w[0, 0, 0] = np.nan
    assert np.isnan(region_errors(a.T_base_world, R_w, p_w, R_t, p_t, bounds, weights)[0]).all()
