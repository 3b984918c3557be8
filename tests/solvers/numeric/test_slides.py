"""A gantry's positions: a target beyond every position its prismatic joints reach within
their limits is ``unreachable`` at once on the numeric solvers, naming the distance, where
the reach bound (infinite with an unlimited rail) let it through to every restart and
``not_converged``; every position it does reach stays solvable
(``solvers/numeric/slides.py``)."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.options import Options
from armik.solvers.numeric import slides

L = 'effort="1" velocity="1"'
# y and z bounded, z upside down (x unlimited by with_limits in the test)
XYZ = f"""<robot name="xyz"><link name="b"/><link name="x"/><link name="y"/><link name="z"/>
<joint name="px" type="prismatic"><parent link="b"/><child link="x"/><axis xyz="1 0 0"/>
  <limit lower="-3" upper="3" {L}/></joint>
<joint name="py" type="prismatic"><parent link="x"/><child link="y"/><axis xyz="0 1 0"/>
  <limit lower="-1" upper="1" {L}/></joint>
<joint name="pz" type="prismatic"><parent link="y"/><child link="z"/><axis xyz="0 0 -1"/>
  <limit lower="0" upper="0.5" {L}/></joint>
</robot>"""
# skewed axes, a fixed tilt between them and a mimic follower: a parallelepiped
SKEWED = f"""<robot name="skew"><link name="b"/><link name="a"/><link name="c"/><link name="d"/>
<link name="e"/>
<joint name="s1" type="prismatic"><parent link="b"/><child link="a"/><axis xyz="0.6 0.8 0"/>
  <origin xyz="0.1 0.2 0.3" rpy="0.3 0.2 0.1"/><limit lower="0" upper="1" {L}/></joint>
<joint name="s2" type="prismatic"><parent link="a"/><child link="c"/><axis xyz="0 0.8 0.6"/>
  <origin rpy="0 0.4 0"/><limit lower="-0.5" upper="0.5" {L}/></joint>
<joint name="s3" type="prismatic"><parent link="c"/><child link="d"/><axis xyz="0.28 0 0.96"/>
  <limit lower="0" upper="0.4" {L}/></joint>
<joint name="s4" type="prismatic"><parent link="d"/><child link="e"/><axis xyz="0 0 1"/>
  <limit lower="-1" upper="1" {L}/><mimic joint="s3" multiplier="0.5" offset="0.05"/></joint>
</robot>"""


@pytest.mark.parametrize("solver", ["auto", "dls", "qp"])
def test_a_position_beyond_a_gantry_s_travel_is_unreachable_at_once(solver):
    """y travels +-1 m, x without limits: a position 5 m along y is 4 m from every one the
    tip reaches (the reach bound is infinite), and so is the pose there; one inside is
    solved. A batch says the same row by row."""
    arm = armik.load_string(XYZ)
    arm = arm.with_limits({"px": (-np.inf, np.inf)})
    assert not np.isfinite(arm.kinematics.reach)
    far = np.array([0.3, 5.0, -0.2])
    for target in (far, (far, np.eye(3))):
        r = arm.solve(target, solver=solver, q0=np.array([0.1, 0.2, 0.3]), seed=0)
        assert r.status == "unreachable" and "4 m from every position the tip reaches" in r.reason
        assert r.iterations == 0 and r.q.tolist() == [0.1, 0.2, 0.3]
    near = np.array([7.0, 0.9, -0.4])
    ok = arm.solve(near, solver=solver, seed=0)
    assert ok.success and np.linalg.norm(arm.fk(ok.q).translation - near) < 1e-6
    if solver != "auto":
        b = arm.solve_batch([near, far, near], solver=solver, seed=0, workers=1, progress=False)
        assert b.success.tolist() == [True, False, True]
        assert b[1].status == "unreachable" and "4 m from every position" in b[1].reason


def test_the_distance_bounds_every_reached_position_and_is_the_true_one_at_a_face():
    """On a skewed gantry with a mimic follower: the distance to any target is at most its
    distance to any reached position (a lower bound), zero at reached ones, and the true
    one for a target moved off a face along its normal."""
    arm = armik.load_string(SKEWED)
    s = slides.SLIDES(arm.kinematics)
    assert s is not None
    rng = np.random.default_rng(0)
    reached = []
    for _ in range(200):
        q = np.asarray(arm.random_q(rng))
        p = arm.fk(q).translation
        reached.append(p)
        assert slides.distance(s, p) < 1e-12
        np.testing.assert_allclose(s.p0 + s.B @ q, p, atol=1e-12)
    reached = np.array(reached)
    for _ in range(50):
        t = reached.mean(axis=0) + rng.normal(size=3)
        assert slides.distance(s, t) <= np.linalg.norm(reached - t, axis=1).min() + 1e-12
    # s1 at its upper limit: the face spanned by the others' columns; off it along its normal
    q = np.array([1.0, 0.1, 0.2])
    n = np.cross(s.B[:, 1], s.B[:, 2])
    n *= np.sign(n @ s.B[:, 0]) / np.linalg.norm(n)
    t = s.p0 + s.B @ q + 0.25 * n
    assert slides.distance(s, t) == pytest.approx(0.25, abs=1e-9)
    r = arm.solve(t, solver="dls", seed=0)
    assert r.status == "unreachable" and "0.25 m from every position" in r.reason


def test_arms_with_a_turning_joint_have_no_slides():
    """Nor does a non-finite position get an answer here: the parser refuses it."""
    gantry = armik.load_string(XYZ)
    assert slides.refused(gantry.kinematics, np.array([np.nan, 9.0, 9.0]), Options()) is None
    assert slides.SLIDES(armik.load("scara").kinematics) is None
    assert slides.SLIDES(armik.load("ur5").kinematics) is None


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_a_gantry_with_a_wrist_refuses_a_position_beyond_its_travel_at_once(solver):
    """Slides first, then a wrist reaching 0.35 m from its first joint: a position 3 m
    beyond the rail's end or the cross slide's, pose or position, is ``unreachable`` by
    ``solve`` (its prepared plan and the general path) and ``solve_batch``, with no
    iteration and the seed returned, where every restart was spent on it
    (``not_converged``); every position reached is within the bound and solved."""
    from .test_long_rail import GANTRY

    arm = armik.load_string(GANTRY.replace("RAIL", "10"))
    s = slides.SLIDES(arm.kinematics)
    assert s is not None and s.wrist == pytest.approx(0.2 + np.hypot(0.02, 0.15))
    rng = np.random.default_rng(4)
    reached = [arm.fk(arm.random_q(rng)) for _ in range(200)]
    for T in reached:
        assert slides.distance(s, T.translation) - s.wrist <= 1e-12
        assert slides.refused(arm.kinematics, T.translation, Options()) is None
    q0 = np.asarray(arm.middle, dtype=float)
    for p in ([13.0, 3.0, 0.5], [5.0, 9.0, 0.5]):
        T = reached[0].copy()
        T.translation = np.array(p)
        for target in (T, (T.translation.copy(), T.rotation.copy()), T.translation):
            r = arm.solve(target, solver=solver, q0=q0, seed=0)
            assert r.status == "unreachable" and r.iterations == 0, r.reason
            assert "2.65 m from every position the tip reaches (its slides" in r.reason
            np.testing.assert_array_equal(r.q, q0)
        b = arm.solve_batch([reached[1], T], solver=solver, seed=0, workers=1, progress=False)
        assert b.success.tolist() == [True, False] and "its slides" in b.reason(1)
        ok = arm.solve(reached[1], solver=solver, seed=0)
        assert ok.success
        assert np.linalg.norm(arm.fk(ok.q).translation - reached[1].translation) < 1e-6
    assert slides.SLIDES(armik.load("scara").kinematics) is None  # a slide after a turn
