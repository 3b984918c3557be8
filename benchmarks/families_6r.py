"""Every 6R family on random arms: completeness, false successes, limit violations and the
time of a verified ``solve_all``.

For each family, ``--arms`` random arms of its kind (``armik.model.random_arms``: random
axes with the family's structure and nothing else, random fixed transforms before joint 1
and after joint 6), ``--configs`` random configurations within the limits each; the target
is the configuration's FK. Per family:

- complete: the generating configuration is among ``solve_all``'s successes (modulo 2 pi),
  out of the targets away from singularities; near-singular: the same count for the
  targets where an answer is flagged singular or the generating configuration's Jacobian
  has a singular value below ``NEAR`` (1e-2: two solutions close to merging);
- false: successes whose pose Pinocchio's FK puts more than 1e-9 (m or rad, ``log6``) from
  the target (0 expected: every success is verified);
- limits: successes outside the joint limits (0 expected);
- the median and 90th percentile of a verified ``solve_all`` (one call per target, the
  targets of an arm one after another as a loop of solves runs them, after one warm-up
  call per arm, compile time excluded); "between": the median again with this script's
  checks run between the calls (colder caches: about 15 us more a closed-form call); the
  median number of solutions.

    python benchmarks/families_6r.py [--arms 5] [--configs 20] [--families two_parallel ...]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
import pinocchio as pin

import armik
from armik.model.random_arms import random_urdf

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

# family (solver name) -> the kind of random arm it is measured on
FAMILIES = {
    "spherical": "parallel_23",
    "three_parallel": "three_parallel",
    "spherical_general": "spherical",
    "three_parallel_general": "three_parallel_free",
    "two_parallel": "two_parallel",
    "two_intersecting": "two_intersecting",
    # the elimination on the searches' arms and on arms with every axis random
    "elimination_6r/two_parallel": "two_parallel",
    "elimination_6r/two_intersecting": "two_intersecting",
    "elimination_6r/general": "general",
}


NEAR = 1e-2  # the smallest singular value of the Jacobian (m, rad) of a near-singular target


def smallest_singular_value(arm: armik.Arm, q: np.ndarray) -> float:
    """Of the tip's Jacobian (local frame) at ``q``: near zero, two solutions merge."""
    kin = arm.kinematics
    J = pin.computeFrameJacobian(kin.model, kin.data, kin.to_pin(q), kin.tip_frame_id, pin.LOCAL)
    return float(np.linalg.svd(J, compute_uv=False)[-1])


def measure(solver: str, kind: str, arms: int, configs: int, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    found = checked = false = outside = near = near_found = 0
    times: list[float] = []
    between: list[float] = []  # each call timed again with the checks run between calls
    counts: list[int] = []
    for _ in range(arms):
        arm = armik.load_string(random_urdf(kind, rng), base="world", tip="tool")
        arm.solve_all(arm.fk(arm.random_q(rng)), solver=solver)  # compile, warm up
        qs = [arm.random_q(rng) for _ in range(configs)]
        Ts = [arm.fk(q) for q in qs]
        answers = []
        for T in Ts:  # the calls one after another, as a loop of solves runs them
            t0 = time.perf_counter()
            answers.append(arm.solve_all(T, solver=solver))
            times.append(time.perf_counter() - t0)
        for q, T in zip(qs, Ts):
            t0 = time.perf_counter()
            results = arm.solve_all(T, solver=solver)
            between.append(time.perf_counter() - t0)
            ok = [r for r in results if r.success]
            counts.append(len(ok))
            for r in ok:
                if np.linalg.norm(pin.log6(arm.fk(r.q).inverse() * T).vector) > 1e-9:
                    false += 1
                if np.any(r.q < arm.lower - 1e-12) or np.any(r.q > arm.upper + 1e-12):
                    outside += 1
            d = [np.abs(np.angle(np.exp(1j * (r.q - q)))).max() for r in ok]
            hit = bool(d) and min(d) < 1e-6
            if any(r.singular for r in results) or smallest_singular_value(arm, q) < NEAR:
                near += 1
                near_found += hit
                continue
            checked += 1
            found += hit
    t = np.array(times) * 1e6
    return {
        "found": found,
        "checked": checked,
        "near": near,
        "near_found": near_found,
        "false": false,
        "limits": outside,
        "median_us": float(np.median(t)),
        "p90_us": float(np.percentile(t, 90)),
        "between_us": float(np.median(between) * 1e6),
        "solutions": float(np.median(counts)),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arms", type=int, default=5)
    ap.add_argument("--configs", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--families", nargs="*", default=list(FAMILIES), choices=list(FAMILIES))
    args = ap.parse_args()
    print(f"{args.arms} random arms x {args.configs} configurations per family")
    print(
        f"{'family':32} {'complete':>12} {'near-singular':>14} {'false':>6} {'limits':>7} "
        f"{'median us':>10} {'p90 us':>8} {'between us':>10} {'solutions':>9}"
    )
    for solver in args.families:
        m = measure(solver.split("/")[0], FAMILIES[solver], args.arms, args.configs, args.seed)
        print(
            f"{solver:32} {m['found']:>5}/{m['checked']:<6} "
            f"{m['near_found']:>6}/{m['near']:<7} {m['false']:>6} {m['limits']:>7} "
            f"{m['median_us']:>10.0f} {m['p90_us']:>8.0f} {m['between_us']:>10.0f} "
            f"{m['solutions']:>9.0f}"
        )


if __name__ == "__main__":
    main()
