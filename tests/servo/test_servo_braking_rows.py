"""The collision rows leave room to stop (``armik.servo.rows``): a pair near the margin
closes no faster than every joint that moves it can brake, however its nearest features
turn, so the margin holds where the joints arrive fast. Each distance is measured here by
coal on the convex hulls of the URDF's collision meshes, placed by Pinocchio's FK, apart
from the servo's own rows."""

from __future__ import annotations

from importlib import metadata
from pathlib import Path

import coal
import numpy as np
import pinocchio as pin

import armik
from armik.servo.streams import START, violations

DT = 0.002


def assert_within_limits(arm, servo, rec, q0) -> None:
    """Every tick of ``rec`` from ``q0`` within ``arm``'s position limits and ``servo``'s
    velocity and acceleration limits."""
    over = violations(
        q0, rec.q, arm.lower, arm.upper, servo.velocity_limits, servo.acceleration_limits, DT
    )
    assert over == {"position": 0.0, "velocity": 0.0, "acceleration": 0.0}


MARGIN = 0.01
SHARE = Path(str(metadata.distribution("example-robot-data").locate_file("cmeel.prefix")))
TALOS = SHARE / "share/example-robot-data/robots/talos_data"


def _hulls(model: pin.Model, urdf: Path) -> pin.GeometryModel:
    """The URDF's collision geometry on ``model``, every mesh as its convex hull."""
    dirs = [str(SHARE / "share")]
    geom = pin.buildGeomFromUrdf(model, str(urdf), pin.COLLISION, package_dirs=dirs)
    for o in geom.geometryObjects:
        if isinstance(o.geometry, coal.BVHModelBase):
            o.geometry.buildConvexHull(True, "Qt")
            o.geometry = o.geometry.convex
    return geom


def _nearest(model, geom, pairs, to_pin, Q, other=None) -> float:
    """The smallest distance (m) over the joint values Q of the geometry pairs ``pairs``
    (or, with ``other``, a coal shape and its placement, of every object against it)."""
    data, gdata = model.createData(), pin.GeometryData(geom)
    request, objects = coal.DistanceRequest(), geom.geometryObjects
    request.gjk_tolerance = 1e-10
    nearest = np.inf
    for q in Q:
        pin.updateGeometryPlacements(model, data, geom, gdata, to_pin(q))
        T = [coal.Transform3s(M.rotation, M.translation) for M in gdata.oMg]
        for a, b in pairs:
            result = coal.DistanceResult()
            d = coal.distance(objects[a].geometry, T[a], objects[b].geometry, T[b], request, result)
            nearest = min(nearest, d)
        if other is not None:
            for a, o in enumerate(objects):
                result = coal.DistanceResult()
                nearest = min(nearest, coal.distance(o.geometry, T[a], *other, request, result))
    return nearest


def _talos() -> armik.Arms:
    return armik.load(
        TALOS / "robots/talos_reduced.urdf",
        tips=["gripper_left_base_link", "gripper_right_base_link"],
        srdf=TALOS / "srdf/talos.srdf",
    )


def _torso_and_arm_pairs(robot: armik.Arms) -> tuple[pin.Model, pin.GeometryModel, list, object]:
    """The union's model, its hulls, every torso-arm and left-right pair (the torso's
    neighbours left out), and the union's q -> Pinocchio's."""
    union = robot._joint()
    geom = _hulls(union.model, TALOS / "robots/talos_reduced.urdf")
    names = [o.name for o in geom.geometryObjects]
    torso = [k for k, name in enumerate(names) if name.startswith("torso_2")]
    sides = [[k for k, name in enumerate(names) if f"_{s}_" in name] for s in ("left", "right")]
    arms = [k for k in sides[0] + sides[1] if not names[k].startswith("leg_")]
    pairs = [(a, b) for a in torso for b in arms if "_1_" not in names[b]]  # (its neighbours)
    pairs += [(a, b) for a in sides[0] for b in sides[1] if a in arms and b in arms]
    return union.model, geom, pairs, union.to_pin


def hands_stream(robot: armik.Arms, ticks: int, total: int) -> list[dict]:
    """TALOS's hands from ``robot.middle`` led in ``ticks`` ticks to 5 cm either side of
    their middle (where the other is), ``total`` ticks in all."""
    left, right = robot.tips
    at = {t: robot.fk(robot.middle, t).translation for t in robot.tips}
    middle = 0.5 * (at[left] + at[right])
    goal = {left: middle + [0.0, -0.05, 0.0], right: middle + [0.0, 0.05, 0.0]}
    share = [min(1.0, k / ticks) for k in range(total)]
    return [{t: at[t] + s * (goal[t] - at[t]) for t in at} for s in share]


def _hands_to_each_other(ticks: int, total: int) -> tuple[armik.Arms, object, object]:
    """``hands_stream`` tracked, self-collision on: (the robot, its servo, the record)."""
    robot = _talos()
    servo = robot.servo(robot.middle, dt=DT, self_collision=True, margin=MARGIN)
    return robot, servo, servo.track(hands_stream(robot, ticks, total))


def test_the_hands_over_the_torso_keep_every_pair_at_the_margin():
    """TALOS's hands led in 1.5 s to where the other is, over the torso's two joints: the
    shoulders turn at up to 2 rad/s beside the torso, where a pair's nearest faces swing
    over (a joint's share of its closing changes sign from one tick to the next). Every
    torso-arm and left-right pair stays at the margin at every tick (before, a shoulder
    passed 0.55 mm inside it, every joint at its acceleration limit), within every limit."""
    robot, servo, rec = _hands_to_each_other(750, 1000)
    q0 = robot.middle
    assert_within_limits(robot, servo, rec, q0)
    model, geom, pairs, to_pin = _torso_and_arm_pairs(robot)
    assert _nearest(model, geom, pairs, to_pin, [q0]) > MARGIN + 0.003
    near = _nearest(model, geom, pairs, to_pin, rec.q)
    assert MARGIN - 1e-5 <= near < MARGIN + 1e-3


def test_the_hands_sent_at_each_other_at_once_brake_in_time():
    """TALOS's hands sent at once to where the other is close at 3 m/s and need 0.2 m to
    stop: the rows are the pairs that must brake first (gap to the margin less braking
    distance), not the nearest, so the fingertips' pair is a row while it can still stop.
    By distance alone, the torso's and the arms' near pairs filled the 16 rows and the
    fingertips came among them 0.17 m apart: they passed 0.2 mm into each other. Every
    torso-arm and left-right pair keeps the margin at every tick, within every limit."""
    robot, servo, rec = _hands_to_each_other(1, 250)
    q0 = robot.middle
    assert np.abs(rec.dq).max() > 1.5  # fast
    assert_within_limits(robot, servo, rec, q0)
    model, geom, pairs, to_pin = _torso_and_arm_pairs(robot)
    assert _nearest(model, geom, pairs, to_pin, rec.q) >= MARGIN - 1e-5


def test_an_arm_arriving_fast_stops_before_the_margin():
    """The UR5 sent 45 cm past a 4 cm ball would come at it at its elbow's velocity limit,
    3.15 rad/s: the rows reach as far out as the joints need to stop
    (``collisions.ahead``), it slows down in time and passes the ball at the margin or
    more (before, 2.4 mm inside it, its rows appearing 5 cm out with the elbow needing 0.1
    m to stop), and reaches the target."""
    arm = armik.load("ur5")
    q0 = START["ur5"]
    T0 = arm.fk(q0)
    centre = T0.translation + np.array([-0.1299, 0.1509, 0.1106])
    ball = armik.Sphere(0.04, tuple(centre))
    target = pin.SE3(T0.rotation, T0.translation + np.array([-0.2774, 0.3002, 0.1883]))
    assert np.abs(arm.servo(q0, dt=DT).track([target] * 800).dq).max() > 3.0  # unhindered
    servo = arm.servo(q0, dt=DT, obstacles=[ball], margin=MARGIN)
    rec = servo.track([target] * 800)
    assert_within_limits(arm, servo, rec, q0)
    first = list(rec.status).index("obstacle")  # braking for the ball, still far off: said so
    assert arm.min_distance(rec.q[first], [ball])[0] > MARGIN + 0.05
    assert "could stop" in rec.reason[first]
    assert rec.status[-1] == "on_target"
    model = pin.buildModelFromUrdf(arm.source)
    geom = _hulls(model, Path(arm.source))
    other = (coal.Sphere(0.04), coal.Transform3s(np.eye(3), centre))
    assert _nearest(model, geom, [], lambda q: q, [q0]) > 0.05
    assert _nearest(model, geom, [], lambda q: q, rec.q, other) >= MARGIN - 1e-6


def test_pairs_near_but_slow_leave_the_rows_to_a_fast_one():
    """The UR5 sent fast past a ball as above, 20 small balls round its base 2 cm off: by
    distance they filled the 16 rows (a pair no joint moves among them) and the ball's
    pair came in too late, the arm 2.7 cm inside it. The rows are the pairs that must
    brake first, and the arm keeps the margin from the ball at every tick."""
    arm = armik.load("ur5")
    q0 = START["ur5"]
    T0 = arm.fk(q0)
    centre = T0.translation + np.array([-0.1299, 0.1509, 0.1106])
    ball = armik.Sphere(0.04, tuple(centre))
    ring = [
        armik.Sphere(0.005, (0.065 * np.cos(t), 0.065 * np.sin(t), 0.0))
        for t in np.linspace(0.0, 2.0 * np.pi, 20, endpoint=False)
    ]
    assert MARGIN < arm.min_distance(q0, ring)[0] < MARGIN + 0.011  # near, and outside
    target = pin.SE3(T0.rotation, T0.translation + np.array([-0.2774, 0.3002, 0.1883]))
    servo = arm.servo(q0, dt=DT, obstacles=[ball, *ring], margin=MARGIN)
    rec = servo.track([target] * 800)
    assert np.abs(rec.dq).max() > 2.5 and rec.status[-1] == "on_target"
    model = pin.buildModelFromUrdf(arm.source)
    geom = _hulls(model, Path(arm.source))
    other = (coal.Sphere(0.04), coal.Transform3s(np.eye(3), centre))
    assert _nearest(model, geom, [], lambda q: q, rec.q, other) >= MARGIN - 1e-6
