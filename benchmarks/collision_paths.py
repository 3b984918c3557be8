"""Paths past an obstacle, with and without sliding colliding answers out of contact.

The Panda follows 8 waypoints 1 cm apart (the tool's orientation held) from random
configurations; a sphere of 6 cm radius sits 10 cm beside the elbow of the blind path's
last answer, where the blind path runs into it (paths whose start collides, or that never
touch it, are left out). Each path is solved with the sphere as an obstacle, interleaved:
``slide`` (armik's default on paths: a colliding numeric answer is slid out of contact
before any restart, ``armik.solve.slide``) and ``restart`` (restarts only). Reported: paths
solved at every waypoint, waypoints ``discontinuous`` and ``collision``, time per path.

Run: PYTHONPATH=src python benchmarks/collision_paths.py [--seeds 80] [--repeats 2]
"""

from __future__ import annotations

import argparse
import os
import time
import warnings

import numpy as np
import pinocchio as pin

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

warnings.simplefilter("ignore")
BUDGET = dict(iteration_budget=3000)


def cases(panda: armik.Arm, seeds: int) -> list:
    out = []
    for seed in range(seeds):
        q = panda.random_q(seed)
        T = panda.fk(q)
        line = [pin.SE3(T.rotation, T.translation + np.array([0, 0.01 * k, 0])) for k in range(8)]
        plain = panda.solve_path(line, q, **BUDGET)
        if not plain.success.all():
            continue
        panda.fk(plain.q[-1])
        elbow = panda.kinematics.data.oMi[4].translation  # placed by that fk
        sphere = armik.Sphere(0.06, elbow + np.array([0, 0.1, 0]))
        hit = [panda.in_collision(x, [sphere]) for x in plain.q]
        if hit[0] or not any(hit):
            continue
        out.append((q, line, sphere))
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=80, help="random starts tried (80)")
    p.add_argument("--repeats", type=int, default=2, help="interleaved passes (2)")
    args = p.parse_args()
    panda = armik.load("panda")
    found = cases(panda, args.seeds)
    for _ in range(args.repeats):
        for label, mode in (("slide", True), ("restart", False)):
            whole = disc = coll = 0
            t0 = time.perf_counter()
            for q, line, sphere in found:
                r = panda.solve_path(line, q, obstacles=[sphere], slide=mode, **BUDGET)
                whole += bool(r.success.all())
                disc += int((r.status == "discontinuous").sum())
                coll += int((r.status == "collision").sum())
            dt = (time.perf_counter() - t0) / max(len(found), 1)
            print(
                f"{label:>7}: {len(found)} paths of 8 waypoints: {whole} solved at every "
                f"waypoint, {disc} waypoints discontinuous, {coll} collision; "
                f"{dt * 1e3:.0f} ms a path"
            )


if __name__ == "__main__":
    main()
