"""``Arms`` and ``Arm`` in one vocabulary: a result's errors are the true distances on every
route of several tips, what a region or a weighting measured beside them (``measured``);
options a chain's own batch or path takes are taken where the chains share no joint; a
flat list of tasks naming their frames is the dict's request, in a batch and a path too.
Every success checked on Pinocchio's FK of the whole URDF."""

from __future__ import annotations

from importlib import metadata
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
from tests.conftest import whole_placements

from .test_arms import dual_irb120

SHARE = Path(str(metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share")))
TALOS = SHARE / "example-robot-data/robots/talos_data/robots/talos_reduced.urdf"
HANDS = ["gripper_left_base_link", "gripper_right_base_link"]
OFFSET = pin.SE3(np.eye(3), np.array([0.02, 0.0, 0.0]))  # 2 cm from the region's centre
BOX = (0.05, 0.05, 0.05, 0.0, 0.0, 0.0)  # a 5 cm box, the rotation exact


@pytest.fixture(scope="module")
def cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])


@pytest.fixture(scope="module")
def talos() -> armik.Arms:
    return armik.load(TALOS, tips=HANDS)


def _whole(robot: armik.Arms, source: str | Path):
    model = pin.buildModelFromXML(source) if "<robot" in str(source) else None
    if model is None:
        model = pin.buildModelFromUrdf(str(source))
    return model, model.createData()


def _distance(model, data, robot, q, frame: str, T: pin.SE3) -> tuple[float, float]:
    """``frame``'s (position, orientation) distance to ``T`` at ``q`` by Pinocchio's FK of
    the whole URDF."""
    whole_placements(model, data, robot.joint_names, q)
    M = data.oMf[model.getFrameId(frame)]
    return float(np.linalg.norm(M.translation - T.translation)), float(
        np.linalg.norm(pin.log3(T.rotation.T @ M.rotation))
    )


@pytest.mark.parametrize("name", ["cell", "talos"])
def test_a_region_s_result_says_true_distances_and_what_it_measured(name, request):
    """A tip in a 5 cm box around a target 2 cm away: ``position_error`` and ``errors[tip]``
    are the distances to the box's centre by Pinocchio's FK, and ``measured`` what the
    region measured (0 inside it), on chains solved apart and together alike (it was None
    apart; ``errors`` was the region's measure together)."""
    robot = request.getfixturevalue(name)
    model, data = _whole(robot, dual_irb120() if name == "cell" else TALOS)
    left, right = robot.tips
    rng = np.random.default_rng(4)
    for _ in range(3):
        q = robot.random_q(rng)
        T = robot.fk(q)
        centre = T[left] * OFFSET
        r = robot.solve({left: [armik.Pose(centre, bounds=BOX, frame=left)], right: T[right]})
        assert r.success, r.reason
        assert robot.within_limits(r.q)
        pos, ori = _distance(model, data, robot, r.q, left, centre)
        assert r.errors[left][0] == pytest.approx(pos, abs=1e-9)
        assert r.errors[left][1] == pytest.approx(ori, abs=1e-6)
        assert r.position_error == pytest.approx(max(pos, r.errors[right][0]), abs=1e-9)
        assert pos > 1e-3  # the box's centre is not where the tip is held
        assert r.measured is not None and r.measured[0] < 1e-6  # inside the region
        for tip, Tt in ((right, T[right]),):
            assert _distance(model, data, robot, r.q, tip, Tt)[0] < 1e-6


@pytest.mark.parametrize("name", ["cell", "talos"])
def test_a_weighted_result_says_the_rotation_it_left_free(name, request):
    """A tip's rotation weighted 0: ``errors[tip]`` is its true angle to the target's
    rotation, as ``orientation_error`` is (it was 0 where the chains share joints)."""
    robot = request.getfixturevalue(name)
    model, data = _whole(robot, dual_irb120() if name == "cell" else TALOS)
    left, right = robot.tips
    q = robot.random_q(2)
    T = robot.fk(q)
    turned = T[left] * pin.SE3(pin.exp3(np.array([0.0, 0.0, 0.3])), np.zeros(3))
    weights = (1, 1, 1, 0, 0, 0)
    r = robot.solve({left: [armik.Pose(turned, weights=weights, frame=left)], right: T[right]})
    assert r.success, r.reason
    pos, ori = _distance(model, data, robot, r.q, left, turned)
    assert pos < 1e-6 and ori > 0.05
    assert r.errors[left][1] == pytest.approx(ori, abs=1e-6)
    assert r.orientation_error == pytest.approx(ori, abs=1e-6)
    assert r.measured is not None and r.measured[1] < 1e-6


def test_a_batch_of_independent_chains_keeps_what_each_row_measured(cell):
    """Each chain's batch measures its region: the joined rows keep it in ``measured`` as
    the one-arm batch does (it was NaN), the distances in ``position_error``."""
    left = cell.chain("l_tool0")
    rng = np.random.default_rng(6)
    Q = cell.random_q(rng, 4)
    rows = {"l_tool0": [cell.fk(q, "l_tool0") * OFFSET for q in Q]}
    rows["r_tool0"] = [cell.fk(q, "r_tool0") for q in Q]
    b = cell.solve_batch(rows, q0=Q, bounds=BOX)
    alone = left.solve_batch(rows["l_tool0"], q0=Q[:, :6], bounds=BOX)
    assert b.success.all() and alone.success.all()
    assert not np.isnan(alone.measured[:, 0]).any()
    np.testing.assert_array_equal(b.measured[:, 0], alone.measured[:, 0])
    np.testing.assert_array_equal(b.position_error, alone.position_error)
    for i, q in enumerate(b.q):
        assert cell.within_limits(q)
        T = cell.fk(q, "l_tool0")
        assert np.linalg.norm(T.translation - rows["l_tool0"][i].translation) == pytest.approx(
            b.position_error[i], abs=1e-9
        )


def test_a_path_holds_a_joint_of_a_chain_as_that_chain_s_path_does(cell):
    """``hold=`` on a path of chains that share no joint: each chain's path holds its own
    joints, as ``Arm.solve_path`` does (it was refused on any chain but a 7-joint one)."""
    rng = np.random.default_rng(8)
    q0 = cell.random_q(rng)
    toward = np.sign(cell.middle - q0)  # every waypoint within the limits
    toward[0] = 0.0
    steps = [q0 + 0.03 * k * toward for k in range(4)]
    rows = {tip: [cell.fk(q, tip) for q in steps] for tip in cell.tips}
    p = cell.solve_path(rows, q0, hold={"l_joint_1": None})
    left = cell.chain("l_tool0").solve_path(rows["l_tool0"], q0[:6], hold={"l_joint_1": None})
    assert p.success.all(), p.reasons
    np.testing.assert_array_equal(p.q[:, :6], left.q)
    assert np.abs(p.q[:, 0] - q0[0]).max() < 1e-9  # held at q0's value
    for q, i in zip(p.q, range(len(steps))):
        assert cell.within_limits(q)
        for tip in cell.tips:
            err = pin.log6(rows[tip][i].actInv(cell.fk(q, tip))).vector
            assert np.linalg.norm(err) < 1e-6


def _rows(robot: armik.Arms, n: int, seed: int) -> tuple[np.ndarray, dict, list]:
    """n configurations, each tip's poses at them as the dict's rows, and the same rows as
    flat lists of tasks naming their frames."""
    Q = robot.random_q(seed, n)
    poses = {tip: [robot.fk(q, tip) for q in Q] for tip in robot.tips}
    flat = [[armik.Pose(poses[tip][i], frame=tip) for tip in robot.tips] for i in range(n)]
    return Q, poses, flat


@pytest.mark.parametrize("name", ["cell", "talos"])
def test_batch_and_path_take_rows_of_flat_task_lists_as_the_dict(name, request):
    """``solve_batch`` and ``solve_path`` take N rows, each a flat list of tasks naming their
    frames, as ``solve`` takes one: the same answers as the dict's (they were refused)."""
    robot = request.getfixturevalue(name)
    model, data = _whole(robot, dual_irb120() if name == "cell" else TALOS)
    Q, poses, flat = _rows(robot, 3, 12)
    b = robot.solve_batch(flat)
    np.testing.assert_array_equal(b.q, robot.solve_batch(poses).q)
    assert b.success.all(), b.reasons
    for i, q in enumerate(b.q):
        assert robot.within_limits(q)
        for tip in robot.tips:
            pos, ori = _distance(model, data, robot, q, tip, poses[tip][i])
            assert pos < 1e-6 and ori < 1e-6
    p = robot.solve_path(flat, Q[0])
    np.testing.assert_array_equal(p.q, robot.solve_path(poses, Q[0]).q)
    np.testing.assert_array_equal(p.success, robot.solve_path(poses, Q[0]).success)


def test_rows_naming_other_tips_are_refused_naming_the_row(cell):
    _, _, flat = _rows(cell, 2, 13)
    with pytest.raises(armik.TargetError, match="row 1 of the tasks gives tips"):
        cell.solve_batch([flat[0], flat[1][:1]])


@pytest.mark.parametrize("name", ["cell", "talos"])
def test_a_servo_steps_to_a_flat_task_list_as_to_the_dict(name, request):
    """``step`` and ``track`` take a flat list of tasks naming their frames, as
    ``Arms.solve`` does: the same ticks as the dict's (it was a ``TargetError``)."""
    robot = request.getfixturevalue(name)
    q0 = robot.random_q(14)
    T = robot.fk(robot.random_q(15))
    flat = [armik.Pose(T[tip], frame=tip) for tip in robot.tips]
    by_dict, by_list = robot.servo(q0), robot.servo(q0)
    for _ in range(3):
        np.testing.assert_array_equal(by_list.step(flat).q, by_dict.step(T).q)
    track = robot.servo(q0).track([flat] * 3)
    np.testing.assert_array_equal(track.q, robot.servo(q0).track([T] * 3).q)


@pytest.mark.parametrize("name", ["cell", "talos"])
def test_limits_replaced_on_every_chain_that_holds_the_joint(name, request):
    """``with_limits`` as on one arm: the robot's limits, each chain's and every answer
    inside the new ones, a shared torso joint's on both hands' chains (it was missing)."""
    robot = request.getfixturevalue(name)
    joint = robot.joint_names[0]
    narrow = robot.with_limits({joint: (-0.1, 0.1)})
    assert isinstance(narrow, armik.Arms) and narrow.joint_names == robot.joint_names
    assert (narrow.lower[0], narrow.upper[0]) == (-0.1, 0.1)
    assert robot.lower[0] < -0.1  # the robot it was made from keeps its own
    for tip in narrow.tips:
        chain = narrow.chain(tip)
        if joint in chain.joint_names:
            i = chain.joint_names.index(joint)
            assert (chain.lower[i], chain.upper[i]) == (-0.1, 0.1)
    assert (np.abs(narrow.random_q(3, 20)[:, 0]) <= 0.1).all()
    r = narrow.solve(narrow.fk(narrow.random_q(4)), q0=narrow.random_q(5))
    assert r.success and narrow.within_limits(r.q) and abs(r.q[0]) <= 0.1
    with pytest.raises(armik.JointError, match="unknown joint 'nope'; this robot's joints"):
        robot.with_limits({"nope": (0.0, 1.0)})


@pytest.mark.parametrize("name", ["cell", "talos"])
def test_joints_locked_on_every_chain(name, request):
    """``with_locked`` as on one arm: the joint leaves every chain, the rest solved."""
    robot = request.getfixturevalue(name)
    joint = robot.joint_names[0]
    locked = robot.with_locked({joint: 0.05})
    assert joint not in locked.joint_names and locked.dof == robot.dof - 1
    model, data = _whole(robot, dual_irb120() if name == "cell" else TALOS)
    q = locked.random_q(6)
    T = locked.fk(q)
    r = locked.solve(T)
    assert r.success and locked.within_limits(r.q)
    full = dict(zip(locked.joint_names, r.q))
    full[joint] = 0.05
    for tip in locked.tips:
        whole_placements(model, data, list(full), list(full.values()))
        base = data.oMf[model.getFrameId(locked.base)]
        M = base.actInv(data.oMf[model.getFrameId(tip)])
        assert np.linalg.norm(pin.log6(T[tip].actInv(M)).vector) < 1e-6
    with pytest.raises(armik.JointError, match="'nope'"):
        robot.with_locked({"nope": 0.0})


def test_names_and_frames_as_one_arm_s(talos):
    """``base``, ``neutral``, ``joint_types`` and ``frames()`` read as ``Arm``'s, over
    ``joint_names`` (they were missing)."""
    left = talos.chain(HANDS[0])
    assert talos.base == left.base
    own = dict(zip(left.joint_names, left.neutral))
    assert [talos.neutral[talos.joint_names.index(n)] for n in own] == list(own.values())
    assert talos.joint_types == ["revolute"] * talos.dof
    assert set(left.frames()) <= set(talos.frames()) and "arm_right_4_link" in talos.frames()
    assert len(talos.frames()) == len(set(talos.frames()))
    q = talos.random_q(7)
    for frame in ("arm_left_4_link", "arm_right_4_link"):
        assert frame in talos.frames()
        talos.fk(q, frame)


@pytest.mark.parametrize("q0", ["x", [object()] * 12, np.ones(12) * 1j])
def test_a_batch_or_path_q0_that_is_not_numbers_is_an_option_error(cell, q0):
    """As ``solve``'s q0: an ``OptionError`` naming q0 (it was numpy's ValueError or
    TypeError, or a complex q0 cast to its real part with a warning)."""
    rows = {tip: [cell.fk(cell.middle, tip)] for tip in cell.tips}
    for call in (cell.solve_batch, lambda r, q0: cell.solve_path(r, q0)):
        with pytest.raises(armik.OptionError, match="q0 must be None, one configuration") as e:
            call(rows, q0=q0)
        assert e.value.option == "q0"


@pytest.mark.parametrize("frame", [["l_tool0"], {}, 3])
def test_a_frame_that_is_no_name_is_a_frame_error(cell, frame):
    """``fk``, ``jacobian`` and ``chain`` given a frame that is no name: a ``FrameError``
    (a list or a dict raised Python's TypeError: unhashable)."""
    q = cell.middle
    with pytest.raises(armik.FrameError):
        cell.fk(q, frame)
    with pytest.raises(armik.FrameError):
        cell.jacobian(q, frame)
    with pytest.raises(armik.FrameError):
        cell.chain(frame)


def test_a_misspelt_frame_names_the_closest_frames(talos):
    """A frame on no chain: the closest frames of every chain, not only the tips (``fk``
    takes any frame of a chain, as ``Arm.fk`` does)."""
    q = talos.middle
    with pytest.raises(armik.FrameError, match="closest: 'arm_right_4_link'") as e:
        talos.fk(q, "arm_right_4_lnk")
    assert e.value.frame == "arm_right_4_lnk" and "arm_right_4_link" in e.value.candidates
    with pytest.raises(armik.FrameError, match="is on no chain of tips"):
        talos.jacobian(q, "nope", reference="local")


@pytest.mark.parametrize("spelling", ["flat", "tasks"])
def test_a_tip_out_of_reach_said_as_tasks_is_the_dict_s_answer(talos, spelling):
    """Over a shared torso, a hand's exact position 3 m away said as a task (a flat list,
    or a tip's task list) is ``unreachable`` at once, naming the hand, the other hand
    solved: the answer of the dict of plain targets (it was a not_converged compromise
    after the whole budget, both hands missed)."""
    left, right = HANDS
    T = talos.fk(talos.random_q(3))
    far = T[right].translation + np.array([3.0, 0.0, 0.0])
    plain = talos.solve({left: T[left], right: far})
    if spelling == "flat":
        said = talos.solve([armik.Pose(T[left], frame=left), armik.Position(far, frame=right)])
    else:
        said = talos.solve({left: [armik.Pose(T[left])], right: [armik.Position(far)]})
    assert said.status is armik.Status.UNREACHABLE and f"tip {right!r}" in said.reason
    np.testing.assert_array_equal(said.q, plain.q)
    assert said.errors == plain.errors
    model, data = _whole(talos, TALOS)
    pos, ori = _distance(model, data, talos, said.q, left, T[left])
    assert pos < 1e-6 and ori < 1e-6 and talos.within_limits(said.q)
    assert said.errors[right][0] == pytest.approx(
        _distance(model, data, talos, said.q, right, pin.SE3(np.eye(3), far))[0], abs=1e-9
    )


def test_a_joint_held_at_q0_s_value_is_held_so_on_every_restart():
    """Over shared joints ``hold={joint: None}`` is ``hold={joint: q0[joint]}``: the same
    answer, found within the budget. Each restart's chains held the joint at the restart's
    random value instead, so that their starts missed and spent the budget (1 restart, a
    failure, where the value said gave an answer after 3)."""
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"])
    rng = np.random.default_rng(61)
    j = 2
    joint = robot.joint_names[j]
    found = 0
    for _ in range(6):
        q0, q = robot.random_q(rng), robot.random_q(rng)
        q[j] = q0[j]
        T = robot.fk(q)
        # restarts counted, not timed: the same restarts on a busy machine
        budget = {"timeout": 10.0, "max_restarts": 8}
        by_value = robot.solve(T, q0=q0, hold={joint: float(q0[j])}, **budget)
        at_q0 = robot.solve(T, q0=q0, hold={joint: None}, **budget)
        np.testing.assert_array_equal(at_q0.q, by_value.q)
        assert at_q0.success == by_value.success and at_q0.restarts == by_value.restarts
        if at_q0.success:
            found += 1
            assert at_q0.q[j] == q0[j] and robot.within_limits(at_q0.q)
            for tip in robot.tips:
                assert np.linalg.norm(pin.log6(T[tip].actInv(robot.fk(at_q0.q, tip))).vector) < 1e-6
    assert found >= 5


def test_the_order_tips_are_given_in_is_no_part_of_the_request(talos):
    """Over a shared torso, ``{right: ..., left: ...}``, ``{left: ..., right: ...}`` and a
    flat list in either order are one request: the same answer (the order a dict or a list
    gave the tips in chose which hand's start set the torso, and so the answer)."""
    left, right = HANDS
    model, data = _whole(talos, TALOS)
    rng = np.random.default_rng(17)
    for _ in range(3):
        T = talos.fk(talos.random_q(rng))
        first = talos.solve({left: T[left], right: T[right]})
        spellings = [
            {right: T[right], left: T[left]},
            [armik.Pose(T[right], frame=right), armik.Pose(T[left], frame=left)],
            [armik.Pose(T[left], frame=left), armik.Pose(T[right], frame=right)],
        ]
        for said in spellings:
            np.testing.assert_array_equal(talos.solve(said).q, first.q)
        np.testing.assert_array_equal(talos.solve_all(spellings[0])[0].q, first.q)
        assert first.success and talos.within_limits(first.q)
        for tip in HANDS:
            pos, ori = _distance(model, data, talos, first.q, tip, T[tip])
            assert pos < 1e-6 and ori < 1e-6


@pytest.mark.parametrize("name", ["cell", "talos"])
def test_a_posture_of_another_length_is_said_of_the_robot(name, request):
    """Over shared joints as apart: the posture is one value a joint of the robot (the
    union's check said "the arm")."""
    robot = request.getfixturevalue(name)
    with pytest.raises(armik.OptionError, match=f"the robot {robot.dof} joints") as e:
        robot.solve(robot.fk(robot.middle), prefer=armik.Posture(np.zeros(3)))
    assert e.value.option == "prefer"


@pytest.mark.parametrize(("name", "elbow"), [("cell", "l_link_3"), ("talos", "arm_left_4_link")])
def test_an_elbow_s_task_counts_in_its_tip_s_errors(name, elbow, request):
    """``r.errors`` is keyed by tip on every route: an elbow's task in the left tip's list
    counts in the left tip's errors, as a chain solved alone counts it (over shared joints
    the elbow had an entry of its own, the tip's left without it)."""
    robot = request.getfixturevalue(name)
    left, right = robot.tips
    q = robot.random_q(12)
    T = robot.fk(q)
    near = robot.fk(q, elbow).translation + np.array([0.03, 0.0, 0.0])
    box = armik.Position(near, (0.05,) * 3, frame=elbow)
    r = robot.solve({left: [armik.Pose(T[left]), box], right: T[right]})
    assert r.success and robot.within_limits(r.q), r.reason
    assert set(r.errors) == {left, right}
    model, data = _whole(robot, dual_irb120() if name == "cell" else TALOS)
    whole_placements(model, data, robot.joint_names, r.q)
    base = data.oMf[model.getFrameId(robot.base)]
    at = base.actInv(data.oMf[model.getFrameId(elbow)]).translation
    tip = _distance(model, data, robot, r.q, left, T[left])[0]
    assert r.errors[left][0] == pytest.approx(max(float(np.linalg.norm(at - near)), tip), abs=1e-9)
    flat = robot.solve([armik.Pose(T[left], frame=left), box, armik.Pose(T[right], frame=right)])
    np.testing.assert_array_equal(flat.q, r.q)
    assert flat.errors == r.errors


def test_solve_path_names_its_waypoints_as_arm_does(cell):
    """``solve_path(poses=...)`` on several tips, as on one arm: the keyword was
    ``waypoints`` there, so the call ``Arm`` takes raised ``TypeError``."""
    q = cell.middle + 0.1
    poses = {tip: [cell.fk(q, tip)] * 2 for tip in cell.tips}
    path = cell.solve_path(poses=poses, q0=q)
    assert path.success.all()
