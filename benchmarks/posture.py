"""A secondary posture (``secondary=[armik.Posture(q_ref)]``) against the same solve
without it, from the same start: how many answers both verify, and how far the answers
lie from the posture. Three routes: a Panda's positions (the compiled step's null-space
pull), two IRB 120s given positions (each chain its own joints' part), TALOS' two hands
over a shared torso (the task solver's move along the tasks' null space).

    python benchmarks/posture.py [-n 200]
    OPENBLAS_CORETYPE=Haswell python benchmarks/posture.py -n 200  (the docs' table)
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))  # the tests package
from tests.test_arms import dual_irb120  # noqa: E402

# deterministic: the same numbers on every machine whose numpy runs the same OpenBLAS
# kernels (OPENBLAS_CORETYPE=Haswell, as tests/golden/blas_kernels.py pins them, gives
# docs/several-tips.md's table; an AVX-512 machine's own kernels move TALOS's 2.23 to 2.21)
BUDGET = {"iteration_budget": 3000}


def compare(name: str, robot, targets, seeds, q_ref: np.ndarray) -> None:
    """One line: both verified, mean distance to ``q_ref`` without and with the posture,
    and the share of answers nearer it."""
    posture = armik.Posture(q_ref)
    plain, pulled = [], []
    for target, q0 in zip(targets, seeds):
        a = robot.solve(target, q0=q0, **BUDGET)
        b = robot.solve(target, q0=q0, secondary=[posture], **BUDGET)
        if a.success and b.success:
            plain.append(float(np.linalg.norm(a.q - q_ref)))
            pulled.append(float(np.linalg.norm(b.q - q_ref)))
    nearer = np.mean(np.array(pulled) < np.array(plain)) if plain else float("nan")
    print(
        f"| {name} | {len(plain)}/{len(targets)} | {np.mean(plain):.2f} | {np.mean(pulled):.2f} "
        f"| {100 * nearer:.1f} % |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("-n", type=int, default=200, help="targets per robot")
    n = parser.parse_args().n
    print("| robot | both verified | from q_ref, plain (rad) | with the posture (rad) | nearer |")
    print("|---|---|---|---|---|")

    panda = armik.load("panda")
    rng = np.random.default_rng(1)
    targets = [panda.fk(panda.random_q(rng)).translation for _ in range(n)]
    compare("Panda, positions", panda, targets, [panda.random_q(rng) for _ in range(n)],
            panda.middle)  # fmt: skip

    cell = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    rng = np.random.default_rng(2)
    qs = [cell.random_q(rng) for _ in range(n)]
    targets = [{t: cell.fk(q, frame=t).translation for t in cell.tips} for q in qs]
    compare("two IRB 120s, positions", cell, targets, [cell.random_q(rng) for _ in range(n)],
            cell.middle)  # fmt: skip

    robots = Path(panda.source).parents[2]
    urdf = robots / "talos_data" / "robots" / "talos_reduced.urdf"
    talos = armik.load(urdf, tips=["gripper_left_base_link", "gripper_right_base_link"])
    rng = np.random.default_rng(3)
    m = max(n // 10, 1)  # the task solver's descents: fewer targets
    qs = [talos.random_q(rng) for _ in range(m)]
    targets = [{t: talos.fk(q, frame=t).translation for t in talos.tips} for q in qs]
    compare("TALOS hands, shared torso", talos, targets, [talos.random_q(rng) for _ in range(m)],
            talos.middle)  # fmt: skip


if __name__ == "__main__":
    main()
