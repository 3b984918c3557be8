"""What the numeric solvers' limits cost on the Panda (README's Limitations): a numeric
``solve_all`` gathering ``max_solutions`` (16) answers, and a target within the reach bound
that no configuration reaches (a full pose at random orientations 5-25 cm above the base,
inside the arm) running to ``not_converged`` on ``max_restarts`` (1000) or ``timeout``
(0.05 s of CPU), whichever comes first. Times are the thread's CPU time (the budget's
clock) and the wall clock, per call.

    python benchmarks/budget_costs.py [-n 50] [--seed 0]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
import pinocchio as pin

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs


def timed(call):
    c, w = time.thread_time(), time.perf_counter()
    out = call()
    return out, 1e3 * (time.thread_time() - c), 1e3 * (time.perf_counter() - w)


def span(values: list[float]) -> str:
    return f"{min(values):.2f}-{max(values):.2f}" if values else "-"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=50)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    panda = armik.load("panda")
    rng = np.random.default_rng(args.seed)
    poses = [panda.fk(panda.random_q(rng)) for _ in range(args.n)]
    panda.solve_all(poses[0])  # compiled before the clock runs
    cpu, wall, counts = [], [], []
    for T in poses:
        answers, c, w = timed(lambda T=T: panda.solve_all(T))
        cpu.append(c)
        wall.append(w)
        counts.append(sum(r.success for r in answers))
    print(
        f"Panda solve_all ({answers[0].solver}), {args.n} reachable poses: verified answers "
        f"{min(counts)}-{max(counts)}; CPU ms median {np.median(cpu):.2f}, max {max(cpu):.2f}; "
        f"wall ms median {np.median(wall):.2f}, max {max(wall):.2f}"
    )
    cpu, wall, restarts, statuses = [], [], [], set()
    for k in range(args.n):
        T = pin.SE3(
            pin.exp3(3.0 * rng.normal(size=3)), np.array([0.0, 0.0, 0.05 + 0.2 * k / args.n])
        )
        r, c, w = timed(lambda T=T: panda.solve(T))
        if r.success:
            continue
        statuses.add(str(r.status.value))
        cpu.append(c)
        wall.append(w)
        restarts.append(r.restarts)
    print(
        f"Panda, poses inside the arm: {len(cpu)} of {args.n} unreached "
        f"({', '.join(sorted(statuses))}), restarts {min(restarts, default=0)}-"
        f"{max(restarts, default=0)}; CPU ms {span(cpu)}; wall ms {span(wall)}"
    )


if __name__ == "__main__":
    main()
