"""The route of one warm call on each row of ``benchmarks/route_table.py``: the Python
calls made inside armik stay within what the one-request design brought them to (at most
the calls of 4b1fe1a on the first three rows, at most half of them on the others), they
enter no more of armik's modules than they do today, and a target is parsed at most once.
Counted by a profile hook, as ``../shared/tools/route.py`` counts them: a count, not a
time."""

from __future__ import annotations

import sys

import numpy as np
import pinocchio as pin
import pytest
from benchmarks.route_table import ROWS

import armik

# the most Python calls inside armik each row may make (its label in ``ROWS``)
MOST = {
    "UR5 solve(T)": 12,
    "UR5 solve(T, bounds=...)": 16,
    "UR5 solve_all(T)": 61,
    "Panda solve(T, obstacles=[sphere])": 50,
    "Panda solve((p, quat), prefer='manipulability')": 1501,
    "Panda solve(T, hold=joint 7)": 81,
    "Panda solve_all(T)": 111,
    "Panda solve_batch(4 poses, workers=1)": 38,
    "UR5 solve_path(3 poses, q)": 174,
    "TALOS Arms.solve, both hands": 115,
}


# the most of armik's modules each row may enter: what each does work in today
MODULES = {
    "UR5 solve(T)": 8,
    "UR5 solve(T, bounds=...)": 10,
    "UR5 solve_all(T)": 7,
    "Panda solve(T, obstacles=[sphere])": 12,
    "Panda solve((p, quat), prefer='manipulability')": 26,
    "Panda solve(T, hold=joint 7)": 17,
    "Panda solve_all(T)": 15,
    "Panda solve_batch(4 poses, workers=1)": 13,
    "UR5 solve_path(3 poses, q)": 19,
    "TALOS Arms.solve, both hands": 26,
}


def _route(setup: str, call: str) -> tuple[int, int, set[str]]:
    """(Python calls inside armik, target parses, modules entered) of one warm ``call``."""
    env: dict = {"armik": armik, "np": np, "pin": pin}
    exec(setup, env)
    exec(call, env)  # warm
    calls = parses = 0
    modules: set[str] = set()

    def hook(frame, event, arg):
        nonlocal calls, parses
        module = frame.f_globals.get("__name__", "")
        if event == "call" and module.startswith("armik"):
            calls += 1
            parses += frame.f_code.co_name == "parse_target"
            modules.add(module)

    sys.setprofile(hook)
    try:
        exec(call, env)
    finally:
        sys.setprofile(None)
    return calls, parses, modules


@pytest.mark.parametrize(("label", "setup", "call"), ROWS, ids=[r[0] for r in ROWS])
def test_a_warm_route_stays_as_short_as_the_design_made_it(label, setup, call):
    calls, parses, modules = _route(setup, call)
    assert parses <= 1, f"{label}: the target parsed {parses} times"
    assert calls <= MOST[label], f"{label}: {calls} Python calls, at most {MOST[label]}"
    assert len(modules) <= MODULES[label], f"{label}: enters {sorted(modules)}"
