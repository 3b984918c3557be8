"""A small batch against a loop of ``solve`` on the same targets: the batch's fixed cost.

For each N, N random reachable poses of the arm (FK of ``random_q(0, n=N)``): the best of
5 rounds of ``solve_batch(T, workers=1)`` and of a loop of ``solve`` over the same poses,
interleaved, reported per target (us). Where the batch's time a target is above the
loop's, its fixed cost (parsing the targets, the result's arrays, the verdict's numpy
calls) outweighs what it saves.

    python benchmarks/batch_vs_loop.py [--arm panda] [--sizes 4 32 256]
"""

from __future__ import annotations

import argparse
import os
import timeit

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arm", default="panda")
    ap.add_argument("--sizes", type=int, nargs="+", default=[4, 32, 256])
    args = ap.parse_args()
    arm = armik.load(args.arm)
    print("| N | batch (us a target) | loop of solve (us a target) |")
    print("|---|---|---|")
    for n in args.sizes:
        T = arm.fk_batch(arm.random_q(0, n=n))
        poses = list(T)
        arm.solve_batch(T, workers=1)  # compiled code loaded, plans kept
        for pose in poses:
            arm.solve(pose)
        number = max(1, 400 // n)

        def batch_call(T=T):
            arm.solve_batch(T, workers=1)

        def loop_call(poses=poses):
            for pose in poses:
                arm.solve(pose)

        batch = loop = float("inf")
        for _ in range(5):  # interleaved: the machine's load falls on both alike
            batch = min(batch, timeit.timeit(batch_call, number=number))
            loop = min(loop, timeit.timeit(loop_call, number=number))
        scale = 1e6 / (number * n)
        print(f"| {n} | {batch * scale:.1f} | {loop * scale:.1f} |")


if __name__ == "__main__":
    main()
