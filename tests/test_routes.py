"""The route of one warm call on each row of ``benchmarks/route_table.py``: the Python
calls made inside armik stay within what the one-request design brought them to (at most
the calls of 4b1fe1a on the first three rows, at most half of them on the others), they
enter no more of armik's modules than they do today, and a target is parsed at most once.
Counted by a profile hook, as ``../shared/tools/route.py`` counts them: a count, not a
time. No call goes against the direction of the imports (a "call up", by that tool's
floors: it sits beside the project's checkout, as in CI)."""

from __future__ import annotations

import functools
import importlib.util
import sys
from pathlib import Path

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


ROUTE = Path(__file__).resolve().parents[1].parent / "shared" / "tools" / "route.py"


@functools.cache
def _floors():
    """``route.py``'s floor of a module (1 + the highest floor it imports at module level),
    read from this checkout's sources: once a test process, as the tool reads them once a
    run (its floors are kept as they are found; read again, each row parsed every module)."""
    return _read_route().floor


def _read_route():
    """``route.py`` loaded, its sources this checkout's."""
    if not ROUTE.is_file():
        pytest.skip(f"{ROUTE} is not beside the checkout: calls up are not counted")
    spec = importlib.util.spec_from_file_location("shared_route", ROUTE)
    route = importlib.util.module_from_spec(spec)  # type: ignore[arg-type]
    # route.py puts the checkout's src first on sys.path when it loads: this process, and
    # every process it starts after (a Dask cluster's workers, the compile tests'), would
    # import armik from there, beside the installed one, and compile it all again
    path = list(sys.path)
    try:
        spec.loader.exec_module(route)  # type: ignore[union-attr]
    finally:
        sys.path[:] = path
    route.SRC = str(Path(__file__).resolve().parents[1] / "src")
    return route


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


@pytest.mark.parametrize(("label", "setup", "call"), ROWS, ids=[r[0] for r in ROWS])
def test_a_warm_route_makes_no_call_up(label, setup, call):
    # the preference sweep's golden section called its function back from swept_7r: 114
    # calls against the direction of the imports
    floor = _floors()
    env: dict = {"armik": armik, "np": np, "pin": pin}
    exec(setup, env)
    exec(call, env)  # warm
    stack: list[str | None] = []
    up: list[tuple[str, str]] = []

    def hook(frame, event, arg):
        if event == "call":
            module = frame.f_globals.get("__name__", "")
            inside = module.startswith("armik")
            if inside and stack and stack[-1] and stack[-1] != module:
                if floor(module) > floor(stack[-1]):
                    up.append((stack[-1], f"{module}.{frame.f_code.co_name}"))
            stack.append(module if inside else None)
        elif event == "return" and stack:
            stack.pop()

    sys.setprofile(hook)
    try:
        exec(call, env)
    finally:
        sys.setprofile(None)
    assert not up, f"{label}: {len(up)} calls up, the first {up[:3]}"


def test_reading_the_route_tool_leaves_sys_path_as_it_was():
    # this process's later imports, and the processes it starts (their sys.path is this
    # one's), import the armik under test, not the checkout's src beside it
    before = list(sys.path)
    _read_route()
    assert sys.path == before
