"""IK-Geo's public test cases (tests/data/ikgeo: the ``test_cases`` folder of
github.com/rpiRobotics/ik-geo, BSD-3-Clause, 10 cases a file): how many of the
configurations IK-Geo drew armik's ``solve_all`` returns (each joint within 1e-6 rad
modulo 2 pi), per file, the solver armik chose, its false solutions (an answer whose tip,
by Pinocchio's FK computed here, misses the target by more than 1e-9 m or rad) and the
mean over the file's cases of a ``solve_all``'s median time over 5 calls (the arm loaded
and its first solve made before timing).

    python benchmarks/ikgeo_cases.py

tests/solvers/closed_form/test_ikgeo_cases.py asserts the same counts.
"""

from __future__ import annotations

import os
import statistics
import sys
import time

import numpy as np
import pinocchio as pin

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from tests.ikgeo_cases import FILES, cases, found  # noqa: E402

FALSE = 1e-9  # m and rad
REPEATS = 5  # calls a case, the median kept


def _false(arm: armik.Arm, answers: list, target: np.ndarray) -> int:
    m = arm.kinematics
    bad = 0
    for q in answers:
        pin.forwardKinematics(m.model, m.data, m.to_pin(q))
        tip = m.T_base_world * pin.updateFramePlacement(m.model, m.data, m.tip_frame_id)
        e = pin.log6(tip.actInv(pin.SE3(target))).vector
        bad += np.linalg.norm(e[:3]) > FALSE or np.linalg.norm(e[3:]) > FALSE
    return int(bad)


def main() -> None:
    print("| IK-Geo file | armik solver | drawn configuration found | false solutions "
          "| solve_all (ms) |")  # fmt: skip
    print("|---|---|---|---|---|")
    total = hits = 0
    for name in FILES:
        found_here, false, seconds, solvers = 0, 0, 0.0, set()
        every = cases(name)
        for case in every:
            arm = armik.load_string(case.urdf, base="world", tip="tool")
            options = {} if case.hold is None else {"hold": case.hold}
            arm.solve_all(case.target, **options)  # loads, classifies: outside the timing
            calls = []
            for _ in range(REPEATS):
                t0 = time.perf_counter()
                results = arm.solve_all(case.target, **options)
                calls.append(time.perf_counter() - t0)
            seconds += statistics.median(calls)
            answers = [r.q for r in results if r.success]
            solvers |= {r.solver for r in results}
            found_here += found(case.q, answers)
            false += _false(arm, answers, case.target)
        total += len(every)
        hits += found_here
        print(f"| {name} | {', '.join(sorted(solvers))} | {found_here}/{len(every)} | {false} "
              f"| {1e3 * seconds / len(every):.3f} |", flush=True)  # fmt: skip
    print(f"\nIK-Geo public test set: {hits}/{total} drawn configurations found")


if __name__ == "__main__":
    main()
