"""The servo over shared joints refuses an obstacle that a link fixed to the base sinks
into, naming it, as one chain's servo and ``Arms.min_distance`` do; one beside that link
is taken."""

from __future__ import annotations

import pytest

import armik
from armik.errors import CollisionError
from armik.servo.streams import START


def test_an_obstacle_through_the_base_link_is_refused_over_shared_joints():
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"])
    q0 = START["panda"]
    through = armik.Box((0.1, 0.1, 0.1), (0.0, 0.0, 0.05))  # panda_link0 sinks 10 cm into it
    with pytest.raises(CollisionError, match="overlaps link 'panda_link0'") as one:
        armik.load("panda").servo(q0, obstacles=[through])
    with pytest.raises(CollisionError, match="overlaps link 'panda_link0'") as union:
        robot.servo(q0, obstacles=[through])
    assert str(union.value) == str(one.value)
    beside = armik.Box((0.1, 0.1, 0.1), (0.0, 0.4, 0.05))
    assert robot.min_distance(q0, [beside])[0] > 0.05
    robot.servo(q0, obstacles=[beside])
