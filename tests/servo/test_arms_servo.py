"""A servo on several tips (``Arms.servo``): each chain its own servo, ticked side by side
(the joined q is each chain's own servo's, bit for bit), every limit on the joined
sequence, the status of the tip most held back, and what is not supported refused by
name."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import OptionError, TargetError
from armik.servo.streams import START as STARTS
from armik.servo.streams import circle, violations

from ..test_arms import dual_irb120


def assert_within_limits(robot, servo, q0, rec) -> None:
    """No commanded position, velocity or acceleration past ``servo``'s limits, by finite
    differences of the record's joint values from q0."""
    over = violations(
        q0, rec.q, robot.lower, robot.upper, servo.velocity_limits, servo.acceleration_limits,
        DT,
    )  # fmt: skip
    assert over == {"position": 0.0, "velocity": 0.0, "acceleration": 0.0}


DT = 0.002
START = np.array([0.0, 0.2, 0.2, 0.0, 0.8, 0.0])  # each IRB 120 of the cell


@pytest.fixture(scope="module")
def cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])


def _streams(cell, q0):
    TL, TR = cell.fk(q0, "l_tool0"), cell.fk(q0, "r_tool0")
    left = circle(TL, 600, DT, radius=0.05)
    right = [TR.translation + np.array([0.0, 0.0, -0.1])] * 600  # a position, 10 cm down
    return left, right


def test_each_chain_is_its_own_servo_and_every_limit_holds(cell):
    q0 = np.concatenate([START, START])
    left, right = _streams(cell, q0)
    servo = cell.servo(q0, dt=DT, acceleration_limits=15.0)
    rec = servo.track([{"l_tool0": a, "r_tool0": b} for a, b in zip(left, right)])
    alone_l = cell.chain("l_tool0").servo(START, dt=DT, acceleration_limits=15.0).track(left)
    alone_r = cell.chain("r_tool0").servo(START, dt=DT, acceleration_limits=15.0).track(right)
    assert rec.q.shape == (600, 12)
    assert np.array_equal(rec.q, np.hstack([alone_l.q, alone_r.q]))
    assert_within_limits(cell, servo, q0, rec)
    # the joined step's errors are the larger tip's; the tips' own FK says where they are
    assert np.array_equal(
        rec.position_error, np.maximum(alone_l.position_error, alone_r.position_error)
    )
    q = rec.q[-1]
    assert np.linalg.norm(cell.fk(q, "r_tool0").translation - right[-1]) < 1e-5
    assert np.linalg.norm(cell.fk(q, "l_tool0").translation - left[-1].translation) < 1e-3
    assert np.array_equal(servo.q, q) and servo.joint_names == cell.joint_names


def test_the_joined_status_is_the_tip_most_held_back(cell):
    q0 = np.concatenate([START, START])
    servo = cell.servo(q0, dt=DT)
    here = cell.fk(q0, "l_tool0")
    far = pin.SE3(np.eye(3), np.array([4.0, -0.5, 0.3]))
    for _ in range(3):
        s = servo.step({"l_tool0": here, "r_tool0": far})
    assert s.tips["l_tool0"].status == "on_target"
    assert s.tips["r_tool0"].status == "out_of_reach"
    assert s.status == "out_of_reach" and "out of reach" in s.reason
    assert s.position_error == s.tips["r_tool0"].position_error > 3.0
    assert np.allclose(s.q[:6], q0[:6], rtol=0.0, atol=1e-12)  # the other arm stays
    assert np.isfinite(s.q).all()


def test_bad_targets_are_refused_by_name(cell):
    servo = cell.servo(np.concatenate([START, START]))
    T = cell.fk(servo.q, "l_tool0")
    with pytest.raises(TargetError, match=r"no target for \['r_tool0'\]"):
        servo.step({"l_tool0": T})
    with pytest.raises(TargetError, match=r"unknown tips \['tool0'\]"):
        servo.step({"l_tool0": T, "r_tool0": T, "tool0": T})
    with pytest.raises(TargetError, match="one target per tip"):
        servo.step(T)
    with pytest.raises(OptionError, match="12 values"):
        cell.servo(START)


def test_what_is_not_supported_is_refused_with_the_way_round(cell):
    with pytest.raises(OptionError, match="self_collision is not supported"):
        cell.servo(np.concatenate([START, START]), self_collision=True)


@pytest.fixture(scope="module")
def elbow_and_hand() -> armik.Arms:
    """The Panda's elbow (``panda_link4``) and hand: chains that share joints 1 to 4."""
    return armik.load("panda", tips=["panda_link4", "panda_hand"])


def test_chains_that_share_joints_step_their_union_within_every_limit(elbow_and_hand):
    robot = elbow_and_hand
    assert robot.shared
    q0 = STARTS["panda"]
    # the hand's pose and the elbow's position along a joint-space sway: 9 rows over 7
    # joints, every tick's targets met by one configuration
    sway = np.array([0.5, -0.3, 0.4, 0.3, -0.5, 0.4, 0.2])
    path = [q0 + 0.2 * np.sin(2 * np.pi * 0.5 * k * DT) * sway for k in range(1, 601)]
    hand = [robot.fk(q, "panda_hand") for q in path]
    elbow = [robot.fk(q, "panda_link4").translation for q in path]
    servo = robot.servo(q0, dt=DT, acceleration_limits=15.0)
    rec = servo.track([{"panda_hand": T, "panda_link4": p} for T, p in zip(hand, elbow)])
    over = violations(q0, rec.q, robot.lower, robot.upper, servo.velocity_limits, 15.0, DT)
    assert over == {"position": 0.0, "velocity": 0.0, "acceleration": 0.0}
    q = rec.q[-1]
    reached = robot.fk(q, "panda_hand")
    assert np.linalg.norm(reached.translation - hand[-1].translation) < 1e-5
    assert np.linalg.norm(pin.log3(hand[-1].rotation @ reached.rotation.T)) < 1e-4
    assert np.linalg.norm(robot.fk(q, "panda_link4").translation - elbow[-1]) < 1e-5
    assert np.max(rec.position_error[100:]) < 1e-5  # once up to speed (from rest)
    assert np.isclose(
        rec.position_error[-1],
        max(
            np.linalg.norm(reached.translation - hand[-1].translation),
            np.linalg.norm(robot.fk(q, "panda_link4").translation - elbow[-1]),
        ),
    )
    assert np.array_equal(servo.q, q) and servo.joint_names == robot.joint_names


def test_a_target_out_of_reach_over_shared_joints_is_said_and_left(elbow_and_hand):
    robot = elbow_and_hand
    q0 = STARTS["panda"]
    hand, elbow = robot.fk(q0, "panda_hand"), robot.fk(q0, "panda_link4").translation
    far = hand.translation + np.array([3.0, 0.0, 0.0])
    servo = robot.servo(q0, dt=DT)
    away = servo.track([{"panda_hand": far, "panda_link4": elbow}] * 300)
    assert away.status[-1] == "out_of_reach" and np.isfinite(away.q).all()
    back = servo.track([{"panda_hand": hand, "panda_link4": elbow}] * 2500)
    assert back.status[-1] == "on_target" and back.position_error[-1] < 1e-4
    Q = np.vstack([away.q, back.q])
    assert violations(q0, Q, robot.lower, robot.upper, servo.velocity_limits,
                      servo.acceleration_limits, DT) == {
        "position": 0.0, "velocity": 0.0, "acceleration": 0.0
    }  # fmt: skip


def test_what_a_servo_over_shared_joints_does_not_take_is_refused(elbow_and_hand):
    robot = elbow_and_hand
    q0 = STARTS["panda"]
    with pytest.raises(OptionError, match="self_collision must be True or False"):
        robot.servo(q0, self_collision="yes")
    with pytest.raises(OptionError, match=r"margin must be a distance"):
        robot.servo(q0, obstacles=[armik.Sphere(0.05, (1.0, 1.0, 1.0))], margin=-0.1)
    with pytest.raises(OptionError, match=r"no option 'weights'.*armik.Pose\(T, weights=...\)"):
        robot.servo(q0, weights=[1.0] * 6)  # no servo takes it: each target says it
    servo = robot.servo(q0)
    with pytest.raises(OptionError, match="share joints: one servo steps their union"):
        servo.servo("panda_hand")
    hand = robot.fk(q0, "panda_hand")
    elsewhere = armik.Pose(hand, frame="panda_link4")
    with pytest.raises(TargetError, match="tip 'panda_hand'.*the servo follows tasks on the tip"):
        servo.step({"panda_hand": elsewhere, "panda_link4": hand.translation})
    with pytest.raises(TargetError, match="the target of tip 'panda_link4'"):
        servo.step({"panda_hand": hand, "panda_link4": "up"})
    bent = hand.homogeneous.copy()
    bent[0, 0] = np.nan  # not a pose: read by the parser, refused naming the tip
    with pytest.raises(TargetError, match="the target of tip 'panda_hand'"):
        servo.step({"panda_hand": bent, "panda_link4": hand.translation})
    with pytest.raises(OptionError, match="q0 must have 7 values"):
        robot.servo(q0[:5])
    with pytest.raises(OptionError, match="q0 must be 7 numbers"):
        robot.servo("up")
    with pytest.raises(OptionError, match="within the joint limits"):
        robot.servo(robot.upper + 0.1)


@pytest.fixture(scope="module")
def pr2() -> armik.Arms:
    """PR2's two grippers: their chains share the torso's lift, a prismatic joint; the
    forearm and wrist rolls are continuous."""
    robots = Path(armik.load("panda").source).parents[2]
    urdf = robots / "pr2_description" / "urdf" / "pr2.urdf"
    return armik.load(urdf, tips=["l_gripper_tool_frame", "r_gripper_tool_frame"])


def test_a_shared_lift_and_continuous_joints_step_within_their_limits(pr2):
    q0 = pr2.middle
    assert pr2.shared == ("torso_lift_joint",)
    up = {tip: pr2.fk(q0, tip).translation + np.array([0.0, 0.0, 0.1]) for tip in pr2.tips}
    servo = pr2.servo(q0, dt=DT)
    rec = servo.track([up] * 1500)
    assert rec.status[-1] == "on_target" and rec.position_error[-1] < 1e-6
    assert_within_limits(pr2, servo, q0, rec)
    for tip in pr2.tips:
        assert np.linalg.norm(pr2.fk(rec.q[-1], tip).translation - up[tip]) < 1e-6


@pytest.mark.parametrize("which", ["panda", "pr2"])
def test_the_rows_over_shared_joints_are_pinocchio_s(which, elbow_and_hand, pr2):
    """The compiled rows of the servo over shared joints (each chain's kernel FK and its
    servo's rows, scattered into the union's columns) against Pinocchio's FK and frame
    Jacobians of the union's model, to 1e-12: a pose's six rows ``-(R_t^T (p - p_t),
    log3(R_t^T R))`` and their Jacobian ``(R_t^T R J_v, Jlog3(R_t^T R) J_w)`` (LOCAL),
    a position's three; revolute joints (the Panda), a prismatic lift and continuous
    joints (PR2)."""
    robot = elbow_and_hand if which == "panda" else pr2
    servo = robot.servo(robot.middle)._union
    union = robot._joint()
    model, data = union.model, union.model.createData()
    rng = np.random.default_rng(7)
    first, second = robot.tips
    for trial in range(20):
        q = robot.random_q(rng)
        near = np.clip(q + rng.uniform(-0.5, 0.5, robot.dof), robot.lower, robot.upper)
        goals = {t: robot.fk(near, t) for t in robot.tips}  # (log3 is ill-conditioned at pi)
        if trial % 2:  # the first tip's position alone
            goals[first] = goals[first].translation
        E, A = servo.rows_at(goals, q)
        assert E.shape == (12,) and A.shape == (12, robot.dof)
        pin.computeJointJacobians(model, data, union.to_pin(q))
        for k, tip in enumerate(robot.tips):
            fid = model.getFrameId(tip)
            T = union.T_base_world * pin.updateFramePlacement(model, data, fid)
            J = pin.getFrameJacobian(model, data, fid, pin.LOCAL)
            goal = goals[tip]
            if not isinstance(goal, pin.SE3):
                goal = pin.SE3(np.eye(3), goal)
            M = goal.rotation.T @ T.rotation
            rows = slice(6 * k, 6 * k + 6)
            assert np.allclose(E[rows][:3], -goal.rotation.T @ (T.translation - goal.translation),
                               rtol=0.0, atol=1e-12)  # fmt: skip
            assert np.allclose(A[rows][:3], M @ J[:3], rtol=0.0, atol=1e-12)
            if tip == first and trial % 2:
                assert not E[rows][3:].any() and not A[rows][3:].any()  # rotation free
                continue
            assert np.allclose(E[rows][3:], -pin.log3(M), rtol=0.0, atol=1e-12)
            assert np.allclose(A[rows][3:], pin.Jlog3(M) @ J[3:], rtol=0.0, atol=1e-12)


def _placed(robot: armik.Arms, q: np.ndarray) -> dict[str, pin.SE3]:
    """Each tip's placement at the robot's q by Pinocchio's FK of the union's model (in
    the base frame), not armik's."""
    union = robot._joint()
    data = union.model.createData()
    pin.framesForwardKinematics(union.model, data, union.to_pin(q))
    return {t: union.T_base_world * data.oMf[union.model.getFrameId(t)] for t in robot.tips}


def test_a_region_over_shared_joints_is_reached_and_held(elbow_and_hand):
    """The hand's target a box 2 cm about a point 6 cm off, its orientation exact, the
    elbow's a 5 cm box about where it is: the hand stops at the box's face, not its
    centre; every limit holds."""
    robot = elbow_and_hand
    q0 = STARTS["panda"]
    start = _placed(robot, q0)
    hand, elbow = start["panda_hand"], start["panda_link4"]
    centre = pin.SE3(hand.rotation, hand.translation + hand.rotation @ [0.06, 0.0, 0.0])
    box = (0.02, 0.02, 0.02, 0.0, 0.0, 0.0)
    targets = {
        "panda_hand": armik.Pose(centre, bounds=box),
        "panda_link4": armik.Pose(elbow, bounds=(0.05, 0.05, 0.05, np.inf, np.inf, np.inf)),
    }
    servo = robot.servo(q0, dt=DT, acceleration_limits=15.0)
    rec = servo.track([targets] * 1000)
    over = violations(q0, rec.q, robot.lower, robot.upper, servo.velocity_limits, 15.0, DT)
    assert over == {"position": 0.0, "velocity": 0.0, "acceleration": 0.0}
    assert rec.status[-1] == "on_target"
    for q in rec.q[-200:]:  # held, by Pinocchio's FK
        at = _placed(robot, q)
        local = centre.rotation.T @ (at["panda_hand"].translation - centre.translation)
        assert np.all(np.abs(local) <= 0.02 + 1e-6)
        assert np.linalg.norm(pin.log3(centre.rotation.T @ at["panda_hand"].rotation)) < 1e-6
        assert np.all(np.abs(at["panda_link4"].translation - elbow.translation) <= 0.05 + 1e-6)
    assert np.isclose(local[0], -0.02, atol=1e-5)  # at the face nearest the start
    assert rec.position_error[-1] > 0.039  # from the box's centre, as a chain's servo says


@pytest.fixture(scope="module")
def talos() -> armik.Arms:
    """TALOS's two hands: their chains share the torso's two joints."""
    from importlib import metadata

    share = Path(str(metadata.distribution("example-robot-data").locate_file("cmeel.prefix")))
    urdf = share / "share/example-robot-data/robots/talos_data/robots/talos_reduced.urdf"
    return armik.load(urdf, tips=["gripper_left_base_link", "gripper_right_base_link"])


def test_an_axis_and_a_look_at_over_shared_joints_are_held_in_their_cones(talos):
    """The left hand 3 cm up with its z axis within 0.05 rad of a direction 0.4 rad off
    its own; the right hand where it is, its z axis on the line to a point (a look-at):
    both held by Pinocchio's FK, every limit on the sequence, on target (the cone's edge
    one row, no singularity)."""
    left, right = talos.tips
    q0 = talos.middle
    start = _placed(talos, q0)
    z0 = start[left].rotation[:, 2]
    turn = np.cross(z0, [0.0, 0.0, 1.0])
    z_left = pin.exp3(0.4 * turn / np.linalg.norm(turn)) @ z0
    point = start[right].translation + start[right].rotation @ [0.2, 0.1, 0.5]
    targets = {
        left: [
            armik.Position(start[left].translation + [0.0, 0.0, 0.03]),
            armik.Axis((0, 0, 1), z_left, within=0.05),
        ],
        right: [armik.Position(start[right].translation), armik.LookAt(point)],
    }
    servo = talos.servo(q0, dt=DT)
    rec = servo.track([targets] * 1500)
    assert_within_limits(talos, servo, q0, rec)
    assert rec.status[-1] == "on_target" and "singularity" not in set(rec.status.tolist()[500:])

    def angle(a: np.ndarray, b: np.ndarray) -> float:
        return float(np.arctan2(np.linalg.norm(np.cross(a, b)), a @ b))

    assert angle(z0, z_left) > 0.39  # it had to turn
    for q in rec.q[-100:]:
        at = _placed(talos, q)
        assert angle(at[left].rotation[:, 2], z_left) <= 0.05 + 1e-9
        sight = point - at[right].translation
        assert angle(at[right].rotation[:, 2], sight) <= 1e-9
        up = at[left].translation - start[left].translation - [0, 0, 0.03]
        assert np.linalg.norm(up) < 1e-9
        assert np.linalg.norm(at[right].translation - start[right].translation) < 1e-9


def test_an_obstacle_over_shared_joints_is_kept_at_the_margin(elbow_and_hand):
    """The hand's circle passes through a sphere; the servo over the elbow and the hand
    keeps it at the margin (each chain's distance by ``Arm.min_distance``), says so, and
    is back on the circle past it; every limit holds."""
    robot = elbow_and_hand
    q0 = STARTS["panda"]
    T0 = robot.fk(q0, "panda_hand")
    sphere = armik.Sphere(0.05, tuple(T0.translation + np.array([0.0, 0.16, -0.16])))
    elbow = armik.Pose(robot.fk(q0, "panda_link4"), bounds=(0.1,) * 3 + (np.inf,) * 3)
    targets = [{"panda_hand": T, "panda_link4": elbow} for T in circle(T0, 3000, DT)]

    def nearest(Q: np.ndarray) -> float:
        return min(
            robot.chain(tip).min_distance(part, [sphere])[0]
            for q in Q
            for tip, part in robot.split(q).items()
        )

    free = robot.servo(q0, dt=DT).track(targets)
    assert nearest(free.q[::10]) < 0.0  # without the sphere the hand passes through it
    servo = robot.servo(q0, dt=DT, obstacles=[sphere], margin=0.01)
    rec = servo.track(targets)
    assert_within_limits(robot, servo, q0, rec)
    assert nearest(rec.q) >= 0.01 - 1e-4
    assert "obstacle" in set(rec.status.tolist())
    end = _placed(robot, rec.q[-1])["panda_hand"]  # back on the circle past the sphere
    assert np.linalg.norm(end.translation - targets[-1]["panda_hand"].translation) < 1e-5


@pytest.fixture(scope="module")
def talos_srdf() -> armik.Arms:
    """TALOS's two hands with its SRDF's pairs that never collide left out."""
    from importlib import metadata

    share = Path(str(metadata.distribution("example-robot-data").locate_file("cmeel.prefix")))
    data = share / "share/example-robot-data/robots/talos_data"
    return armik.load(
        data / "robots/talos_reduced.urdf",
        tips=["gripper_left_base_link", "gripper_right_base_link"],
        srdf=data / "srdf/talos.srdf",
    )


def _between(robot: armik.Arms, Q: np.ndarray) -> float:
    """The smallest distance between a link of the left arm and one of the right, by
    coal on the URDF's collision meshes (not the servo's convex hulls) placed by
    Pinocchio on the union's model."""
    from importlib import metadata

    union = robot._joint()
    share = Path(str(metadata.distribution("example-robot-data").locate_file("cmeel.prefix")))
    urdf = share / "share/example-robot-data/robots/talos_data/robots/talos_reduced.urdf"
    dirs = [str(share / "share")]
    geom = pin.buildGeomFromUrdf(union.model, str(urdf), pin.COLLISION, package_dirs=dirs)
    sides = [
        [k for k, o in enumerate(geom.geometryObjects) if side in o.name]
        for side in ("_left_", "_right_")
    ]
    legs = {k for k, o in enumerate(geom.geometryObjects) if o.name.startswith("leg_")}
    for a in sides[0]:
        for b in sides[1]:
            if a not in legs and b not in legs:
                geom.addCollisionPair(pin.CollisionPair(a, b))
    data, gdata = union.model.createData(), pin.GeometryData(geom)
    # each shape's bounding sphere: a pair whose spheres are FAR apart is farther than any
    # margin asked here, and counts as that distance; the others are measured on the meshes
    spheres = []
    for o in geom.geometryObjects:
        o.geometry.computeLocalAABB()
        spheres.append((np.array(o.geometry.aabb_center), float(o.geometry.aabb_radius)))
    pairs = [(p.first, p.second) for p in geom.collisionPairs]
    nearest = np.inf
    for q in Q:
        pin.updateGeometryPlacements(union.model, data, geom, gdata, union.to_pin(q))
        for k, (a, b) in enumerate(pairs):
            centre = [gdata.oMg[i].act(spheres[i][0]) for i in (a, b)]
            apart = np.linalg.norm(centre[0] - centre[1]) - spheres[a][1] - spheres[b][1]
            if apart > FAR:
                nearest = min(nearest, FAR)
            else:
                nearest = min(nearest, pin.computeDistance(geom, gdata, k).min_distance)
    return nearest


FAR = 0.05  # m: five times the margins these tests ask


def test_self_collision_between_the_chains_is_kept_at_the_margin(talos_srdf):
    """Each hand led in 1.5 s to where the other is: without self_collision the arms pass
    into each other; with it every left-arm link stays the margin from every right-arm
    link (coal on the URDF's meshes), the servo says so, and every limit holds."""
    robot = talos_srdf
    left, right = robot.tips
    q0 = robot.middle
    at = {t: robot.fk(q0, t).translation for t in robot.tips}
    middle = 0.5 * (at[left] + at[right])
    goal = {left: middle + [0.0, -0.05, 0.0], right: middle + [0.0, 0.05, 0.0]}
    stream = [{t: at[t] + min(1.0, k / 750) * (goal[t] - at[t]) for t in at} for k in range(1000)]
    free = robot.servo(q0, dt=DT).track(stream)
    assert free.status[-1] == "on_target"
    assert _between(robot, free.q[-1:]) < 0.0
    servo = robot.servo(q0, dt=DT, self_collision=True, margin=0.01)
    rec = servo.track(stream)
    assert_within_limits(robot, servo, q0, rec)
    assert _between(robot, rec.q[::4]) >= 0.01 - 1e-4
    assert rec.status[-1] == "obstacle" and rec.position_error[-1] > 0.02


def test_the_collision_rows_over_shared_joints_are_the_distances_derivatives(talos_srdf):
    """Each self-collision row's C (the pair's normal on its witness points' Jacobians,
    each from its chain, in the union's columns) is the derivative of the pair's distance,
    which the test measures by coal on the same shapes placed by Pinocchio's FK of the
    union's model: central differences along random directions, the torso's joints
    moving both chains' links at once."""
    import coal

    robot = talos_srdf
    left, right = robot.tips
    q0 = robot.middle
    at = {t: robot.fk(q0, t).translation for t in robot.tips}
    middle = 0.5 * (at[left] + at[right])
    goal = {left: middle + [0.0, -0.05, 0.0], right: middle + [0.0, 0.05, 0.0]}
    servo = robot.servo(q0, dt=DT, self_collision=True, margin=0.01)
    q = servo.track([goal] * 400).q[-1]  # the hands at the margin
    rows = servo._union._collisions
    C = rows.at(q).copy()
    assert len(C) >= 4 and rows.nearest < 0.03
    union = robot._joint()
    model, data = union.model, union.model.createData()
    request = coal.DistanceRequest()
    request.gjk_tolerance = 1e-12

    def placed(k: int, qq: np.ndarray) -> coal.Transform3s:
        c, i = rows.objects[k]
        obj = rows.geometry[c].model.geometryObjects[i]
        frame = rows.arms[c].model.frames[obj.parentFrame]
        link = frame.placement.inverse() * obj.placement  # the object in its link's frame
        pin.framesForwardKinematics(model, data, union.to_pin(qq))
        M = data.oMf[model.getFrameId(frame.name)] * link
        return coal.Transform3s(M.rotation, M.translation)

    def distance(a: int, b: int, qq: np.ndarray) -> float:
        Ta, Tb = placed(a, qq), placed(b, qq)
        result = coal.DistanceResult()
        return coal.distance(rows.geoms[a], Ta, rows.geoms[b], Tb, request, result)

    rng = np.random.default_rng(3)
    between = 0
    for k, (a, b) in enumerate(rows.pairs[:6]):
        names = rows.names[a], rows.names[b]
        between += ("left" in names[0]) != ("left" in names[1])
        for _ in range(3):
            v = rng.normal(size=robot.dof)
            h = 1e-6
            slope = (distance(a, b, q + h * v) - distance(a, b, q - h * v)) / (2 * h)
            assert abs(slope - C[k, :-1] @ v) <= 1e-5 * (1.0 + np.linalg.norm(C[k, :-1])), names
    assert between >= 1  # a pair of a link of each arm among them
