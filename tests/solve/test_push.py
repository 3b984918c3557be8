"""Pushing a colliding answer clear with the servo's collision rows (solve/push.py): the
pose held to first order and the near pairs opened, and a collision-aware solve that
pushes before it restarts (``avoid.PUSH``, off by default) still gives verified, clear
answers."""

from __future__ import annotations

import numpy as np

import armik
from armik.constraints.collision import checker
from armik.solve import avoid, push

from ..conftest import arm

BOX = armik.Box((0.3, 0.3, 0.3), (0.5, 0.2, 0.4))


def _colliding(a, n: int, seed: int) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    found = []
    while len(found) < n:
        q = a.random_q(rng)
        d = a.min_distance(q, [BOX], self_collision=True)[0]
        if -0.02 < d < 0.0:
            found.append(q)
    return found


def test_a_push_opens_the_near_pairs_and_holds_the_pose():
    a = arm("panda")
    ch = checker(a.kinematics, (BOX,), True)
    opened = 0
    for q in _colliding(a, 12, 3):
        before = a.min_distance(q, [BOX], self_collision=True)[0]
        moved = push.pushed(a.kinematics, ch, q, 0.0)
        assert moved is not None  # a pair inside the margin: something to push
        assert a.kinematics.within_limits(moved, 0.0)
        T0, T1 = a.fk(q), a.fk(moved)
        # the pose rows weigh against the pairs': the tip moves a little, the joints more
        assert np.linalg.norm(T1.translation - T0.translation) < 0.05
        opened += a.min_distance(moved, [BOX], self_collision=True)[0] > before
    assert opened >= 9


def test_nothing_to_push_far_from_every_obstacle():
    a = arm("panda")
    far = armik.Sphere(0.05, (3.0, 3.0, 3.0))
    ch = checker(a.kinematics, (far,), False)
    assert push.pushed(a.kinematics, ch, a.middle, 0.01) is None


def test_a_solve_that_pushes_gives_verified_clear_answers(monkeypatch):
    a = arm("panda")
    monkeypatch.setattr(avoid, "PUSH", True)
    rng = np.random.default_rng(11)
    solved = 0
    for _ in range(12):
        q = a.random_q(rng)
        if a.in_collision(q, [BOX], self_collision=True, margin=0.01):
            continue
        T = a.fk(q)
        r = a.solve(T, q0=a.middle, obstacles=[BOX], self_collision=True)
        if not r.success:
            continue
        solved += 1
        assert a.min_distance(r.q, [BOX], self_collision=True)[0] >= -1e-9
        reached = a.fk(r.q)
        assert np.linalg.norm(reached.translation - T.translation) <= 1e-6
    assert solved >= 5
