"""The halfway check of a global plan on a 7R arm (``armik.solve.ladder``): a step whose
halfway pose the swept closed form misses, where a solution lies next to the step's
middle, hides no jump."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .. import conftest

STEP = 0.3  # rad: max_joint_step


def _spin(panda, k: int) -> tuple[np.ndarray, list[pin.SE3]]:
    """A start and the tool turned 1.5 rad about a random axis over 30 waypoints."""
    q = panda.random_q(k + 500)
    T0 = panda.fk(q)
    rng = np.random.default_rng(k)
    rng.normal(size=3)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    return q, [T0 * pin.SE3(pin.exp3(axis * 1.5 * i / 29), np.zeros(3)) for i in range(30)]


def test_a_step_along_a_joint_limit_is_not_a_hidden_jump():
    """Following these spins solves every waypoint within the step (in one, joint 2 on its
    limit throughout); the swept closed form finds no branch halfway along some of its
    steps, but a descent from their middle does, next to both ends: the plan from the same
    q0 solves every waypoint too, verified, within the step, moving no more than following."""
    panda = conftest.arm("panda")
    budget = {"iteration_budget": 2000, "seed": 0}  # deterministic, not timed
    for k in (12, 20):
        q, poses = _spin(panda, k)
        follow = panda.solve_path(poses, q, max_joint_step=STEP, **budget)
        planned = panda.solve_path(poses, q, max_joint_step=STEP, plan="global", **budget)
        assert follow.success.all(), follow.summary()
        assert planned.success.all(), [planned.reason(i) for i in np.flatnonzero(~planned.success)]
        for pose, x in zip(poses, planned.q):
            assert np.abs(pin.log6(pose.actInv(panda.fk(x))).vector).max() <= 1e-6
            assert panda.within_limits(x)
        steps = np.diff(np.vstack([q, planned.q]), axis=0)
        assert np.abs(steps).max() <= STEP + 1e-9
        followed = np.diff(np.vstack([q, follow.q]), axis=0)
        assert np.linalg.norm(steps, axis=1).sum() <= np.linalg.norm(followed, axis=1).sum() + 1e-9
