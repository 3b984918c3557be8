"""The global plan's path against an independent optimum over EAIK's solutions.

Per arm, ``--paths`` Cartesian paths from random configurations (lines 5 mm apart,
orientation held; arcs of a circle of 5-15 cm radius, 5 mm apart; the tool spun about
its own axis by up to two turns), ``-n`` waypoints each. armik plans each with
``solve_path(poses, None, max_joint_step=0.3, plan="global")`` (from any start) and
follows it greedily from the path's own start configuration. Independently, EAIK
(``eaik``, its own decomposition of the same URDF) gives every solution of every
waypoint; each exact one (Pinocchio's FK within 1e-6) at every 2 pi turn its joints'
limits allow is a rung, an edge joins rungs of consecutive waypoints where no joint moves
by more than 0.3 rad, and a dynamic programme written here (not armik's) finds the least
total joint motion (the sum of the steps' Euclidean norms) from any rung of the first
waypoint, or the first waypoint no continuous path reaches.

Reported per arm: paths where a continuous path exists (by EAIK) and of them, those
greedy following breaks; those armik's plan solves end to end, and its motion against
the optimum (the worst ratio, and how many within 1 %); paths with no continuous path and
whether armik flags them at the waypoint where every path breaks; armik's steps above 0.3
rad (none expected). armik checks every step halfway and refuses a step that hides a jump
there, which the dynamic programme here does not: such a path is counted apart.

    python benchmarks/global_paths_eaik.py [--arms ur5 ur10 abb_irb120] [--paths 30] [-n 150]
"""

from __future__ import annotations

import argparse
import itertools
import math
import os
import sys

import numpy as np
import pinocchio as pin

import armik
from armik.tools.peers import EAIKPeer, PeerUnavailable

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

sys.path.insert(0, os.path.dirname(__file__))
from global_paths import line, spun  # noqa: E402

STEP = 0.3
EXACT = 1e-6


def paths(arm: armik.Arm, count: int, n: int, rng: np.random.Generator):
    """(kind, start configuration, poses): lines, arcs and spins in turn, each reachable at
    a tenth of its waypoints at least (a path mostly out of reach says little)."""
    kinds = ("line", "arc", "spin")
    made = 0
    while made < count:
        kind = kinds[made % 3]
        q = arm.random_q(rng)
        T0 = arm.fk(q)
        if kind == "line":
            poses = line(T0, n, rng)
        elif kind == "arc":
            radius = rng.uniform(0.05, 0.15)
            u, v = np.linalg.qr(rng.normal(size=(3, 2)))[0].T  # the circle's plane
            centre = T0.translation - radius * u
            a = 0.005 / radius  # 5 mm of arc a step
            poses = [
                pin.SE3(T0.rotation, centre + radius * (math.cos(a * k) * u + math.sin(a * k) * v))
                for k in range(n)
            ]
        else:
            poses = spun(T0, n, rng)
        if all(arm.solve_all(T.homogeneous, q0=q)[0].success for T in poses[:: n // 10]):
            made += 1
            yield kind, q, poses


def rungs(arm: armik.Arm, peer: EAIKPeer, T: pin.SE3) -> np.ndarray:
    """Every exact EAIK solution of ``T`` at every 2 pi turn within the limits (R x dof)."""
    sol = peer.robot.IK(peer.B_inv @ T.homogeneous @ peer.E_inv)
    lo, hi = np.asarray(arm.lower), np.asarray(arm.upper)
    out = []
    for q, ls in zip(sol.Q, sol.is_LS):
        q = np.asarray(q, dtype=float)
        if ls or np.abs(pin.log6(T.actInv(arm.fk(q))).vector).max() > EXACT:
            continue
        choices = []
        for v, a, b in zip(q, lo, hi):
            k0 = math.ceil((a - v) / (2 * math.pi) - 1e-12)
            k1 = math.floor((b - v) / (2 * math.pi) + 1e-12)
            choices.append([v + 2 * math.pi * k for k in range(k0, k1 + 1)])
        out.extend(np.clip(np.array(c), lo, hi) for c in itertools.product(*choices))
    return np.array(out).reshape(-1, arm.dof)


def optimum(layers: list[np.ndarray]) -> tuple[float, int | None]:
    """(least total motion over a continuous path from any first rung, None) or
    (inf, the first waypoint no continuous path reaches)."""
    cost = np.zeros(len(layers[0]))
    for w in range(1, len(layers)):
        A, B = layers[w - 1], layers[w]
        if len(A) == 0 or len(B) == 0:
            return math.inf, w if len(B) == 0 else w - 1
        D = B[None, :, :] - A[:, None, :]  # A x B x dof
        ok = np.abs(D).max(axis=2) <= STEP + 1e-12
        total = np.where(ok, cost[:, None] + np.linalg.norm(D, axis=2), np.inf)
        cost = total.min(axis=0)
        if not np.isfinite(cost).any():
            return math.inf, w
    return float(cost.min()), None


def motion(Q: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(Q, axis=0), axis=1).sum())


def run(name: str, count: int, n: int) -> None:
    arm = armik.load(name)
    try:
        peer = EAIKPeer(arm, EXACT)
    except PeerUnavailable as exc:
        print(f"| {name} | EAIK unavailable: {exc} |")
        return
    rng = np.random.default_rng(35)
    exists = follow_broke = solved = within = hidden = none = flagged_right = big = 0
    worst = 1.0
    for kind, q, poses in paths(arm, count, n, rng):
        best, breaks = optimum([rungs(arm, peer, T) for T in poses])
        planned = arm.solve_path(poses, None, max_joint_step=STEP, plan="global")
        steps = np.abs(np.diff(planned.q, axis=0)).max(axis=1)
        ok = planned.success[1:] & planned.success[:-1]
        big += int((steps[ok] > STEP + 1e-9).sum())
        bad = np.flatnonzero(~planned.success)
        if breaks is None:
            exists += 1
            followed = arm.solve_path(poses, q, max_joint_step=STEP)
            follow_broke += int(not followed.success.all())
            if planned.success.all():
                solved += 1
                ratio = motion(planned.q) / best if best > 0 else 1.0
                worst = max(worst, ratio)
                within += ratio <= 1.01
            elif any("hides a jump" in planned.reasons[i] for i in bad):
                hidden += 1
            else:
                print(f"  {name} {kind}: a continuous path exists, armik flags {bad[:5]}")
        else:
            none += 1
            right = len(bad) > 0 and int(bad[0]) == breaks
            flagged_right += right
            if not right:
                print(f"  {name} {kind}: every path breaks at {breaks}, armik flags {bad[:5]}")
    print(
        f"| {name} | {exists} ({follow_broke} broken by following) | {solved} | "
        f"{within} / {solved} (worst {worst:.4f}) | {hidden} | {none} | "
        f"{flagged_right} / {none} | {big} |",
        flush=True,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--arms", nargs="+", default=["ur5", "ur10", "abb_irb120"])
    parser.add_argument("--paths", type=int, default=30)
    parser.add_argument("-n", type=int, default=150)
    args = parser.parse_args()
    print("| arm | a continuous path exists | armik plans it end to end | motion within 1 % of "
          "the optimum | refused halfway | no continuous path | flagged where every path "
          "breaks | steps above 0.3 |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|")
    for name in args.arms:
        run(name, args.paths, args.n)


if __name__ == "__main__":
    main()
