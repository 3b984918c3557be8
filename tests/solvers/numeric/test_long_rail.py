"""An arm on a long rail: the null-space pull toward q0 along a prismatic joint counts at
most ``kernel.step.PULL_REACH``, so that hundreds of metres between q0 and the answer do
not outweigh the error."""

from __future__ import annotations

import numpy as np
import pytest

import armik

GANTRY = """<?xml version="1.0"?>
<robot name="gantry">
  <link name="base"/><link name="x"/><link name="y"/><link name="z"/><link name="w1"/>
  <link name="w2"/><link name="w3"/><link name="tcp"/>
  <joint name="px" type="prismatic"><parent link="base"/><child link="x"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="RAIL" effort="1" velocity="1"/></joint>
  <joint name="py" type="prismatic"><parent link="x"/><child link="y"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="6" effort="1" velocity="1"/></joint>
  <joint name="pz" type="prismatic"><parent link="y"/><child link="z"/>
    <origin xyz="0 0 2" rpy="3.14159265 0 0"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="r1" type="revolute"><parent link="z"/><child link="w1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="r2" type="revolute"><parent link="w1"/><child link="w2"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="r3" type="continuous"><parent link="w2"/><child link="w3"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/></joint>
  <joint name="t" type="fixed"><parent link="w3"/><child link="tcp"/>
    <origin xyz="0.02 0 0.15" rpy="0 0.3 0"/></joint>
</robot>
"""


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_positions_along_a_rail_1000_m_long_are_reached(solver):
    """Positions of a gantry whose rail is 1000 m long (six joints for three numbers: the
    pull acts): every one reached, where the pull toward q0, the rail's middle, held the
    search back (6 of 40 with dls, 9 with qp); each checked by Pinocchio's FK."""
    arm = armik.load_string(GANTRY.replace("RAIL", "1000"))
    rng = np.random.default_rng(1)
    for _ in range(20):
        p = arm.fk(arm.random_q(rng)).translation
        r = arm.solve(p, solver=solver, seed=0)
        assert r.success, r.reason
        assert np.linalg.norm(arm.fk(r.q).translation - p) < 1e-6 and arm.within_limits(r.q)
