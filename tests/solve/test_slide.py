"""Sliding a colliding answer out of contact (solve/slide.py): the damper's rows against
finite differences, and a slide that keeps the pose and ends clear."""

from __future__ import annotations

import time

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.constraints.collision import checker
from armik.solve import slide as S
from armik.targets.pose import parse_target

from ..conftest import arm, model

BOX = armik.Box((0.3, 0.3, 0.3), (0.5, 0.2, 0.4))


def _distances(a, ch, q, pairs):
    gd = ch.geometry_data()
    pin.updateGeometryPlacements(a.model, a.data, ch.model, gd, a.to_pin(q))
    return np.array([pin.computeDistance(ch.model, gd, k).min_distance for k in pairs])


def test_the_rows_are_the_distances_rates():
    a = model("panda")
    ch = checker(a, (BOX,), True)
    rng = np.random.default_rng(1)
    compared = 0
    for _ in range(8):
        q = a.random_q(rng)
        pin.computeJointJacobians(a.model, a.data, a.to_pin(q))
        A, b, _ = S._rows(a, ch, q, 0.0)
        gd = ch.geometry_data()
        pairs = [
            k
            for k in range(len(ch.pair_names))
            if pin.computeDistance(ch.model, gd, k).min_distance < S.D_ACT
        ]
        assert len(A) == len(pairs) == len(b)
        dq = rng.normal(size=a.dof) * 1e-6
        fd = (_distances(a, ch, q + dq, pairs) - _distances(a, ch, q - dq, pairs)) / 2
        if len(fd):
            # a witness point may jump between faces of a hull: most rows, not every one
            close = np.abs(A @ dq - fd) <= 1e-3 * np.abs(fd).max() + 1e-12
            assert close.mean() >= 0.8
            compared += len(fd)
    assert compared >= 10


def test_a_colliding_answer_slides_out_of_contact_keeping_the_pose():
    a = arm("panda")
    rng = np.random.default_rng(5)
    slid = 0
    for _ in range(30):
        q = a.random_q(rng)
        a.fk(q)
        sphere = armik.Sphere(
            0.05, a.kinematics.data.oMi[4].translation + rng.normal(size=3) * 0.03
        )
        if not a.in_collision(q, [sphere]):
            continue
        ch = checker(a.kinematics, (sphere,), False)
        target = parse_target(a.fk(q))
        out, used = S.slide(a.kinematics, target, q, ch, 0.0, 30, time.thread_time() + 1.0, 1e-7)
        T = a.fk(out)
        assert a.within_limits(out) and 0 < used <= 30
        if used == 30:
            continue  # the elbow cannot leave it near this pose: the restarts' job
        # stopped early: clear of the sphere, at the pose
        assert ch.distance(out)[0] >= 0
        assert np.linalg.norm(T.translation - target.position) < 1e-6
        assert np.linalg.norm(pin.log3(T.rotation.T @ target.rotation)) < 1e-6
        slid += 1
    assert slid >= 3


def test_the_slide_is_an_option_a_followed_path_sets():
    """``slide=True`` slides the first colliding answer out of contact (its reason says
    so); a solve without it restarts at once; a followed path slides, as ``slide=True``
    does. An option decides it, no hidden state: the same call gives the same answer
    wherever it is made."""
    a = arm("panda")
    rng = np.random.default_rng(5)
    seen = 0
    for _ in range(200):
        q = a.random_q(rng)
        a.fk(q)
        sphere = armik.Sphere(0.05, a.kinematics.data.oMi[4].translation)
        if not a.in_collision(q, [sphere]):
            continue
        T = a.fk(q)
        options = dict(obstacles=[sphere], iteration_budget=2000, solver="dls")
        slid = a.solve(T, q0=q, slide=True, **options)
        if "slid out of contact" not in slid.reason:
            continue
        assert "slid out of contact" not in a.solve(T, q0=q, **options).reason
        path = a.solve_path([T], q, **options)
        np.testing.assert_allclose(path.q[0], slid.q, atol=1e-9)  # slid as well
        again = a.solve(T, q0=q, slide=True, **options)
        np.testing.assert_allclose(again.q, slid.q, atol=1e-9)  # coal warm-starts its GJK
        seen += 1
        if seen == 2:
            break
    assert seen == 2
    with pytest.raises(armik.OptionError, match="slide"):
        a.solve(a.fk(a.middle), slide="yes")
