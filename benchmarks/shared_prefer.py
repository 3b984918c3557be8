"""A preference over joints shared by several tips: TALOS's two hands over its torso.

``-n`` targets from FK of random configurations within the limits, both hands' positions
or both hands' poses, solved from mid-limits with each preference in turn (none; an
``armik.Posture`` at mid-limits weighted on the two torso joints only; ``"nearest"``;
``"limits"``), armik's default budget. Reported per case: successes, and over the answers
the torso's distance from mid-limits (rad), the whole configuration's, the smallest limit
margin (each joint's distance to its nearer limit as a fraction of its range) and the mean
time.

    python benchmarks/shared_prefer.py [-n 100]
"""

from __future__ import annotations

import argparse
import os
import time
from importlib import metadata
from pathlib import Path

import numpy as np

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs


def talos() -> armik.Arms:
    share = Path(str(metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share")))
    urdf = share / "example-robot-data/robots/talos_data/robots/talos_reduced.urdf"
    return armik.load(urdf, tips=["gripper_left_base_link", "gripper_right_base_link"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-n", type=int, default=100)
    n = parser.parse_args().n
    robot = talos()
    torso = np.isin(robot.joint_names, robot.shared)
    cases = {
        "None": None,
        "Posture(middle, torso only)": armik.Posture(robot.middle, torso.astype(float)),
        '"nearest"': "nearest",
        '"limits"': "limits",
    }
    lo, hi = robot.lower, robot.upper
    print("| targets | prefer | success | torso from middle (rad) | q from middle (rad) | "
          "limit margin | ms |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    for kind in ("positions", "poses"):
        rng = np.random.default_rng(5)
        targets = []
        for q in (robot.random_q(rng) for _ in range(n)):
            placed = {tip: robot.fk(q, frame=tip) for tip in robot.tips}
            targets.append(
                {t: T.translation if kind == "positions" else T for t, T in placed.items()}
            )
        for name, prefer in cases.items():
            ok, torso_d, whole, margin, spent = 0, [], [], [], 0.0
            for t in targets:
                started = time.perf_counter()
                r = robot.solve(t, prefer=prefer)
                spent += time.perf_counter() - started
                ok += r.success
                if r.success:
                    d = r.q - robot.middle
                    torso_d.append(np.linalg.norm(d[torso]))
                    whole.append(np.linalg.norm(d))
                    margin.append(np.min(np.minimum(r.q - lo, hi - r.q) / (hi - lo)))
            print(
                f"| both hands' {kind} | {name} | {ok}/{n} | {np.mean(torso_d):.3f} | "
                f"{np.mean(whole):.3f} | {np.mean(margin):.3f} | {1e3 * spent / n:.1f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
