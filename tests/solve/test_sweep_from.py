"""A global path's rungs on a 7R arm start the swept closed form's sweep at each value they
try by the value itself (``registry.swept_from``, a ``Sweep.from_value`` a solver may
declare), never by writing it into the seed the answers are ranked nearest."""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

from armik.solvers import registry
from tests.conftest import arm as bundled


@pytest.fixture
def recorded():
    """The swept solver re-registered with a ``from_value`` that records each call's seed
    and value and answers as its ``run`` does from that value; the original put back."""
    original = registry.get("swept")
    calls: list[tuple[np.ndarray, float]] = []

    def from_value(arm, target, seed, value, opts, every):
        calls.append((np.array(seed), value))
        start = np.array(seed, dtype=float)
        start[original.sweep.joint] = value
        return original.run(arm, target, start, opts, every)

    registry.unregister("swept")
    registry.register(
        dataclasses.replace(original, sweep=original.sweep._replace(from_value=from_value))
    )
    yield calls
    registry.unregister("swept")
    registry.register(original)


def _line():
    a = bundled("panda")
    q = a.middle + 0.1
    T = a.fk(q)
    return a, q, [pin.SE3(T.rotation, T.translation + [0, 0.02 * k, 0]) for k in range(4)]


def test_a_global_paths_rungs_give_the_sweep_its_value_as_an_argument(recorded):
    a, q, line = _line()
    b = a.solve_path(line, q, plan="global", solver="swept")
    assert b.success.all()
    assert len(recorded) >= len(line) * 5  # every waypoint's values about the followed path
    values = {v for _, v in recorded}
    assert len(values) > 5
    for seed, _ in recorded:  # the seed is the path's start, never rewritten to a value
        assert np.array_equal(seed, q)


def test_the_declared_sweep_gives_the_plan_its_run_gave(recorded):
    a, q, line = _line()
    declared = a.solve_path(line, q, plan="global", solver="swept")
    assert recorded
    swept = registry.get("swept")
    registry.unregister("swept")
    registry.register(dataclasses.replace(swept, sweep=swept.sweep._replace(from_value=None)))
    plain = a.solve_path(line, q, plan="global", solver="swept")
    np.testing.assert_array_equal(declared.q, plain.q)
    assert [declared.reason(i) for i in range(len(line))] == [
        plain.reason(i) for i in range(len(line))
    ]
