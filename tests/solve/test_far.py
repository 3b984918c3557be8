"""A target beyond reach answers at once: in a fresh process with an empty numba cache, its
first solve compiles and loads nothing, and its answer is the kernel path's, field for
field."""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solve import far
from armik.solve.read import read

from ..conftest import arm

FIELDS = [f.name for f in dataclasses.fields(armik.IKResult) if f.name not in ("time", "extra")]


def far_pose() -> pin.SE3:
    return pin.SE3(pin.rpy.rpyToMatrix(0.3, -0.2, 1.0), np.array([2.0, -1.5, 0.7]))


# (target, options): every spelling the reach test answers on the Panda
CASES = {
    "SE3": lambda a: (far_pose(), {}),
    "4x4": lambda a: (far_pose().homogeneous, {}),
    "position array": lambda a: (np.array([8.0, 0.0, 0.0]), {}),
    "position tuple": lambda a: ((8, 0, 0), {}),
    "position list, q0": lambda a: ([0.0, 3.0, 0.5], {"q0": a.middle + 0.1}),
    "position_only": lambda a: (far_pose(), {"position_only": True}),
    "qp": lambda a: (far_pose(), {"solver": "qp"}),
    "a looser tolerance": lambda a: ((1.5, 0, 0.3), {"tol_position": 1e-3, "seed": 4}),
}


@pytest.mark.parametrize("name", list(CASES))
def test_a_far_target_is_answered_as_the_kernel_answers_it(name, monkeypatch):
    a = arm("panda")
    target, options = CASES[name](a)
    monkeypatch.setattr(far, "first_use", False)  # the solver's way: the kernel says it
    kernel = a.solve(target, **options)
    assert kernel.status == armik.Status.UNREACHABLE and kernel.iterations == 0
    called = []
    answer = far.beyond_reach
    monkeypatch.setattr(far, "first_use", True)
    monkeypatch.setattr(far, "beyond_reach", lambda *args: called.append(1) or answer(*args))
    at_once = a.solve(target, **options)
    assert called and far.first_use  # answered here: the process's first use goes on
    for field in FIELDS:
        x, y = getattr(at_once, field), getattr(kernel, field)
        if isinstance(x, np.ndarray):
            assert np.array_equal(x, y), field
        else:
            assert x == y, field  # the errors too, bit for bit


@pytest.mark.parametrize(
    "target, options",
    [
        ((0.3, 0.0, 0.5), {}),  # within reach
        ((8.0, 0.0, 0.0), {"weights": [1, 1, 1, 0.5, 0.5, 0.5]}),  # weights: the kernel's
        ((8.0, 0.0, 0.0), {"bounds": [0.1, 0.1, 0.1, 0, 0, 0]}),  # a region: the kernel's
    ],
)
def test_what_it_cannot_answer_goes_on_and_ends_the_first_use(target, options, monkeypatch):
    monkeypatch.setattr(far, "first_use", True)
    panda = arm("panda").kinematics
    req = read(panda, target, None, "auto", options)
    assert far.beyond_reach(panda, req) is None
    assert not far.first_use  # later solves pay one flag's read


FRESH = r"""
import gc, json, sys
from numba.core import event
from numba.core.dispatcher import Dispatcher

compiled = []


class Seen(event.Listener):
    def on_start(self, ev):
        compiled.append(ev.data["dispatcher"].py_func.__qualname__)

    def on_end(self, ev):
        pass


event.register("numba:compile", Seen())
import armik

a = armik.load("panda")
refused = None
try:
    a.solve((8, 0, "far"))
except armik.ArmikError as exc:
    refused = type(exc).__name__
r = a.solve((8, 0, 0))
loaded = sorted(
    d.py_func.__qualname__ for d in gc.get_objects() if isinstance(d, Dispatcher) and d.overloads
)
print(json.dumps({"status": r.status.value, "q": r.q.tolist(), "reason": r.reason,
                  "refused": refused, "compiled": compiled, "loaded": loaded}))
"""


def test_a_fresh_process_with_an_empty_cache_compiles_and_loads_nothing(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "ARMIK_COMPILE_NOTICE": "1"}
    out = subprocess.run(
        [sys.executable, "-c", FRESH], env=env, capture_output=True, text=True, check=True
    )
    got = json.loads(out.stdout.splitlines()[-1])
    assert got["refused"] == "TargetError"  # a bad target is refused before anything too
    assert (got["compiled"], got["loaded"]) == ([], [])
    assert "compiling" not in out.stderr  # no notice: nothing was compiled
    assert not [p for p in tmp_path.rglob("*") if p.is_file()]  # nor written to the cache
    a = arm("panda")
    assert got["status"] == "unreachable" and got["q"] == a.kinematics.seed(None).tolist()
    assert "beyond the arm's reach" in got["reason"]
