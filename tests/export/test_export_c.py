"""The exported C solvers, built with the machine's compiler and loaded with ctypes, against
Pinocchio and ``solve_all``: the bundled arms of each exported family and random arms."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from tests.export.build import Solver
from tests.solvers.closed_form.random_arms import load_arm, random_axes, urdf_text, wrapped_distance

TARGETS = 50
BUNDLED = ["ur5", "ur10", "z1", "abb_irb120", "planar_2link", "ur5+tool"]
RANDOM = [
    ("three_parallel", 1),
    ("three_parallel", 2),
    ("parallel_23", 3),
    ("meeting_12", 4),
    ("spherical", 5),  # spherical_general: SP5
    ("three_parallel_free", 6),  # three_parallel_general: SP6
]


def arm_of(case) -> armik.Arm:
    if case == "ur5+tool":  # a tool offset, as loaded
        return armik.load("ur5", tip_offset=(0.03, -0.02, 0.15))
    if isinstance(case, str):
        return armik.load(case)
    kind, seed = case
    return load_arm(kind, np.random.default_rng(seed))


@pytest.fixture(scope="module", params=BUNDLED + RANDOM, ids=str)
def built(request, tmp_path_factory):
    arm = arm_of(request.param)
    return arm, Solver(arm, "arm", tmp_path_factory.mktemp("export"))


def reached(arm: armik.Arm, q: np.ndarray, T: np.ndarray) -> tuple[float, float]:
    """(m, rad) by which Pinocchio's FK of ``q`` misses ``T``."""
    got = arm.fk(q)
    position = float(np.linalg.norm(got.translation - T[:3, 3]))
    return position, float(np.linalg.norm(pin.log3(got.rotation.T @ T[:3, :3])))


def poses(arm: armik.Arm, rng: np.random.Generator, n: int) -> list[np.ndarray]:
    return [arm.fk(arm.random_q(rng)).homogeneous for _ in range(n)]


def check_solutions(arm: armik.Arm, Q: np.ndarray, T: np.ndarray) -> None:
    """Every row finite, within the limits, reaching ``T`` within 1e-9 m and 1e-9 rad."""
    assert np.isfinite(Q).all()
    for q in Q:
        assert np.all(q >= arm.lower - 1e-12) and np.all(q <= arm.upper + 1e-12)
        position, orientation = reached(arm, q, T)
        assert position < 1e-9 and orientation < 1e-9, (q.tolist(), position, orientation)


def same_as_solve_all(arm: armik.Arm, Q: np.ndarray, T: np.ndarray) -> None:
    """The rows are ``solve_all``'s verified answers, in its order (each joint within 1e-7
    rad, modulo 2 pi)."""
    expected = [r.q for r in arm.solve_all(T) if r.success]
    assert len(Q) == len(expected), (Q.tolist(), [q.tolist() for q in expected])
    for got, want in zip(Q, expected):
        assert wrapped_distance(got, want) < 1e-7, (got.tolist(), want.tolist())


def test_fk_is_pinocchios(built):
    arm, solver = built
    rng = np.random.default_rng(7)
    for _ in range(TARGETS):
        q = arm.random_q(rng)
        assert np.abs(solver.fk(q) - arm.fk(q).homogeneous).max() < 1e-12


def test_every_solution_reaches_the_target_as_solve_all_finds_them(built):
    arm, solver = built
    found = 0
    for T in poses(arm, np.random.default_rng(11), TARGETS):
        Q = solver.ik(T)
        check_solutions(arm, Q, T)
        same_as_solve_all(arm, Q, T)
        found += len(Q)
    assert found >= TARGETS  # a target made from joint values within the limits is reached


def test_out_of_reach_and_bad_poses(built):
    arm, solver = built
    far = np.eye(4)
    far[:3, 3] = arm.kinematics.first_joint_origin + [0.0, 0.0, 10.0 + arm.kinematics.reach]
    n, Q = solver.ik_count(far)
    assert n == 0 and not arm.solve_all(far)[0].success
    T = poses(arm, np.random.default_rng(3), 1)[0]
    for bad in (np.nan, np.inf):
        broken = T.copy()
        broken[1, 3] = bad
        assert solver.ik_count(broken)[0] == -1
    skewed = T.copy()
    skewed[:3, :3] *= 1.001
    assert solver.ik_count(skewed)[0] == -1
    for x in (2e6, -1e300):  # beyond MAX_POSITION: a TargetError in Python, -1 in C
        remote = T.copy()
        remote[0, 3] = x
        with pytest.raises(armik.TargetError, match="beyond"):
            arm.solve_all(remote)
        assert solver.ik_count(remote)[0] == -1


def test_limits_narrower_than_a_turn(tmp_path):
    """Limits that exclude branches: every row within them, the same as ``solve_all``."""
    arm = armik.load("ur5").with_limits(
        {"shoulder_lift_joint": (-2.0, -0.5), "wrist_2_joint": (0.2, 2.5)}
    )
    solver = Solver(arm, "narrow", tmp_path)
    for T in poses(arm, np.random.default_rng(5), 20):
        Q = solver.ik(T)
        assert len(Q) >= 1
        check_solutions(arm, Q, T)
        same_as_solve_all(arm, Q, T)


def test_continuous_joints(tmp_path):
    """Joints without limits (continuous): values in (-pi, pi], as ``solve_all`` gives them."""
    rng = np.random.default_rng(21)
    c, h = random_axes("three_parallel", rng)
    text = urdf_text(c, h, rng)
    for joint in ("j1", "j4", "j6"):
        start = text.index(f'<joint name="{joint}" type="revolute"')
        end = text.index("</joint>", start)
        part = text[start:end].replace('type="revolute"', 'type="continuous"')
        part = part[: part.index("<limit")]
        text = text[:start] + part + text[end:]
    arm = armik.load_string(text, base="world", tip="tool")
    assert np.isinf(arm.kinematics.upper).sum() == 3
    solver = Solver(arm, "cont", tmp_path)
    for T in poses(arm, np.random.default_rng(4), 20):
        Q = solver.ik(T)
        assert len(Q) >= 1
        check_solutions(arm, Q, T)
        same_as_solve_all(arm, Q, T)


def test_tighter_tolerances(tmp_path):
    """With 1e-9 m and 1e-9 rad the C keeps what ``solve_all`` verifies at those
    tolerances: on the UR5's target 1624 of seed 0, a branch 7.8e-7 m out of reach, which
    the default 1e-6 m accepts, is dropped."""
    arm = armik.load("ur5")
    tight = {"tol_position": 1e-9, "tol_orientation": 1e-9}
    loose = Solver(arm, "loose", tmp_path / "loose")
    solver = Solver(arm, "tight", tmp_path / "tight", **tight)
    rng = np.random.default_rng(0)
    qs = [arm.random_q(rng) for _ in range(1625)]
    dropped = 0
    for q in qs[1600:]:
        T = arm.fk(q).homogeneous
        Q = solver.ik(T)
        check_solutions(arm, Q, T)
        expected = [r.q for r in arm.solve_all(T, **tight) if r.success]
        assert len(Q) == len(expected)
        for got, want in zip(Q, expected):
            assert wrapped_distance(got, want) < 1e-7
        dropped += len(loose.ik(T)) - len(Q)
    assert dropped >= 1


# a rotation taking the x axis to (1, 1, 1) / sqrt(3)
DIAGONAL = pin.exp3(np.array([0.0, -1.0, 1.0]) / np.sqrt(2.0) * np.arccos(1.0 / np.sqrt(3.0)))


@pytest.mark.parametrize("name", ["ur5", "abb_irb120", "kinova", "panda"])
def test_poses_solve_all_refuses_are_refused(name, tmp_path):
    """-1 where ``solve_all`` raises a ``TargetError``: a reflection (orthonormal,
    determinant -1) and a last row other than (0, 0, 0, 1) beyond the parser's 1e-12; a
    last row within 1e-12 of it is solved as the pose itself, as ``solve_all`` solves it."""
    arm = armik.load(name)
    solver = Solver(arm, name, tmp_path)
    rng = np.random.default_rng(17)
    for _ in range(5):
        q = arm.random_q(rng)
        held = None if solver.held is None else q[solver.held]
        T = arm.fk(q).homogeneous
        reflected = T.copy()
        reflected[:3, 0] *= -1
        assert np.allclose(reflected[:3, :3].T @ reflected[:3, :3], np.eye(3))
        rows = ([1.0, 2.0, 3.0, 4.0], [0.0, 0.0, 0.0, 1.0 + 2e-12], [0.0, -2e-12, 0.0, 1.0])
        bad = [reflected] + [np.vstack([T[:3], row]) for row in rows]
        nan_row = T.copy()
        nan_row[3, 2] = np.nan
        # |R^T R - I| (the parser's measure) 1.5e-6 where |R R^T - I| is 5e-7, and back
        columns, rows_only = T.copy(), T.copy()
        columns[:3, :3] = DIAGONAL @ np.diag([1.0 + 0.75e-6, 1.0, 1.0])
        rows_only[:3, :3] = columns[:3, :3].T
        for wrong in bad + [nan_row, columns]:
            with pytest.raises(armik.TargetError):
                arm.solve_all(wrong)
            assert solver.ik_count(wrong, held)[0] == -1
        arm.solve_all(rows_only)  # within 1e-6 of a rotation: no TargetError
        assert solver.ik_count(rows_only, held)[0] >= 0
        near = T.copy()
        near[3] += [5e-13, -5e-13, 5e-13, -5e-13]
        Q = solver.ik(near, held)
        assert len(Q) >= 1 and np.array_equal(Q, solver.ik(T, held))
        if held is None:
            same_as_solve_all(arm, Q, near)
        else:
            hold = {arm.joint_names[solver.held]: held}
            expected = [r.q for r in arm.solve_all(near, hold=hold) if r.success]
            assert len(Q) == len(expected)


def test_nearly_orthonormal_rotations_are_solved_as_their_nearest_rotation(tmp_path):
    """A rotation within 1e-6 of orthonormal (one ``solve_all`` accepts) is snapped onto the
    nearest rotation and every row verified against it, as the parser snaps it: near the
    UR5's wrist singularity (q5 within 0.1 rad of 0), where the raw matrix's error grows past
    the 1e-6 verification, the C returns ``solve_all``'s solutions, no fewer."""
    arm = armik.load("ur5")
    solver = Solver(arm, "ur5", tmp_path)
    rng = np.random.default_rng(1)
    for _ in range(40):
        q = arm.random_q(rng)
        q[4] = rng.uniform(-0.1, 0.1)
        T = arm.fk(q).homogeneous
        T[:3, :3] += rng.uniform(-2e-7, 2e-7, (3, 3))
        assert 1e-14 < np.abs(T[:3, :3].T @ T[:3, :3] - np.eye(3)).max() <= 1e-6
        same_as_solve_all(arm, solver.ik(T), T)
