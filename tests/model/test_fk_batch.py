"""fk_batch (compiled FK of many configurations) against Pinocchio's FK, and random_q(n)."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.errors import OptionError

from ..conftest import ALL_ROBOTS, arm


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_fk_batch_is_pinocchio_fk_row_by_row(name):
    a = arm(name)
    Q = a.random_q(np.random.default_rng(5), n=40)
    expected = np.array([a.fk(q).homogeneous for q in Q])
    np.testing.assert_allclose(a.fk_batch(Q), expected, rtol=0, atol=1e-12)


def test_fk_batch_with_a_tool_offset_another_base_and_wide_angles():
    a = armik.load("ur5", base="base_link", tip="wrist_3_link", tip_offset=(0.01, -0.02, 0.15))
    k = armik.load("kinova")  # continuous joints, given angles beyond pi
    for b in (a, k):
        Q = b.random_q(3, n=20) * 3.0
        expected = np.array([b.fk(q).homogeneous for q in Q])
        np.testing.assert_allclose(b.fk_batch(Q), expected, rtol=0, atol=1e-12)


def test_fk_batch_shapes_and_bad_input():
    a = arm("ur5")
    assert a.fk_batch(np.zeros((0, 6))).shape == (0, 4, 4)
    assert a.fk_batch(np.zeros(6)).shape == (1, 4, 4)  # one configuration
    with pytest.raises(OptionError, match=r"shape \(N, 6\)"):
        a.fk_batch(np.zeros((3, 5)))
    with pytest.raises(OptionError, match="row 1 of Q is not finite"):
        a.fk_batch([[0.0] * 6, [np.nan] * 6])
    with pytest.raises(OptionError, match="joint values"):
        a.fk_batch("zeros")


def test_random_q_of_n_configurations():
    a = arm("panda")
    Q = a.random_q(7, n=100)
    assert Q.shape == (100, 7)
    assert (Q >= a.lower).all() and (Q <= a.upper).all()
    np.testing.assert_array_equal(Q, a.random_q(7, n=100))  # seeded
    assert a.random_q(7).shape == (7,)  # without n: one configuration, as always
    with pytest.raises(OptionError, match="whole number"):
        a.random_q(n=-1)
