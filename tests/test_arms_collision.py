"""``Arms.min_distance``, ``Arms.in_collision`` and ``Arms.intervals``, as ``Arm``'s: with one
tip the same answers as the ``Arm``; on TALOS's two hands every chain's links at the
robot's configuration, between the chains too, checked by coal on Pinocchio's placements
of the whole URDF; intervals of the chain its parameter belongs to."""

from __future__ import annotations

import math
import re
from pathlib import Path

import coal
import numpy as np
import pinocchio as pin
import pytest

import armik
from tests.conftest import whole_placements

from .test_arms_parity import HANDS, SHARE, TALOS

OBSTACLES = [armik.Box((0.3, 0.3, 0.3), (0.4, 0.0, 0.4)), armik.HalfSpace((0, 0, 1), -0.2)]


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_one_tip_measures_as_its_arm(name):
    arm = armik.load(name)
    robot = armik.load(name, tips=[arm.tip])
    for q in arm.random_q(1, 12):
        for obstacles, itself in ((OBSTACLES, False), ((), True), (OBSTACLES, True)):
            d, pair = robot.min_distance(q, obstacles, itself)
            expected, expected_pair = arm.min_distance(q, obstacles, itself)
            assert pair == expected_pair and d == pytest.approx(expected, abs=1e-6)
            for margin in (0.0, 0.05):
                got = robot.in_collision(q, obstacles, itself, margin=margin)
                assert got == arm.in_collision(q, obstacles, itself, margin=margin)


def _hulls():
    """TALOS's whole URDF, its collision meshes as convex hulls (as armik checks them)."""
    model = pin.buildModelFromUrdf(str(TALOS))
    geom = pin.buildGeomFromUrdf(model, str(TALOS), pin.COLLISION, package_dirs=[str(SHARE)])
    for o in geom.geometryObjects:
        if isinstance(o.geometry, coal.BVHModelBase):
            o.geometry.buildConvexHull(True, "Qt")
            o.geometry = o.geometry.convex
    return model, geom


def _coal(geometry_a, Ma: pin.SE3, geometry_b, Mb: pin.SE3) -> float:
    return coal.distance(
        geometry_a,
        coal.Transform3s(Ma.rotation, Ma.translation),
        geometry_b,
        coal.Transform3s(Mb.rotation, Mb.translation),
        coal.DistanceRequest(),
        coal.DistanceResult(),
    )


def test_two_hands_are_measured_against_each_other_and_obstacles_at_the_robot_s_q():
    robot = armik.load(TALOS, tips=HANDS, srdf=TALOS.parents[1] / "srdf" / "talos.srdf")
    model, geom = _hulls()
    data, gd = model.createData(), pin.GeometryData(geom)
    links = [model.frames[o.parentFrame].name for o in geom.geometryObjects]
    left = [i for i, n in enumerate(links) if n.startswith(("arm_left", "gripper_left"))]
    right = [i for i, n in enumerate(links) if n.startswith(("arm_right", "gripper_right"))]
    # the hands brought together: they overlap, which neither chain alone sees (each holds
    # the other arm where it was cut)
    p = sum(robot.fk(robot.middle, tip).translation for tip in HANDS) / 2 + [0.25, 0.0, 0.0]
    r = robot.solve({HANDS[0]: p + [0, 0.03, 0], HANDS[1]: p - [0, 0.03, 0]})
    assert r.success
    rng = np.random.default_rng(3)
    for q in [r.q, *robot.random_q(rng, 4)]:
        whole_placements(model, data, robot.joint_names, q)
        pin.updateGeometryPlacements(model, data, geom, gd)
        placed = list(gd.oMg)
        d, (a, b) = robot.min_distance(q, self_collision=True)
        ia, ib = links.index(a), links.index(b)
        g = geom.geometryObjects
        assert d == pytest.approx(_coal(g[ia].geometry, placed[ia], g[ib].geometry, placed[ib]))
        between = min(
            _coal(g[i].geometry, placed[i], g[k].geometry, placed[k]) for i in left for k in right
        )
        assert d <= between + 1e-9
        assert robot.in_collision(q, self_collision=True) == (d < 0)
        if d >= 1e-6:  # a margin is a distance: one within it is in collision
            assert robot.in_collision(q, self_collision=True, margin=d + 1e-6)
            assert not robot.in_collision(q, self_collision=True, margin=d - 1e-6)
        # a ball beside the left hand: the nearest of every link the robot moves
        ball = armik.Sphere(0.05, (*(robot.fk(q, HANDS[0]).translation + [0.0, 0.0, 0.12]),))
        d, (link, obstacle) = robot.min_distance(q, [ball])
        world = pin.SE3(ball.placement())  # the base is TALOS's root: world and base agree
        each = [_coal(o.geometry, M, coal.Sphere(0.05), world) for o, M in zip(g, placed)]
        assert obstacle == "obstacles[0] (Sphere)" and link == links[int(np.argmin(each))]
        assert d == pytest.approx(min(each))
    d, pair = robot.min_distance(r.q, self_collision=True)
    assert pair == tuple(HANDS) and d < 0
    for tip in HANDS:
        assert robot.chain(tip).min_distance(robot.split(r.q)[tip], self_collision=True)[0] > 0


def test_bad_collision_queries_are_armik_errors():
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"])
    with pytest.raises(armik.OptionError, match="9 values|7 values|one per joint"):
        robot.min_distance(np.zeros(3), self_collision=True)
    with pytest.raises(armik.CollisionError, match="nothing to measure"):
        robot.min_distance(robot.middle)
    with pytest.raises(armik.CollisionError):
        robot.min_distance(robot.middle, obstacles="box")
    arm = robot.chain("panda_hand")
    for margin in ("1 cm", -0.01, float("nan")):  # not a distance: refused, as one arm's
        with pytest.raises(armik.OptionError, match="margin must be a distance") as said:
            robot.in_collision(robot.middle, self_collision=True, margin=margin)
        with pytest.raises(armik.OptionError) as one:
            arm.in_collision(arm.middle, self_collision=True, margin=margin)
        assert str(said.value) == str(one.value)


def test_intervals_are_the_chain_s_whose_parameter_is_asked():
    robot = armik.load("kuka_iiwa14", tips=["iiwa_link_4", "iiwa_link_ee"])
    arm = robot.chain("iiwa_link_ee")
    q = robot.random_q(np.random.default_rng(2))
    T = {tip: robot.fk(q, tip) for tip in robot.tips}
    got = robot.intervals({"iiwa_link_ee": T["iiwa_link_ee"]}, "swivel", q0=q)
    expected = arm.intervals(T["iiwa_link_ee"], "swivel", q0=robot.split(q)["iiwa_link_ee"])
    assert got == expected and got.branches
    # each interval's middle: its branch's answer at that swivel, checked by Pinocchio's FK
    for label, spans in got.branches.items():
        lo, hi = spans[0]
        answers = arm.solve_all(T["iiwa_link_ee"], swivel=(lo + hi) / 2)
        found = [a for a in answers if a.branch == label]
        assert found and found[0].success
        X = arm.fk(found[0].q)
        assert np.linalg.norm(pin.log6(T["iiwa_link_ee"].actInv(X)).vector) < 1e-6
    one = armik.load("kuka_iiwa14", tips=[arm.tip])
    assert one.intervals({arm.tip: T["iiwa_link_ee"]}, "swivel") == arm.intervals(
        T["iiwa_link_ee"], "swivel"
    )
    with pytest.raises(armik.OptionError, match="one chain's self-motion"):
        robot.intervals(T, "iiwa_joint_1")  # on both chains
    with pytest.raises(armik.OptionError, match="give one tip's target"):
        robot.intervals(T, "swivel")
    with pytest.raises(armik.TargetError, match="iiwa_link_ee"):
        robot.intervals({"iiwa_link_4": T["iiwa_link_4"]}, "iiwa_joint_7")
    with pytest.raises(armik.FrameError, match="unknown tip"):
        robot.intervals({"hand": T["iiwa_link_4"]}, "swivel")
    with pytest.raises(armik.OptionError, match="target must map"):
        robot.intervals(T["iiwa_link_ee"], "swivel")


def dual(name: str) -> str:
    """Two of the bundled ``name`` 1 m apart on one base, links and joints prefixed."""
    text = Path(armik.load(name).source).read_text()
    body = re.sub(r"<!--.*?-->", "", text[text.index("<robot") :], flags=re.S)
    body = body[body.index(">") + 1 : body.rindex("</robot>")]
    children = set(re.findall(r'<child link="([^"]+)"', body))
    base = next(n for n in re.findall(r'<link name="([^"]+)"', body) if n not in children)
    arms = [
        re.sub(
            r'(?<=\s)(name|link)="([^"]+)"',
            lambda m, s=side: f'{m.group(1)}="{s}{m.group(2)}"',
            body,
        )
        + f'<joint name="{side}mount" type="fixed"><parent link="cell"/>'
        f'<child link="{side}{base}"/><origin xyz="0 {y} 0"/></joint>'
        for side, y in (("l_", 0.5), ("r_", -0.5))
    ]
    return '<robot name="dual"><link name="cell"/>' + "".join(arms) + "</robot>"


def test_two_arms_that_share_no_joint_are_checked_against_each_other():
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    down = pin.utils.rpyToMatrix(np.pi, 0.0, 0.0)
    # both tools 8 cm apart between the arms: each chain alone is clear (the other arm
    # held where it was cut), the two arms at their answers overlap
    close = {
        "l_tool0": pin.SE3(down, np.array([0.4, 0.04, 0.3])),
        "r_tool0": pin.SE3(down, np.array([0.4, -0.04, 0.3])),
    }
    plain = robot.solve(close)
    assert plain.success and robot.min_distance(plain.q, self_collision=True)[0] < 0
    rows = {tip: [T] for tip, T in close.items()}
    for given in (
        {"self_collision": True},
        {"constraints": [armik.Collisions(self_collision=True)]},
    ):
        results = [
            robot.solve(close, **given),
            robot.solve_batch(rows, **given)[0],
            robot.solve_path(rows, None, **given)[0],
            *robot.solve_all(close, **given),
        ]
        for r in results:
            d, pair = robot.min_distance(r.q, self_collision=True)
            assert r.success == (d >= 0.0), (r.reason, d, pair)
            if not r.success and r.status == armik.Status.COLLISION and d < 0:
                assert r.closest_pair == pair and "chains' answers together" in r.reason
        assert not results[0].success and results[0].status == armik.Status.COLLISION
    apart = {
        "l_tool0": pin.SE3(down, np.array([0.4, 0.3, 0.3])),
        "r_tool0": pin.SE3(down, np.array([0.4, -0.3, 0.3])),
    }
    r = robot.solve(apart, self_collision=True, margin=0.001)
    assert r.success and r.min_distance >= 0.001
    assert (r.min_distance, r.closest_pair) == robot.min_distance(r.q, self_collision=True)
    b = robot.solve_batch({tip: [T, T] for tip, T in apart.items()}, self_collision=True)
    assert b.success.all() and (b.min_distance >= 0).all() and "collision-free" in b.reason(0)


def test_a_relative_target_out_of_reach_with_options_the_joint_descent_refuses_is_a_failure():
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    left = pin.SE3(pin.utils.rpyToMatrix(np.pi, 0.0, 0.0), np.array([0.4, 0.3, 0.3]))
    beside = pin.SE3(np.eye(3), np.array([0.0, 0.6, 0.0]))
    options = [
        {"self_collision": True},
        {"obstacles": [armik.Sphere(0.05, (2.0, 2.0, 2.0))]},
        {"prefer": "nearest"},
    ]
    for given in options:
        near = {"l_tool0": left, "r_tool0": armik.Relative("r_tool0", "l_tool0", beside)}
        r = robot.solve(near, **given)
        assert r.success
        T = robot.fk(r.q, "l_tool0").actInv(robot.fk(r.q, "r_tool0"))
        assert np.linalg.norm(pin.log6(beside.actInv(T)).vector) < 1e-6
        # 5 m from the left tool: the same call, a failure naming the tip, not an error
        far = armik.Relative("r_tool0", "l_tool0", pin.SE3(np.eye(3), np.array([0.0, 5.0, 0.0])))
        r = robot.solve({"l_tool0": left, "r_tool0": far}, **given)
        assert not r.success and r.status == armik.Status.UNREACHABLE
        assert r.reason.startswith("r_tool0: unreachable") and f"{next(iter(given))}=" in r.reason


def test_a_collision_flag_or_a_parameter_that_is_no_name_is_refused_by_name():
    robot = armik.load("kuka_iiwa14", tips=["iiwa_link_4", "iiwa_link_ee"])
    for flag in ("yes", 1, np.zeros((2, 2))):
        with pytest.raises(armik.CollisionError, match="self_collision must be True or False"):
            robot.min_distance(robot.middle, self_collision=flag)
    T = {"iiwa_link_ee": robot.fk(robot.middle, "iiwa_link_ee")}
    for over in (np.zeros((2, 2)), None, 7):
        with pytest.raises(armik.OptionError, match="over must name a joint") as info:
            robot.intervals(T, over)  # type: ignore[arg-type]
        assert info.value.option == "over"


def test_arms_that_collide_take_another_combination_of_their_answers():
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    rng = np.random.default_rng(0)
    rows = []
    for _ in range(30):  # both tools 8-30 cm apart between the arms, one orientation
        R, c = pin.exp3(rng.normal(size=3)), np.array([rng.uniform(0.2, 0.6), 0.0, 0.35])
        gap = np.array([0.0, rng.uniform(0.04, 0.15), 0.0])
        rows.append({"l_tool0": pin.SE3(R, c + gap), "r_tool0": pin.SE3(R, c - gap)})
    moved = 0  # targets whose first answer collides and another combination does not
    results = [robot.solve(row, self_collision=True) for row in rows]
    for row, r in zip(rows, results):
        d, pair = robot.min_distance(r.q, self_collision=True)
        if r.success:
            assert d >= 0.0
        first = robot.solve(row)
        if r.success and robot.min_distance(first.q, self_collision=True)[0] < 0:
            moved += 1
        if r.status == armik.Status.COLLISION:
            assert not robot.solve_all(row, self_collision=True)[0].success
    assert moved >= 1
    b = robot.solve_batch(
        {tip: [row[tip] for row in rows] for tip in robot.tips}, self_collision=True
    )
    np.testing.assert_array_equal(b.success, [r.success for r in results])
    np.testing.assert_allclose(b.q[b.success], [r.q for r in results if r.success], atol=1e-9)


def test_obstacles_beside_self_collision_are_in_the_closest_pair_a_success_reports():
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    down = pin.utils.rpyToMatrix(np.pi, 0.0, 0.0)
    apart = {
        "l_tool0": pin.SE3(down, np.array([0.5, 0.3, 0.4])),
        "r_tool0": pin.SE3(down, np.array([0.5, -0.3, 0.4])),
    }
    ball = armik.Sphere(0.05, (0.5, 0.3, 0.349))  # 1 mm under the left tool
    given = [
        {"obstacles": [ball], "self_collision": True},
        {"constraints": [armik.Collisions(obstacles=[ball], self_collision=True)]},
    ]
    for options in given:
        r = robot.solve(apart, **options)
        b = robot.solve_batch({tip: [T] for tip, T in apart.items()}, **options)
        assert r.success and b.success[0]
        closest = robot.min_distance(r.q, [ball], True)
        assert (r.min_distance, r.closest_pair) == closest and "obstacles[0]" in closest[1][1]
        assert (b.min_distance[0], b.closest_pair(0)) == robot.min_distance(b.q[0], [ball], True)


def test_two_arms_checked_against_obstacles_say_the_robot_s_closest_pair():
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    down = pin.utils.rpyToMatrix(np.pi, 0.0, 0.0)
    apart = {
        "l_tool0": pin.SE3(down, np.array([0.5, 0.3, 0.4])),
        "r_tool0": pin.SE3(down, np.array([0.5, -0.3, 0.4])),
    }
    balls = [armik.Sphere(0.05, (0.5, 0.3, 0.3)), armik.Sphere(0.05, (0.5, -0.3, 0.32))]
    r = robot.solve(apart, obstacles=balls, margin=0.01)
    b = robot.solve_batch({tip: [T, T] for tip, T in apart.items()}, obstacles=balls, margin=0.01)
    assert r.success and b.success.all()
    d, pair = robot.min_distance(r.q, balls)
    assert r.min_distance == pytest.approx(d, abs=1e-9) and r.closest_pair == pair
    for i in range(2):
        d, pair = robot.min_distance(b.q[i], balls)
        assert b.min_distance[i] == pytest.approx(d, abs=1e-9) and b.closest_pair(i) == pair
        assert "collision-free: closest" in b.reason(i) and "(margin 0.01 m)" in b.reason(i)


def test_three_tips_two_sharing_a_torso_place_every_link_where_the_robot_does():
    # TALOS's hands share the torso, its left foot shares nothing: a link is taken from a
    # chain that moves it, never from one that froze it where it was cut
    robot = armik.load(TALOS, tips=[*HANDS, "leg_left_6_link"])
    model, geom = _hulls()
    data, gd = model.createData(), pin.GeometryData(geom)
    links = [model.frames[o.parentFrame].name for o in geom.geometryObjects]
    g = geom.geometryObjects
    arms = [i for i, n in enumerate(links) if n.startswith(("arm_", "gripper_"))]
    leg = [i for i, n in enumerate(links) if n.startswith("leg_left")]
    fixed = ("base_link", "leg_right")
    for q in robot.random_q(np.random.default_rng(5), 4):
        whole_placements(model, data, robot.joint_names, q)
        pin.updateGeometryPlacements(model, data, geom, gd)
        placed = list(gd.oMg)
        for tip, off in ((HANDS[0], 0.12), (HANDS[1], 0.12), ("leg_left_6_link", 0.3)):
            ball = armik.Sphere(0.05, (*(robot.fk(q, tip).translation + [off, 0.0, 0.12]),))
            each = [
                _coal(o.geometry, M, coal.Sphere(0.05), pin.SE3(ball.placement()))
                for o, M in zip(g, placed)
            ]
            # links fixed to the base (the right leg, held) are checked once, not measured
            each = [e if not links[i].startswith(fixed) else math.inf for i, e in enumerate(each)]
            d, (link, _) = robot.min_distance(q, [ball])
            assert d == pytest.approx(min(each)) and link == links[int(np.argmin(each))]
        d, (a, b) = robot.min_distance(q, self_collision=True)
        ia, ib = links.index(a), links.index(b)
        assert d == pytest.approx(_coal(g[ia].geometry, placed[ia], g[ib].geometry, placed[ib]))
        apart = min(
            _coal(g[i].geometry, placed[i], g[k].geometry, placed[k]) for i in arms for k in leg
        )
        assert d <= apart + 1e-9


def _nearest_in_a_stream(robot, servo, goal, shape, ticks: int) -> float:
    """The smallest distance from ``shape`` to any link of the robot at its middle and
    after each of ``ticks`` ticks toward ``goal``, each by coal on Pinocchio's placements of
    the whole URDF (the base is TALOS's root: world and base agree)."""
    model, geom = _hulls()
    data, gd = model.createData(), pin.GeometryData(geom)
    world = pin.SE3(shape.placement())
    nearest = math.inf
    for tick in range(ticks + 1):
        q = servo.step(goal).q if tick else robot.middle
        whole_placements(model, data, robot.joint_names, q)
        pin.updateGeometryPlacements(model, data, geom, gd)
        for o, M in zip(geom.geometryObjects, gd.oMg):
            nearest = min(nearest, _coal(o.geometry, M, shape.geometry(), world))
    return nearest


def test_a_servo_over_shared_joints_keeps_a_half_space_at_the_margin():
    two = armik.load(TALOS, tips=HANDS)
    # a wall 10 cm before the robot's foremost point (x >= 0 solid: as deep as that point)
    foremost = -_nearest_in_a_stream(two, None, None, armik.HalfSpace((-1.0, 0.0, 0.0), 0.0), 0)
    wall = armik.HalfSpace((-1.0, 0.0, 0.0), -(foremost + 0.1))
    T = two.fk(two.middle)
    goal = {t: pin.SE3(T[t].rotation, T[t].translation + [0.4, 0.0, 0.0]) for t in HANDS}
    servo = two.servo(two.middle, obstacles=[wall], margin=0.01)  # both hands sent through it
    assert _nearest_in_a_stream(two, servo, goal, wall, 800) >= 0.01 - 1e-4


def test_a_servo_over_shared_joints_keeps_clear_with_a_third_tip_off_the_torso():
    two = armik.load(TALOS, tips=HANDS)
    # a thick box: held, the left hand stops at the margin before it
    x = float(two.fk(two.middle, HANDS[0]).translation[0]) + 0.15
    box = armik.Box((1.0, 4.0, 4.0), (x + 0.5, 0.0, 0.0))
    servo = two.servo(two.middle, obstacles=[box], margin=0.01)
    T = two.fk(two.middle)
    goal = {**T, HANDS[0]: pin.SE3(T[HANDS[0]].rotation, T[HANDS[0]].translation + [0.4, 0, 0])}
    for _ in range(800):
        step = servo.step(goal)
    assert two.min_distance(step.q, [box])[0] >= 0.01 - 1e-6
    # the hands on the torso and the left foot, which shares none of their joints: each
    # hand's links are read from its own chain (the other hand's holds them frozen)
    srdf = TALOS.parents[1] / "srdf" / "talos.srdf"
    three = armik.load(TALOS, tips=[*HANDS, "leg_left_6_link"], srdf=srdf)
    q0, T = three.middle, three.fk(three.middle)
    ahead = T[HANDS[0]].translation
    for dx in np.arange(0.15, 0.5, 0.01):  # a ball 8 cm or more before the left hand
        ball = armik.Sphere(0.05, (*(ahead + [dx, 0.0, 0.0]),))
        if _nearest_in_a_stream(three, None, None, ball, 0) > 0.08:
            break
    goal = {**T, HANDS[0]: pin.SE3(T[HANDS[0]].rotation, ahead + [0.3, 0.0, 0.0])}
    servo = three.servo(q0, obstacles=[ball], margin=0.01)  # the hand sent through it
    assert _nearest_in_a_stream(three, servo, goal, ball, 800) >= 0.01 - 1e-4
    # each hand led in 1.5 s to where the other is: every left-arm link stays the margin
    # from every right-arm link
    at = {t: T[t].translation for t in HANDS}
    middle = 0.5 * (at[HANDS[0]] + at[HANDS[1]])
    end = {HANDS[0]: middle - [0.0, 0.05, 0.0], HANDS[1]: middle + [0.0, 0.05, 0.0]}
    servo = three.servo(q0, self_collision=True, margin=0.01)
    model, geom = _hulls()
    data, gd = model.createData(), pin.GeometryData(geom)
    links = [model.frames[o.parentFrame].name for o in geom.geometryObjects]
    left = [i for i, n in enumerate(links) if n.startswith(("arm_left", "gripper_left"))]
    right = [i for i, n in enumerate(links) if n.startswith(("arm_right", "gripper_right"))]
    g = geom.geometryObjects
    for k in range(1000):
        share = min(1.0, k / 750)
        goal = {**T, **{t: at[t] + share * (end[t] - at[t]) for t in HANDS}}
        q = servo.step(goal).q
        if k % 4 == 3:
            whole_placements(model, data, three.joint_names, q)
            pin.updateGeometryPlacements(model, data, geom, gd)
            P = gd.oMg
            apart = min(
                _coal(g[i].geometry, P[i], g[j].geometry, P[j]) for i in left for j in right
            )
            assert apart >= 0.01 - 1e-4, k


def test_two_collisions_constraints_keep_the_larger_margin_between_the_chains_too():
    # obstacles at 1.5 cm and self-collision (at 0) are one check at 1.5 cm for every pair,
    # as each chain applies it; between the chains the robot took the self-collision's 0
    robot = armik.load(dual("panda"), tips=["l_panda_hand", "r_panda_hand"])
    far = armik.Sphere(0.05, (3.0, 3.0, 3.0))
    two = [armik.Collisions(obstacles=[far], margin=0.015), armik.Collisions(self_collision=True)]
    down, c = pin.utils.rpyToMatrix(np.pi, 0.0, 0.0), np.array([0.5, 0.0, 0.4])
    solved = 0
    for gap in np.linspace(0.095, 0.115, 9):  # the hands from touching to 2 cm apart
        T = {
            "l_panda_hand": pin.SE3(down, c + [0, gap, 0]),
            "r_panda_hand": pin.SE3(down, c - [0, gap, 0]),
        }
        r = robot.solve(T, constraints=two)
        if r.success:
            solved += 1
            d, pair = robot.min_distance(r.q, [far], True)
            assert d >= 0.015 and (r.min_distance, r.closest_pair) == (d, pair)
    assert solved


def test_one_arm_s_chain_holds_the_other_arm_in_the_leg_until_it_is_locked_clear():
    # docs/several-tips.md: TALOS's left chain holds the right hand in the right leg at the
    # upright torso; the torso held upright, a collision naming the pair; the right
    # shoulder locked out (``locked=``), clear of the leg at every torso value, solved
    srdf = TALOS.parents[1] / "srdf" / "talos.srdf"
    left = HANDS[0]
    arm = armik.load(TALOS, tip=left, srdf=srdf)
    model, geom = _hulls()
    data, gd = model.createData(), pin.GeometryData(geom)
    links = [model.frames[o.parentFrame].name for o in geom.geometryObjects]
    leg = [i for i, n in enumerate(links) if n == "leg_right_3_link"]
    hand = [i for i, n in enumerate(links) if n.startswith(("gripper_right", "wrist_right"))]
    g = geom.geometryObjects

    def gap(names, q) -> float:  # the right hand's distance to the right leg, whole URDF
        whole_placements(model, data, names, q)
        pin.updateGeometryPlacements(model, data, geom, gd)
        return min(
            _coal(g[a].geometry, gd.oMg[a], g[b].geometry, gd.oMg[b]) for a in leg for b in hand
        )

    q = arm.middle.copy()
    q[:2] = 0.0  # the torso upright
    assert gap(arm.joint_names, q) < -0.05
    upright = {"torso_1_joint": 0.0, "torso_2_joint": 0.0}
    r = arm.solve(arm.fk(q), q0=q, self_collision=True, hold=upright)
    assert not r.success and r.status is armik.Status.COLLISION
    assert "leg_right_3_link" in r.reason and "gripper_right" in r.reason
    out = {"arm_right_2_joint": -0.4}
    clear = armik.load(TALOS, tip=left, srdf=srdf, locked=out)
    names = [*clear.joint_names, *out]
    for torso in clear.random_q(0, 20)[:, :2]:
        assert gap(names, [*torso, *q[2:], -0.4]) > 0.0
    r = clear.solve(arm.fk(q), q0=q, self_collision=True, hold=upright)
    assert r.success and np.allclose(r.q[:2], 0.0)
    assert gap(names, [*r.q, -0.4]) > 0.0
    whole_placements(model, data, names, [*r.q, -0.4])
    T = data.oMf[model.getFrameId(left)]
    assert np.linalg.norm(pin.log6(T.actInv(arm.fk(q))).vector) < 1e-5
