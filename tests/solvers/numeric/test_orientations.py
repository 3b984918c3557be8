"""Rotations a chain's structure never takes (a gantry's one, a SCARA's about one axis):
refused by the numeric solvers at once as ``unreachable``, naming the orientation, where
they spent every restart and said ``not_converged``; every rotation the chain does take
stays solvable (``solvers/numeric/orientations.py``)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.options import Options
from armik.solvers.numeric import orientations

L = 'effort="1" velocity="1"'
GANTRY = f"""<robot name="xyz"><link name="b"/><link name="x"/><link name="y"/><link name="z"/>
<joint name="px" type="prismatic"><parent link="b"/><child link="x"/><axis xyz="1 0 0"/>
  <limit lower="-2" upper="2" {L}/></joint>
<joint name="py" type="prismatic"><parent link="x"/><child link="y"/><axis xyz="0 1 0"/>
  <origin xyz="0 0 1" rpy="0.3 0.2 0.1"/><limit lower="-1" upper="1" {L}/></joint>
<joint name="pz" type="prismatic"><parent link="y"/><child link="z"/><axis xyz="0 0 -1"/>
  <limit lower="0" upper="0.5" {L}/></joint>
</robot>"""
# a SCARA whose second axis is TILT rad off the first: its rotations within 2 TILT of a
# rotation about the first axis
SCARA = f"""<robot name="s"><link name="b"/><link name="l1"/><link name="l2"/><link name="l3"/>
<link name="l4"/>
<joint name="j1" type="revolute"><parent link="b"/><child link="l1"/><axis xyz="0 0 1"/>
  <origin xyz="0 0 0.4"/><limit lower="-2.5" upper="2.5" {L}/></joint>
<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><axis xyz="0 0 1"/>
  <origin xyz="0.35 0 0" rpy="TILT 0 0"/><limit lower="-2.5" upper="2.5" {L}/></joint>
<joint name="j3" type="prismatic"><parent link="l2"/><child link="l3"/><axis xyz="0 0 -1"/>
  <origin xyz="0.3 0 0"/><limit lower="0" upper="0.2" {L}/></joint>
<joint name="j4" type="continuous"><parent link="l3"/><child link="l4"/><axis xyz="0 0 1"/>
  </joint>
</robot>"""


def _tilted(T: pin.SE3, angle: float, axis=(1.0, 0.0, 0.0)) -> pin.SE3:
    return pin.SE3(T.rotation @ pin.exp3(angle * np.asarray(axis)), T.translation)


@pytest.mark.parametrize("solver", ["auto", "dls", "qp"])
def test_a_gantry_given_another_rotation_is_unreachable_at_once(solver):
    """Three prismatic joints have one orientation: any other is ``unreachable`` with the
    angle in the reason, before an iteration, the seed returned; a pose with that very
    orientation is solved."""
    arm = armik.load_string(GANTRY)
    T = arm.fk(np.array([0.3, 0.2, 0.1]))
    q0 = np.array([0.1, -0.2, 0.3])
    r = arm.solve(_tilted(T, 0.5, (0.0, 1.0, 0.0)), q0=q0, solver=solver, seed=0)
    assert r.status == "unreachable" and not r.success, r.reason
    assert "0.5 rad from the one orientation the tip has" in r.reason
    assert r.iterations == 0 and r.restarts == 0
    np.testing.assert_array_equal(r.q, q0)
    ok = arm.solve(T, solver=solver, seed=0)
    assert ok.success and np.linalg.norm(arm.fk(ok.q).translation - T.translation) < 1e-6


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_a_scara_given_a_tilt_is_unreachable_in_every_route(solver):
    """A SCARA's tip turns about the vertical only: a tilted pose is ``unreachable`` by
    ``solve``, again (its prepared plan), ``solve_all`` and ``solve_batch``, whose other
    rows are solved as before (each checked here by Pinocchio's FK)."""
    arm = armik.load("scara")
    rng = np.random.default_rng(3)
    Ts = [arm.fk(arm.random_q(rng)) for _ in range(3)]
    Ts[1] = _tilted(Ts[1], 0.2)
    for _ in range(3):  # the first solve, then the prepared plan's
        r = arm.solve(Ts[1], solver=solver, seed=1)
        assert r.status == "unreachable" and "0.2 rad from every orientation" in r.reason
        assert r.iterations == 0
    every = arm.solve_all(Ts[1], solver=solver, seed=1)
    assert not any(x.success for x in every)
    b = arm.solve_batch(Ts, solver=solver, seed=1, workers=1, progress=False)
    assert b.success.tolist() == [True, False, True]
    assert b[1].status == "unreachable" and "0.2 rad from every orientation" in b[1].reason
    for i in (0, 2):
        got = arm.fk(b.q[i])
        assert np.linalg.norm(pin.log6(got.actInv(Ts[i])).vector) < 1e-5


def test_every_rotation_a_chain_takes_is_within_its_family():
    """Rotations of random configurations (a gantry, the SCARA, a SCARA whose axes are 1e-4
    rad apart, a planar arm) are never refused, nor any within the tolerance of one; a tilt
    beyond the tolerance (and the slack of axes not quite parallel) always is."""
    arms = [armik.load_string(GANTRY), armik.load("scara"), armik.load("planar_3link")]
    arms += [armik.load_string(SCARA.replace("TILT", "1e-4"))]
    rng = np.random.default_rng(0)
    opts = Options()
    for arm in arms:
        family = orientations.FAMILY(arm.kinematics)
        assert family is not None
        for _ in range(200):
            T = arm.fk(arm.random_q(rng))
            assert orientations.gap(family, T.rotation) <= 1e-12
            axis = rng.normal(size=3)
            near = _tilted(T, 0.9 * opts.tol_orientation, axis / np.linalg.norm(axis))
            assert orientations.refused(arm.kinematics, near.rotation, opts) is None
            # about a line across the family's axis, in the base frame: that far from it
            across = np.cross(family.axis, axis) if family.axis is not None else axis
            tilt = 2 * family.slack + 10 * opts.tol_orientation
            R = pin.exp3(tilt * across / np.linalg.norm(across)) @ T.rotation
            assert orientations.refused(arm.kinematics, R, opts) is not None


def test_a_scara_with_axes_not_quite_parallel_reaches_its_own_tilts():
    """Axes 1e-4 rad apart tilt the tip by up to 2e-4 rad: those poses are solved, not
    refused."""
    arm = armik.load_string(SCARA.replace("TILT", "1e-4"))
    rng = np.random.default_rng(5)
    for _ in range(10):
        T = arm.fk(arm.random_q(rng))
        r = arm.solve(T, solver="dls", seed=0)
        assert r.success, r.reason


def test_arms_whose_axes_are_not_parallel_have_no_family():
    for name in ("ur5", "panda", "kinova"):
        assert orientations.FAMILY(armik.load(name).kinematics) is None
