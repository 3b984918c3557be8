"""A rail without limits that a turning joint before it turns (a telescope on a turntable):
the restart box along the rail is centred where the rail, turned by one of several
configurations of the joints before it, brings the tip nearest the target. Centred with
those joints at q0 only, a target 300 m out at 1.5 rad from q0's direction was never
reached (1000 restarts, ``not_converged``): the rail at q0 passes 280 m from it."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.solvers.numeric import rails

TELESCOPE = """<robot name="telescope"><link name="base"/><link name="l0"/><link name="l1"/>
<link name="l2"/><link name="tool0"/>
<joint name="turn" type="revolute"><parent link="base"/><child link="l0"/>
<origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
<limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
<joint name="rail" type="prismatic"><parent link="l0"/><child link="l1"/><axis xyz="1 0 0"/>
<limit lower="0" upper="0" effort="1" velocity="1"/></joint>
<joint name="tilt" type="revolute"><parent link="l1"/><child link="l2"/>
<origin xyz="0.3 0 0"/><axis xyz="0 1 0"/>
<limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
<joint name="tool" type="fixed"><parent link="l2"/><child link="tool0"/>
<origin xyz="0.05 0.02 0.1"/></joint></robot>"""


def _arm():
    with pytest.warns(armik.ArmikWarning):  # the rail's "0 0" limits read as none
        return armik.load_string(TELESCOPE, tip="tool0")


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_a_target_far_along_a_turned_rail_is_reached(solver):
    arm = _arm()
    for q in ([1.5, 300.0, 0.3], [-1.2, 45.0, -0.5], [0.9, -120.0, 1.0]):
        p = arm.fk(np.array(q)).translation
        r = arm.solve(p, q0=arm.middle, solver=solver, seed=0)
        assert r.success, r.reason
        assert np.linalg.norm(arm.fk(r.q).translation - p) < 1e-6  # Pinocchio's FK
        b = arm.solve_batch([p, p], q0=arm.middle, solver=solver, seed=0, workers=1)
        assert b.success.all()


def test_the_centre_comes_from_the_turn_that_brings_the_rail_nearest():
    """The centre is within the tool's reach of the true rail value, where q0's turn alone
    gave 300 cos(1.5) = 21 m; a gantry's rail (no turning joint before it) keeps q0's."""
    arm = _arm()
    kin = arm.kinematics
    joints = rails.UNLIMITED(kin)
    assert rails.TURNING(kin).tolist() == [0]
    p = arm.fk(np.array([1.5, 300.0, 0.3])).translation
    q0 = np.zeros(3)
    assert abs(rails.centres(kin, p, q0, joints)[0] - 300.0) < 0.5
    # a target within pi m of q0's rail: q0's centre, nothing swept
    near = arm.fk(np.array([0.01, 2.0, 0.0])).translation
    x, miss = rails._centres_at(kin, near[None], q0[None], joints)
    assert miss[0] < rails.FAR
    assert rails.centres(kin, near, q0, joints)[0] == x[0, 0]
    from .numeric.test_long_rail import GANTRY

    gantry = armik.load_string(GANTRY.replace("RAIL", "10")).with_limits({"px": (0.0, np.inf)})
    assert len(rails.TURNING(gantry.kinematics)) == 0


def test_a_large_batch_s_centres_are_found_in_chunks_as_one_by_one():
    arm = _arm()
    kin = arm.kinematics
    joints = rails.UNLIMITED(kin)
    rng = np.random.default_rng(0)
    Q = np.array([arm.random_q(rng) for _ in range(rails.CHUNK + 5)])
    Q[:, 1] = rng.uniform(-400.0, 400.0, len(Q))
    P = np.array([arm.fk(q).translation for q in Q])
    Q0 = np.zeros_like(Q)
    many = rails.centres_many(kin, P, Q0, joints)
    assert many.shape == (len(Q), 1)
    for i in (0, rails.CHUNK - 1, rails.CHUNK, len(Q) - 1):
        assert many[i] == pytest.approx(rails.centres(kin, P[i], Q0[i], joints), abs=1e-9)
