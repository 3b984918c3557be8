"""How much slower armik's kernels run as Python (``kernel.as_python``) than compiled.

The same Panda targets (30 random poses from the mid-limit seed, 2000 iterations at most)
solved with dls and with qp, once compiled (a process with ``ARMIK_FIRST_CALLS=compile``
on the current cache) and once as Python (``ARMIK_FIRST_CALLS=python`` on an empty cache):
thread CPU time per solve and per iteration, and their ratio, which ``as_python.SLOWER``
is set from (the Python runs' budget clock runs that much slower).

    python benchmarks/as_python.py
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile

CHILD = r"""
import time, numpy as np, armik
a = armik.load('panda'); rng = np.random.default_rng(3)
targets = [a.fk(a.random_q(rng)) for _ in range(30)]
for solver in ('dls', 'qp'):
    a.solve(targets[0], solver=solver, q0=a.middle)  # loaded or made Python before the clock
    t, n = time.thread_time(), 0
    for T in targets:
        n += a.solve(T, solver=solver, q0=a.middle, iteration_budget=2000).iterations
    print(solver, (time.thread_time() - t) / n)
"""


def per_iteration(mode: str) -> dict[str, float]:
    env = {**os.environ, "ARMIK_FIRST_CALLS": mode, "ARMIK_COMPILE_NOTICE": "0"}
    if mode == "python":
        env["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="armik-python-")
    out = subprocess.run([sys.executable, "-c", CHILD], env=env, check=True, capture_output=True)
    return {s: float(v) for s, v in (line.split() for line in out.stdout.decode().splitlines())}


def main() -> None:
    compiled, python = per_iteration("compile"), per_iteration("python")
    print(f"{'solver':8s} {'compiled':>12s} {'Python':>12s} {'ratio':>7s}")
    for s in compiled:
        c, p = compiled[s] * 1e6, python[s] * 1e6
        print(f"{s:8s} {c:9.2f} us {p:9.1f} us {p / c:7.0f}")


if __name__ == "__main__":
    main()
