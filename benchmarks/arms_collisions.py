"""Two UR5s 1 m apart on one base (no shared joint) sent to close targets: both tools at one
orientation, 8-30 cm apart between the arms, so that the chains' first answers often
collide. Counted per target: whether the chains' first answers collide with each other,
with no collision check (``robot.solve(row)``) and with each chain checked alone
(``robot.chain(tip).solve(target, self_collision=True)``: its own links against the other
arm held where it was cut, as the robot's solve checks each chain before it tries the other
combinations of the chains' answers), and what ``robot.solve(row,
self_collision=True)`` gives (a success, or a ``collision`` failure). Every success is
checked again: ``robot.min_distance`` at its q keeps every pair apart, and Pinocchio's FK
puts each tool within 1e-6 of its target. ``solve_batch`` on the same rows must agree
with ``solve`` row by row.

    python benchmarks/arms_collisions.py [-n 60] [--seed 0]

from a checkout: it builds the robot with the tests' helper (``tests/test_arms_collision.py``).
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np
import pinocchio as pin

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))  # the tests package
from tests.test_arms_collision import dual  # noqa: E402


def rows(n: int, seed: int) -> list[dict[str, pin.SE3]]:
    """``n`` targets of the tests' kind: one random orientation, the tools 8-30 cm apart."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        R, c = pin.exp3(rng.normal(size=3)), np.array([rng.uniform(0.2, 0.6), 0.0, 0.35])
        gap = np.array([0.0, rng.uniform(0.04, 0.15), 0.0])
        out.append({"l_tool0": pin.SE3(R, c + gap), "r_tool0": pin.SE3(R, c - gap)})
    return out


def measure(n: int = 60, seed: int = 0) -> dict:
    """The counts over ``n`` targets of ``rows(n, seed)`` (the module docstring)."""
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    targets = rows(n, seed)
    index = {name: k for k, name in enumerate(robot.joint_names)}
    out: dict = {"first": 0, "alone": 0, "checked": 0, "false": 0, "statuses": {}}
    results = []
    for row in targets:
        first = robot.solve(row)
        if first.success and robot.min_distance(first.q, self_collision=True)[0] < 0.0:
            out["first"] += 1
        solved, alone = True, np.array(robot.middle, dtype=float)
        for tip in robot.tips:
            chain = robot.chain(tip)
            each = chain.solve(row[tip], self_collision=True)
            solved = solved and each.success
            alone[[index[j] for j in chain.joint_names]] = each.q
        if solved and robot.min_distance(alone, self_collision=True)[0] < 0.0:
            out["alone"] += 1
        r = robot.solve(row, self_collision=True)
        results.append(r)
        status = str(r.status.value)
        out["statuses"][status] = out["statuses"].get(status, 0) + 1
        if r.success:
            out["checked"] += 1
            apart = robot.min_distance(r.q, self_collision=True)[0] >= 0.0
            near = all(
                np.linalg.norm(pin.log6(row[t].actInv(robot.fk(r.q, t))).vector) < 1e-6
                for t in robot.tips
            )
            out["false"] += not (apart and near)
    b = robot.solve_batch({t: [row[t] for row in targets] for t in robot.tips}, self_collision=True)
    out["batch_agrees"] = bool(np.array_equal(b.success, [r.success for r in results]))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=60)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    m = measure(args.n, args.seed)
    print(
        f"two UR5s, {args.n} close targets (seed {args.seed}): first answers colliding "
        f"{m['first']}, each chain checked alone {m['alone']}; with self_collision=True: "
        + ", ".join(f"{k} {v}" for k, v in sorted(m["statuses"].items()))
        + f"; successes re-checked {m['checked']}, false {m['false']}; "
        f"solve_batch agrees: {m['batch_agrees']}"
    )


if __name__ == "__main__":
    main()
