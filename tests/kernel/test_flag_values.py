"""The compile flags' values in one merge (``kernel.flag_values``) are numba's own."""

from __future__ import annotations

import pickle

from numba.core import targetconfig
from numba.core.compiler import Flags

from armik.kernel import flag_values


def _flags(**set_: object) -> Flags:
    flags = Flags()
    for name, value in set_.items():
        setattr(flags, name, value)
    return flags


def test_numbas_values_are_replaced_by_the_merge():
    assert targetconfig.TargetConfig.values is flag_values.values
    flag_values.install()  # twice: still the merge, not wrapped again
    assert targetconfig.TargetConfig.values is flag_values.values


def test_the_merge_gives_numbas_keys_order_and_values():
    cases = [
        _flags(),
        _flags(nrt=True, boundscheck=True),
        _flags(error_model="numpy", release_gil=True, no_cpython_wrapper=True),
        _flags(inline="always", fastmath=True, boundscheck=False),
    ]
    cases.append(Flags(cases[2]))  # a copy
    for flags in cases:
        ours, numbas = flags.values(), flag_values.numbas(flags)
        assert list(ours.items()) == list(numbas.items())
        assert (ours != _flags().values()) == bool(flags._values)  # the set values are read


def test_flags_hash_and_compare_as_numbas_values_say():
    a, b, c = _flags(nrt=True), _flags(nrt=True), _flags(nrt=False)
    assert a == b and hash(a) == hash(b)
    assert a != c  # a value set to another than the default's
    assert _flags(nrt=False) == _flags()  # set to the default: the same flags
    assert hash(_flags(nrt=False)) == hash(_flags())
    assert pickle.loads(pickle.dumps(a)) == a
