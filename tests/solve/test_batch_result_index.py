"""A ``BatchResult`` indexed by anything but an int, a slice, a mask of its length or a
list of ints in range: an ``IndexError`` in its own words naming the key and the rows, where
numpy's words came through (or a float, a bool, a string read as a row)."""

from __future__ import annotations

import numpy as np
import pytest

import armik


def test_a_bad_key_is_named_with_the_batch_s_rows():
    arm = armik.load("ur5")
    b = arm.solve_batch(arm.fk_batch(arm.random_q(1, 3)))
    assert b[-1].q.tolist() == b.q[2].tolist() and len(b[[0, 0]]) == 2 and len(b[[]]) == 0
    assert len(b[np.array([True, False, True])]) == 2
    for key in ["a", 1.5, [5], [True, False], np.array([True]), None, (0, 1), [1.0], True]:
        with pytest.raises(IndexError, match=r"BatchResult of 3 rows .* got ") as info:
            b[key]  # noqa: B018
        assert repr(key)[:20] in str(info.value)
    for key in ["x", 1.9, True]:
        with pytest.raises(IndexError, match=r"a target index is a whole number in \[-3, 3\)"):
            b.reason(key)  # type: ignore[arg-type]
