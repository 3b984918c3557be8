"""Batches on forked processes: every chunk collected once, a child's failure raised here,
a collision-checked batch on processes equal to one solved in this process, and a batch
too small to pay for a fork, or on a machine with no core to spare, on threads."""

from __future__ import annotations

import math
import multiprocessing
import os
import sys
import time

import numpy as np
import pytest

import armik
from armik.errors import ArmikError, OptionError
from armik.solve import batch, forked

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="batches fork worker processes on Linux only"
)
WAIT = 60.0  # s: only a broken fork waits this long; every test passes without waiting it


def _child_takes_one(child_work):
    """A work function whose parent side waits until a child has taken a chunk, so that
    a child runs ``child_work`` whatever the scheduling."""
    parent = os.getpid()
    started = multiprocessing.get_context("fork").Event()

    def work(start):
        if os.getpid() == parent:
            assert started.wait(WAIT), "no child took a chunk"
            return start, parent
        started.set()
        return child_work(start)

    return work


def test_every_chunk_is_collected_once_and_children_do_work():
    got = {}
    work = _child_takes_one(lambda start: (start, os.getpid()))
    forked.run(work, range(0, 40, 4), 2, lambda start, value: got.setdefault(start, value))
    assert sorted(got) == list(range(0, 40, 4))
    assert all(value[0] == start for start, value in got.items())
    assert any(pid != os.getpid() for _, pid in got.values())


def test_an_exception_in_a_child_is_raised_here():
    def fail(start):
        raise ValueError(f"bad chunk {start}")

    with pytest.raises(ValueError, match="bad chunk"):
        forked.run(_child_takes_one(fail), range(3), 2, lambda start, value: None)


def test_a_child_that_dies_is_an_armik_error_with_its_exit_code():
    with pytest.raises(ArmikError, match="exit code 3"):
        forked.run(_child_takes_one(lambda start: os._exit(3)), range(3), 2, lambda s, v: None)


GJK_TOL = 1e-6  # m: coal.DistanceRequest().gjk_tolerance


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_a_collision_checked_batch_on_processes_equals_one_in_this_process(name, monkeypatch):
    a = armik.load(name)
    obstacles = (armik.HalfSpace((0, 0, 1), 0.0), armik.Box((0.2, 0.2, 0.2), (0.45, 0.0, 0.3)))
    T = a.fk_batch(a.random_q(5, n=40))
    opts = dict(obstacles=obstacles, self_collision=True, iteration_budget=2000)
    here = a.solve_batch(T, q0=a.middle, workers=1, progress=False, **opts)
    runs = []
    run = forked.run
    monkeypatch.setattr(forked, "usable", lambda: True)
    monkeypatch.setattr(forked, "run", lambda *args: runs.append(1) or run(*args))
    monkeypatch.setattr(batch, "FORK_WORTH", 0.0)  # however little work is left: fork
    monkeypatch.setattr(batch, "_idle", lambda: True)  # however busy the machine
    seen = []
    there = a.solve_batch(
        T, q0=a.middle, workers=2, chunk_size=4, progress=lambda d, n: seen.append(d), **opts
    )
    assert runs == [1]  # the processes' path was taken
    assert seen[-1] == len(T) and seen == sorted(seen)
    np.testing.assert_array_equal(there.q, here.q)
    np.testing.assert_array_equal(there.status_code, here.status_code)
    # coal's distances are exact to its GJK tolerance (1e-6 m by default), and which
    # process measures which chunk, hence each checker's GJK warm start, follows the scheduler
    np.testing.assert_allclose(there.min_distance, here.min_distance, atol=GJK_TOL)
    assert [there.closest_pair(i) for i in range(len(T))] == [
        here.closest_pair(i) for i in range(len(T))
    ]
    assert there.reasons == here.reasons


@pytest.mark.parametrize("small, busy", [(True, False), (False, True)])
def test_a_batch_too_small_to_pay_for_a_fork_or_on_a_busy_machine_runs_on_threads(
    monkeypatch, small, busy
):
    ur5 = armik.load("ur5")
    T = ur5.fk_batch(ur5.random_q(4, n=40))
    opts = dict(self_collision=True, iteration_budget=2000)
    one = ur5.solve_batch(T, q0=ur5.middle, workers=1, progress=False, **opts)
    monkeypatch.setattr(forked, "usable", lambda: True)
    monkeypatch.setattr(forked, "run", lambda *a: pytest.fail("forked where it does not pay"))
    monkeypatch.setattr(batch, "FORK_WORTH", math.inf if small else 0.0)
    monkeypatch.setattr(batch.os, "getloadavg", lambda: (8.0 if busy else 0.0, 0.0, 0.0))
    threads = []
    pool = batch.ThreadPoolExecutor
    monkeypatch.setattr(batch, "ThreadPoolExecutor", lambda **k: threads.append(1) or pool(**k))
    seen = []
    r = ur5.solve_batch(
        T, q0=ur5.middle, workers=2, chunk_size=8, progress=lambda d, n: seen.append(d), **opts
    )
    assert threads == [1]
    assert seen[-1] == len(T) and seen == sorted(seen)
    np.testing.assert_array_equal(r.q, one.q)
    np.testing.assert_array_equal(r.status_code, one.status_code)


def test_a_batch_falls_back_to_threads_when_another_thread_runs(monkeypatch):
    monkeypatch.setattr(forked.threading, "active_count", lambda: 2)
    assert not forked.usable()
    ur5 = armik.load("ur5")
    T = ur5.fk_batch(ur5.random_q(2, n=8))
    monkeypatch.setattr(forked, "run", lambda *a: pytest.fail("forked with threads alive"))
    r = ur5.solve_batch(T, workers=2, chunk_size=2, progress=False, self_collision=True)
    one = ur5.solve_batch(T, workers=1, progress=False, self_collision=True)
    np.testing.assert_array_equal(r.q, one.q)
    assert r.success.sum() >= 6


def test_an_armik_error_in_a_child_comes_back_with_its_fields():
    def fail(start):
        raise OptionError("bad value", option="timeout", value=start)

    with pytest.raises(OptionError, match="bad value") as caught:
        forked.run(_child_takes_one(fail), range(3), 2, lambda start, value: None)
    assert caught.value.option == "timeout"


def test_children_end_on_their_own_after_a_run():
    """The parent returns once every child has said it is done, without waiting for their
    exit; they end all the same (reaped by multiprocessing), none left running."""
    # children this process had before (a Dask cluster's workers, kept for the session)
    before = {child.pid for child in multiprocessing.active_children()}
    got = {}
    forked.run(lambda s: s, list(range(8)), 3, got.__setitem__)
    assert sorted(got) == list(range(8))

    def left() -> list:  # reaps the ended ones
        return [c for c in multiprocessing.active_children() if c.pid not in before]

    for _ in range(int(WAIT / 0.01)):
        if not left():
            break
        time.sleep(0.01)
    assert not left()
