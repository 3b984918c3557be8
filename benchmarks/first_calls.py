"""Each feature's first call in a new process, on a cache ``armik compile`` filled.

With ``--fresh`` (the default), ``NUMBA_CACHE_DIR`` points to a new empty directory and
``armik compile --all`` fills it first (its time is printed); without, the current cache is
used as it is. Then every feature runs in an interpreter of its own, and its first call is
timed after the arm's load (the import and the load are printed apart): dls with weights,
qp, a closed form's ``solve_all``, the swept solver, ``hold=``, the general 6R search on a
locked Panda, ``solve_batch``, ``solve_path`` and a collision-checked solve. A first call
that compiled anything would print the compile notice on stderr, which is shown.

    python benchmarks/first_calls.py [--no-fresh] [--features dls_weights qp ...]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

CHILD = r"""
import sys, time
t0 = time.perf_counter()
import armik
ur5 = armik.load("ur5"); panda = armik.load("panda")
T = ur5.fk(ur5.middle + 0.2); Tp = panda.fk(panda.middle + 0.2)
loaded = time.perf_counter()
feature = sys.argv[1]
if feature == "dls_weights":
    ur5.solve(T, solver="dls", weights=(1, 1, 1, 1, 1, 0.5))
elif feature == "qp":
    ur5.solve(T, solver="qp")
elif feature == "closed_solve_all":
    ur5.solve_all(T)
elif feature == "swept":
    panda.solve_all(Tp, solver="swept")
elif feature == "hold":
    panda.solve_all(Tp, hold={"panda_joint1": 0.3})
elif feature == "general_6r":
    panda.with_locked({"panda_joint7": 0.3}).solve_all(Tp)
elif feature == "solve_batch":
    ur5.solve_batch(ur5.fk_batch(ur5.random_q(0, n=100)), progress=False)
elif feature == "solve_path":
    ur5.solve_path([ur5.fk(ur5.middle + 0.01 * k) for k in range(5)], ur5.middle)
elif feature == "collisions":
    ur5.solve(T, obstacles=[armik.HalfSpace((0, 0, 1), -0.5)], self_collision=True)
else:
    raise SystemExit(f"unknown feature {feature!r}")
done = time.perf_counter()
print(f"{done - loaded:.3f} {loaded - t0:.2f}")
"""

FEATURES = (
    "dls_weights",
    "qp",
    "closed_solve_all",
    "swept",
    "hold",
    "general_6r",
    "solve_batch",
    "solve_path",
    "collisions",
)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--no-fresh", dest="fresh", action="store_false", help="use the cache as is")
    p.add_argument("--features", nargs="+", default=list(FEATURES), choices=FEATURES)
    args = p.parse_args()
    env = dict(os.environ)
    if args.fresh:
        env["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="armik-first-calls-")
        t0 = time.perf_counter()
        subprocess.run(
            [sys.executable, "-m", "armik.tools.cli", "compile", "--all"], env=env, check=True
        )
        print(f"armik compile --all: {time.perf_counter() - t0:.1f} s")
    print(f"{'feature':18s} {'first call':>11s} {'import+load':>12s}")
    for feature in args.features:
        done = subprocess.run(
            [sys.executable, "-c", CHILD, feature],
            env=env,
            capture_output=True,
            text=True,
            check=True,
        )
        call, load = done.stdout.split()
        print(f"{feature:18s} {float(call):9.3f} s {float(load):10.2f} s")
        if done.stderr.strip():
            print("   stderr: " + done.stderr.strip().replace("\n", "\n   "))


if __name__ == "__main__":
    main()
