"""Several tips with no shared joint: a dual-arm cell of two IRB 120s (each arm by its
closed form) against one arm's closed-form solve, interleaved target by target; and the
Baxter's two 7-joint arms (example-robot-data) by the numeric solver.

    python benchmarks/several_tips.py [-n 2000]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))  # the tests package
from tests.test_arms import dual_irb120  # noqa: E402


def cell(n: int) -> None:
    robot = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    one = robot.chain("l_tool0")
    rng = np.random.default_rng(0)
    pairs = []
    for _ in range(n):
        q = robot.random_q(rng)
        pairs.append({t: robot.fk(q, t).homogeneous for t in robot.tips})
    robot.solve(pairs[0])
    seed = one.middle
    t_cell = t_one = 0.0
    ok = 0
    for p in pairs:  # interleaved, target by target
        t0 = time.perf_counter()
        r = robot.solve(p)
        t1 = time.perf_counter()
        one.solve(p["l_tool0"], q0=seed)
        t2 = time.perf_counter()
        t_cell += t1 - t0
        t_one += t2 - t1
        ok += r.success
    print(
        f"dual IRB 120 cell: {ok}/{n} both tips verified; cell {1e6 * t_cell / n:.1f} us, "
        f"one arm {1e6 * t_one / n:.1f} us, ratio {t_cell / t_one:.2f}"
    )


def baxter(n: int) -> None:
    robots = Path(armik.load("panda").kinematics.source).parents[2]
    path = robots / "baxter_description/urdf/baxter.urdf"
    robot = armik.load(path, tips=["left_gripper", "right_gripper"])
    rng = np.random.default_rng(1)
    targets = []
    for _ in range(n):
        q = robot.random_q(rng)
        targets.append({t: robot.fk(q, t) for t in robot.tips})
    robot.solve(targets[0])
    t0 = time.perf_counter()
    ok = sum(robot.solve(t, timeout=0.005).success for t in targets)
    dt = time.perf_counter() - t0
    print(f"Baxter, both hands' poses: {ok}/{n} verified, {1e3 * dt / n:.2f} ms a solve")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=2000)
    args = parser.parse_args()
    cell(args.n)
    baxter(min(args.n, 300))


if __name__ == "__main__":
    main()
