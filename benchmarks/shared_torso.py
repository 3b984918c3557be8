"""Several frames at once on two-armed robots of example-robot-data, armik against Pink on
the same targets, in one loop.

Robots (``--robots``): ``talos``, TALOS's upper body (talos_reduced.urdf, the grippers over
a two-joint torso, both chains sharing it); ``pr2``, the PR2 (pr2.urdf, the tool frames of
two 7-joint arms over the torso's lift, shared; forearm and wrist rolls continuous);
``baxter``, the Baxter (baxter.urdf, two 7-joint arms sharing no joint).

Cases (``--cases``), the first tip A and the second B: ``full``, both hands' poses;
``position``, A's pose and B's position; ``relative``, A's pose and B's pose in A's frame
(``armik.Relative(B, A, T)``). Targets from FK of random configurations within the limits
(continuous joints in [-pi, pi]); seeds at mid-limits (zero for a continuous joint).

armik: ``armik.load(urdf, tips=[A, B]).solve({A: ..., B: ...})`` (default options: 1e-6
tolerances, 50 ms budget). Pink (``pin-pink``): one model, the chains' union
(``armik.model.union``), a ``FrameTask`` per tip (position only: ``orientation_cost=0``) or
a ``RelativeFrameTask`` for B in A, ``solve_ik`` with osqp and the configuration limits,
integrated with dt = 1 from the same seed until every task is within 1e-5 or 500 steps.
Pink's default limits add the URDF's velocity limits, which with dt = 1 cap each step (the
PR2's lift at 13 mm): ``--pink-limits default`` takes them (the previous version of this
script did). The two solve the same target one after the other (the order alternating),
so the time ratio is measured in one loop.

Success, for both: every task within 1e-5 (position m, orientation rad) by Pinocchio's FK
of the union model, and every joint within its limits. Every armik success is checked
again by an independent FK (yourdfpy: the URDF, the joint values set by name): a success
it puts outside 1e-5 or outside the URDF's limits is a false success.

    python benchmarks/shared_torso.py --robots talos pr2 baxter \\
        --cases full position relative -n 200 [--failures] [--pink-limits default]
"""

from __future__ import annotations

import argparse
import logging
import math
import os
import time
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin

import armik
from armik.model.union import Union

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

ROBOTS = {  # name: (label, URDF in example-robot-data's robots folder, (tip A, tip B))
    "talos": (
        "TALOS",
        "talos_data/robots/talos_reduced.urdf",
        ("gripper_left_base_link", "gripper_right_base_link"),
    ),
    "pr2": (
        "PR2",
        "pr2_description/urdf/pr2.urdf",
        ("l_gripper_tool_frame", "r_gripper_tool_frame"),
    ),
    "baxter": ("Baxter", "baxter_description/urdf/baxter.urdf", ("left_gripper", "right_gripper")),
}
CASES = ("full", "position", "relative")
TOL = 1e-5
STEPS = 500


def robots_folder() -> Path:
    return Path(armik.load("panda").kinematics.source).parents[2]


def targets_for(case: str, a: str, b: str, T_a: pin.SE3, T_b: pin.SE3) -> dict:
    """armik's targets of one case, A's and B's placements from FK."""
    if case == "full":
        return {a: T_a, b: T_b}
    if case == "position":
        return {a: T_a, b: T_b.translation.copy()}
    return {a: T_a, b: armik.Relative(b, a, T_a.actInv(T_b))}


def task_errors(case: str, a: str, b: str, T_a: pin.SE3, T_b: pin.SE3, fk) -> list[tuple]:
    """(position m, orientation rad or None) of each task at the placements ``fk(tip)``."""
    F_a, F_b = fk(a), fk(b)
    if case == "relative":  # B's pose in A's, against the target's
        T_b, F_b = T_a.actInv(T_b), F_a.actInv(F_b)
    out = [_pose_error(T_a, F_a)]
    if case == "position":
        out.append((float(np.linalg.norm(F_b.translation - T_b.translation)), None))
    else:
        out.append(_pose_error(T_b, F_b))
    return out


def _pose_error(T: pin.SE3, F: pin.SE3) -> tuple[float, float]:
    position = float(np.linalg.norm(F.translation - T.translation))
    orientation = float(np.linalg.norm(pin.log3(T.rotation.T @ F.rotation)))
    return position, orientation


def within(errors: list[tuple]) -> bool:
    return all(p <= TOL and (o is None or o <= TOL) for p, o in errors)


class Robot:
    """One robot of ``ROBOTS``: armik's ``Arms``, the union model Pink and the check use,
    and the URDF loaded by yourdfpy."""

    def __init__(self, name: str) -> None:
        self.label, rel, (self.a, self.b) = ROBOTS[name]
        self.path = robots_folder() / rel
        self.arms = armik.load(self.path, tips=[self.a, self.b])
        # the chains' union, also where they share no joint (Baxter)
        self.union = Union([self.arms.chain(t).kinematics for t in self.arms.tips])
        # the union's joint values from armik's q (ordered as arms.joint_names)
        self.cols = np.array([self.arms.joint_names.index(n) for n in self.union.joint_names])
        model = self.union.model
        joints = [model.joints[model.getJointId(n)] for n in self.union.joint_names]
        self.idx_q = [(j.idx_q, j.nq) for j in joints]
        self._urdf = None

    def fk(self, q_union: np.ndarray):
        """``tip -> T_base_tip`` at the union's joint values, by Pinocchio."""
        return lambda tip: self.union.fk(q_union, tip)

    def from_pin(self, qp: np.ndarray) -> np.ndarray:
        """The union's joint values from Pinocchio's q (an angle per continuous joint)."""
        return np.array([qp[i] if n == 1 else math.atan2(qp[i + 1], qp[i]) for i, n in self.idx_q])

    def urdf_check(self, case: str, T_a, T_b, q_union: np.ndarray) -> bool:
        """The answer by yourdfpy's FK of the URDF and the URDF's limits: every task within
        TOL, every joint within its limits."""
        import yourdfpy

        if self._urdf is None:
            self._urdf = yourdfpy.URDF.load(
                str(self.path), load_meshes=False, build_collision_scene_graph=False
            )
        urdf = self._urdf
        cfg = dict(zip(self.union.joint_names, q_union))
        for name, value in cfg.items():
            limit = urdf.joint_map[name].limit
            if urdf.joint_map[name].type == "continuous" or limit is None:
                continue
            if not limit.lower - 1e-12 <= value <= limit.upper + 1e-12:
                return False
        urdf.update_cfg(cfg)
        base = self.arms.chain(self.a).base

        def fk(tip: str) -> pin.SE3:
            M = urdf.get_transform(frame_to=tip, frame_from=base)
            return pin.SE3(M[:3, :3], M[:3, 3])

        return within(task_errors(case, self.a, self.b, T_a, T_b, fk))


def pink_solver(robot: Robot, case: str, velocity_limits: bool = False):
    """Pink on the union model: ``solve(T_a, T_b, q0) -> union joint values``."""
    import pink
    from pink.exceptions import NoSolutionFound
    from pink.tasks import FrameTask, RelativeFrameTask

    # a configuration outside the limits (by osqp's tolerance) is logged on every step, and
    # qpsolvers warns on every call that it converts the matrices for osqp
    logging.getLogger().setLevel(logging.ERROR)
    warnings.filterwarnings("ignore", module="qpsolvers")

    union, a, b = robot.union, robot.a, robot.b
    world = union.T_base_world.inverse()  # the base in the model's world

    def solve(T_a: pin.SE3, T_b: pin.SE3, q0: np.ndarray) -> np.ndarray:
        config = pink.Configuration(union.model, union.model.createData(), union.to_pin(q0))
        limits = None if velocity_limits else [config.model.configuration_limit]
        task_a = FrameTask(a, position_cost=1.0, orientation_cost=1.0)
        task_a.set_target(world * T_a)
        if case == "relative":
            task_b = RelativeFrameTask(b, a, position_cost=1.0, orientation_cost=1.0)
            task_b.set_target(T_a.actInv(T_b))
        else:
            task_b = FrameTask(b, position_cost=1.0, orientation_cost=float(case == "full"))
            task_b.set_target(world * T_b)
        tasks = [task_a, task_b]

        def placed(tip: str) -> pin.SE3:
            return union.T_base_world * config.get_transform_frame_to_world(tip)

        for _ in range(STEPS):
            if within(task_errors(case, a, b, T_a, T_b, placed)):
                break
            try:
                v = pink.solve_ik(
                    config, tasks, 1.0, solver="osqp", safety_break=False, limits=limits
                )
            except NoSolutionFound:  # osqp found no step: Pink's answer is where it stands
                break
            config.integrate_inplace(v, 1.0)
        return robot.from_pin(config.q)

    return solve


def timed(f, *args):
    t0 = time.perf_counter()
    out = f(*args)
    return out, time.perf_counter() - t0


def run(robot: Robot, case: str, n: int, failures: bool, velocity_limits: bool) -> dict:
    rng = np.random.default_rng(0)
    a, b, union = robot.a, robot.b, robot.union
    samples = []
    for _ in range(n):
        q = robot.arms.random_q(rng)
        samples.append((robot.arms.fk(q, a), robot.arms.fk(q, b)))
    try:
        pink = pink_solver(robot, case, velocity_limits)
    except ImportError:
        pink = None
    seed = robot.arms.middle[robot.cols]  # mid-limits, as armik's default seed
    robot.arms.solve(targets_for(case, a, b, *samples[0]))  # compiled before timing
    if pink is not None:
        pink(*samples[0], seed)
    ok = claimed = false = pink_ok = pink_near = 0
    t_armik = t_pink = 0.0
    for k, (T_a, T_b) in enumerate(samples):
        targets = targets_for(case, a, b, T_a, T_b)

        armik_first = k % 2 == 0  # the order alternates
        if armik_first:
            r, dt = timed(robot.arms.solve, targets)
        qp, dp = timed(pink, T_a, T_b, seed) if pink is not None else (None, 0.0)
        if not armik_first:
            r, dt = timed(robot.arms.solve, targets)
        t_armik += dt
        t_pink += dp
        q = r.q[robot.cols]
        errors = task_errors(case, a, b, T_a, T_b, robot.fk(q))
        good = within(errors) and union.within_limits(q)
        claimed += r.success
        if r.success and good:
            ok += 1
            false += not robot.urdf_check(case, T_a, T_b, q)
        elif failures:
            print(f"  {robot.label} {case} #{k}: success={r.success} status={r.status.value}")
            print(f"    reason: {r.reason}")
            print(f"    errors by Pinocchio (m, rad): {errors}; limits: {union.within_limits(q)}")
            print(f"    iterations {r.iterations}, restarts {r.restarts}, {1e3 * dt:.1f} ms")
            if "task_errors" in r.extra:
                print(f"    task_errors: {r.extra['task_errors']}")
        if qp is not None and within(task_errors(case, a, b, T_a, T_b, robot.fk(qp))):
            pink_ok += union.within_limits(qp)
            pink_near += union.within_limits(qp, tol=1e-4)  # osqp's tolerance on the limits
    return {
        "robot": robot.label,
        "case": case,
        "ok": ok,
        "claimed": claimed,
        "false": false,
        "armik_ms": 1e3 * t_armik / n,
        "pink_ok": pink_ok if pink is not None else None,
        "pink_near": pink_near,
        "pink_ms": 1e3 * t_pink / n if pink is not None else None,
        "ratio": t_armik / t_pink if pink is not None else None,
        "n": n,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", nargs="+", choices=list(ROBOTS), default=list(ROBOTS))
    parser.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES))
    parser.add_argument("-n", type=int, default=200)
    parser.add_argument("--failures", action="store_true", help="print armik's misses")
    parser.add_argument(
        "--pink-limits",
        choices=("configuration", "default"),
        default="configuration",
        help="Pink's limits: the configuration's, or Pink's default (velocity too)",
    )
    args = parser.parse_args()
    print(
        "| robot | case | armik success | false successes (yourdfpy) | armik ms "
        "| Pink success | Pink ms | time ratio |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for name in args.robots:
        robot = Robot(name)
        for case in args.cases:
            s = run(robot, case, args.n, args.failures, args.pink_limits == "default")
            n = s["n"]
            row = (
                f"| {s['robot']} | {case} | {100 * s['ok'] / n:.1f} % ({s['ok']}/{n}) "
                f"| {s['false']} | {s['armik_ms']:.2f} |"
            )
            if s["pink_ok"] is None:
                row += " - | - | - |"
            else:
                row += f" {100 * s['pink_ok'] / n:.1f} % | {s['pink_ms']:.1f} | {s['ratio']:.3f} |"
            notes = []
            if s["claimed"] != s["ok"]:
                notes.append(f"armik claimed {s['claimed']}")
            if s["pink_ok"] is not None and s["pink_near"] != s["pink_ok"]:
                notes.append(f"Pink {s['pink_near']} with the limits within 1e-4")
            if notes:
                row += " " + "; ".join(notes)
            print(row, flush=True)


if __name__ == "__main__":
    main()
