"""First-call (compile) times from an empty numba cache, and where they go.

Runs a fresh interpreter with ``NUMBA_CACHE_DIR`` set to a new empty directory (so
nothing cached is read) and times, in order: the first Panda ``solve`` with dls, then one
with qp, then a ``solve_batch`` with dls; then the same again in a second interpreter on the
now-filled cache. With ``--events``, the first interpreter also prints the functions numba
compiled for the first solve and how long each took (nested: a caller's time includes its
callees'); with ``--profile``, it runs the first solve under cProfile and prints the share
of LLVM, numba's inlining and its lowering. Extra environment (``NUMBA_OPT=1``, ...) passes through;
``ARMIK_COMPILE_HELPER=0`` measures one process compiling alone (``kernel.warmup``), and
the events then list everything the first solve compiles. With ``--parts [NAME ...]``,
``armik compile``'s parts (all by default; ``demo`` for ``armik demo``) in one process, each
function's own compile CPU time and how many times it compiled.

With ``--closed-forms``, the first closed-form solves instead: the UR5 (three parallel
axes), then the IRB 120 (spherical wrist) in the same interpreter. With ``--general``, the
general 6R families (``three_parallel_general``, ``spherical_general``) on a random arm of
each, one interpreter each: the first ``solve``, ``solve_all`` and ``solve_batch``, each
with its CPU time.

    python benchmarks/compile_time.py [--events] [--profile] [--closed-forms | --general]
    python benchmarks/compile_time.py --parts [demo | dls qp ...]
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

CHILD = r"""
import sys, time
events = "--events" in sys.argv
if events:
    from numba.core import event
    recording = event.install_recorder("numba:compile")
    recorder = recording.__enter__()
import numpy as np
import armik
a = armik.load("panda")
T = a.fk(a.random_q(1))
profile = "--profile" in sys.argv
if profile:
    import cProfile
    profiler = cProfile.Profile()
    profiler.enable()
t = time.perf_counter(); a.solve(T, solver="dls"); dls = time.perf_counter() - t
if profile:
    profiler.disable()
    import pstats
    stats = pstats.Stats(profiler).stats  # (file, line, name) -> (cc, nc, tottime, cumtime, _)
    def share(path, name, column):  # column 2: own time, 3: with callees
        got = [v[column] for k, v in stats.items() if k[0].endswith(path) and k[2] == name]
        return max(got, default=0.0)
    total = share("arm.py", "solve", 3)
    parts = {
        "LLVM (llvmlite's calls into it, own time)": share("ffi.py", "__call__", 2),
        "inlining (numba's InlineInlinables pass)": share("untyped_passes.py", "_do_work", 3),
        "of which copying IR (copy.deepcopy)": share("copy.py", "deepcopy", 3),
        "lowering (numba's lower, LLVM inside)": share("lowering.py", "lower", 3),
    }
    print(f"under cProfile (slows Python more than LLVM) the first dls solve took {total:.1f} s:")
    for name, seconds in parts.items():
        print(f"  {seconds:6.2f} s  {100 * seconds / total:4.1f} %  {name}")
if events:
    recording.__exit__(None, None, None)
t = time.perf_counter(); a.solve(T, solver="qp"); qp = time.perf_counter() - t
Ts = np.array([T.homogeneous] * 3)
t = time.perf_counter(); a.solve_batch(Ts, solver="dls", workers=1); batch = time.perf_counter() - t
print(f"first dls solve {dls:.2f} s, then qp {qp:.2f} s, then solve_batch {batch:.2f} s")
if events:
    starts, rows = {}, []
    for ts, ev in recorder.buffer:
        d = ev.data.get("dispatcher")
        key = (id(d), str(ev.data.get("args")))
        if ev.is_start:
            starts[key] = ts
        else:
            name = d.py_func.__module__.split(".")[-1] + "." + d.py_func.__qualname__
            rows.append((ts - starts.get(key, ts), name))
    for seconds, name in sorted(rows, reverse=True)[:12]:
        print(f"  {seconds:6.2f} s  {name}")
"""

CLOSED_FORMS = r"""
import time
import numpy as np
import armik
for name in ("ur5", "abb_irb120"):
    a = armik.load(name)
    T = a.fk(a.random_q(np.random.default_rng(0)))
    t = time.perf_counter(); r = a.solve(T); took = time.perf_counter() - t
    print(f"first {name} solve ({r.solver}) {took:.2f} s")
"""


GENERAL = r"""
import sys, time
import numpy as np
import armik
from armik.model.random_arms import random_urdf
family = sys.argv[1]
kind = {"three_parallel_general": "three_parallel_free", "spherical_general": "spherical"}[family]
a = armik.load_string(random_urdf(kind, np.random.default_rng(0)), base="world", tip="tool")
rng = np.random.default_rng(1)
T = a.fk(a.random_q(rng))
poses = np.array([a.fk(a.random_q(rng)).homogeneous for _ in range(5)])
calls = {
    "solve": lambda: a.solve(T, solver=family),
    "solve_all": lambda: a.solve_all(T, solver=family),
    "solve_batch": lambda: a.solve_batch(poses, solver=family, workers=1, progress=False),
}
for name, call in calls.items():
    t, c = time.perf_counter(), time.process_time()
    call()
    took, cpu = time.perf_counter() - t, time.process_time() - c
    print(f"{family}: first {name} {took:.1f} s ({cpu:.1f} s of CPU)", flush=True)
"""


PARTS = r"""
import importlib, pkgutil, sys, time
from collections import defaultdict
from numba.core import event
from numba.core.registry import CPUDispatcher

class Own(event.Listener):  # each compilation's CPU time, its nested callees' left out
    def __init__(self):
        self.stack, self.own, self.times = [], defaultdict(float), defaultdict(int)
    def on_start(self, ev):
        self.stack.append([time.process_time(), 0.0])
    def on_end(self, ev):
        t0, nested = self.stack.pop()
        took = time.process_time() - t0
        f = ev.data["dispatcher"].py_func
        name = f"{f.__module__}.{f.__qualname__}"
        self.own[name] += took - nested
        self.times[name] += 1
        if self.stack:
            self.stack[-1][1] += took

own = Own()
event.register("numba:compile", own)
import armik
from armik import precompile
names = [n for n in sys.argv[1:] if n != "-v"] or list(precompile.PARTS)
total = 0.0
for name in names:
    c = time.process_time()
    if name == "demo":  # not a part: the demo's compilations, the helper off
        from armik.tools.cli import main
        main(["demo"])
    else:
        precompile.PARTS[name]()
    total += time.process_time() - c
    print(f"{name:24s} {time.process_time() - c:6.1f} s of CPU", flush=True)
print(f"{'every part':24s} {total:6.1f} s of CPU")
print("the functions' own compilations, most CPU first:")
for name, seconds in sorted(own.own.items(), key=lambda kv: -kv[1])[:25]:
    print(f"  {seconds:6.2f} s  x{own.times[name]}  {name}")
print("compiled for more than one signature:")
for info in pkgutil.walk_packages(armik.__path__, "armik."):
    if info.name.endswith("__main__") or info.name.startswith(("armik.view", "armik.tools")):
        continue
    for key, value in vars(importlib.import_module(info.name)).items():
        if isinstance(value, CPUDispatcher) and value.py_func.__module__ == info.name:
            if len(value.signatures) > 1:
                print(f"  {info.name}.{key}: {len(value.signatures)}")
                if "-v" in sys.argv[1:]:  # the signatures, to see where they differ
                    for signature in value.signatures:
                        print(f"    {signature}")
"""


def main() -> None:
    events = [f for f in ("--events", "--profile") if f in sys.argv]
    if "--parts" in sys.argv:
        names = sys.argv[sys.argv.index("--parts") + 1 :]
        with tempfile.TemporaryDirectory() as cache:
            env = {**os.environ, "NUMBA_CACHE_DIR": cache, "ARMIK_COMPILE_HELPER": "0"}
            env["ARMIK_COMPILE_NOTICE"] = "0"
            subprocess.run([sys.executable, "-c", PARTS, *names], env=env, check=True)
        return
    if "--general" in sys.argv:
        for family in ("three_parallel_general", "spherical_general"):
            with tempfile.TemporaryDirectory() as cache:
                env = {**os.environ, "NUMBA_CACHE_DIR": cache}
                subprocess.run([sys.executable, "-c", GENERAL, family], env=env, check=True)
        return
    child = CLOSED_FORMS if "--closed-forms" in sys.argv else CHILD
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        for label, extra in (("empty cache", events), ("filled cache", [])):
            print(f"{label}:", flush=True)
            subprocess.run([sys.executable, "-c", child, *extra], env=env, check=True)


if __name__ == "__main__":
    main()
