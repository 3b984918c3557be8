"""A collision with a link the chain holds (its own joints none of the chain's, kept where
the chain was cut: ``armik.constraints.carried``) says so, and how to move it: TALOS's
left arm's chain holds the right hand in the right leg at the upright torso. The pair is
checked all the same (tests/constraints/test_held_links_checked.py)."""

from __future__ import annotations

import pickle

import numpy as np

import armik
from armik.model.catalogue import erd_share

from ..conftest import arm as bundled

ROBOT = "example-robot-data/robots/talos_data"
HAND = "gripper_right_motor_single_link"


def _talos(**kw):
    share = erd_share()
    urdf = f"{share}/{ROBOT}/robots/talos_reduced.urdf"
    srdf = f"{share}/{ROBOT}/srdf/talos.srdf"
    return armik.load(urdf, tip="gripper_left_base_link", srdf=srdf, **kw)


def test_a_collision_with_a_held_link_says_it_is_held_and_the_fix():
    arm = _talos()
    q = arm.middle.copy()
    q[:2] = 0.0
    upright = {"torso_1_joint": 0.0, "torso_2_joint": 0.0}
    r = arm.solve(arm.fk(q), q0=q, self_collision=True, hold=upright)
    assert not r.success and r.status == "collision", r.reason
    assert HAND in r.extra["closest_pair"]
    assert f"link {HAND!r} is held" in r.reason, r.reason
    assert "tip='gripper_left_base_link', locked={'arm_right_1_joint': value}" in r.reason
    assert "leg_right_3_link' is held" not in r.reason  # the base holds it: no chain's answer
    # the words the distance gives are kept with its pair where results travel
    pair = arm.min_distance(q, self_collision=True)[1]
    assert pair == ("leg_right_3_link", HAND)
    assert pickle.loads(pickle.dumps(pair)).note == pair.note != ""
    # locked where the hand is clear (the fix said): the upright torso's answer is found
    clear = _talos(locked={"arm_right_2_joint": -0.4})
    assert clear.solve(arm.fk(q), q0=q, self_collision=True, hold=upright).success


def test_a_collision_of_the_chains_own_links_says_nothing_held():
    ur5 = bundled("ur5")
    q = np.array([0.0, -1.0, 2.9, 0.0, 0.0, 0.0])  # the forearm folded into the upper arm
    d, pair = ur5.min_distance(q, self_collision=True)
    assert d < 0
    assert type(pair) is tuple  # no held link: a plain pair


def test_an_obstacle_on_a_held_link_says_nothing_held():
    """The chain clears an obstacle by moving the joints that carry the held link."""
    arm = _talos()
    q = arm.middle.copy()
    q[:2] = (0.6, 0.0)  # the torso turned: the held hand out of the leg
    hand = arm.fk(q, frame=HAND).translation
    d, pair = arm.min_distance(q, obstacles=[armik.Sphere(0.02, tuple(hand))])
    assert d < 0 and pair[0].startswith("gripper_right") and pair[1].startswith("obstacles")
    assert type(pair) is tuple
