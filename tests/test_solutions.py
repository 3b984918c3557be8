"""``Solutions`` (what ``solve_all`` returns) reads as the list it was: built results and
results built on first access alike."""

from __future__ import annotations

import copy
import pickle
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from armik.solutions import Solutions

from .conftest import arm


def _both():
    """(a closed form's lazy ``Solutions``, the same results as a list)."""
    a = arm("abb_irb120")  # some branches outside its limits: failures among them
    T = a.fk(a.random_q(np.random.default_rng(3)))
    lazy = a.solve_all(T)
    assert lazy._make is not None  # built on access: the closed form's route
    return lazy, list(Solutions._lazy(len(lazy), lazy._make, lazy._args))  # built apart


def test_it_reads_as_a_list():
    lazy, built = _both()
    n = len(built)
    assert len(lazy) == n > 2 and bool(lazy)
    assert lazy[0] == built[0] and lazy[-1] == built[-1] and lazy[1] == built[1]
    assert lazy[1:3] == built[1:3] and type(lazy[1:3]) is list and lazy[::-1] == built[::-1]
    with pytest.raises(IndexError):
        lazy[n]  # noqa: B018
    assert [r.q for r in lazy][0] is lazy[0].q  # each result built once, then kept
    assert lazy == built and built == lazy and not lazy != built
    assert lazy == Solutions(built) and lazy != built[:-1] and lazy != tuple(built)
    assert built[2] in lazy and lazy.index(built[2]) == 2 and lazy.count(built[0]) == 1
    assert lazy + [] == built and [] + lazy == built and type(lazy + lazy) is list
    assert repr(lazy) == repr(built)
    assert not Solutions() and Solutions() == []
    assert not isinstance(lazy, list)


def test_it_pickles_and_copies_as_its_results():
    lazy, built = _both()
    for other in (pickle.loads(pickle.dumps(lazy)), copy.copy(lazy), copy.deepcopy(lazy)):
        assert type(other) is Solutions and other == built
    assert all(r.reason for r in pickle.loads(pickle.dumps(lazy)))


def test_changing_it_changes_its_results():
    lazy, built = _both()
    lazy.sort(key=lambda r: -r.position_error)
    assert lazy == sorted(built, key=lambda r: -r.position_error)
    lazy.append(built[0])
    del lazy[0]
    lazy.reverse()
    assert lazy[0] == built[0] and len(lazy) == len(built)
    lazy[0] = built[1]
    assert lazy[0] is built[1] and lazy.pop() is not None and len(lazy) == len(built) - 1
    lazy += [built[0]]
    assert lazy[-1] is built[0]


def test_every_route_returns_solutions():
    for name, kw in (("panda", {"max_solutions": 2, "seed": 0}), ("ur5", {}), ("planar_2link", {})):
        a = arm(name)
        T = a.fk(a.middle + 0.1)
        target = T.translation if name == "planar_2link" else T
        got = a.solve_all(target, **kw)
        assert type(got) is Solutions and got[0].success


def test_threads_reading_it_at_once_read_the_same_results():
    """The first read makes a closed form's rows whole (measured, ordered, labelled) and
    read-only; threads that read at once all read what one thread alone reads."""
    a = arm("abb_irb120")
    T = a.fk(a.random_q(np.random.default_rng(3)))
    alone = [(r.branch, r.status, r.position_error, tuple(r.q)) for r in a.solve_all(T)]
    for _ in range(5):
        lazy = a.solve_all(T)
        start = threading.Barrier(4)

        def read(lazy=lazy, start=start):
            start.wait()
            return [(r.branch, r.status, r.position_error, tuple(r.q)) for r in lazy]

        with ThreadPoolExecutor(4) as pool:
            got = [f.result() for f in [pool.submit(read) for _ in range(4)]]
        assert all(g == alone for g in got)
