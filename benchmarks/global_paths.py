"""Global path plans against greedy following on Cartesian lines and spins.

Per arm, ``--paths`` paths from random configurations within the limits: a straight line
of ``-n`` waypoints 5 mm apart in a random direction (orientation held), or the tool spun
about its own axis by up to two turns; only paths whose every waypoint a closed form
reaches are kept. Each is solved with ``plan="follow"`` and ``plan="global"`` from the
start configuration (and the global plan again with ``q0=None``), ``max_joint_step`` 0.3
rad. Reported per plan: the paths solved end to end, the waypoints flagged
``discontinuous`` (and of them, those the global plan reaches only through steps that
hide a jump halfway), the largest joint step, the mean total joint motion of the paths
both plans solve, and the mean time, interleaved path by path. ``--spacing`` sets the
lines' step (m).

    python benchmarks/global_paths.py [--arms ur5 ur10 abb_irb120] [--paths 40] [-n 200]
        [--spacing 0.005]

``--prefer`` plans each path from any start with no preference, ``"manipulability"`` and
``"limits"``: the answers' mean manipulability and limit margin, the time; with
``--follow``, each path followed from its start configuration instead.

``--spin`` times instead, best of ``--repeats``, interleaved, one path: the UR5's tool spun
one and a half turns over ``-n`` waypoints from mid-limits with wrist 2 at 1 rad (the
path of docs/paths.md), followed from there, planned from there, planned from any start.
"""

from __future__ import annotations

import argparse
import math
import os
import time

import numpy as np
import pinocchio as pin

import armik
from armik.problem.scores import manipulability

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

STEP = 0.3
HIDDEN = "hides a jump"  # in the reason of a waypoint only a step with a hidden jump reaches


def line(T0: pin.SE3, n: int, rng: np.random.Generator, spacing: float = 0.005) -> list:
    """``n`` poses ``spacing`` apart from ``T0`` along a random direction, orientation held."""
    d = rng.normal(size=3)
    d *= spacing / np.linalg.norm(d)
    return [pin.SE3(T0.rotation, T0.translation + k * d) for k in range(n)]


def spun(T0: pin.SE3, n: int, rng: np.random.Generator) -> list:
    """``n`` poses of ``T0``'s tool spun about its own z by half a turn to two turns."""
    turns = rng.uniform(0.5, 2.0) * 2.0 * math.pi
    return [
        T0 * pin.SE3(pin.exp3(np.array([0.0, 0.0, turns * k / (n - 1)])), np.zeros(3))
        for k in range(n)
    ]


def paths(arm: armik.Arm, count: int, n: int, rng: np.random.Generator, spacing: float = 0.005):
    made = 0
    while made < count:
        q = arm.random_q(rng)
        T0 = arm.fk(q)
        poses = line(T0, n, rng, spacing) if made % 2 == 0 else spun(T0, n, rng)
        if all(arm.solve_all(T.homogeneous, q0=q)[0].success for T in poses[:: n // 10]):
            made += 1
            yield q, poses


def motion(q0, Q) -> float:
    return float(np.linalg.norm(np.diff(np.vstack([q0, Q]), axis=0), axis=1).sum())


def run(
    name: str, count: int, n: int, spacing: float, iteration_budget: int | None = None
) -> dict[str, tuple[int, int]]:
    """Prints a line per plan; returns each plan's (paths solved, waypoints flagged).
    ``iteration_budget``: each solve's, in place of its CPU timeout (the same counts, by no
    clock)."""
    budget = {} if iteration_budget is None else {"iteration_budget": iteration_budget}
    arm = armik.load(name)
    rng = np.random.default_rng(35)
    plans = {"follow": [], "global": [], "global, any start": []}
    T = arm.fk(arm.middle)
    arm.solve_path([T, T], arm.middle, plan="global")  # compiled before the clock runs
    for q, poses in paths(arm, count, n, rng, spacing):
        for label, plan, q0 in (
            ("follow", "follow", q), ("global", "global", q), ("global, any start", "global", None)
        ):  # fmt: skip
            t0 = time.perf_counter()
            p = arm.solve_path(poses, q0, max_joint_step=STEP, plan=plan, **budget)
            dt = time.perf_counter() - t0
            start = q if q0 is not None else p.q[0]
            hidden = sum(HIDDEN in text for text in p.reasons.values())
            plans[label].append((p.success.all(), int((~p.success).sum()), p, start, dt, hidden))
    both = [i for i in range(count) if plans["follow"][i][0] and plans["global"][i][0]]
    counts = {}
    for label, rows in plans.items():
        solved = sum(r[0] for r in rows)
        flagged = sum(r[1] for r in rows)
        hidden = sum(r[5] for r in rows)
        steps = max(np.abs(np.diff(r[2].q, axis=0)).max() for r in rows if r[0]) if solved else 0
        moved = np.mean([motion(rows[i][3], rows[i][2].q) for i in both]) if both else math.nan
        print(
            f"{name:<10} {label:<18} solved {solved:3d}/{count}  flagged waypoints {flagged:5d} "
            f"(hidden jumps: {hidden})  "
            f"largest step {steps:.3f}  motion (both solved) {moved:7.3f}  "
            f"{1e3 * np.mean([r[4] for r in rows]):6.1f} ms",
            flush=True,
        )
        counts[label] = (int(solved), int(flagged))
    return counts


def spin(n: int, repeats: int) -> None:
    arm = armik.load("ur5")
    q = arm.middle.copy()
    q[4] = 1.0
    T0 = arm.fk(q)
    turn = [pin.exp3(np.array([0.0, 0.0, 3.0 * math.pi * k / (n - 1)])) for k in range(n)]
    poses = [T0 * pin.SE3(R, np.zeros(3)) for R in turn]
    runs = {"follow": ("follow", q), "global": ("global", q), "global, any start": ("global", None)}
    arm.solve_path(poses, None, max_joint_step=STEP, plan="global")  # compiled first
    best = dict.fromkeys(runs, math.inf)
    solved = {}
    for _ in range(repeats):
        for label, (plan, q0) in runs.items():
            t0 = time.perf_counter()
            p = arm.solve_path(poses, q0, max_joint_step=STEP, plan=plan)
            best[label] = min(best[label], time.perf_counter() - t0)
            solved[label] = int(p.success.sum())
    for label in runs:
        print(
            f"ur5 spin, {n} waypoints, {label:<18} {solved[label]}/{n} solved  "
            f"{1e3 * best[label]:.1f} ms (best of {repeats}; "
            f"{best[label] / best['follow']:.2f}x follow)"
        )


def prefer(names: list[str], count: int, n: int, plan: str = "global") -> None:
    """Each path with each preference, planned globally from any start or (``plan``
    "follow") followed from its start configuration: waypoints solved, the mean
    manipulability and smallest limit margin (each joint's distance to its nearer limit
    over its range) of the answers, the mean time."""
    print("| arm | prefer | waypoints solved | mean manipulability | mean limit margin | ms |")
    print("|---|---|---|---|---|---|")
    for name in names:
        arm = armik.load(name)
        lo, hi = arm.lower, arm.upper
        rows: dict = {None: [], "manipulability": [], "limits": []}
        for q, poses in paths(arm, count, n, np.random.default_rng(35)):
            q0 = None if plan == "global" else q
            for score, kept in rows.items():
                t0 = time.perf_counter()
                p = arm.solve_path(poses, q0, max_joint_step=STEP, plan=plan, prefer=score)
                dt = time.perf_counter() - t0
                Q = p.q[p.success]
                m = [manipulability(arm.jacobian(x)) for x in Q]
                g = [float(np.min(np.minimum(x - lo, hi - x) / (hi - lo))) for x in Q]
                kept.append(
                    (len(Q), np.mean(m) if m else math.nan, np.mean(g) if g else math.nan, dt)
                )
        for score, kept in rows.items():
            v = np.array(kept, dtype=float)
            print(
                f"| {name} | {score} | {int(v[:, 0].sum())} | {np.nanmean(v[:, 1]):.4f} | "
                f"{np.nanmean(v[:, 2]):.3f} | {1e3 * v[:, 3].mean():.0f} |",
                flush=True,
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arms", nargs="+", default=["ur5", "ur10", "abb_irb120"])
    parser.add_argument("--paths", type=int, default=40)
    parser.add_argument("-n", type=int, default=200)
    parser.add_argument("--spacing", type=float, default=0.005, help="m between line waypoints")
    parser.add_argument("--spin", action="store_true", help="time the spun tool path instead")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--prefer", action="store_true", help="the plan with each preference")
    parser.add_argument("--follow", action="store_true", help="with --prefer: followed paths")
    args = parser.parse_args()
    if args.prefer:
        prefer(args.arms, args.paths, args.n, "follow" if args.follow else "global")
        return
    if args.spin:
        spin(args.n, args.repeats)
        return
    for name in args.arms:
        run(name, args.paths, args.n, args.spacing)


if __name__ == "__main__":
    main()
