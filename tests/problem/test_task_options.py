"""``position_only=True`` beside a task list the compiled path solves (``problem.lower``):
refused by name on every route where a ``Pose`` holds the rotation it would drop; taken
beside a ``Position``, which holds no rotation, the position on an FK computed here."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

import armik

from .. import conftest


def _routes(arm, tasks, q, option):
    return [
        lambda: arm.solve(tasks, q0=q, **option),
        lambda: arm.solve_all(tasks, q0=q, **option),
        lambda: arm.solve_batch([tasks, tasks], q0=q, progress=False, **option),
        lambda: arm.solve_path([tasks, tasks], q, **option),
    ]


def test_position_only_beside_a_pose_task_is_refused_on_every_route():
    """``[Pose(T)]`` with ``position_only=True``: the option dropped the pose's rotation,
    and an answer 1 rad from the task's rotation was a success with no orientation error."""
    panda = conftest.arm("panda")
    q = panda.middle + 0.2
    T = panda.fk(q)
    turned = pin.SE3(pin.exp3(np.array([0.0, 0.0, 1.0])) @ T.rotation, T.translation)
    for call in _routes(panda, [armik.Pose(turned)], q, {"position_only": True}):
        try:
            r = call()
        except armik.OptionError as e:
            assert e.option == "position_only"
            assert "drops the rotation a Pose task holds" in str(e)
            continue
        first = r[0] if not isinstance(r, armik.IKResult) else r
        F = panda.fk(first.q)
        off = np.linalg.norm(pin.log3(turned.rotation.T @ F.rotation))
        raise AssertionError(f"taken: success {first.success}, {off:.3f} rad off the Pose")


def test_position_only_beside_a_position_task_is_taken():
    """A ``Position`` holds no rotation: nothing is dropped, and the answer reaches it."""
    ur5 = conftest.arm("ur5")
    p = ur5.fk(ur5.random_q(2)).translation
    r = ur5.solve([armik.Position(p)], q0=ur5.middle, position_only=True)
    assert r.success, r.reason
    assert np.linalg.norm(ur5.fk(r.q).translation - p) <= 1e-6


def test_bounds_beside_an_axis_that_says_its_own_name_the_tasks_that_take_a_box():
    """``bounds=`` beside ``[Position(p), Axis(a, d)]`` (the spin about the axis freed by
    bounds of the list's own): the refusal named ``armik.Pose(T, bounds=...)`` alone, a
    task the list does not hold; it names the Position's box and why the list has bounds."""
    ur5 = conftest.arm("ur5")
    T = ur5.fk(ur5.random_q(4))
    tasks = [armik.Position(T.translation), armik.Axis((0, 0, 1), T.rotation[:, 2])]
    try:
        ur5.solve(tasks, bounds=(0.01, 0.01, 0.01, 0, 0, 0))
    except armik.OptionError as e:
        assert e.option == "bounds"
        assert "armik.Position(p, bounds=...)" in str(e)
        assert "an armik.Axis or armik.LookAt says the bounds of what it frees itself" in str(e)
    else:
        raise AssertionError("taken")
