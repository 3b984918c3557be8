"""The cold first solve compiled on two cores (``kernel.warmup``): the helper's step is the
one the entries load, the parts this process compiles are the ones the entries call, and
the answers are those of a single process."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

import armik
from armik.kernel import measure as check
from armik.kernel import problem, step, tier, warmup
from tests.kernel import seeded_cache

# A fresh interpreter on a cache without the kernel's entries, descent, steps and share (see
# ``_seed_with_callees``): a first dls solve and batch, then what compiled.
COLD = r"""
import json, numpy as np, armik
from armik.kernel import step, warmup
a = armik.load("panda")
T = a.fk(a.random_q(np.random.default_rng(5)))
r = a.solve(T, solver="dls", seed=1)
a.solve_batch(np.array([T.homogeneous] * 2), solver="dls", workers=1, seed=1)
step_types, share = warmup._parts()
print(json.dumps({
    "q": r.q.tolist(),
    "step_loaded": step.dls.stats.cache_hits.get(step_types, 0),
    "step_compiled": sum(step.dls.stats.cache_misses.values()),
    "share": [
        [d.py_func.__name__, [str(s) for s in d.signatures], str(types)] for d, types in share
    ],
}))
"""


# What the cold solve compiles itself: the entries, the descent, the steps, the helper's check
# and this process's share (``warmup._parts``). The rest of what they call (the FK, the
# region's rows, the linear algebra) may come from the suite's cache when the tour has
# filled it: numba would only compile it again, and the test is about the helper.
COLD_MODULES = ("armik.kernel.descent", "armik.kernel.single", "armik.kernel.entry")


def _seed_with_callees(cache: Path) -> None:
    """Seed ``cache`` with the kernel's entries but those the cold solve compiles itself."""
    cold = {step.dls, step.qp, check.placement_check, *(d for d, _ in warmup._parts()[1])}
    seeded_cache.seed(cache, lambda d, module: d in cold or module in COLD_MODULES)


def test_cold_first_solve_loads_the_helpers_step(tmp_path):
    _seed_with_callees(tmp_path)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), tier.HELPER: "1"}
    out = subprocess.run(
        [sys.executable, "-c", COLD], env=env, capture_output=True, text=True, check=True
    )
    got = json.loads(out.stdout.splitlines()[-1])
    # the step came from the helper's cache entry; this process compiled none
    assert got["step_loaded"] >= 1 and got["step_compiled"] == 0
    # each part compiled here has one signature, the warm-up's: the pose and batch entries
    # called it with exactly those types
    for name, signatures, types in got["share"]:
        assert signatures == [types], name
    # the answer of a single process (whatever its cache holds)
    a = armik.load("panda")
    T = a.fk(a.random_q(np.random.default_rng(5)))
    assert np.array_equal(np.array(got["q"]), a.solve(T, solver="dls", seed=1).q)


def test_the_environment_decides_first(monkeypatch):
    monkeypatch.setenv(tier.HELPER, "0")
    assert not tier.helper_allowed()
    monkeypatch.setenv(tier.HELPER, "1")
    assert tier.helper_allowed()


def test_no_helper_once_compiled(monkeypatch):
    a = armik.load("panda")
    a.solve(a.fk(a.middle), solver="dls")  # compiled or loaded: nothing left to share
    monkeypatch.setenv(tier.HELPER, "1")
    monkeypatch.setattr(warmup, "PREPARED", set())

    def refuse(kind):
        raise AssertionError("a helper started with nothing to compile")

    monkeypatch.setattr(warmup, "_start_helper", refuse)
    warmup.prepare(problem.STEP_DLS)
    assert problem.STEP_DLS in warmup.PREPARED


class _Helper:
    """A helper process that has compiled its step."""

    stdout = iter(["step\n"])

    def kill(self):
        raise AssertionError("the helper was stopped")

    def communicate(self):
        return "", ""


class _Part:
    """A compiled part of this process's share: records its compilations."""

    def __init__(self, done: list) -> None:
        self.done = done

    def compile(self, types) -> None:
        self.done.append(types)


def test_start_begins_the_helper_and_prepare_does_the_rest(monkeypatch):
    """``armik demo`` starts the helper before its 2-link arm: nothing compiles in this
    process until ``prepare``, which compiles the share and waits for that very helper."""
    compiled, started = [], []
    monkeypatch.setattr(warmup, "PREPARED", set())
    monkeypatch.setattr(warmup, "_started", {})
    monkeypatch.setattr(warmup, "_needs_helper", lambda kind: True)
    monkeypatch.setattr(warmup, "_parts", lambda: ((), [(_Part(compiled), ("types",))]))
    monkeypatch.setattr(warmup, "_start_helper", lambda kind: started.append(kind) or _Helper())
    warmup.start(problem.STEP_DLS)
    warmup.start(problem.STEP_DLS)  # once
    assert started == [problem.STEP_DLS] and compiled == []
    warmup.prepare(problem.STEP_DLS)
    assert started == [problem.STEP_DLS] and compiled == [("types",)]  # no second helper
    assert warmup._started == {} and problem.STEP_DLS in warmup.PREPARED
    warmup.start(problem.STEP_DLS)  # prepared already: nothing
    assert started == [problem.STEP_DLS]


def test_demo_starts_the_helper_and_prepares_nothing_before_its_2_link_arm(monkeypatch):
    from armik.tools.cli import arms

    calls = []
    monkeypatch.setattr(warmup, "start", lambda kind: calls.append(("start", kind)))
    monkeypatch.setattr(warmup, "prepare", lambda kind: calls.append(("prepare", kind)))

    def stop(name):
        calls.append(("load", name))
        raise KeyboardInterrupt  # stop before any solve

    monkeypatch.setattr(arms, "load", stop)
    try:
        arms.cmd_demo(None)
    except KeyboardInterrupt:
        pass
    assert calls == [("start", problem.STEP_DLS), ("load", "planar_2link")]
