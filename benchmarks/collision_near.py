"""Collision-aware IK with targets next to the obstacles: the Panda shelf scene of
``collision_scenes.py`` (a table, a shelf of two plates, a wall; self-collision on), its
targets the tip poses of configurations clear of everything by 1 cm whose tip lies 1 to 8
cm from an obstacle's surface, seeds at mid-limits, ``margin=0``, the default budget.

A numeric solve whose first answer collides either restarts at once (before: the
restarts of ``armik.solve.avoid``) or first steps the answer clear with the servo's
collision rows (after: ``armik.solve.push``); the two are switched by
``armik.solve.avoid.PUSH`` and interleaved, ``--rounds`` times each. Reported per pass: the
mean time of a collision-aware ``solve``, the mean over the targets whose plain answer
collides, ``solve_batch``'s throughput on ``--workers`` workers (processes fork with the
switch as set), success, and false successes: a success that coal finds closer than the
margin (``arm.min_distance``, and the independent model of ``collision_scenes.py``) or
away from its pose (Pinocchio's FK) or outside its limits.

Run: PYTHONPATH=src python benchmarks/collision_near.py [-n 400] [--rounds 3]
"""

from __future__ import annotations

import argparse
import gc
import os
import time
import warnings

import numpy as np
from collision_scenes import POSE_TOL, SCENES, TOL, Independent, armik_shapes
from collision_scenes import near_targets as scene_targets

import armik
from armik.solve import avoid

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

warnings.simplefilter("ignore")


def near_targets(arm: armik.Arm, n: int, seed: int) -> list:
    return scene_targets(arm, SCENES["panda"], n, seed)


def one_pass(arm, T, opts, hard: list[int], workers: int, ind: Independent, shapes) -> dict:
    gc.collect()
    gc.disable()
    try:
        t0 = time.perf_counter()
        results = [arm.solve(t, q0=arm.middle, **opts) for t in T]
        per = (time.perf_counter() - t0) / len(T)
        t0 = time.perf_counter()
        for i in hard:
            arm.solve(T[i], q0=arm.middle, **opts)
        per_hard = (time.perf_counter() - t0) / max(len(hard), 1)
    finally:
        gc.enable()
    batch = np.array([t.homogeneous for t in T])
    b = arm.solve_batch(batch, q0=arm.middle, workers=workers, progress=False, **opts)
    false = 0
    for r, t in zip(results, T):
        if r.success:
            d, dp, dr, within = ind.check(r.q, t)
            d2 = arm.min_distance(r.q, shapes, self_collision=True)[0]
            false += min(d, d2) < -TOL or dp > POSE_TOL or dr > POSE_TOL or not within
    for i in np.flatnonzero(b.success).tolist():
        d, dp, dr, within = ind.check(b.q[i], T[i])
        false += d < -TOL or dp > POSE_TOL or dr > POSE_TOL or not within
    return {
        "solve_ms": per * 1e3,
        "hard_ms": per_hard * 1e3,
        "batch_per_s": len(T) / b.time,
        "solved": sum(r.success for r in results),
        "batch_solved": int(b.success.sum()),
        "false": false,
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-n", type=int, default=400, help="targets (400)")
    p.add_argument("--rounds", type=int, default=3, help="interleaved before/after pairs (3)")
    p.add_argument("--workers", type=int, default=2, help="solve_batch workers (2)")
    p.add_argument("--seed", type=int, default=0, help="target sampling seed (0)")
    args = p.parse_args()
    arm = armik.load("panda")
    shapes = armik_shapes(SCENES["panda"])
    opts = dict(obstacles=shapes, self_collision=True)
    T = near_targets(arm, args.n, args.seed)
    armik.compile(["dls", "qp", "batch", "collisions"], progress=False)
    plain = [arm.solve(t, q0=arm.middle) for t in T]
    hard = [
        i
        for i, r in enumerate(plain)
        if not r.success or arm.in_collision(r.q, shapes, self_collision=True)
    ]
    ind = Independent(arm, SCENES["panda"])
    for t in T[:20]:
        arm.solve(t, q0=arm.middle, **opts)
    print(
        f"panda shelf scene, {len(T)} targets 1-8 cm from an obstacle, {len(hard)} whose "
        f"plain answer collides; solve_batch on {args.workers} workers"
    )
    for r in range(args.rounds):
        for label, push in (("restarts (before)", False), ("push (after)", True)):
            avoid.PUSH = push
            m = one_pass(arm, T, opts, hard, args.workers, ind, shapes)
            print(
                f"  {r + 1} {label:18s} solve {m['solve_ms']:.3f} ms mean, colliding-first "
                f"{m['hard_ms']:.3f} ms, batch {m['batch_per_s']:,.0f} targets/s; solved "
                f"{m['solved']}/{len(T)}, batch {m['batch_solved']}/{len(T)}, false "
                f"successes {m['false']}"
            )


if __name__ == "__main__":
    main()
