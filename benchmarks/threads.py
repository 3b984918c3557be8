"""``arm.solve`` from several threads: the same answers, and how much faster.

3000 seeded Panda targets (the benchmark's protocol: seeds from mid-limits, 5 ms CPU-time
budget, tolerance 1e-5), solved in a loop of ``arm.solve`` by 1 thread, then split in
contiguous chunks over 2 and 8 threads. Prints how many answers equal the one-thread answers
bit for bit, and the speed-up of 2 threads over 1 (best of ``--repeats`` interleaved rounds),
next to a plain compiled loop's 2-thread speed-up at the same moment: what the machine's two
cores give then (other processes share them).

    python benchmarks/threads.py [-n 3000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from batch_bench import reference_ratio  # benchmarks/ is on the path when run as a script

import armik
from armik.tools import bench

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

OPTIONS = dict(timeout=0.005, tol_position=1e-5, tol_orientation=1e-5)


def solve_all(arm, poses, threads: int):
    q0 = arm.middle

    def chunk(k: int):
        lo, hi = k * len(poses) // threads, (k + 1) * len(poses) // threads
        return [arm.solve(poses[i], q0=q0, seed=i, **OPTIONS) for i in range(lo, hi)]

    t = time.perf_counter()
    if threads == 1:
        out = chunk(0)
    else:
        with ThreadPoolExecutor(threads) as pool:
            out = [r for part in pool.map(chunk, range(threads)) for r in part]
    return out, time.perf_counter() - t


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-n", type=int, default=3000)
    p.add_argument("--repeats", type=int, default=5)
    args = p.parse_args()
    arm = armik.load("panda")
    poses = bench.targets(arm, args.n, 42)
    solve_all(arm, poses[:50], 1)  # compiled code loaded, caches filled
    one, _ = solve_all(arm, poses, 1)
    eight, _ = solve_all(arm, poses, 8)
    same = sum(np.array_equal(a.q, b.q) and a.status == b.status for a, b in zip(one, eight))
    print(f"8 threads: {same} of {len(poses)} answers equal to one thread's")
    best1 = best2 = np.inf
    for _ in range(args.repeats):
        best1 = min(best1, solve_all(arm, poses, 1)[1])
        best2 = min(best2, solve_all(arm, poses, 2)[1])
    print(
        f"1 thread {best1 / len(poses) * 1e6:.1f} us/target, 2 threads "
        f"{best2 / len(poses) * 1e6:.1f} us/target: {best1 / best2:.2f}x "
        f"(a plain compiled loop: {reference_ratio():.2f}x)"
    )


if __name__ == "__main__":
    main()
