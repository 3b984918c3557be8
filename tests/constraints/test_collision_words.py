"""A collision's words agree with its distance: a pair that overlaps is in collision by a
depth, a pair still apart inside the margin is closer than the margin, never "in
collision ... apart"."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik import reasons
from armik.servo import collisions

from ..conftest import arm


def test_a_pair_apart_inside_the_margin_is_not_said_to_collide():
    a = arm("ur5")
    T = a.fk(a.random_q(4))
    near = armik.Sphere(0.05, T.translation + np.array([0.0, 0.0, 0.08]))  # clear of the tip
    r = a.solve(T, obstacles=[near], margin=0.1, timeout=0.01)
    assert r.status == armik.Status.COLLISION and 0 < r.extra["min_distance"] < 0.1
    assert "in collision" not in r.reason and "closer than the margin" in r.reason
    assert f"{r.extra['min_distance']:.3g} m apart (margin 0.1 m)" in r.reason
    inside = armik.Sphere(0.05, T.translation)  # every answer puts the tip inside it
    r = a.solve(T, obstacles=[inside], margin=0.1, timeout=0.01)
    depth = -r.extra["min_distance"]
    assert r.status == armik.Status.COLLISION and depth > 0
    assert (
        f"in collision: wrist_3_link and obstacles[0] (Sphere) overlapping by {depth:.3g} m"
        in r.reason
    )
    assert "apart" not in r.reason.partition("(margin")[0]


@pytest.mark.parametrize(
    "distance, said",
    [
        (0.004, "closer than the margin: a and b 0.004 m apart"),
        (0.0, "in collision: a and b touching"),
        (-0.002, "in collision: a and b overlapping by 0.002 m"),
    ],
)
def test_each_distance_has_its_words(distance, said):
    assert reasons.in_collision(("a", "b"), distance, 0.01) == f"{said} (margin 0.01 m)"


def test_the_servo_says_an_overlapping_pair_overlaps():
    with pytest.warns(armik.ArmikWarning, match="a and b are overlapping by 0.002 m, inside"):
        collisions.still(set(), "a", "b", -0.002)
    with pytest.warns(armik.ArmikWarning, match="a and b are 0.004 m apart, inside"):
        collisions.still(set(), "a", "b", 0.004)
    with pytest.warns(armik.ArmikWarning, match="a and b are touching, inside"):  # not "-0 m"
        collisions.still(set(), "a", "b", 0.0)
