"""One TALOS arm's chain holds the other arm where it was cut, its gripper in the right leg
at the neutral configuration: pairs of two held links overlapping there are left out of
the chain's self-collision check (MoveIt's "Default" pairs) with a warning naming them;
every other pair is still checked, and the robot of both hands, which moves that arm,
still checks the pair."""

from __future__ import annotations

import warnings

import coal
import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.constraints.collision import arm_geometry

from .test_arms_parity import HANDS, SHARE, TALOS


def test_links_a_chain_holds_in_each_other_are_left_out_by_name():
    arm = armik.load(TALOS, tip=HANDS[0], srdf=TALOS.parents[1] / "srdf" / "talos.srdf")
    g = arm_geometry(arm.kinematics)
    left = {(a, b): d for a, b, d in g.held_overlaps}
    pair = ("leg_right_3_link", "gripper_right_base_link")
    assert pair in left
    # the depth, by coal on the whole URDF at its neutral configuration
    model = pin.buildModelFromUrdf(str(TALOS))
    geom = pin.buildGeomFromUrdf(model, str(TALOS), pin.COLLISION, package_dirs=[str(SHARE)])
    data, gd = model.createData(), pin.GeometryData(geom)
    pin.updateGeometryPlacements(model, data, geom, gd, pin.neutral(model))
    links = [model.frames[o.parentFrame].name for o in geom.geometryObjects]
    a, b = (links.index(n) for n in pair)
    hulls = []
    for k in (a, b):
        shape = geom.geometryObjects[k].geometry
        if isinstance(shape, coal.BVHModelBase):
            shape.buildConvexHull(True, "Qt")
            shape = shape.convex
        hulls.append((shape, coal.Transform3s(gd.oMg[k].rotation, gd.oMg[k].translation)))
    depth = -coal.distance(*hulls[0], *hulls[1], coal.DistanceRequest(), coal.DistanceResult())
    assert left[pair] == pytest.approx(depth, abs=1e-6) and depth > 0.01
    # none of the pairs left is one of the chain's own links, and those stay checked
    names = [(g.links[i], g.links[k]) for i, k in g.self_pairs]
    assert ("torso_2_link", "arm_left_2_link") in names and pair not in names
    assert all("left" not in x and "left" not in y for x, y in left)
    with warnings.catch_warnings(record=True) as heard:
        warnings.simplefilter("always")
        d, closest = arm.min_distance(arm.middle, self_collision=True)
    assert any("leg_right_3_link" in str(w.message) for w in heard)
    assert d > 0 and closest not in left
    # the robot of both hands moves the right arm: the pair is checked there
    robot = armik.load(TALOS, tips=HANDS)
    q = np.zeros(robot.dof)
    d, closest = robot.min_distance(q, self_collision=True)
    assert d < 0 and set(closest) & {"leg_right_3_link"}
