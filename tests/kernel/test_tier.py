"""First calls as Python while a helper process compiles (``kernel.tier``, ``as_python``)."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import time
import types
from pathlib import Path

import numpy as np
import pytest

from tests.kernel import python_battery

HERE = Path(__file__).resolve()


def test_every_feature_answers_as_python_as_compiled(tmp_path):
    """Each feature's call run as Python on an empty cache, nothing compiled, against the
    same call compiled: the same kernels, so the same answers (to rounding: numba's and
    NumPy's sums and products may round differently in the last bits)."""
    env = {
        **os.environ,
        "NUMBA_CACHE_DIR": str(tmp_path / "cache"),
        "ARMIK_FIRST_CALLS": "python",
        "PYTHONPATH": os.pathsep.join([str(HERE.parents[2]), os.environ.get("PYTHONPATH", "")]),
    }
    code = (
        "from numba.core import event\n"
        "import runpy, sys\n"
        "with event.install_recorder('numba:compile') as rec:\n"
        f"    sys.argv = ['', {str(tmp_path / 'python.npz')!r}]\n"
        f"    runpy.run_path({str(HERE.parent / 'python_battery.py')!r}, run_name='__main__')\n"
        "print(len([e for e in rec.buffer if e[1].is_start]))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr[-3000:]
    assert out.stdout.split()[-1] == "0"  # nothing compiled: every kernel ran as Python
    python = np.load(tmp_path / "python.npz")
    compiled = python_battery.answers()
    assert sorted(python.files) == sorted(compiled)
    for name, value in compiled.items():
        assert python[name].shape == value.shape, name
        if name.endswith(".ok"):
            assert np.array_equal(python[name], value), name
            assert value.all(), name
        else:
            np.testing.assert_allclose(python[name], value, atol=1e-9, rtol=0, err_msg=name)


HELPED = r"""
import json, sys
from numba.core import event
import numpy as np
import armik
from armik.kernel import tier
with event.install_recorder("numba:compile") as rec:
    arm = armik.load("planar_2link")
    first = [r.q for r in arm.solve_all([1.2, 0.5])]
    tier.wait()  # the helper has compiled what the first call ran as Python
    second = [r.q for r in arm.solve_all([1.2, 0.5])]
compiled_here = [e[1].data["dispatcher"].py_func.__qualname__ for e in rec.buffer if e[1].is_start]
hits = sum(sum(f.stats.cache_hits.values()) for f in tier.ran_as_python())
print(json.dumps({"compiled_here": compiled_here, "ran": len(tier.ran_as_python()),
                  "cache_hits": hits, "same": bool(np.allclose(first, second, atol=1e-12)),
                  "helper_left": tier._state.helper is not None}))
"""


def _first_calls_by_default(code: str, cache: Path) -> tuple[dict, str]:
    """(the JSON ``code`` prints last, its stderr) in a process with the library's default
    first calls (a helper even on one CPU, the notice on) on the empty cache ``cache``."""
    env = {
        **os.environ,
        "NUMBA_CACHE_DIR": str(cache),
        "ARMIK_COMPILE_HELPER": "1",
        "ARMIK_COMPILE_NOTICE": "1",
        "PYTHONPATH": os.pathsep.join([str(HERE.parents[2]), os.environ.get("PYTHONPATH", "")]),
    }
    env.pop("ARMIK_FIRST_CALLS")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads(out.stdout.splitlines()[-1]), out.stderr


def test_a_first_call_runs_as_python_and_the_next_loads_the_helpers_code(tmp_path):
    got, stderr = _first_calls_by_default(HELPED, tmp_path)
    assert got["compiled_here"] == []  # the helper compiled; this process loaded
    assert got["ran"] >= 1 and got["cache_hits"] >= got["ran"]
    assert got["same"]
    assert not got["helper_left"]  # it was told to end once all was done
    assert "in the background" in stderr


def test_an_arrays_type_is_numbas():
    from numba import njit, typeof

    from armik.kernel.tier import _type_of

    f = njit(lambda x: x)
    a = np.zeros((4, 3))
    readonly = np.ones(3, dtype=np.int64)
    readonly.flags.writeable = False
    for value in (a, a.T, a[:, 1], a[::2], readonly, np.zeros(()), np.zeros(2, np.bool_), 3, 2.5):
        assert _type_of(f, value) == typeof(value), value


COMPILE = r"""
import json
from numba.core import event
import armik
from armik.kernel import tier
with event.install_recorder("numba:compile") as rec:
    armik.compile(["fk_batch"], jobs=1, progress=False)
print(json.dumps({"compiled": sum(e[1].is_start for e in rec.buffer),
                  "helped": len(tier.ran_as_python())}))
"""


def test_armik_compile_compiles_in_its_process_whatever_the_first_calls_do(tmp_path):
    got, _ = _first_calls_by_default(COMPILE, tmp_path)
    assert got["compiled"] >= 1 and got["helped"] == 0
    assert os.environ["ARMIK_FIRST_CALLS"] == "compile"  # the tests' setting, untouched


def _count(now):
    now[0] += 1.0  # a second of CPU time, run as Python


def test_a_python_run_is_counted_by_the_budgets_at_compiled_speed(monkeypatch):
    from numba import njit

    from armik import cpu_time
    from armik.kernel import as_python

    now = [100.0]
    monkeypatch.setattr(time, "thread_time", lambda: now[0])
    before = cpu_time.thread_time()
    as_python.run(njit(_count))(now)
    assert cpu_time.thread_time() - before == pytest.approx(1.0 / as_python.SLOWER)


def test_the_helpers_other_output_is_ignored_and_it_is_let_go_once_done(monkeypatch):
    from armik.kernel import tier

    state = tier._State()
    monkeypatch.setattr(tier, "_state", state)
    helper = object.__new__(tier._Helper)
    stdin = io.BytesIO()
    lines = [b"[cache] index saved\n", b"armik-compiled 0\n", b"armik-compiled 1\n"]
    helper.process = types.SimpleNamespace(stdout=iter(lines[:2]), stdin=stdin)
    helper.sent = [("f", ()), ("g", ())]
    state.helper, state.jobs = helper, dict.fromkeys(helper.sent, "compiling")
    helper._read()  # its output ends after job 0: it ended, job 1 is numba's call's now
    assert state.jobs == dict.fromkeys(helper.sent, "done") and state.helper is None
    helper.process.stdout = iter(lines)
    state.helper, state.jobs = helper, dict.fromkeys(helper.sent, "compiling")
    helper._read()
    assert stdin.closed  # both done: told to end


def test_a_compiling_block_compiles_and_leaves_the_environment_alone(monkeypatch):
    from armik.kernel import tier

    monkeypatch.setenv("ARMIK_FIRST_CALLS", "python")
    assert tier.python_first()
    with tier.compiling():
        with tier.compiling():
            assert not tier.python_first()
        assert not tier.python_first()
    assert tier.python_first() and os.environ["ARMIK_FIRST_CALLS"] == "python"


def _jobs_in_child(queue):
    from armik.kernel import tier

    queue.put((len(tier._state.jobs), tier._state.helper is None, tier.wait(0)))


def test_a_forked_process_starts_with_no_jobs_of_its_parent(monkeypatch):
    import multiprocessing

    from armik.kernel import tier

    monkeypatch.setitem(tier._state.jobs, ("f", ()), "compiling")
    context = multiprocessing.get_context("fork")
    queue = context.Queue()
    child = context.Process(target=_jobs_in_child, args=(queue,))
    child.start()
    child.join()
    assert queue.get(timeout=60) == (0, True, True)
