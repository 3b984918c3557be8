"""``position_only=True`` beside a task list the compiled path solves (``problem.lower``):
refused by name on every route where a ``Pose`` holds the rotation it would drop; taken
beside a ``Position``, which holds no rotation, the position on an FK computed here."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

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


def test_bounds_beside_a_position_and_a_cone_are_refused_on_every_route():
    """``[Position(p), Axis(a, d, 0.1)]`` lowers to a pose whose rotation the lowering
    chooses (one taking a onto d): ``bounds=`` beside it was read in that rotation's frame,
    so a box free along x let a UR5's tip off along y and z, a success; the keyword spelling
    and ``Position(p, bounds=...)`` read the box in the base frame. Refused by name; the
    Position's own box is taken, the tip off along base x alone on an FK computed here."""
    ur5 = conftest.arm("ur5")
    q = np.array([0.2, -1.0, 1.4, -0.6, 1.1, 0.3])
    T = ur5.fk(q)
    d = T.rotation[:, 2]
    p = T.translation + np.array([0.0, 0.04, 0.0])
    box = (0.05, 0.0, 0.0, 0.0, 0.0, 0.0)
    tasks = [armik.Position(p), armik.Axis((0, 0, 1), d, 0.1)]
    for call in _routes(ur5, tasks, q, {"bounds": box}):
        try:
            call()
        except armik.OptionError as e:
            assert e.option == "bounds" and "armik.Position(p, bounds=(bx, by, bz))" in str(e)
            continue
        raise AssertionError("taken")
    r = ur5.solve([armik.Position(p, bounds=box[:3]), armik.Axis((0, 0, 1), d, 0.1)], q0=q)
    assert r.success, r.reason
    F = ur5.fk(r.q)
    off = F.translation - p
    assert abs(off[0]) <= 0.05 + 1e-6 and np.linalg.norm(off[1:]) <= 1e-6
    assert float(F.rotation[:, 2] @ d) >= np.cos(0.1 + 1e-6)
    r = ur5.solve(tasks, q0=q, bounds=(0,) * 6)  # a box of nothing widens nothing: taken
    assert r.success, r.reason
    assert np.linalg.norm(ur5.fk(r.q).translation - p) <= 1e-6


@pytest.mark.parametrize("within", [0.0, 0.05])
def test_a_free_position_weight_beside_a_position_and_an_axis_is_the_base_frame_s(within):
    """``weights=(0, 1, 1, 1, 1, 1)`` beside ``[Position(p), Axis(a, d)]``: read in the
    frame of the pose's rotation the lowering chose (one taking a onto d), the free x was
    an axis no one named, and a UR5's tip 1.9 cm off along it a success. Read in the base
    frame, as the keyword spelling ``toward=d`` reads it: the same answer, off along base x
    alone on an FK computed here, the axis within its cone."""
    ur5 = conftest.arm("ur5")
    q = np.array([0.2, -1.0, 1.4, -0.6, 1.1, 0.3])
    T = ur5.fk(q)
    d = T.rotation[:, 2]
    p = T.translation + 0.03 * T.rotation[:, 1]
    w = (0, 1, 1, 1, 1, 1)
    tasks = [armik.Position(p), armik.Axis((0, 0, 1), d, within)]
    r = ur5.solve(tasks, q0=q, weights=w)
    keyword = ur5.solve(p, q0=q, cone=(0, 0, 1, within), toward=tuple(d), weights=w)
    assert r.success and keyword.success, (r.reason, keyword.reason)
    np.testing.assert_array_equal(r.q, keyword.q)
    F = ur5.fk(r.q)
    assert np.linalg.norm((F.translation - p)[1:]) <= 1e-6
    assert float(F.rotation[:, 2] @ d) >= np.cos(within + 1e-6)
    batch = ur5.solve_batch([tasks, tasks], q0=q, weights=w, progress=False)
    np.testing.assert_array_equal(batch[1].q, r.q)
