"""The numeric driver writes and reads the packed kernel settings by slot (a call's look-at
point, the budget, the failure words' weights and bounds): each slot is the field
``unpack`` reads back, so a field added to ``pack_settings`` cannot shift them unseen."""

from __future__ import annotations

import typing

import numpy as np

from armik.kernel.problem import Settings, pack_settings, unpack
from armik.solvers.numeric import driver


def _distinct() -> Settings:
    """Settings whose every number differs from every other (a slot read off by one shows)."""
    counter = iter(range(1, 1000))

    def many(k: int) -> np.ndarray:
        return np.array([float(next(counter)) for _ in range(k)])

    values = {}
    for name, kind in typing.get_type_hints(Settings).items():
        if kind is np.ndarray:
            values[name] = many(3 if name in ("cone_axis", "look_point") else 6)
        else:
            values[name] = kind(next(counter))
    values["posture"], values["posture_w"] = many(7), many(7)
    return Settings(**values)


def test_each_slot_the_driver_names_is_the_field_unpack_reads():
    st = _distinct()
    sf, si = pack_settings(st)
    back = unpack(sf, si)
    floats = [
        (driver._WEIGHTS, back.w),
        (driver._BOUNDS, back.bounds),
        (driver._LOOK_POINT, back.look_point),
    ]
    for slot, field in floats:
        assert np.array_equal(sf[slot], field)
    assert np.array_equal(sf[driver._BOUNDS], st.bounds)
    assert si[driver._MAX_RESTARTS] == st.max_restarts == back.max_restarts
    assert si[driver._TIMEOUT_NS] == st.timeout_ns == back.timeout_ns
    assert si[driver._ITERATION_BUDGET] == st.iteration_budget == back.iteration_budget
