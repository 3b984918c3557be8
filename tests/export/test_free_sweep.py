"""Singular poses whose free joint at the middle of its limits leaves every row outside the
limits: ``N_ik`` tries the joint's other values as ``solve_all`` does (nearest the middle
first, the first that gives a verified row kept) and returns ``solve_all``'s answers, in its
order, for every family whose closed form sweeps a free joint."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers.closed_form import spherical_wrist
from tests.export.build import Solver
from tests.export.test_export_c import check_solutions
from tests.export.test_singular import held_of, verified_answers
from tests.solvers.closed_form.random_arms import wrapped_distance


def shoulder_singular(arm: armik.Arm, rng: np.random.Generator) -> list[np.ndarray]:
    """Poses of a spherical-wrist arm with the wrist centre on axis 1 (joint 1 free)."""
    geo = spherical_wrist.classify(arm.kinematics)
    assert not isinstance(geo, str)
    poses = []
    for _ in range(20):
        R = pin.exp3(rng.normal(size=3))
        centre = np.array([0.0, 0.0, rng.uniform(0.3, 0.7)])
        poses.append(pin.SE3(R, centre + R @ geo.R_tip0.T @ geo.p[6]).homogeneous)
    return poses


def reached_with(joint: int) -> object:
    """Poses reached within the limits with joint ``joint`` at 0 (a singularity)."""

    def poses(arm: armik.Arm, rng: np.random.Generator) -> list[np.ndarray]:
        out = []
        while len(out) < 20:
            q = arm.random_q(rng)
            q[joint] = 0.0
            if arm.within_limits(q):
                out.append((arm.fk(q).homogeneous, held_of(arm, q)))
        return out

    return poses


def ur5_narrow() -> armik.Arm:
    ur5 = armik.load("ur5")
    names = ur5.joint_names
    return ur5.with_limits({names[0]: (-1.5, 1.5), names[3]: (-1.0, 1.0), names[5]: (-0.8, 0.8)})


def narrowed(name: str, joint: int, limits: tuple[float, float]) -> armik.Arm:
    arm = armik.load(name)
    return arm.with_limits({arm.joint_names[joint]: limits})


def joint1_narrow(name: str, **load: object) -> armik.Arm:
    arm = armik.load(name, **load)
    return arm.with_limits({arm.joint_names[0]: (-0.4, 0.4)})


# (the arm, its singular poses, the joint they leave free)
CASES = {
    "abb_irb120 wrist centre on axis 1": (lambda: armik.load("abb_irb120"), shoulder_singular, 0),
    # axes 4 and 6 in line: joint 4 free, its middle leaving joint 6 outside its limits
    "abb_irb120 wrist singular, joint 6 narrowed": (
        lambda: narrowed("abb_irb120", 5, (-0.5, 0.5)),
        reached_with(4),
        3,
    ),
    "ur5 wrist singular, wrists narrowed": (ur5_narrow, reached_with(4), 5),
    # joint 2 at 0: axes 1 and 3 in line, the reversed chain's wrist singular (joint 3 free)
    "panda joint 7 held": (lambda: joint1_narrow("panda"), reached_with(1), 2),
    "panda joint 7 locked": (
        lambda: joint1_narrow("panda", locked={"panda_joint7": 0.4}),
        reached_with(1),
        2,
    ),
    "kuka_iiwa14 joint 7 held": (lambda: joint1_narrow("kuka_iiwa14"), reached_with(1), 2),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_free_joint_swept_as_solve_all_sweeps_it(case, tmp_path):
    """Every pose: N_ik's rows are solve_all's successes, in its order; on some the free
    joint is away from the middle of its limits (swept)."""
    make, poses, free = CASES[case]
    arm = make()
    solver = Solver(arm, "sweep", tmp_path)
    swept = 0
    for pose in poses(arm, np.random.default_rng(2)):
        T, held = pose if isinstance(pose, tuple) else (pose, None)
        n, Q = solver.ik_count(T, held)
        expected = verified_answers(arm, T, held)
        assert n == len(expected)
        Q = Q[:n]
        check_solutions(arm, Q, T)
        assert all(wrapped_distance(a, b) < 1e-7 for a, b in zip(Q, expected))
        swept += bool(n) and bool(np.all(np.abs(Q[:, free] - arm.kinematics.middle[free]) > 1e-6))
    assert swept > 0
