"""A task on a frame that a mimic joint off the chain moves with a chain joint (a finger
driven by the elbow): the task solver places that frame as ROS tools and ``Arm.fk(q,
frame=...)`` do, the mimic joint following its driver, not where the chain's model holds
the mimic joint at its reference value."""

from __future__ import annotations

import io
import warnings

import numpy as np
import pytest

import armik

yourdfpy = pytest.importorskip("yourdfpy")

JOINT = (
    '<joint name="{0}" type="{4}"><parent link="{1}"/><child link="{2}"/>'
    '<origin xyz="{3}"/><axis xyz="0 0 1"/>'
    '<limit lower="-2" upper="2" effort="1" velocity="1"/>{5}</joint>'
)
URDF = (
    '<robot name="finger_on_the_elbow"><link name="a"/><link name="b"/><link name="c"/>'
    '<link name="f"/><link name="ft"/>'
    + JOINT.format("j1", "a", "b", "0 0 0.1", "revolute", "")
    + JOINT.format("j2", "b", "c", "0.3 0 0", "revolute", "")
    + JOINT.format("finger", "c", "f", "0.1 0 0", "revolute", '<mimic joint="j2" multiplier="2"/>')
    + JOINT.format("ft_joint", "f", "ft", "0.2 0 0", "fixed", "")
    + "</robot>"
)


@pytest.fixture(scope="module")
def arm():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return armik.load_string(URDF, tip="c")


def _ros(q: np.ndarray) -> np.ndarray:
    """Where ROS tools put frame ``ft`` at q (yourdfpy, the mimic joint following j2)."""
    robot = yourdfpy.URDF.load(io.StringIO(URDF))
    robot.update_cfg({"j1": q[0], "j2": q[1]})
    return robot.get_transform("ft", "a")[:3, 3]


@pytest.mark.parametrize("q_goal", [(0.5, 0.9), (-1.2, 0.4), (0.3, -1.5)])
def test_a_position_on_a_frame_a_mimic_joint_moves_is_reached_where_ros_places_it(arm, q_goal):
    goal = _ros(np.array(q_goal))
    r = arm.solve([armik.Position(goal, frame="ft")], seed=0)
    assert r.success, r.reason
    assert np.linalg.norm(_ros(r.q) - goal) < 1e-6
    assert np.linalg.norm(arm.fk(r.q, frame="ft").translation - goal) < 1e-6


def test_a_success_stands_where_ros_places_the_frame_not_where_the_chain_holds_it(arm):
    """The frame where the chain's model (the finger held at 0) puts it at q: the finger,
    following j2, puts it elsewhere; a success there must stand on ROS's placement."""
    q = np.array([0.5, 0.9])
    elbow = arm.fk(q).translation
    c, s = np.cos(q.sum()), np.sin(q.sum())
    held = elbow + np.array([0.3 * c, 0.3 * s, 0.0])  # the finger at 0: ft 0.3 m along c's x
    r = arm.solve([armik.Position(held, frame="ft")], seed=0)
    assert r.success, r.reason  # the finger bent, ft still reaches that point
    assert np.linalg.norm(_ros(r.q) - held) < 1e-6


def test_a_chain_joint_named_universe_moves_the_frame_as_ros_does():
    """Pinocchio names its root joint 'universe': a URDF joint of that name is the URDF's
    joint, in the frame's placement, its Jacobian and the task solver."""
    text = URDF.replace('name="j1"', 'name="universe"')
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        arm = armik.load_string(text, tip="c")
    robot = yourdfpy.URDF.load(io.StringIO(text))
    q = np.array([0.5, 0.9])
    robot.update_cfg({"universe": q[0], "j2": q[1]})
    goal = robot.get_transform("ft", "a")[:3, 3]
    assert np.linalg.norm(arm.fk(q, frame="ft").translation - goal) < 1e-12
    h = 1e-7
    J = arm.jacobian(q, frame="ft", reference="base")[:3]
    for k in range(2):
        dq = np.zeros(2)
        dq[k] = h
        slope = arm.fk(q + dq, frame="ft").translation - arm.fk(q - dq, frame="ft").translation
        assert np.allclose(J[:, k], slope / (2 * h), atol=1e-6)
    r = arm.solve([armik.Position(goal, frame="ft")], q0=q + 0.2, seed=0)
    assert r.success, r.reason
    robot.update_cfg({"universe": r.q[0], "j2": r.q[1]})
    assert np.linalg.norm(robot.get_transform("ft", "a")[:3, 3] - goal) < 1e-6


def test_over_shared_joints_a_task_on_such_a_frame_is_refused_by_name(tmp_path):
    """Several tips over a shared joint solve on the union of their chains, which holds a
    mimic joint off the chains still: a task on a frame it turns is refused, naming the
    chain that takes it alone, not solved where the frame is not."""
    extra = '<link name="d"/>' + JOINT.format("j3", "b", "d", "0 0.2 0", "revolute", "")
    path = tmp_path / "two.urdf"
    path.write_text(URDF.replace("</robot>", extra + "</robot>"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = armik.load(path, tips=["c", "d"])
    q = np.array([0.5, 0.9, 0.3])
    d = robot.fk(q)["d"].translation
    ft = robot.fk(q, frame="ft").translation
    with pytest.raises(armik.TargetError, match="'ft' is turned by a mimic joint.*chain\\('c'\\)"):
        robot.solve([armik.Position(ft, frame="ft"), armik.Position(d, frame="d")], seed=0)


def test_the_frame_placed_in_one_pass_is_where_fk_and_the_jacobian_put_it(arm):
    """The task solver's one pass (``mimic_frames.placed``) gives the frame's placement and
    Jacobian that ``Arm.fk`` and ``Arm.jacobian`` give, and the Jacobian is the slope."""
    import pinocchio as pin

    from armik.model import mimic_frames

    fid = mimic_frames.full_frame(arm.kinematics, "ft")
    for q in np.random.default_rng(0).uniform(-1.5, 1.5, (10, 2)):
        T, J = mimic_frames.placed(arm.kinematics, q, fid, pin.LOCAL)
        assert T.isApprox(arm.fk(q, frame="ft"), 1e-14)
        assert np.allclose(J, arm.jacobian(q, frame="ft", reference="local"), atol=1e-14)
