"""Where the servo comes to rest on random reachable targets (docs/servo.md's "the step"
and "stalled"): per arm, ``-n`` targets, each the FK of the configuration halfway from a
random start q0 to another random configuration (so a path of joint motion reaches it),
the full pose held for ``--seconds`` at dt = 2 ms from q0 at rest (``Servo.track``, the
default limits: the URDF's positions and velocities, 20 rad/s^2).

Counted per arm: reached (the last tick ``on_target``, checked by Pinocchio's FK within
1e-6 m and rad), and of those, any with a ``stalled`` tick on the way; the others by their
last status (``stalled``, ``singularity``, ``joint_limit``, ...), with the range of their
final position error (m), of the smallest singular value sigma at the end, and how many
still move (a joint faster than 1e-6 rad/s over the last 100 ticks).

    python benchmarks/servo_settle.py [--arms panda ur5 kinova xarm7 kuka_iiwa14 abb_irb120
        so101] [-n 20] [--seconds 5] [--seed 0] [--detail]
"""

from __future__ import annotations

import argparse
import os
from collections import Counter

import numpy as np
import pinocchio as pin

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # compiled ticks, not Python runs

ARMS = ("panda", "ur5", "kinova", "xarm7", "kuka_iiwa14", "abb_irb120", "so101")
DT = 0.002


def run_arm(name: str, n: int, ticks: int, seed: int, detail: bool = False) -> dict:
    arm = armik.load(name)
    rng = np.random.default_rng(seed)
    reached = stalled_on_way = moving = 0
    last: Counter[str] = Counter()
    errors, sigmas = [], []
    for _ in range(n):
        q0 = arm.random_q(int(rng.integers(1e9)))
        q1 = arm.random_q(int(rng.integers(1e9)))
        target = arm.fk(q0 + 0.5 * (q1 - q0))
        record = arm.servo(q0, dt=DT).track([target] * ticks)
        T = arm.fk(record.q[-1])
        d = pin.log6(target.actInv(T)).vector
        true_on = np.linalg.norm(d[:3]) < 1e-6 and np.linalg.norm(d[3:]) < 1e-6
        status = str(record.status[-1])
        if status == "on_target" and true_on:
            reached += 1
            stalled_on_way += "stalled" in set(record.status.tolist())
            continue
        last[status if status != "on_target" else "on_target_by_its_word_only"] += 1
        errors.append(float(record.position_error[-1]))
        sigmas.append(float(record.sigma[-1]))
        still = bool(np.abs(record.dq[-100:]).max() > 1e-6)
        moving += still
        if detail:
            print(
                f"  {name}: {status}, error {errors[-1]:.3g} m, sigma {sigmas[-1]:.3g}, "
                f"{'moving' if still else 'at rest'}; {record.reason[-1]}"
            )
    return {
        "arm": name,
        "n": n,
        "reached": reached,
        "stalled_on_way": stalled_on_way,
        "last": last,
        "errors": errors,
        "sigmas": sigmas,
        "moving": moving,
    }


def totals(
    arms=ARMS, n: int = 20, seconds: float = 5.0, seed: int = 0, each=None, detail: bool = False
) -> Counter[str]:
    """The counts summed over ``arms``: targets, reached, stalled_on_way, moving, and
    ``last STATUS`` for each last status of a target not reached; ``each(row)`` is called
    with each arm's ``run_arm`` row as it is measured."""
    total: Counter[str] = Counter()
    for name in arms:
        row = run_arm(name, n, round(seconds / DT), seed, detail)
        if each is not None:
            each(row)
        total.update(
            targets=row["n"],
            reached=row["reached"],
            stalled_on_way=row["stalled_on_way"],
            moving=row["moving"],
        )
        total.update({f"last {k}": v for k, v in row["last"].items()})
    return total


def span(values: list[float]) -> str:
    return f"{min(values):.2g}-{max(values):.2g}" if values else "-"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arms", nargs="+", default=list(ARMS))
    parser.add_argument("-n", type=int, default=20)
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--detail", action="store_true", help="a line per target not reached")
    args = parser.parse_args()
    ticks = round(args.seconds / DT)
    print(f"{args.n} targets an arm, {ticks} ticks ({args.seconds:g} s) each, seed {args.seed}")
    print(
        "arm | reached | stalled tick on the way | not reached, by last status | error (m) "
        "| sigma | still moving"
    )

    def show(row: dict) -> None:
        rest = ", ".join(f"{k} {v}" for k, v in sorted(row["last"].items())) or "-"
        print(
            f"{row['arm']} | {row['reached']}/{row['n']} | {row['stalled_on_way']} | {rest} | "
            f"{span(row['errors'])} | {span(row['sigmas'])} | {row['moving']}"
        )

    total = totals(args.arms, args.n, args.seconds, args.seed, show, args.detail)
    print("total: " + ", ".join(f"{k} {v}" for k, v in total.items()))


if __name__ == "__main__":
    main()
