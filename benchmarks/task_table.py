"""Task lists on several frames: the task solver's compiled descent (``armik.kernel.task_rows``)
against its Python descent (the same Levenberg-Marquardt on Pinocchio's placements), the
same targets in one loop, the order alternating.

Cases (``--cases``), targets from FK of random configurations within the limits:
``panda``, the Panda's tip at a point with its z axis within 0.05 rad of a direction and
its elbow (``panda_link4``) within a 3 cm box (three tasks, two frames of one chain);
``talos``, TALOS's two grippers' poses over the shared torso; ``talos_elbow``, those and
the left elbow (``arm_left_4_link``) within a 5 cm box; ``pr2``, the PR2's left tool's
pose and its right tool's position over the shared lift. Seeds at mid-limits; armik's
default options (1e-6 tolerances, 50 ms budget).

Success: ``r.success``. Every success is checked again on yourdfpy's FK of the URDF (each
task within 1e-6 and every joint within the URDF's limits): a success it refuses is a
false success.

    python benchmarks/task_table.py -n 200 [--cases panda talos talos_elbow pr2]
"""

from __future__ import annotations

import argparse
import math
import os
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

import armik
import armik.solve.tasks as task_solver
from armik.solve.task_table import task_table

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

ROBOTS = Path(armik.load("panda").source).parents[2]
TALOS = (
    "talos_data/robots/talos_reduced.urdf",
    ("gripper_left_base_link", "gripper_right_base_link"),
)
PR2 = ("pr2_description/urdf/pr2.urdf", ("l_gripper_tool_frame", "r_gripper_tool_frame"))
CASES = ("panda", "talos", "talos_elbow", "pr2")


class Case:
    """A robot, its targets' maker and its yourdfpy check."""

    def __init__(self, name: str) -> None:
        import yourdfpy

        self.name = name
        if name == "panda":
            self.robot = armik.load("panda")
            path = Path(self.robot.source)
        else:
            rel, tips = TALOS if name.startswith("talos") else PR2
            path = ROBOTS / rel
            self.robot = armik.load(str(path), tips=list(tips))
            self.tips = tips
        self.urdf = yourdfpy.URDF.load(
            str(path), load_meshes=False, build_collision_scene_graph=False
        )
        kin = (
            self.robot.kinematics if name == "panda" else self.robot.chain(self.tips[0]).kinematics
        )
        self.base = kin.base
        self.pin = pin.buildModelFromUrdf(str(path))

    def frame(self, q: np.ndarray, frame: str) -> pin.SE3:
        """``frame``'s placement in the base frame at ``q``, by the URDF's Pinocchio model."""
        model, data = self.pin, self.pin.createData()
        qf = pin.neutral(model)
        for name, value in zip(self.robot.joint_names, q):
            j = model.joints[model.getJointId(name)]
            qf[j.idx_q : j.idx_q + j.nq] = (
                value if j.nq == 1 else (math.cos(value), math.sin(value))
            )
        pin.framesForwardKinematics(model, data, qf)
        placed = lambda f: data.oMf[model.getFrameId(f)]  # noqa: E731
        return placed(self.base).actInv(placed(frame))

    def target(self, rng: np.random.Generator):
        """(what ``solve`` takes, the tasks with their frames for the check)."""
        q = self.robot.random_q(rng)
        if self.name == "panda":
            T, elbow = self.frame(q, self.robot.tip), self.frame(q, "panda_link4").translation
            tasks = [
                armik.Position(T.translation),
                armik.Axis((0, 0, 1), T.rotation[:, 2], 0.05),
                armik.Position(elbow, bounds=(0.03,) * 3, frame="panda_link4"),
            ]
            return tasks, [(t, t.frame or self.robot.tip) for t in tasks]
        a, b = self.tips
        T_a, T_b = self.frame(q, a), self.frame(q, b)
        left = [armik.Pose(T_a)]
        right = armik.Position(T_b.translation) if self.name == "pr2" else armik.Pose(T_b)
        if self.name == "talos_elbow":
            elbow = self.frame(q, "arm_left_4_link").translation
            left.append(armik.Position(elbow, bounds=(0.05,) * 3, frame="arm_left_4_link"))
        checked = [(t, t.frame or a) for t in left] + [(right, b)]
        return {a: left, b: right}, checked

    def urdf_holds(self, q: np.ndarray, checked) -> bool:
        cfg = dict(zip(self.robot.joint_names, q))
        for name, value in cfg.items():
            joint = self.urdf.joint_map[name]
            if joint.type != "continuous" and joint.limit is not None:
                if not joint.limit.lower - 1e-12 <= value <= joint.limit.upper + 1e-12:
                    return False
        self.urdf.update_cfg(cfg)
        for task, frame in checked:
            M = self.urdf.get_transform(frame_to=frame, frame_from=self.base)
            if not task.measure(pin.SE3(M[:3, :3], M[:3, 3]), 1e-6, 1e-6).within:
                return False
        return True


def _python_descent(*args):
    return None


def run(case: Case, n: int) -> dict:
    rng = np.random.default_rng(0)
    targets = [case.target(rng) for _ in range(n)]
    case.robot.solve(targets[0][0])  # compiled before timing
    got = {"compiled": [0, 0, 0.0], "python": [0, 0, 0.0]}  # success, false, seconds
    for k, (target, checked) in enumerate(targets):
        order = ("compiled", "python") if k % 2 == 0 else ("python", "compiled")
        for mode in order:
            task_solver.task_table = task_table if mode == "compiled" else _python_descent
            t0 = time.perf_counter()
            r = case.robot.solve(target)
            got[mode][2] += time.perf_counter() - t0
            if r.success:
                got[mode][0] += 1
                got[mode][1] += not case.urdf_holds(r.q, checked)
    task_solver.task_table = task_table
    return got


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES))
    parser.add_argument("-n", type=int, default=200)
    args = parser.parse_args()
    print("| case | compiled success | false | ms | Python success | false | ms | time ratio |")
    print("|---|---|---|---|---|---|---|---|")
    for name in args.cases:
        got = run(Case(name), args.n)
        (cs, cf, ct), (ps, pf, pt) = got["compiled"], got["python"]
        print(
            f"| {name} | {100 * cs / args.n:.1f} % | {cf} | {1e3 * ct / args.n:.2f} | "
            f"{100 * ps / args.n:.1f} % | {pf} | {1e3 * pt / args.n:.2f} | {ct / pt:.3f} |"
        )


if __name__ == "__main__":
    main()
