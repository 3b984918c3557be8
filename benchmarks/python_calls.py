"""Python function calls per warm solve (cProfile's count over repeated solves): what a
solve costs outside compiled code, by target kind.

Kinds: ``pose`` (a plain SE3), ``cone`` (a point and the tool's z within 0.05 rad of a
direction, a task list), ``spin`` (``bounds=(0, 0, 0, 0, 0, inf)``).

    python benchmarks/python_calls.py [--arms ur5 panda] [--kinds pose cone spin] [-n 100]
"""

from __future__ import annotations

import argparse
import cProfile
import math
import os
import pstats

import numpy as np

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

SPIN = (0.0, 0.0, 0.0, 0.0, 0.0, math.inf)


def calls(arm: armik.Arm, kind: str, n: int) -> float:
    rng = np.random.default_rng(0)
    poses = [arm.fk(arm.random_q(rng)) for _ in range(n)]
    if kind == "cone":
        asks = [
            ([armik.Position(T.translation), armik.Axis((0, 0, 1), T.rotation[:, 2], 0.05)], {})
            for T in poses
        ]
    else:
        asks = [(T, {"bounds": SPIN} if kind == "spin" else {}) for T in poses]
    for target, options in asks:  # warm: compiled code loaded, plans prepared
        arm.solve(target, **options)
    profile = cProfile.Profile()
    profile.enable()
    for target, options in asks:
        arm.solve(target, **options)
    profile.disable()
    return pstats.Stats(profile).total_calls / n  # type: ignore[attr-defined]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arms", nargs="+", default=["ur5", "panda"])
    parser.add_argument("--kinds", nargs="+", default=["pose", "cone", "spin"])
    parser.add_argument("-n", type=int, default=100, help="solves per arm and kind (100)")
    args = parser.parse_args()
    for name in args.arms:
        arm = armik.load(name)
        for kind in args.kinds:
            print(f"{name:<8} {kind:<5} {calls(arm, kind, args.n):6.1f} Python calls a solve")


if __name__ == "__main__":
    main()
