"""A path of several tips whose tips are given a ``Relative`` (one tip's pose in another's
frame) or a ``Position`` within bounds: each step is judged halfway on the whole robot
(``armik.arms_halfway``), the row's targets moved halfway in each task's own measure, by
the rule a tip given poses is judged by on its chain. A jump hidden between two waypoints
is ``discontinuous``, in the words of the other hidden jumps, naming the tip; a smooth path
is not."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
import armik.arms_halfway
from armik.arms_many import _read
from armik.arms_many_read import read_rows
from armik.arms_steps import hidden_steps
from armik.solve.halfway import within

from .test_arms import dual_irb120
from .test_arms_many import talos

# TALOS: two configurations within 0.9 rad of each other on every joint, whose right hand's
# step hides a jump (tests/test_arms_many.py: a descent from 200 seeds about it finds none)
Q_A = np.array(
    [-0.748, 0.175, 0.121, 0.789, 1.543, -2.103, -0.322, 0.946, -0.421, 0.11]
    + [-1.892, -1.408, -0.186, 0.289, 0.965, 0.048]
)
Q_B = np.array(
    [-1.309, -0.262, 0.524, 0.937, 0.812, -2.223, -0.36, 0.334, 0.001, -0.524]
    + [-2.088, -1.378, -0.311, 0.445, 1.393, 0.698]
)


@pytest.fixture(scope="module")
def cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])


def _halfway(Ta: pin.SE3, Tb: pin.SE3) -> pin.SE3:
    """The pose halfway: the translations' mean, the rotation halfway along its geodesic."""
    R = Ta.rotation @ pin.exp3(0.5 * pin.log3(Ta.rotation.T @ Tb.rotation))
    return pin.SE3(R, 0.5 * (Ta.translation + Tb.translation))


def _relative(robot: armik.Arms, q: np.ndarray, frame: str, reference: str) -> pin.SE3:
    return robot.fk(q, reference).actInv(robot.fk(q, frame))


def test_a_relative_step_that_hides_a_jump_is_discontinuous_as_the_poses_step_is():
    """TALOS, the left hand at its pose and the right hand given armik.Relative to it, from
    Q_A to the poses at Q_B (max_joint_step 1 rad): the same step given both hands' poses
    is a hidden jump, naming the right hand. The relative step was passed unjudged and
    called converged; it is judged on the robot now: halfway (the left pose and the
    relative pose each halfway) the robot reaches the row, but no descent from 40 starts
    within 1 rad of both ends finds an answer there. The same words as the poses' jump;
    with a bound that lets every joint flip it goes through, each task held by FK."""
    robot = talos()
    left, right = robot.tips
    poses = {tip: [robot.fk(q, tip) for q in (Q_A, Q_B)] for tip in robot.tips}
    grip = [_relative(robot, q, right, left) for q in (Q_A, Q_B)]
    rows = [
        [armik.Pose(poses[left][i], frame=left), armik.Relative(right, left, grip[i])]
        for i in range(2)
    ]
    by_poses = robot.solve_path(poses, Q_A, max_joint_step=1.0)
    assert by_poses.status.tolist() == ["converged", "discontinuous"], by_poses.summary()
    tight = robot.solve_path(rows, Q_A, max_joint_step=1.0)
    assert tight.status.tolist() == ["converged", "discontinuous"], tight.summary()
    words = by_poses.reason(1)[: by_poses.reason(1).index("; q is the followed answer")]
    assert words.startswith(f"{right}: reachable only by a jump: the step from the previous")
    assert tight.reason(1).startswith(words + "; q is the followed answer, verified: ")
    ends = tight.q
    half = {
        left: [armik.Pose(_halfway(*poses[left]), frame=left)],
        right: [armik.Relative(right, left, _halfway(*grip))],
    }
    there = robot.solve(half)  # reachable halfway, but not near both ends
    assert there.success, there.reason
    held = half[right][0].pose.T.actInv(_relative(robot, there.q, right, left))
    assert np.abs(pin.log6(held).vector).max() < 1e-6
    assert min(np.abs(there.q - q).max() for q in ends) > 1.0
    step = np.full(robot.dof, 1.0)
    lo = np.maximum(ends.max(axis=0) - step, robot.lower)
    hi = np.minimum(ends.min(axis=0) + step, robot.upper)
    rng = np.random.default_rng(1)
    for _ in range(40):
        r = robot.solve(half, q0=rng.uniform(lo, hi), max_restarts=0, max_iterations=1000)
        assert not (r.success and within(np.asarray(r.q), ends[0], ends[1], step))
    loose = robot.solve_path(rows, Q_A, max_joint_step=10.0)  # no jump can hide
    assert loose.success.all(), loose.summary()
    for i in range(2):
        err = pin.log6(poses[left][i].actInv(robot.fk(loose.q[i], left))).vector
        assert np.abs(err).max() <= 1e-6
        err = pin.log6(grip[i].actInv(_relative(robot, loose.q[i], right, left))).vector
        assert np.abs(err).max() <= 1e-6


@pytest.mark.parametrize("bounds", [[0.001] * 3, [0.01, 0.01, 0.001]])
def test_a_bounded_position_step_that_hides_a_jump_is_discontinuous(cell, bounds):
    """The left IRB 120's shoulder turned 3 rad between two waypoints (max_joint_step 3.1):
    halfway, the tool's position is out of reach, within the bounds too. The robot's path
    judges its rows' steps (``arms_steps.hidden_steps``: the rows solved again after a
    failed row, or rows solved one by one); given the left tool's positions, the step is a
    hidden jump; given armik.Position(p, bounds=...), it was passed unjudged. It is judged
    on the robot now, in the task's measure: a hidden jump, naming the tool."""
    left = cell.tips[0]
    cols = cell._columns[left]
    q = cell.middle.copy()
    q[cols] = [-2.713, 0.168, 1.018, 1.764, -2.083, 4.99]
    q2 = q.copy()
    q2[cols[0]] += 3.0
    ways = {tip: [cell.fk(x, tip) for x in (q, q2)] for tip in cell.tips}
    step = np.full(cell.dof, 3.1)
    exact = [T.translation for T in ways[left]]
    within_bounds = [armik.Position(T.translation, bounds=bounds) for T in ways[left]]
    for rows in (exact, within_bounds):
        out = cell.solve_path(ways, q, max_joint_step=10.0)  # no jump can hide: at q, q2
        assert out.success.all() and np.allclose(out.q, [q, q2], atol=1e-6), out.summary()
        hidden_steps(cell, out, read_rows(cell, {**ways, left: rows}), step, _read({}))
        assert out.status.tolist() == ["converged", "discontinuous"], out.summary()
        assert out.reason(1).startswith(f"{left}: reachable only by a jump: the step from")
        assert "hides a jump between the waypoints" in out.reason(1)
    middle = 0.5 * (ways[left][0].translation + ways[left][1].translation)
    there = cell.chain(left).solve(armik.Position(middle, bounds=bounds))
    assert not there.success and there.position_error > 0.01  # out of reach halfway


def _smooth(robot: armik.Arms, rng: np.random.Generator, n: int, move: float) -> np.ndarray:
    """``n`` configurations along a straight joint motion of at most ``move`` per joint a
    step, 0.05 inside the limits and away from every tip's singularities (each chain's
    Jacobian's smallest singular value over 0.05)."""
    span = robot.upper - robot.lower
    while True:
        q0 = robot.lower + span * rng.uniform(0.15, 0.85, robot.dof)
        Q = q0 + np.outer(np.arange(n), rng.uniform(-move, move, robot.dof))
        if not ((Q > robot.lower + 0.05) & (Q < robot.upper - 0.05)).all():
            continue
        J = [robot.jacobian(q, tip) for q in Q for tip in robot.tips]
        if min(np.linalg.svd(j, compute_uv=False).min() for j in J) > 0.05:
            return Q


def _row(robot: armik.Arms, q: np.ndarray, kind: str) -> list:
    """One row of tasks at ``q``: the left tip's pose and the right tip's ``kind``."""
    left, right = robot.tips
    T_l = robot.fk(q, left)
    if kind == "relative":
        task = armik.Relative(right, left, T_l.actInv(robot.fk(q, right)))
    elif kind == "relative within bounds":
        bounds = [0.002] * 3 + [0.01] * 3
        task = armik.Relative(right, left, T_l.actInv(robot.fk(q, right)), bounds=bounds)
    else:
        task = armik.Position(robot.fk(q, right).translation, bounds=[0.002] * 3, frame=right)
    return [armik.Pose(T_l, frame=left), task]


@pytest.mark.parametrize(
    ("robot", "kind"),
    [
        ("talos", "relative"),
        ("talos", "relative within bounds"),
        ("talos", "position within bounds"),
        ("cell", "relative"),
    ],
)
def test_smooth_paths_of_relative_and_bounded_tasks_hide_no_jump(cell, robot, kind, monkeypatch):
    """20 random smooth paths of each kind (6 waypoints along a straight joint motion of up
    to 0.1 rad a joint a step, inside the limits and away from singularities; TALOS's
    shared torso, and two IRB 120s apart): the rows' steps are judged halfway on the robot
    (steps over an eighth of the bound: not passed as small), and none is called a hidden
    jump; nearly every row converges."""
    robot = cell if robot == "cell" else talos()
    judged = []
    solution = armik.arms_halfway._solution

    def counted(*args):
        judged.append(args)
        return solution(*args)

    monkeypatch.setattr(armik.arms_halfway, "_solution", counted)
    rng = np.random.default_rng(2)
    converged = 0
    for _ in range(20):
        Q = _smooth(robot, rng, 6, 0.1)
        b = robot.solve_path([_row(robot, q, kind) for q in Q], Q[0], max_joint_step=0.5)
        hidden = [b.reason(i) for i in range(len(Q)) if "hides a jump" in b.reason(i)]
        assert not hidden, hidden
        converged += int(b.success.sum())
    assert len(judged) >= 40  # steps judged halfway, not only passed as small and straight
    assert converged >= 0.9 * 20 * 6


def _riding(robot: armik.Arms, seed: int, trial: int) -> np.ndarray:
    """The configurations of random path ``trial`` (from 0) drawn with ``seed``: 6 along a
    straight joint motion of up to 0.2 rad a joint a step from a random configuration,
    clipped into the limits (riding some)."""
    rng = np.random.default_rng(seed)
    for _ in range(trial + 1):
        q0 = robot.random_q(rng)
        d = rng.uniform(-0.2, 0.2, robot.dof)
    return np.clip(q0 + np.outer(np.arange(6), d), robot.lower, robot.upper)


def _half_row(rows: list, i: int) -> list:
    """Row ``i - 1`` and row ``i`` (a left ``Pose`` and a ``Relative``) halfway."""
    (pose_a, rel_a), (pose_b, rel_b) = rows[i - 1], rows[i]
    bounds = rel_a.pose.bounds
    return [
        armik.Pose(_halfway(pose_a.T, pose_b.T), frame=pose_a.frame),
        armik.Relative(
            rel_a.frame, rel_a.relative_to, _halfway(rel_a.pose.T, rel_b.pose.T), bounds
        ),
    ]


def test_a_step_along_joint_limits_is_judged_from_about_the_step_not_only_its_middle():
    """TALOS, a Relative path whose joints ride their limits (the torso's pitch, the left
    elbow, the right shoulder): halfway along step 3 -> 4 a descent from the step's middle
    stalls against the limits, 0.3 mm off the tasks, while the self-motion holds an answer
    within max_joint_step of both ends further along. Judged from the middle and the ends
    alone, rows 4 and 5 were called hidden jumps; descents from points spread over the
    configurations within the step of both ends find it, and the rows converge."""
    robot = talos()
    left, right = robot.tips
    Q = _riding(robot, 1, 19)
    rows = [
        [
            armik.Pose(robot.fk(q, left), frame=left),
            armik.Relative(right, left, _relative(robot, q, right, left)),
        ]
        for q in Q
    ]
    b = robot.solve_path(rows, Q[0], max_joint_step=0.5)
    assert b.status[4:].tolist() == ["converged"] * 2, b.summary()
    Qa, Qb, step = b.q[3], b.q[4], np.full(robot.dof, 0.5)
    middle = 0.5 * (Qa + Qb)
    assert ((middle <= robot.lower + 1e-9) | (middle >= robot.upper - 1e-9)).sum() >= 2
    half = _half_row(rows, 4)
    stalled = robot.solve(half, q0=middle, max_restarts=0, max_iterations=1000)
    assert not (stalled.success and within(np.asarray(stalled.q), Qa, Qb, step))
    for i in (4, 5):
        for task in rows[i]:
            T = (
                robot.fk(b.q[i], left)
                if task.frame == left
                else _relative(robot, b.q[i], right, left)
            )
            goal = task.T if task.frame == left else task.pose.T
            assert np.abs(pin.log6(goal.actInv(T)).vector).max() <= 1e-6


def test_a_step_onto_a_bounded_relative_is_judged_by_descents_long_enough_to_close_in(cell):
    """Two IRB 120s, the right tool given armik.Relative to the left within bounds (2 mm,
    0.01 rad), riding the limits: halfway along step 3 -> 4 descents of the default 100
    iterations from the step's middle and from either end stop outside the region (300
    from the middle too); longer ones close in, within max_joint_step of both ends. Judged
    by descents of 100 iterations, row 4 was a hidden jump; it converges, within its
    region by FK."""
    left, right = cell.tips
    Q = _riding(cell, 1, 2)
    bounds = [0.002] * 3 + [0.01] * 3
    rows = [
        [
            armik.Pose(cell.fk(q, left), frame=left),
            armik.Relative(right, left, _relative(cell, q, right, left), bounds),
        ]
        for q in Q
    ]
    b = cell.solve_path(rows, Q[0], max_joint_step=0.5)
    assert b.status[:5].tolist() == ["converged"] * 5, b.summary()
    Qa, Qb, step = b.q[3], b.q[4], np.full(cell.dof, 0.5)
    half = _half_row(rows, 4)
    for seed, iterations in ((0.5 * (Qa + Qb), 300), (0.5 * (Qa + Qb), 100), (Qa, 100), (Qb, 100)):
        short = cell.solve(half, q0=seed, max_restarts=0, max_iterations=iterations)
        assert not (short.success and within(np.asarray(short.q), Qa, Qb, step))
    D = rows[4][1].pose.T.actInv(_relative(cell, b.q[4], right, left))  # in the target's frame
    err = np.concatenate((D.translation, pin.log3(D.rotation)))
    assert (np.abs(err) <= np.array(bounds) + 1e-6).all()
