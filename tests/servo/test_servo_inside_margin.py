"""A pair that starts inside the collision margin never comes nearer, while the tips still
track: each distance measured at every tick by coal on the convex hulls of the URDF's
collision meshes, placed by Pinocchio's FK, apart from the servo's own rows."""

from __future__ import annotations

from pathlib import Path

import coal
import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.servo.streams import START
from tests.servo.test_servo_braking_rows import (
    DT,
    _hulls,
    _talos,
    _torso_and_arm_pairs,
    assert_within_limits,
    hands_stream,
)

TOLERANCE = 1e-6  # m: coal's on the hulls, far below the falls measured before


def _distances(model, geom, pairs, to_pin, Q, other=None) -> np.ndarray:
    """(len(Q), pairs): each pair's distance (m) at each joint values of Q (with ``other``, a
    coal shape and its placement, each moving object's distance to it)."""
    data, gdata = model.createData(), pin.GeometryData(geom)
    request, objects = coal.DistanceRequest(), geom.geometryObjects
    request.gjk_tolerance = 1e-10
    if other is not None:
        pairs = [(a, -1) for a, o in enumerate(objects) if o.parentJoint != 0]
    out = np.zeros((len(Q), len(pairs)))
    for t, q in enumerate(Q):
        pin.updateGeometryPlacements(model, data, geom, gdata, to_pin(q))
        T = [coal.Transform3s(M.rotation, M.translation) for M in gdata.oMg]
        for p, (a, b) in enumerate(pairs):
            shape, at = other if b < 0 else (objects[b].geometry, T[b])
            result = coal.DistanceResult()
            out[t, p] = coal.distance(objects[a].geometry, T[a], shape, at, request, result)
    return out


def _never_nearer(D: np.ndarray, margin: float) -> int:
    """The pairs inside ``margin`` at the first row of D, each asserted never nearer."""
    inside = np.flatnonzero(D[0] < margin)
    for p in inside.tolist():
        assert D[:, p].min() >= D[0, p] - TOLERANCE, (p, D[0, p], D[:, p].min())
    return len(inside)


@pytest.mark.parametrize("ticks", [750, 1])
def test_talos_torso_and_upper_arms_inside_the_margin_never_come_nearer(ticks):
    """TALOS at ``robot.middle`` has its torso and each upper arm 14.1 mm apart; with a 3 cm
    margin and its hands led to each other over 1.5 s the left shoulder turns at 1.8 rad/s
    beside the torso (or sent there at once). Before, both pairs' dampers asked them out by
    0.3 mm a tick (50 rad of their joints), and the torso's pair with the left arm came to
    12.3 mm; sent at once, the braking row of the pair with the right arm, held no more
    firmly than the rows it competed with, let it come 2.1 um nearer."""
    robot = _talos()
    q0 = robot.middle
    rec = _tracked_within_limits(robot, q0, hands_stream(robot, ticks, 1000))
    assert np.abs(rec.dq).max() > 1.0  # fast beside the torso
    model, geom, pairs, to_pin = _torso_and_arm_pairs(robot)
    D = _distances(model, geom, pairs, to_pin, np.vstack([q0, rec.q]))
    assert _never_nearer(D, 0.03) == 2  # the torso with each upper arm
    apart = np.linalg.norm(np.subtract(*[robot.fk(q0, t).translation for t in robot.tips]))
    hands = [robot.fk(rec.q[-1], t).translation for t in robot.tips]
    assert np.linalg.norm(hands[0] - hands[1]) < apart - 0.1  # the hands still came on


def test_a_ur5_beside_a_ball_inside_the_margin_never_comes_nearer():
    """The UR5's shoulder 3.2 cm off a ball, inside a 5 cm margin, its tip led 25 cm along y
    and then sent 25 cm along -x: the shoulder's pair came 2 um nearer before."""
    arm = armik.load("ur5")
    q0 = START["ur5"]
    T0 = arm.fk(q0)
    centre = np.array([0.12, 0.0, 0.02])
    ball = armik.Sphere(0.03, tuple(centre))
    led = [np.array([0.0, 0.25 * min(1.0, k / 200), 0.0]) for k in range(600)]
    sent = [np.array([-0.25, 0.25, 0.0])] * 600
    targets = [pin.SE3(T0.rotation, T0.translation + x) for x in led + sent]
    servo = arm.servo(q0, dt=DT, obstacles=[ball], margin=0.05)
    rec = servo.track(targets)
    assert_within_limits(arm, servo, rec, q0)
    model = pin.buildModelFromUrdf(arm.source)
    geom = _hulls(model, Path(arm.source))
    other = (coal.Sphere(0.03), coal.Transform3s(np.eye(3), centre))
    D = _distances(model, geom, [], lambda q: q, np.vstack([q0, rec.q]), other)
    assert _never_nearer(D, 0.05) == 1
    assert rec.position_error[-1] < np.linalg.norm(sent[0]) - 0.02  # it came on


def test_a_panda_pair_inside_the_margin_never_comes_nearer():
    """The Panda at START has a pair of its own links 2.2 cm apart; with self-collision, a
    5 cm margin and its tip on a 25 cm arc, that pair came 4 um nearer before."""
    arm = armik.load("panda")
    q0 = START["panda"]
    T0 = arm.fk(q0)
    servo = arm.servo(q0, dt=DT, self_collision=True, margin=0.05)
    arc = [
        np.array([0.0, 0.25 * np.sin(k / 150), -0.1 * (1 - np.cos(k / 150))]) for k in range(1500)
    ]
    rec = servo.track([pin.SE3(T0.rotation, T0.translation + x) for x in arc])
    assert_within_limits(arm, servo, rec, q0)
    check = servo._collisions.check  # the servo's own pairs, named on the hulls
    model = pin.buildModelFromUrdf(arm.source)
    geom = _hulls(model, Path(arm.source))
    names = [o.name for o in geom.geometryObjects]
    objects = check.model.geometryObjects
    pairs = [
        (names.index(objects[p.first].name), names.index(objects[p.second].name))
        for p in check.model.collisionPairs
        if objects[p.first].name in names and objects[p.second].name in names
    ]
    pad = lambda q: np.concatenate([q, np.zeros(model.nq - len(q))])  # noqa: E731 (fingers)
    D = _distances(model, geom, pairs, pad, np.vstack([q0, rec.q]))
    assert _never_nearer(D, 0.05) >= 1
    assert np.ptp(rec.q, axis=0).max() > 0.3  # it moved


def test_a_pair_inside_the_margin_keeps_its_row_before_fast_pairs():
    """TALOS's torso and upper arms inside a 3 cm margin, every joint at 6 rad/s: the
    fingertips' pairs, 0.8 m off but needing 3.6 rad of each joint to stop, are more urgent
    by gap less braking distance, and before they took all 16 rows, the pairs inside the
    margin none. A pair inside the margin keeps its row before any outside it."""
    robot = _talos()
    q0 = robot.middle
    servo = robot.servo(q0, dt=DT, self_collision=True, margin=0.03)
    rows = servo._union._collisions
    fast = np.full(robot.dof, 6.0)
    C = rows.at(q0, 1.0, fast, np.full(robot.dof, 5.0))
    d = 0.03 - C[:, -1] / rows.gain
    named = {frozenset((rows.names[a], rows.names[b])) for a, b in rows.pairs if b >= 0}
    assert len(C) == 16 and np.sum(d < 0.03) == 2
    for arm in ("arm_left_2_link", "arm_right_2_link"):
        assert frozenset(("torso_2_link", arm)) in named


def test_a_pair_no_joint_moves_takes_no_row_and_is_said_once(monkeypatch):
    """A pair whose row is all zeros (no joint the servo commands moves it) gives the step
    nothing: it takes no row from the others, and inside the margin an ``ArmikWarning``
    names it, once."""
    robot = _talos()
    q0 = robot.middle
    servo = robot.servo(q0, dt=DT, self_collision=True, margin=0.03)
    rows = servo._union._collisions
    closing = type(rows)._closing

    def still(self, found):  # the torso and its left upper arm held still
        C, L = closing(self, found)
        for i, (_, a, b, _) in enumerate(found):
            if {self.names[a], self.names[b] if b >= 0 else ""} == {
                "torso_2_link",
                "arm_left_2_link",
            }:
                C[i] = 0.0
        return C, L

    monkeypatch.setattr(type(rows), "_closing", still)
    with pytest.warns(armik.ArmikWarning, match="torso_2_link and arm_left_2_link") as said:
        C = rows.at(q0)
        rows.at(q0)
    assert len([w for w in said if "arm_left_2_link" in str(w.message)]) == 1
    assert np.all(np.abs(C[:, :-1]).sum(axis=1) > 0)
    named = {frozenset((rows.names[a], rows.names[b])) for a, b in rows.pairs if b >= 0}
    assert frozenset(("torso_2_link", "arm_right_2_link")) in named
    assert frozenset(("torso_2_link", "arm_left_2_link")) not in named


def test_talos_pairs_inside_the_margin_never_come_nearer_under_wandering_targets():
    """TALOS's hands wandering at random (a seeded random walk) with a 3 cm margin and
    ``acceleration_limits=5``: a shoulder turning past where its pair with the torso is
    widest along it grows the pair's lever as it brakes, which a braking distance counted
    with this tick's lever left out (the torso and the right upper arm came 37 um nearer
    than they started). Each braking row of a pair inside the margin counts its levers'
    growth over the braking turn."""
    robot = _talos()
    left, right = robot.tips
    q0 = robot.middle
    at = {t: robot.fk(q0, t).translation for t in robot.tips}
    rng = np.random.default_rng(2)
    pos = {t: at[t].copy() for t in at}
    vel = {t: np.zeros(3) for t in at}
    stream = []
    for _ in range(400):
        for t in at:
            vel[t] = 0.98 * vel[t] + rng.normal(0.0, 0.01, 3)
            pos[t] = pos[t] + vel[t] * DT * 10
        stream.append({t: pos[t].copy() for t in at})
    rec = _tracked_within_limits(robot, q0, stream)
    model, geom, pairs, to_pin = _torso_and_arm_pairs(robot)
    D = _distances(model, geom, pairs, to_pin, np.vstack([q0, rec.q]))
    assert _never_nearer(D, 0.03) == 2


def _tracked_within_limits(robot, q0, stream):
    """The record of TALOS's servo (3 cm margin, 5 rad/s^2) tracking ``stream``, every
    position, velocity and acceleration limit held."""
    amax = np.full(robot.dof, 5.0)
    servo = robot.servo(q0, dt=DT, self_collision=True, margin=0.03, acceleration_limits=amax)
    rec = servo.track(stream)
    assert_within_limits(robot, servo, rec, q0)
    return rec
