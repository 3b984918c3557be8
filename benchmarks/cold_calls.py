"""Each feature's first call in a fresh process with an empty cache: the whole process timed.

Issue 52's list: every feature runs in an interpreter of its own with ``NUMBA_CACHE_DIR``
a new empty directory, and the whole process is timed (import, load, compile, solve): wall
time, and the CPU time of the process and its children (the compile helper), which a
loaded machine changes less. ``import`` is ``import armik`` alone, ``demo`` is ``armik
demo``. The compile notice is off (``ARMIK_COMPILE_NOTICE=0``). A first call runs as Python
while a helper process compiles (``kernel.tier``); the helper outlives the call to fill the
cache, and the next feature starts when it has ended. ``far_ur5`` prints the first solve's
own time too (a target 8 m away), after the load.

    python benchmarks/cold_calls.py [--features dls_weights qp ...] [--repeat N]
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

TALOS = (
    "from importlib import metadata; from pathlib import Path\n"
    "share = metadata.distribution('example-robot-data').locate_file('cmeel.prefix/share')\n"
    "urdf = Path(str(share)) / 'example-robot-data/robots/talos_data/robots/talos_reduced.urdf'\n"
    "tips = ['gripper_left_base_link', 'gripper_right_base_link']\n"
    "robot = armik.load(urdf, tips=tips)\n"
    "q = robot.random_q(np.random.default_rng(14))\n"
    "robot.solve({tip: robot.fk(q, frame=tip) for tip in robot.tips})\n"
)

CALLS = {
    "import": "",
    "dls_weights": "a = armik.load('panda'); a.solve(a.fk(a.middle + 0.2), solver='dls', "
    "weights=(1, 1, 1, 1, 1, 0.5))",
    "qp": "a = armik.load('panda'); a.solve(a.fk(a.middle + 0.2), solver='qp')",
    "ur5_solve_all": "a = armik.load('ur5'); a.solve_all(a.fk(a.middle + 0.2))",
    "panda_swept_all": "a = armik.load('panda'); a.solve_all(a.fk(a.middle + 0.2), solver='swept')",
    "solve_batch": "a = armik.load('panda'); "
    "a.solve_batch(a.fk_batch(a.random_q(0, n=20)), progress=False)",
    "solve_path": "a = armik.load('panda'); "
    "a.solve_path([a.fk(a.middle + 0.01 * k) for k in range(5)], a.middle)",
    "tolerance": "a = armik.load('panda'); "
    "a.solve(a.fk(a.middle + 0.2), bounds=(0.01, 0.01, 0.01, 0.1, 0.1, 0.1))",
    "talos_tips": TALOS,
    # the first solve alone (its time printed: issue 52's <= 50 ms), after the load
    "far_ur5": "a = armik.load('ur5'); T = np.eye(4); T[:3, 3] = (8, 0, 0)\n"
    "import time; t = time.perf_counter(); a.solve(T); print('call', time.perf_counter() - t)",
    "demo": None,  # the CLI
}


def run(feature: str) -> tuple[float, float, str]:
    """(wall s, CPU s of the process and its children, the call's own time where the
    feature prints it) of ``feature`` on an empty cache."""
    cache = tempfile.mkdtemp(prefix="armik-cold-")
    env = {**os.environ, "NUMBA_CACHE_DIR": cache, "ARMIK_COMPILE_NOTICE": "0"}
    code = CALLS[feature]
    if code is None:
        command = [sys.executable, "-m", "armik.tools.cli", feature]
    else:
        command = [sys.executable, "-c", f"import numpy as np\nimport armik\n{code}"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run(command, env=env, check=True, capture_output=True, text=True).stdout
    wall = time.perf_counter() - t0
    # the compile helper outlives a call that ran as Python, filling the cache for later
    # processes: let it end before the next feature (its time is not the call's)
    while (
        subprocess.run(
            ["pgrep", "-f", "armik.kernel.tier as t; t.serve"], stdout=subprocess.DEVNULL
        ).returncode
        == 0
    ):
        time.sleep(0.2)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    shutil.rmtree(cache, ignore_errors=True)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    call = next(
        (
            f"{float(line.split()[1]) * 1e3:.1f} ms"
            for line in out.splitlines()
            if line.startswith("call ")
        ),
        "",
    )
    return wall, cpu, call


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--features", nargs="+", default=list(CALLS), choices=list(CALLS))
    p.add_argument("--repeat", type=int, default=1, help="runs of each feature")
    args = p.parse_args()
    print(f"{'feature':16s} {'wall':>8s} {'CPU':>8s} {'call':>9s}", flush=True)
    for feature in args.features:
        for _ in range(args.repeat):
            wall, cpu, call = run(feature)
            print(f"{feature:16s} {wall:7.1f}s {cpu:7.1f}s {call:>9s}", flush=True)


if __name__ == "__main__":
    main()
