"""The options an arm keeps once validated (``armik.solve.read.settings``) never change
what validation accepts: a value refused on a fresh arm is refused after an equal one
(``True == 1``, the same hash) was accepted, and the other way round."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.solve.read import settings

_REFUSED = "hold's value for joint 'panda_joint7' must be a finite number"


@pytest.mark.parametrize("flag", [True, np.True_])
def test_a_held_bool_is_refused_after_an_equal_number_was_kept(flag):
    arm = armik.load("panda")  # a fresh arm: its own kept options
    target = arm.fk(arm.middle + 0.1)
    with pytest.raises(armik.OptionError, match=_REFUSED):
        arm.solve(target, hold={"panda_joint7": flag})
    opts, key, _ = settings(arm.kinematics, {"hold": {"panda_joint7": 1}})
    assert key is not None and opts.hold == (("panda_joint7", 1.0),)
    arm.solve(target, hold={"panda_joint7": 1})
    with pytest.raises(armik.OptionError, match=_REFUSED):
        arm.solve(target, hold={"panda_joint7": flag})
    with pytest.raises(armik.OptionError, match=_REFUSED):
        settings(arm.kinematics, {"hold": {"panda_joint7": flag}})
    again, key_again, _ = settings(arm.kinematics, {"hold": {"panda_joint7": 1}})
    assert again is opts and key_again == key  # the number's still kept
