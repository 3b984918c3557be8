"""``arm.intervals(T, over)`` with ``over`` neither a joint of the arm nor an option a solver
declares: an unknown joint, named, with the arm's joints listed."""

from __future__ import annotations

import pytest

import armik

from ..conftest import arm


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_an_unknown_joint_is_named_with_the_joints(name):
    a = arm(name)
    with pytest.raises(armik.JointError, match="unknown joint 'zz'") as got:
        a.intervals(a.fk(a.middle), "zz")
    assert all(repr(j) in str(got.value) for j in a.joint_names)
    assert got.value.candidates == tuple(a.joint_names)
    with pytest.raises(armik.OptionError, match="it can be swept over"):
        a.intervals(a.fk(a.middle), a.joint_names[0])  # a joint, no closed form of it
