"""Preferences beside TRAC-IK's modes on the same targets: manipulability against its
Manip1 mode, distance to q0 against its Distance mode, success checked by yourdfpy's FK.

Per arm, ``-n`` targets from FK of random configurations within the limits; armik solves
with ``prefer="manipulability"`` or ``prefer="nearest"`` from mid-limits with a 5 ms
budget (on the Panda the swept closed form searches joint 7 over its range; elsewhere the
numeric search: ``solve_all``'s answers, answers from starts near q0, the best moved along
the self-motion); TRAC-IK (``pytracik``) runs Manip1 or Distance with a 5 ms timeout from
the same seed, target by target in the same loop. Reported: each side's success (an
answer within 1e-5 of the target by yourdfpy's FK), mean time, and on the targets both
solve, how often armik's answer is at least as good (manipulability >= TRAC-IK's;
distance to q0 <= TRAC-IK's, plus 1e-9). ``--lost`` prints each target where it is not:
both scores, the signs of joints 2, 4 and 6 (shoulder, elbow, wrist) of both answers,
how many answers armik ranked, its time and where its answer came from.

    python benchmarks/preferences.py [-n 150] [--arms panda xarm7] [--lost]
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import re
import sys
import time

import numpy as np
import pinocchio as pin

from armik.problem.scores import manipulability

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

sys.path.insert(0, os.path.dirname(__file__))
from tolerances import independent_fk, load, tracik  # noqa: E402

MODES = {"manipulability": "Manip1", "nearest": "Distance"}


def close(fk, q, T: pin.SE3) -> bool:
    err = pin.log6(T.inverse() * fk(q)).vector
    return bool(np.abs(err).max() <= 1e-5)


def signs(q) -> str:
    """The signs of joints 2, 4, 6 (on a 7R arm: shoulder, elbow and wrist)."""
    return "".join("+" if v >= 0.0 else "-" for v in np.asarray(q)[1:6:2])


def lost(prefer: str, r, got, mine: float, theirs: float, spent: float) -> None:
    among = re.search(r"ranked among (\d+)", r.reason)
    origin = "moved along the self-motion" if "self-motion" in r.reason else r.solver
    print(
        f"  lost: armik {prefer} {mine:.4f} ({signs(r.q)}) TRAC-IK {theirs:.4f} "
        f"({signs(got)}); armik ranked {among.group(1) if among else '?'} answers in "
        f"{1e3 * spent:.2f} ms, its answer: {origin}"
    )


def run(name: str, prefer: str, n: int, show_lost: bool = False) -> None:
    a = load(name)
    rng = np.random.default_rng(0)
    targets = [a.fk(a.random_q(rng)) for _ in range(n)]
    fk, other = independent_fk(a), tracik(a, MODES[prefer])
    seed = a.middle
    a.solve(targets[0], prefer=prefer, timeout=0.005)  # compiled before the clock runs
    ok = peer_ok = both = better = 0
    t_armik = t_peer = 0.0
    for T in targets:
        t0 = time.perf_counter()
        r = a.solve(T, q0=seed, prefer=prefer, timeout=0.005)
        spent = time.perf_counter() - t0
        t_armik += spent
        mine = r.success and close(fk, r.q, T) and a.within_limits(r.q)
        ok += mine
        t0 = time.perf_counter()
        got = other.ik(T.translation, T.rotation, seed)
        t_peer += time.perf_counter() - t0
        theirs = got is not None and close(fk, np.asarray(got), T)
        peer_ok += theirs
        if mine and theirs:
            both += 1
            if prefer == "manipulability":
                mine, theirs = manipulability(a.jacobian(r.q)), manipulability(a.jacobian(got))
                at_least = mine >= theirs - 1e-9
            else:
                mine, theirs = np.linalg.norm(r.q - seed), np.linalg.norm(np.asarray(got) - seed)
                at_least = mine <= theirs + 1e-9
            better += at_least
            if show_lost and not at_least:
                lost(prefer, r, got, mine, theirs, spent)
    print(
        f"{name:<7} {prefer:<15} n={n}  armik {100 * ok / n:5.1f} % {1e3 * t_armik / n:.2f} ms  "
        f"TRAC-IK {MODES[prefer]} {100 * peer_ok / n:5.1f} % {1e3 * t_peer / n:.2f} ms  "
        f"armik at least as good on {better}/{both} ({100 * better / max(both, 1):.1f} %)",
        flush=True,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=150)
    parser.add_argument("--arms", nargs="+", default=["panda", "xarm7"])
    parser.add_argument("--prefer", nargs="+", default=list(MODES))
    parser.add_argument("--lost", action="store_true", help="print each target armik loses")
    args = parser.parse_args()
    if importlib.util.find_spec("trac_ik") is None:  # the comparison is the point
        parser.exit(2, "preferences.py compares with TRAC-IK: pip install pytracik\n")
    for name in args.arms:
        for prefer in args.prefer:
            run(name, prefer, args.n, args.lost)


if __name__ == "__main__":
    main()
