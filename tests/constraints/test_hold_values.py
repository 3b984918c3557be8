"""A held or locked joint's value checked against the arm's own limits: ``hold=`` on a joint
``with_limits`` widened takes a value within the widened limits (the arm with the joint
locked is built within them), and a value of more than four turns on a joint without a
limit (170 on a continuous joint: degrees by mistake) is refused by name, as
``with_limits`` refuses such a limit."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik

from ..conftest import arm


def test_hold_takes_a_value_within_limits_with_limits_widened():
    wide = arm("panda").with_limits({"panda_joint1": (-25.0, 25.0)})
    q = wide.middle.copy()
    q[0] = 20.0
    T = wide.fk(q)
    every = wide.solve_all(T, hold={"panda_joint1": 20.0})
    for r in [wide.solve(T, hold={"panda_joint1": 20.0}), *every]:
        assert r.q[0] == 20.0
        if r.success:
            assert np.linalg.norm(pin.log6(wide.fk(r.q).inverse() * T).vector) < 1e-9
    assert any(r.success for r in every)
    with pytest.raises(armik.JointError, match=r"outside joint 'panda_joint1'.*25"):
        wide.solve(T, hold={"panda_joint1": 26.0})  # beyond the arm's limits still refused
    with pytest.raises(armik.JointError, match="URDF limits"):
        arm("panda").with_locked({"panda_joint1": 20.0})  # the URDF's: no limits widened


@pytest.mark.parametrize("value", [170.0, -170.0])
def test_four_turns_on_a_continuous_joint_are_refused_as_degrees(value):
    scara = arm("scara")
    p = scara.fk(np.array([0.3, 0.4, 0.1, 0.5])).translation
    radians = f"{np.radians(value):.6g} rad"
    for call in (
        lambda: scara.solve(p, hold={"tool_roll": value}),
        lambda: scara.solve(armik.Position(p), constraints=[armik.Hold("tool_roll", value)]),
        lambda: armik.load("scara", locked={"tool_roll": value}),
        lambda: scara.with_locked({"tool_roll": value}),
    ):
        with pytest.raises(armik.JointError, match="degrees") as got:
            call()
        assert "'tool_roll'" in str(got.value) and radians in str(got.value)
        assert got.value.joint == "tool_roll"
    r = scara.solve(p, hold={"tool_roll": 20.0})  # within four turns: radians, taken
    assert r.q[3] == 20.0
    assert armik.load("scara", locked={"tool_roll": 20.0}).locked == {"tool_roll": 20.0}
