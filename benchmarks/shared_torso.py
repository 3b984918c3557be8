"""Several tips over a shared torso: TALOS's two hands (example-robot-data, the torso's two
joints shared) by armik against Pink, on the same targets, in one loop.

Targets: both grippers' poses from FK of random configurations within the limits; seeds
at mid-limits. armik: ``armik.load(urdf, tips=[...]).solve({tip: pose})`` (each chain by
its compiled solver first, then the descent over every joint; 50 ms budget). Pink
(``pin-pink``): a ``FrameTask`` per gripper on the same union model, ``solve_ik`` with
osqp and the configuration limits, integrated with dt = 1 until both frames are within
1e-5 or 500 steps. Success for both: every frame within 1e-5 m and rad by Pinocchio's
FK of the union model, and every joint within its limits.

    python benchmarks/shared_torso.py [-n 200]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

import armik

TIPS = ["gripper_left_base_link", "gripper_right_base_link"]


def talos() -> armik.Arms:
    robots = Path(armik.load("panda").source).parents[2]
    return armik.load(robots / "talos_data/robots/talos_reduced.urdf", tips=TIPS)


def reached(union, q, targets) -> bool:
    for tip, T in targets.items():
        err = pin.log6(T.inverse() * union.fk(q, tip)).vector
        if np.abs(err).max() > 1e-5:
            return False
    return union.within_limits(q)


def pink_solver(union):
    import pink
    from pink.tasks import FrameTask

    def solve(targets, q0):
        config = pink.Configuration(union.model, union.model.createData(), union.to_pin(q0))
        tasks = []
        for tip, T in targets.items():
            task = FrameTask(tip, position_cost=1.0, orientation_cost=1.0)
            task.set_target(union.T_base_world.inverse() * T)
            tasks.append(task)
        for _ in range(500):
            errors = [np.abs(t.compute_error(config)).max() for t in tasks]
            if max(errors) < 1e-5:
                break
            v = pink.solve_ik(config, tasks, 1.0, solver="osqp", safety_break=False)
            config.integrate_inplace(v, 1.0)
        return config.q

    return solve


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=200)
    args = parser.parse_args()
    robot = talos()
    union = robot._union
    rng = np.random.default_rng(0)
    cases = []
    for _ in range(args.n):
        q = robot.random_q(rng)
        cases.append({tip: union.fk(q, tip) for tip in TIPS})
    try:
        pink = pink_solver(union)
    except ImportError:
        pink = None
    robot.solve(cases[0])
    ok = pink_ok = 0
    t_armik = t_pink = 0.0
    for targets in cases:
        t0 = time.perf_counter()
        r = robot.solve(targets)
        t_armik += time.perf_counter() - t0
        ok += r.success and reached(union, r.q, targets)
        if pink is not None:
            t0 = time.perf_counter()
            qp = pink(targets, robot.middle)
            t_pink += time.perf_counter() - t0
            pink_ok += reached(union, qp, targets)  # TALOS's joints are revolute: q is q
    n = args.n
    line = f"TALOS two hands, torso shared: armik {100 * ok / n:.1f} %, {1e3 * t_armik / n:.2f} ms"
    if pink is not None:
        line += f"; Pink {100 * pink_ok / n:.1f} %, {1e3 * t_pink / n:.2f} ms"
        line += f"; time ratio {t_armik / t_pink:.2f}"
    print(line)


if __name__ == "__main__":
    main()
