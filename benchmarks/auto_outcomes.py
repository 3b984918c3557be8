"""What ``solver="auto"`` answers on reachable targets: every outcome counted, none hidden.

For each robot (a bundled name, or a URDF path with ``--tip``), ``-n`` targets from FK of
seeded random configurations within the limits (every one reachable). Counted per call
(``solve``, ``solve_all``'s first result, ``solve_batch`` on one worker): the solver that
answered and the status; then the mean time of ``solve`` under "auto" and under "dls",
interleaved target by target (the ratio is what to read on a noisy machine). A
``unreachable`` among these targets is a wrong answer; a ``not_converged`` is an honest
failure.

    python benchmarks/auto_outcomes.py irb140 ur5 panda -n 1000

``irb140`` is the ABB IRB 140 that rtb-data ships, copied in ``tests/data/rtb`` (tip ``tool0``).
"""

from __future__ import annotations

import argparse
import os
import time
from collections import Counter

import numpy as np

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs


def load(robot: str, tip: str | None) -> armik.Arm:
    if robot == "irb140":
        folder = os.path.join(os.path.dirname(__file__), "..", "tests", "data", "rtb")
        path = os.path.join(folder, "abb_irb140_description", "urdf", "irb140.urdf")
        return armik.load(path, tip="tool0")
    return armik.load(robot, tip=tip) if tip else armik.load(robot)


def outcomes(arm: armik.Arm, n: int) -> None:
    rng = np.random.default_rng(0)
    poses = np.array([arm.fk(arm.random_q(rng)).homogeneous for _ in range(n)])
    arm.solve(poses[0]), arm.solve(poses[0], solver="dls"), arm.solve_all(poses[0])  # compile
    one, every, times = Counter(), Counter(), {"auto": 0.0, "dls": 0.0}
    for k, H in enumerate(poses):
        # the order alternates: the solve after solve_all's search meets colder caches
        for solver in ("auto", "dls") if k % 2 == 0 else ("dls", "auto"):
            t0 = time.perf_counter()
            r = arm.solve(H, solver=solver)
            times[solver] += time.perf_counter() - t0
            if solver == "auto":
                one[(r.solver, str(r.status))] += 1
        first = arm.solve_all(H)[0]
        every[(first.solver, str(first.status))] += 1
    batch = arm.solve_batch(poses, workers=1, progress=False)
    many = Counter(zip([batch.solver] * n, batch.status))
    print(f"{arm.name}: {n} reachable targets")
    for label, counts in (("solve", one), ("solve_all[0]", every), ("solve_batch", many)):
        text = ", ".join(f"{s}/{st} {c}" for (s, st), c in sorted(counts.items()))
        print(f"  {label:<13} {text}")
    ratio = times["auto"] / times["dls"]
    print(
        f"  solve mean: auto {1e3 * times['auto'] / n:.4f} ms, dls {1e3 * times['dls'] / n:.4f} "
        f"ms (auto/dls {ratio:.2f})"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="+", help="bundled names, URDF paths, or irb140")
    parser.add_argument("--tip", default=None, help="the tip frame of a URDF path")
    parser.add_argument("-n", type=int, default=1000, help="targets per robot")
    args = parser.parse_args()
    for robot in args.robots:
        outcomes(load(robot, args.tip), args.n)


if __name__ == "__main__":
    main()
