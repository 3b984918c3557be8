"""Joint values handed to a model (locked=, with_locked, with_limits, tip_offset) that
float() reads but that are no joint value: a bool, read as 1 or 0, and an int beyond the
floats, which float() refuses with OverflowError. Each is an armik error naming it."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import armik
from armik.errors import JointError, OptionError

from ..conftest import arm

HUGE = 10**400  # a Python int float() cannot hold


def _load(**kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return armik.load("scara", **kw)


@pytest.mark.parametrize("value", [True, False, np.bool_(True)])
def test_a_bool_is_no_locked_value(value):
    # True would lock the quill at 1 m (outside its limits) or a revolute joint at 1 rad
    with pytest.raises(JointError, match=r"locked value for 'shoulder' must be a finite number"):
        _load(locked={"shoulder": value})
    with pytest.raises(JointError, match=r"locked value for 'shoulder' must be a finite number"):
        arm("scara").with_locked({"shoulder": value})


def test_an_int_beyond_the_floats_is_no_locked_value():
    with pytest.raises(JointError, match=r"locked value for 'shoulder' must be a finite number"):
        _load(locked={"shoulder": HUGE})
    with pytest.raises(JointError, match=r"'shoulder'"):
        arm("scara").with_locked({"shoulder": HUGE})


@pytest.mark.parametrize("pair", [(0, HUGE), (-HUGE, 0.1), (False, True)])
def test_with_limits_refuses_huge_ints_and_bools(pair):
    with pytest.raises(JointError, match=r"limits for 'shoulder' must be numbers"):
        arm("scara").with_limits({"shoulder": pair})


def test_tip_offset_refuses_an_int_beyond_the_floats():
    with pytest.raises(OptionError, match="tip_offset must be numbers"):
        _load(tip_offset=(HUGE, 0, 0))


def test_plain_numbers_still_lock():
    locked = _load(locked={"shoulder": 1, "elbow": np.float32(0.5)})
    assert locked.locked == {"shoulder": 1.0, "elbow": 0.5}
