"""A task list's position_error and orientation_error are the true distances of its frames to
their targets, whatever its tasks measure for the verdict: a weight of 0 frees an axis for
the verdict (``measured``) and is measured all the same, as ``Arm.solve(T, weights=...)``
measures it (``armik.verify.distances``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik

from ..conftest import arm

ORIENTATION_ONLY = (0.0, 0.0, 0.0, 1.0, 1.0, 1.0)


def _moved(T: pin.SE3, shift) -> pin.SE3:
    return pin.SE3(T.rotation, T.translation + np.asarray(shift, dtype=float))


def test_a_pose_weighted_0_measures_its_frames_distance_all_the_same():
    T = pin.SE3(np.eye(3), np.array([0.3, 0.0, 0.5]))
    pose = armik.Pose(T, weights=ORIENTATION_ONLY)
    at = _moved(T, (0.2, 0.0, 0.0))
    assert pose.measure(at, 1e-6, 1e-6).within  # the verdict's: the position free
    centre = pose.centre()
    assert centre is not pose
    assert centre.measure(at, 1e-6, 1e-6).position == pytest.approx(0.2, abs=1e-12)
    # an infinite bound frees its component for the verdict, not for the distance
    free = armik.Pose(T, bounds=(np.inf, 0, 0, 0, 0, 0))
    assert free.measure(at, 1e-6, 1e-6).within
    assert free.centre().measure(at, 1e-6, 1e-6).position == pytest.approx(0.2, abs=1e-12)
    exact = armik.Pose(T)
    assert exact.centre() is exact
    assert exact.centre().measure(at, 1e-6, 1e-6).position == pytest.approx(0.2)


def test_a_weighted_pose_beside_a_task_on_another_frame_reports_the_tips_distance():
    """Alone the pose is lowered to the compiled path, which reports the tip's 0.2 m; beside
    a loose position of another link (the task solver) it reports the same."""
    panda = arm("panda")
    q = panda.middle + 0.1
    T = _moved(panda.fk(q), (0.2, 0.0, 0.0))
    link4 = panda.fk(q, "panda_link4").translation
    pose = armik.Pose(T, weights=ORIENTATION_ONLY)
    alone = panda.solve(pose, q0=q)
    beside = panda.solve([pose, armik.Position(link4, (0.5,) * 3, "panda_link4")], q0=q)
    for r in (alone, beside):
        assert r.success, r.reason
        tip = float(np.linalg.norm(panda.fk(r.q).translation - T.translation))
        assert r.position_error == pytest.approx(tip, abs=1e-9)
        assert r.position_error == pytest.approx(0.2, abs=1e-6)
        assert r.measured is not None and r.measured[0] <= 1e-6
    assert "0.2 m" in beside.reason


def test_a_lone_weighted_pose_on_the_task_solver_says_the_weighted_axes():
    """A weighted pose of a link (no compiled form: the task solver): its reason says the
    verdict measured the weighted axes and how far the link is from its target."""
    panda = arm("panda")
    q = panda.middle + 0.1
    T = _moved(panda.fk(q, "panda_link4"), (0.1, 0.0, 0.0))
    r = panda.solve(armik.Pose(T, weights=ORIENTATION_ONLY, frame="panda_link4"), q0=q)
    assert r.success, r.reason
    far = float(np.linalg.norm(panda.fk(r.q, "panda_link4").translation - T.translation))
    assert r.position_error == pytest.approx(far, abs=1e-9)
    assert r.position_error > 0.05
    assert r.measured is not None and r.measured[0] <= 1e-6
    assert "weighted axes" in r.reason and f"{far:.3g} m" in r.reason


def test_weighted_poses_over_a_shared_torso_report_each_tips_true_distance():
    robots = Path(armik.load("panda").source).parents[2]
    urdf = robots / "talos_data" / "robots" / "talos_reduced.urdf"
    robot = armik.load(urdf, tips=["gripper_left_base_link", "gripper_right_base_link"])
    q = robot.random_q(3)
    T = {t: _moved(robot.fk(q, t), (0.3, 0.0, 0.0)) for t in robot.tips}
    r = robot.solve({t: armik.Pose(v, weights=ORIENTATION_ONLY) for t, v in T.items()})
    assert r.success, r.reason
    far = [float(np.linalg.norm(robot.fk(r.q, t).translation - T[t].translation)) for t in T]
    assert min(far) > 0.1  # the positions free: neither hand is at its target's position
    assert r.position_error == pytest.approx(max(far), abs=1e-9)
    assert r.measured is not None and r.measured[0] <= 1e-6


def test_one_task_on_another_frame_is_not_called_the_tip_s():
    """One task with a region on the Panda's fourth link: its distance to the region's
    centre was "the tip is ... from the region's centre" in the reason, the tip being
    elsewhere; it is the task's frame's, the distance an FK computed here gives."""
    panda = arm("panda")
    q = panda.middle + 0.2
    elbow = panda.fk(q, "panda_link4").translation
    box = armik.Position(elbow + [0.0, 0.0, 0.03], bounds=(0.05,) * 3, frame="panda_link4")
    r = panda.solve([box], q0=q, iteration_budget=500)
    assert r.success, r.reason
    reached = panda.fk(r.q, "panda_link4").translation
    assert r.position_error == pytest.approx(np.linalg.norm(reached - box.p), abs=1e-9)
    assert "the tip is" not in r.reason and "frame 'panda_link4' is" in r.reason
    on_tip = panda.solve([armik.Position(panda.fk(q).translation, bounds=(0.05,) * 3)], q0=q)
    assert on_tip.success and "frame '" not in on_tip.reason  # the tip's is no other frame's
