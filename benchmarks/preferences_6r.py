"""A preference on closed-form 6R arms against the best over EAIK's full solution set.

Per arm, ``-n`` targets from FK of random configurations within the limits; armik solves
each with ``prefer=`` a score from mid-limits (``solver="auto"``: the arm's closed form,
every branch at its best 2 pi variant). EAIK (``eaik``, its own decomposition of the same
URDF) gives every solution of the same target in the same loop; each of its exact
solutions (FK within 1e-6, least-squares ones dropped) is taken at every combination of
2 pi turns its joints' limits allow, and the best score over all of them is the optimum
over the finite set of solutions. Scores, all computed here, none by armik's code:
``manipulability`` (Yoshikawa's sqrt(det(J J^T)) of Pinocchio's tip Jacobian, larger is
better), ``limits`` (the smallest distance to a limit as a fraction of the joint's range,
larger is better) and ``cost`` (a custom callable, lower is better, neither periodic nor
split by joints: ``sum((q - c)^2) + 0.5 * q1 * q6`` with ``c`` a fixed posture).

Reported: armik's success (its answer within 1e-5 of the target by yourdfpy's FK and
within the URDF's limits), how often its score equals EAIK's optimum (within 1e-9
relative) or beats it, and each side's mean time (armik's preferred solve; EAIK's IK call
alone, without the turns and scoring done here). ``--lost`` prints each target where
armik's answer scores worse.

    python benchmarks/preferences_6r.py [-n 150] [--arms ur5 ur10 abb_irb120] [--lost]
"""

from __future__ import annotations

import argparse
import itertools
import math
import os
import sys
import time

import numpy as np
import pinocchio as pin

import armik
from armik.tools.peers import EAIKPeer, PeerUnavailable

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

sys.path.insert(0, os.path.dirname(__file__))
from tolerances import independent_fk  # noqa: E402

SCORES = ("manipulability", "limits", "cost")
EXACT = 1e-6  # m and rad: an EAIK solution counted as exact


def manipulability(arm: armik.Arm, q: np.ndarray) -> float:
    J = arm.jacobian(q)
    return math.sqrt(max(float(np.linalg.det(J @ J.T)), 0.0))


def margin(arm: armik.Arm, q: np.ndarray) -> float:
    lo, hi = np.asarray(arm.lower), np.asarray(arm.upper)
    return float(np.min(np.minimum(q - lo, hi - q) / (hi - lo)))


def custom(arm: armik.Arm):
    c = 0.25 * (np.asarray(arm.lower) + np.asarray(arm.upper)) + 0.3  # off the middle

    def cost(q: np.ndarray) -> float:
        return float(np.sum((q - c) ** 2) + 0.5 * q[0] * q[5])

    return cost


def goodness(arm: armik.Arm, score: str, cost):
    """The score as "larger is better", so one comparison serves all three."""
    if score == "manipulability":
        return lambda q: manipulability(arm, q)
    if score == "limits":
        return lambda q: margin(arm, q)
    return lambda q: -cost(q)


def turns(arm: armik.Arm, q: np.ndarray):
    """Every configuration 2 pi turns of ``q``'s joints away within the limits."""
    lo, hi = np.asarray(arm.lower), np.asarray(arm.upper)
    choices = []
    for v, a, b in zip(q, lo, hi):
        k0 = math.ceil((a - v) / (2 * math.pi) - 1e-12)
        k1 = math.floor((b - v) / (2 * math.pi) + 1e-12)
        choices.append([v + 2 * math.pi * k for k in range(k0, k1 + 1)])
    for combo in itertools.product(*choices):
        x = np.clip(np.array(combo), lo, hi)
        yield x


def eaik_best(arm: armik.Arm, peer: EAIKPeer, H: np.ndarray, good) -> tuple[float, int, float]:
    """(best goodness over every turn of every exact EAIK solution, solutions, IK time)."""
    T = peer.B_inv @ H @ peer.E_inv
    t = time.perf_counter()
    sol = peer.robot.IK(T)
    spent = time.perf_counter() - t
    target = pin.SE3(H)
    best, count = -math.inf, 0
    for q, ls in zip(sol.Q, sol.is_LS):
        q = np.asarray(q, dtype=float)
        if ls or np.abs(pin.log6(target.actInv(arm.fk(q))).vector).max() > EXACT:
            continue
        count += 1
        for x in turns(arm, q):
            best = max(best, good(x))
    return best, count, spent


def run(name: str, n: int, show_lost: bool) -> None:
    arm = armik.load(name)
    try:
        peer = EAIKPeer(arm, 1e-6)
    except PeerUnavailable as exc:
        print(f"| {name} | EAIK unavailable: {exc} |")
        return
    fk = independent_fk(arm)
    cost = custom(arm)
    rng = np.random.default_rng(6)
    targets = [arm.fk(arm.random_q(rng)) for _ in range(n)]
    for score in SCORES:
        good = goodness(arm, score, cost)
        prefer = cost if score == "cost" else score
        arm.solve(targets[0], prefer=prefer)  # compiled before it is timed
        ok = equal = better = worse = both = 0
        t_armik = t_eaik = 0.0
        for i, T in enumerate(targets):
            H = T.homogeneous
            t = time.perf_counter()
            r = arm.solve(T, prefer=prefer)
            t_armik += time.perf_counter() - t
            best, count, spent = eaik_best(arm, peer, H, good)
            t_eaik += spent
            true = (
                r.success
                and np.abs(pin.log6(T.actInv(fk(r.q))).vector).max() <= 1e-5
                and arm.within_limits(r.q)
            )
            ok += true
            if not true or count == 0:
                continue
            both += 1
            mine = good(np.asarray(r.q))
            tol = 1e-9 * max(1.0, abs(best))
            if mine > best + tol:
                better += 1
            elif mine >= best - tol:
                equal += 1
            else:
                worse += 1
                if show_lost:
                    print(f"  lost {name} {score} #{i}: armik {mine:.9g} EAIK best {best:.9g}")
        print(
            f"| {name} | {score} | {ok}/{n} | {equal + better}/{both} "
            f"({100.0 * (equal + better) / max(both, 1):.1f} %) | {better} | {worse} | "
            f"{1e3 * t_armik / n:.3f} | {1e3 * t_eaik / n:.3f} |",
            flush=True,
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-n", type=int, default=150)
    parser.add_argument("--arms", nargs="+", default=["ur5", "ur10", "abb_irb120"])
    parser.add_argument("--lost", action="store_true", help="print armik's worse answers")
    args = parser.parse_args()
    print("| arm | score | armik success | armik's score = optimum (or better) | better | "
          "worse | armik ms | EAIK IK ms |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|")
    for name in args.arms:
        run(name, args.n, args.lost)


if __name__ == "__main__":
    main()
