"""The 2-link arm's closed form against the UR5's, one ``arm.solve`` after the other.

``-n`` targets from FK of seeded random configurations for each arm; per target, the
2-link arm solves its (x, y) position and its full pose and the UR5 its pose (4x4 arrays,
``solver="auto"``, seed at mid-limits), the three calls timed one after the other in one
loop. Reported: the mean of each and the 2-link's ratios to the UR5's.

    python benchmarks/closed_form_cost.py [-n 2000]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-n", type=int, default=2000)
    n = parser.parse_args().n
    planar, ur5 = armik.load("planar_2link"), armik.load("ur5")
    rng = np.random.default_rng(0)
    poses = [planar.fk(planar.random_q(rng)).homogeneous for _ in range(n)]
    points = [H[:2, 3].copy() for H in poses]
    ur5_poses = [ur5.fk(ur5.random_q(rng)).homogeneous for _ in range(n)]
    planar.solve(points[0]), planar.solve(poses[0]), ur5.solve(ur5_poses[0])  # compiled
    spent = {"2-link (x, y)": 0.0, "2-link pose": 0.0, "UR5 pose": 0.0}
    for xy, H, G in zip(points, poses, ur5_poses):
        for label, arm, target in (
            ("2-link (x, y)", planar, xy),
            ("2-link pose", planar, H),
            ("UR5 pose", ur5, G),
        ):
            t0 = time.perf_counter()
            arm.solve(target)
            spent[label] += time.perf_counter() - t0
    base = spent["UR5 pose"]
    for label, total in spent.items():
        print(f"{label:<14} {1e6 * total / n:6.1f} us  ({total / base:.2f}x the UR5's)")


if __name__ == "__main__":
    main()
