"""Several tips over many targets: ``Arms.solve_batch`` (tip -> N targets) and
``Arms.solve_path`` (tip -> N waypoints). Independent chains by each chain's own batch,
equal to solving each arm alone; a shared torso and relative tasks row by row; a jump on
a path reported, naming the joint; bad input named."""

from __future__ import annotations

import itertools
import multiprocessing
import operator
import pickle
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.arms_many import _read
from armik.arms_many_read import read_rows
from armik.arms_steps import hidden_steps
from armik.constraints.base import Check, Constraint
from armik.errors import FrameError, OptionError, TargetError

from .test_arms import dual_irb120


@pytest.fixture(scope="module")
def cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])


def test_a_batch_of_independent_chains_is_each_arm_alone(cell):
    rng = np.random.default_rng(11)
    qs = np.array([cell.random_q(rng) for _ in range(30)])
    left = np.array([cell.fk(q, "l_tool0").homogeneous for q in qs])
    right = np.array([cell.fk(q, "r_tool0").translation for q in qs])
    right[3] = [5.0, 0.0, 0.0]  # out of reach
    b = cell.solve_batch({"l_tool0": left, "r_tool0": right})
    assert len(b) == 30 and b.q.shape == (30, 12) and b.joint_names == cell.joint_names
    alone = cell.chain("l_tool0").solve_batch(left, q0=cell.split(cell.middle)["l_tool0"])
    np.testing.assert_array_equal(b.q[:, :6], alone.q)
    assert b.success.sum() == 29 and not b.success[3]
    assert b.status[3] == "unreachable" and b.reason(3).startswith("r_tool0: unreachable")
    assert np.isnan(b.orientation_error).sum() == 0  # the left tip measures orientation
    for i in np.flatnonzero(b.success):
        parts = cell.split(b.q[i])
        T = cell.chain("l_tool0").fk(parts["l_tool0"])
        assert np.allclose(T.homogeneous, left[i], atol=1e-6)
        assert np.allclose(
            cell.chain("r_tool0").fk(parts["r_tool0"]).translation, right[i], atol=1e-6
        )


def test_a_batch_with_relative_tasks_goes_row_by_row(cell):
    rng = np.random.default_rng(12)
    left, grips = [], []
    for _ in range(5):
        q = cell.random_q(rng)
        T_l, T_r = cell.fk(q, "l_tool0"), cell.fk(q, "r_tool0")
        left.append(T_l)
        grips.append(armik.Relative("r_tool0", "l_tool0", T_l.actInv(T_r)))
    b = cell.solve_batch({"l_tool0": left, "r_tool0": grips})
    assert b.success.all() and b.solver == "arms"
    for i, row in enumerate(b.q):
        parts = cell.split(row)
        T_l = cell.chain("l_tool0").fk(parts["l_tool0"])
        T_r = cell.chain("r_tool0").fk(parts["r_tool0"])
        err = pin.log6(grips[i].pose.T.inverse() * T_l.actInv(T_r)).vector
        assert np.abs(err).max() <= 2e-6


def line(T: pin.SE3, dx: np.ndarray, n: int) -> list[pin.SE3]:
    return [pin.SE3(T.rotation, T.translation + dx * k / (n - 1)) for k in range(n)]


def test_a_path_of_two_independent_arms(cell):
    q0 = cell.middle + 0.2
    T_l, T_r = cell.fk(q0, "l_tool0"), cell.fk(q0, "r_tool0")
    ways = {
        "l_tool0": line(T_l, np.array([0.0, 0.0, 0.1]), 20),
        "r_tool0": line(T_r, np.array([0.05, 0.0, 0.0]), 20),
    }
    for plan in ("follow", "global"):
        b = cell.solve_path(ways, q0, max_joint_step=0.2, plan=plan)
        assert b.success.all(), b.summary()
        steps = np.abs(np.diff(np.vstack([q0, b.q]), axis=0))
        assert steps.max() <= 0.2 + 1e-12
    for bad in (True, "0.2", [0.2, 0.2]):  # a bool is no step: not read as 1.0 rad
        with pytest.raises(OptionError, match="max_joint_step must be one number"):
            cell.solve_path(ways, q0, max_joint_step=bad)


def talos() -> armik.Arms:
    robots = Path(armik.load("panda").source).parents[2]
    urdf = robots / "talos_data" / "robots" / "talos_reduced.urdf"
    return armik.load(urdf, tips=["gripper_left_base_link", "gripper_right_base_link"])


def test_a_path_over_a_shared_torso_reports_a_jump():
    robot = talos()
    tips = robot.tips
    union = robot._union
    q0 = robot.middle
    T = {tip: union.fk(q0, tip) for tip in tips}
    ways = {tip: line(T[tip], np.array([0.0, 0.0, 0.06]), 7) for tip in tips}
    b = robot.solve_path(ways, q0, max_joint_step=0.3, iteration_budget=3000)
    assert b.success.all(), b.summary()
    assert np.abs(np.diff(np.vstack([q0, b.q]), axis=0)).max() <= 0.3 + 1e-12
    far = robot.random_q(np.random.default_rng(1))
    jump = {tip: [union.fk(far, tip)] for tip in tips}
    r = robot.solve_path(jump, q0, max_joint_step=0.05, iteration_budget=3000)
    assert r.status[0] == "discontinuous" and not r.success[0]
    assert "reachable only by a jump" in r.reason(0) and "max_joint_step 0.05" in r.reason(0)
    with pytest.raises(OptionError, match="plan='follow'"):
        robot.solve_path(ways, q0, plan="global")


def test_bad_many_targets_are_named(cell):
    with pytest.raises(TargetError, match="as many targets"):
        cell.solve_batch({"l_tool0": np.zeros((3, 3)), "r_tool0": np.zeros((2, 3))})
    with pytest.raises(FrameError, match="unknown tips"):
        cell.solve_batch({"hand": np.zeros((2, 3))})
    with pytest.raises(OptionError, match="one per target"):
        cell.solve_batch({"l_tool0": np.zeros((2, 3))}, q0=np.zeros((3, 12)))
    with pytest.raises(OptionError, match="map tip names"):
        cell.solve_batch(np.zeros((2, 3)))
    with pytest.raises(OptionError, match="positive and finite"):
        cell.solve_path({"l_tool0": np.zeros((2, 3))}, cell.middle, max_joint_step=-1.0)
    # a step per joint of one chain (6 of the robot's 12), or words: named, no numpy error
    for step in (np.full(6, 0.1), "abc"):
        with pytest.raises(OptionError, match="one number or 12 numbers") as info:
            cell.solve_path({"l_tool0": np.zeros((2, 3))}, cell.middle, max_joint_step=step)
        assert info.value.option == "max_joint_step" and "r_joint_6" in str(info.value)


def baxter() -> armik.Arms:
    robots = Path(armik.load("panda").source).parents[2]
    urdf = robots / "baxter_description" / "urdf" / "baxter.urdf"
    return armik.load(urdf, tips=["left_gripper", "right_gripper"])


def _loop(robot: armik.Arms, targets: dict, n: int) -> np.ndarray:
    return np.array([robot.solve({t: rows[i] for t, rows in targets.items()}).q for i in range(n)])


@pytest.mark.parametrize("shared", [False, True], ids=["baxter", "panda_link4+hand"])
def test_a_batch_takes_arm_s_batch_keywords_and_gives_the_loop_s_rows(shared):
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"]) if shared else baxter()
    assert bool(robot.shared) == shared
    n = 5
    targets = robot.fk_batch(robot.random_q(3, n=n))
    loop = _loop(robot, targets, n)
    heard: list[tuple[int, int]] = []
    keywords = [
        {"workers": 2, "chunk_size": 2},
        {"workers": 1, "chunk_size": 4, "progress": False},
        {"workers": 2, "progress": lambda done, total: heard.append((done, total))},
    ]
    for kw in keywords:
        b = robot.solve_batch(targets, **kw)
        assert b.success.all(), b.summary()
        np.testing.assert_array_equal(b.q, loop)
    assert heard and heard[-1][0] == heard[-1][1] == n
    with pytest.raises(OptionError, match="workers must be a whole number"):
        robot.solve_batch(targets, workers=0)
    with pytest.raises(OptionError, match="chunk_size must be a whole number"):
        robot.solve_batch(targets, chunk_size=0)


def test_a_batch_s_backend_goes_to_each_chain_or_runs_its_rows():
    robot = baxter()
    targets = robot.fk_batch(robot.random_q(4, n=3))
    b = robot.solve_batch(targets, backend="threads", workers=2)
    np.testing.assert_array_equal(b.q, _loop(robot, targets, 3))


def _reversed(jobs, workers):
    """A backend that gives the jobs' results last first: each is put at its own rows."""
    return [job() for job in reversed(jobs)]


def _rows_batches() -> list[tuple[armik.Arms, dict, dict]]:
    """Batches solved row by row: a shared joint (one row out of reach), a Relative task,
    a cost of the whole configuration, each with a joint limit tightened by constraints."""
    shared = armik.load("panda", tips=["panda_link4", "panda_hand"])
    rows = shared.fk_batch(shared.random_q(4, n=6))
    rows["panda_hand"][4] = np.array(rows["panda_hand"][4])
    rows["panda_hand"][4][:3, 3] = [3.0, 0.0, 0.5]
    cell = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    qs = cell.random_q(5, n=5)
    left = [cell.fk(q, "l_tool0") for q in qs]
    grips = [
        armik.Relative("r_tool0", "l_tool0", cell.fk(q, "l_tool0").actInv(cell.fk(q, "r_tool0")))
        for q in qs
    ]
    both = {tip: [cell.fk(q, tip) for q in qs] for tip in cell.tips}
    cost = {"prefer": lambda q: float(np.sum(np.asarray(q) ** 2))}
    return [
        (shared, rows, {"seed": 3}),
        (cell, {"l_tool0": left, "r_tool0": grips}, {"seed": 4}),
        (cell, both, cost),
    ]


@pytest.mark.parametrize("backend", ["threads", "processes", _reversed])
def test_a_batch_solved_row_by_row_runs_on_a_backend_as_here(backend):
    """Chains that share joints, a Relative task, a cost of the whole configuration: the
    rows go as chunks of rows (``armik.arms_rows.ArmsRows``) to the backend, each solved
    there as ``Arms.solve`` solves it, the same answers and failures row by row."""
    for robot, targets, options in _rows_batches():
        here = robot.solve_batch(targets, progress=False, **options)
        got = robot.solve_batch(
            targets, backend=backend, workers=2, chunk_size=2, progress=False, **options
        )
        np.testing.assert_array_equal(got.q, here.q)
        np.testing.assert_array_equal(got.success, here.success)
        np.testing.assert_array_equal(got.status_code, here.status_code)
        assert got.reasons == here.reasons and got.solver == here.solver == "arms"
        assert here.success.sum() >= len(here) - 1, here.summary()
    assert not here.success.all() or len(here) == 5
    with pytest.raises(OptionError, match="unknown batch backend 'nowhere'"):
        robot.solve_batch(targets, backend="nowhere", **options)


class BaseTurn(Constraint):
    """The Panda's joint 1 below 0.3 rad (a check alone, of the test's own)."""

    def check(self, arm, Q):
        return Check(Q[:, 0] < 0.3, armik.Status.JOINT_LIMITS, lambda i: "base turned")


def _pickled_pool(jobs, workers):
    """The jobs on a pool of forked processes, each job pickled there and back."""
    context = multiprocessing.get_context("fork")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        return list(pool.map(operator.call, jobs))


def test_a_job_of_rows_checks_every_constraint_where_it_runs():
    """Jobs of rows pickled and called in other processes: the robot travels as its
    chains' recipes and each row's constraints are checked there (a held joint kept at its
    seed's value, a check of the test's own on one tip's chain), as ``Arms.solve`` checks
    them here."""
    shared = armik.load("panda", tips=["panda_link4", "panda_hand"])
    assert type(pickle.loads(pickle.dumps(shared))) is armik.Arms
    qs = shared.random_q(8, n=6)
    qs[:, 0] = [0.1, 0.6, -0.4, 0.9, 0.2, 0.5]  # rows 1, 3 and 5 break BaseTurn
    targets = {tip: [shared.fk(q, tip) for q in qs] for tip in shared.tips}
    options = {"hold": {"panda_joint2": None}, "constraints": {"panda_hand": [BaseTurn()]}}
    # restarts counted, not timed: a failed row's reason says them, the same in a job
    options |= {"max_restarts": 8, "timeout": 10.0}
    here = shared.solve_batch(targets, q0=qs, progress=False, **options)
    got = shared.solve_batch(
        targets, q0=qs, backend=_pickled_pool, workers=2, chunk_size=2, **options
    )
    np.testing.assert_array_equal(got.q, here.q)
    np.testing.assert_array_equal(got.success, [True, False, True, False, True, False])
    np.testing.assert_array_equal(got.success, here.success)
    np.testing.assert_array_equal(got.q[:, 1], qs[:, 1])  # held at each row's seed
    assert "base turned" in got.reason(1) and got.reasons == here.reasons


def test_batch_and_path_take_solve_s_prefer_and_solver(cell):
    """What Arms.solve takes, solve_batch and solve_path take on independent chains:
    prefer= and solver= went to each chain's batch, then were refused as unknown options
    (after the work); a Posture over the robot's 12 joints is split by chain, as
    secondary= is, on solve too."""
    q = cell.random_q(np.random.default_rng(21))
    T = {tip: cell.fk(q, tip) for tip in cell.tips}
    many = {tip: [T[tip], T[tip]] for tip in cell.tips}
    ways = {tip: line(T[tip], np.array([0.0, 0.002, 0.0]), 3) for tip in cell.tips}
    posture = armik.Posture(q)  # one value per joint of the robot: the answer nearest q
    assert np.allclose(cell.solve(T, prefer=posture).q, q, atol=1e-6)
    b = cell.solve_batch(many, prefer=posture)
    assert b.success.all() and np.allclose(b.q, q, atol=1e-6)
    for options in ({"prefer": "manipulability"}, {"solver": "dls"}):
        assert cell.solve_batch(many, **options).success.all()
        assert cell.solve_path(ways, q, **options).success.all()
    assert "dls" in cell.solve_batch(many, solver="dls").solver
    p = cell.solve_path(ways, q, prefer=posture)
    assert p.success.all() and np.allclose(p.q[0], q, atol=1e-6)
    assert cell.solve_batch(many, secondary=[posture]).success.all()  # split as in solve
    with pytest.raises(OptionError, match="has 6 values, the robot 12 joints"):
        cell.solve(T, prefer=armik.Posture(q[:6]))


def test_batch_and_path_refuse_a_bad_option_before_any_chain_runs(cell, monkeypatch):
    def ran(*args, **kwargs):
        raise AssertionError("a chain's batch ran before the options were checked")

    chain = type(cell.chain("l_tool0"))
    monkeypatch.setattr(chain, "solve_batch", ran)
    monkeypatch.setattr(chain, "solve_path", ran)
    rows = {tip: np.zeros((2, 3)) for tip in cell.tips}
    with pytest.raises(OptionError, match="unknown option 'tolerance'"):
        cell.solve_batch(rows, tolerance=1e-3)
    with pytest.raises(OptionError, match="unknown option 'tolerance'"):
        cell.solve_path(rows, cell.middle, tolerance=1e-3)


def test_holding_a_locked_joint_says_it_is_locked():
    """As on one arm: the joint is named as locked at its value, not as unknown."""
    robot = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"], locked={"l_joint_1": 0.2})
    T = robot.fk(robot.middle)
    with pytest.raises(armik.JointError, match=r"'l_joint_1' is locked at 0.2"):
        robot.solve(T, hold={"l_joint_1": 0.2})


@pytest.mark.parametrize("robot", ["cell", "talos"])
def test_one_pose_per_tip_is_refused_naming_the_tip_and_solve(cell, robot):
    """``Arms.solve``'s dict, one pose per tip, given to ``solve_batch`` or ``solve_path``
    (which take each tip's N rows): a ``TargetError`` naming the tip, what it was given and
    ``Arms.solve``, whatever the pose's spelling and whether the chains share joints."""
    arms = cell if robot == "cell" else talos()
    q = arms.middle + 0.1
    poses = {tip: arms.fk(q, tip) for tip in arms.tips}
    first = repr(arms.tips[0])
    spellings = {
        "one SE3": poses,
        r"an array of shape \(4, 4\)": {t: T.homogeneous for t, T in poses.items()},
        "one 4x4 matrix": {t: T.homogeneous.tolist() for t, T in poses.items()},
        r"an array of shape \(3,\)": {t: T.translation for t, T in poses.items()},
        r"one \(position, quaternion\)": {
            t: (T.translation, pin.Quaternion(T.rotation).coeffs()) for t, T in poses.items()
        },
    }
    for said, targets in spellings.items():
        for call, args in ((arms.solve_batch, ()), (arms.solve_path, (q,))):
            with pytest.raises(TargetError, match=f"tip {first} needs a sequence of poses") as e:
                call(targets, *args)
            assert said.replace("\\", "") in str(e.value) and "Arms.solve takes one pose" in str(
                e.value
            )
    rows = {tip: [T, T] for tip, T in poses.items()}  # each tip's rows: solved
    assert len(arms.solve_batch(rows)) == 2


def _true_errors(robot: armik.Arms, q: np.ndarray, tip: str, target: np.ndarray):
    """(position m, orientation rad or None) of ``tip`` at ``q`` from ``target`` (a 4x4
    pose or a position), by Pinocchio's FK of the tip's chain."""
    X = robot.chain(tip).fk(robot.split(q)[tip])
    if np.shape(target) == (3,):
        return float(np.linalg.norm(X.translation - target)), None
    T = pin.SE3(np.asarray(target))
    rot = float(np.linalg.norm(pin.log3(T.rotation.T @ X.rotation)))
    return float(np.linalg.norm(X.translation - T.translation)), rot


@pytest.mark.parametrize("shared", [False, True], ids=["cell", "panda_link4+hand"])
def test_a_batch_s_rows_give_each_tip_s_errors_as_solve_does(cell, shared):
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"]) if shared else cell
    first, last = robot.tips
    qs = robot.random_q(6, n=4)
    rows = {first: [robot.fk(q, first).translation for q in qs]}
    rows[last] = [robot.fk(q, last).homogeneous for q in qs]
    rows[last][2] = np.array(rows[last][2])
    rows[last][2][:3, 3] = [3.0, 0.0, 0.5]  # out of reach: a failure, its errors all the same
    batch = robot.solve_batch(rows)
    path = robot.solve_path(rows, robot.middle, max_joint_step=10.0)
    for b in (batch, path):
        assert list(b.errors) == list(robot.tips) and not b.success[2]
        for i, r in enumerate(b):
            assert list(r.errors) == list(robot.tips)
            for tip in robot.tips:
                pos, rot = _true_errors(robot, r.q, tip, rows[tip][i])
                assert r.errors[tip][0] == pytest.approx(pos, abs=1e-9)
                assert (r.errors[tip][1] is None) == (rot is None)
                if rot is not None:
                    assert r.errors[tip][1] == pytest.approx(rot, abs=1e-9)
            assert r.position_error == max(e[0] for e in r.errors.values())
        assert b[2:][0].errors == b[2].errors  # a slice keeps them
    assert batch[0].errors.keys() == robot.solve({t: rows[t][0] for t in rows}).errors.keys()


def test_a_batch_reads_the_tips_in_the_robot_s_order_as_solve_does(cell):
    q = cell.random_q(3)
    T = cell.fk(q, "l_tool0")
    # both out of reach, the dict naming the right tip first: the reason names the left
    # first, as solve's does, and the row's status is the left tip's
    targets = {
        "r_tool0": np.array([0.0, -0.5, 3.0]),
        "l_tool0": T * pin.SE3(np.eye(3), np.array([3.0, 0.0, 0.0])),
    }
    r = cell.solve(targets)
    rows = {tip: [target] for tip, target in targets.items()}
    for b in (cell.solve_batch(rows), cell.solve_path(rows, q)):
        assert b.reason(0) == r.reason and b.reason(0).startswith("l_tool0: ")
        assert b.status[0] == r.status.value and list(b.errors) == list(cell.tips)


@pytest.mark.parametrize("backend", [None, "threads"])
def test_a_bad_row_solved_row_by_row_is_named(backend):
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"])
    rows = robot.fk_batch(robot.random_q(2, n=4))
    rows["panda_hand"] = np.array(rows["panda_hand"])
    rows["panda_hand"][2, 0, 0] = np.nan
    with pytest.raises(TargetError, match=r"^target 2: the target of tip 'panda_hand': .*NaN"):
        robot.solve_batch(rows, backend=backend, chunk_size=1, workers=2)
    with pytest.raises(TargetError, match=r"^target 2: the target of tip 'panda_hand'"):
        robot.solve_path(rows, robot.middle)


@pytest.mark.parametrize("robot", ["cell", "talos"])
def test_a_tip_left_out_keeps_q0_clipped_into_the_limits(cell, robot):
    robot = cell if robot == "cell" else talos()
    given, left_out = robot.tips
    q0 = robot.middle.copy()
    j = robot.joint_names.index(robot.chain(left_out).joint_names[-1])
    q0[j] = robot.upper[j] + 0.5  # a joint of the tip left out beyond its limit
    T = robot.fk(robot.random_q(1), given)
    calls = [
        lambda: robot.solve({given: T}, q0=q0),
        lambda: robot.solve_batch({given: [T]}, q0=q0)[0],
        lambda: robot.solve_batch({given: [T]}, q0=q0[None, :])[0],
        lambda: robot.solve_path({given: [T]}, q0, max_joint_step=10.0)[0],
    ]
    for call in calls:
        with pytest.warns(armik.ArmikWarning, match=f"clipped into them: {robot.joint_names[j]}"):
            r = call()
        assert r.success and robot.within_limits(r.q, tol=0.0)
        assert r.q[j] == robot.upper[j]


def test_a_path_over_a_shared_torso_reports_a_jump_hidden_between_waypoints():
    """TALOS, both hands from one configuration to one within 0.9 rad of it on every joint:
    the step is within max_joint_step (1 rad), but halfway along the right hand's straight
    tool line its chain's solutions swing the wrist by more than that (a descent from 200
    seeds about the step finds none within 1 rad of both ends). The path of several tips,
    solved row by row, called it converged; it is a hidden jump now, naming the hand, as
    the hand's own chain reports it. With a bound that lets every joint flip it goes
    through, each hand on its pose by FK."""
    robot = talos()
    union, right = robot._union, robot.tips[1]
    q = np.array([-0.748, 0.175, 0.121, 0.789, 1.543, -2.103, -0.322, 0.946, -0.421, 0.11])
    q = np.concatenate((q, [-1.892, -1.408, -0.186, 0.289, 0.965, 0.048]))
    q2 = np.array([-1.309, -0.262, 0.524, 0.937, 0.812, -2.223, -0.36, 0.334, 0.001, -0.524])
    q2 = np.concatenate((q2, [-2.088, -1.378, -0.311, 0.445, 1.393, 0.698]))
    ways = {tip: [union.fk(q, tip), union.fk(q2, tip)] for tip in robot.tips}
    b = robot.solve_path(ways, q, max_joint_step=1.0)
    assert b.status.tolist() == ["converged", "discontinuous"], b.summary()
    assert b.reason(1).startswith(f"{right}: ") and "hide" in b.reason(1)
    cols = robot._columns[right]
    Ta, Tb = ways[right]
    H = pin.SE3(
        Ta.rotation @ pin.exp3(0.5 * pin.log3(Ta.rotation.T @ Tb.rotation)),
        0.5 * (Ta.translation + Tb.translation),
    )
    there = robot.chain(right).solve(H)  # reachable halfway, but not near both ends
    assert there.success
    assert np.abs(pin.log6(H.actInv(union.fk(_with(q, cols, there.q), right))).vector).max() < 1e-6
    assert max(np.abs(there.q - b.q[0][cols]).max(), np.abs(there.q - b.q[1][cols]).max()) > 1.0
    loose = robot.solve_path(ways, q, max_joint_step=10.0)
    assert loose.success.all(), loose.summary()
    for i in range(2):
        for tip in robot.tips:
            err = pin.log6(ways[tip][i].actInv(union.fk(loose.q[i], tip))).vector
            assert np.abs(err).max() <= 1e-6


def test_a_path_of_flat_task_lists_is_checked_halfway_as_one_of_poses_by_tip():
    """The TALOS step above given as rows of flat task lists, each hand's Pose naming its
    frame: the same request as the mapping tip -> poses. The steps of such rows were not
    judged halfway (called converged); now both spellings give the same answers and report
    the same hidden jump, and with a bound that lets every joint flip go through alike."""
    robot = talos()
    union = robot._union
    q = np.array([-0.748, 0.175, 0.121, 0.789, 1.543, -2.103, -0.322, 0.946, -0.421, 0.11])
    q = np.concatenate((q, [-1.892, -1.408, -0.186, 0.289, 0.965, 0.048]))
    q2 = np.array([-1.309, -0.262, 0.524, 0.937, 0.812, -2.223, -0.36, 0.334, 0.001, -0.524])
    q2 = np.concatenate((q2, [-2.088, -1.378, -0.311, 0.445, 1.393, 0.698]))
    ways = {tip: [union.fk(q, tip), union.fk(q2, tip)] for tip in robot.tips}
    flat = [[armik.Pose(ways[tip][i], frame=tip) for tip in robot.tips] for i in range(2)]
    for step in (1.0, 10.0):
        by_tip = robot.solve_path(ways, q, max_joint_step=step)
        by_rows = robot.solve_path(flat, q, max_joint_step=step)
        assert by_rows.status.tolist() == by_tip.status.tolist(), by_rows.summary()
        assert [by_rows.reason(i) for i in range(2)] == [by_tip.reason(i) for i in range(2)]
        assert np.array_equal(by_rows.q, by_tip.q)
    assert by_tip.success.all()
    tight = robot.solve_path(flat, q, max_joint_step=1.0)
    assert tight.status.tolist() == ["converged", "discontinuous"], tight.summary()
    assert "hide" in tight.reason(1)
    for i in range(2):  # the loose path's answers on each hand's pose by Pinocchio
        for tip in robot.tips:
            err = pin.log6(ways[tip][i].actInv(union.fk(by_rows.q[i], tip))).vector
            assert np.abs(err).max() <= 1e-6


@pytest.mark.parametrize(
    "loosened", [{"weights": [1, 1, 1, 0.5, 0.5, 0.5]}, {"bounds": [0.001] * 3 + [0.01] * 3}]
)
def test_a_hand_given_a_loosened_pose_is_judged_halfway_as_its_chain_is(loosened):
    """The TALOS step above, the right hand given armik.Pose(T, weights=...) or
    Pose(T, bounds=...) (as flat task lists, or the mapping tip -> tasks): a tip given
    tasks was not judged halfway, and the hidden jump was called converged. Each such tip's
    poses are read as one arm reads them (the weights or bounds beside them), and the step
    is judged as the hand's own path judges it: a hidden jump; with a bound that lets
    every joint flip both spellings go through, each hand on its pose by FK."""
    robot = talos()
    union, (left, right) = robot._union, robot.tips
    q = np.array([-0.748, 0.175, 0.121, 0.789, 1.543, -2.103, -0.322, 0.946, -0.421, 0.11])
    q = np.concatenate((q, [-1.892, -1.408, -0.186, 0.289, 0.965, 0.048]))
    q2 = np.array([-1.309, -0.262, 0.524, 0.937, 0.812, -2.223, -0.36, 0.334, 0.001, -0.524])
    q2 = np.concatenate((q2, [-2.088, -1.378, -0.311, 0.445, 1.393, 0.698]))
    ways = {tip: [union.fk(q, tip), union.fk(q2, tip)] for tip in robot.tips}
    rows = [
        [armik.Pose(ways[left][i], frame=left), armik.Pose(ways[right][i], frame=right, **loosened)]
        for i in range(2)
    ]
    by_tip = {tip: [row[k] for row in rows] for k, tip in enumerate(robot.tips)}
    cols = robot._columns[right]
    alone = robot.chain(right).solve_path(
        [armik.Pose(T, **loosened) for T in ways[right]], q[cols], max_joint_step=1.0
    )
    assert alone.status.tolist() == ["converged", "discontinuous"]
    bound = np.array(loosened.get("bounds", [0.0] * 6)) + 1e-6
    for spelled in (rows, by_tip):
        tight = robot.solve_path(spelled, q, max_joint_step=1.0)
        assert tight.status.tolist() == ["converged", "discontinuous"], tight.summary()
        assert tight.reason(1).startswith(f"{right}: ") and "hide" in tight.reason(1)
        loose = robot.solve_path(spelled, q, max_joint_step=10.0)
        assert loose.success.all(), loose.summary()
        for i in range(2):
            err = pin.log6(ways[left][i].actInv(union.fk(loose.q[i], left))).vector
            assert np.abs(err).max() <= 1e-6
            err = pin.log6(ways[right][i].actInv(union.fk(loose.q[i], right))).vector
            assert (np.abs(err) <= bound).all()


@pytest.mark.parametrize(
    "loosened",
    [
        {"position_only": True},
        {"weights": [1, 1, 1, 0.5, 0.5, 0.5]},
        {"bounds": [0, 0, 0, 0, 0, np.inf]},
    ],
)
def test_a_path_of_independent_chains_judges_its_steps_halfway_under_a_loosened_task(
    cell, loosened
):
    """The left IRB120's shoulder turned 3 rad between two waypoints (max_joint_step 3.1):
    halfway, the tool's position is out of reach (1000 restarts end 6 cm off). A robot's
    path judges its rows' steps tip by tip (``arms_steps.hidden_steps``: the rows solved
    again after a failed row, or a collision between the chains) and skipped every step
    under ``position_only``, ``weights`` or ``bounds``; it judges them under the loosened
    task now, as the chain's own path does."""
    left = cell.tips[0]
    cols = cell._columns[left]
    q = cell.middle.copy()
    q[cols] = [-2.713, 0.168, 1.018, 1.764, -2.083, 4.99]
    q2 = q.copy()
    q2[cols[0]] += 3.0
    ways = {tip: [cell.fk(q, tip), cell.fk(q2, tip)] for tip in cell.tips}
    out = cell.solve_path(ways, q, max_joint_step=10.0, **loosened)  # no jump can hide
    assert out.success.all(), out.summary()
    for i, tip in itertools.product(range(2), cell.tips):  # on the positions by Pinocchio
        assert np.linalg.norm(cell.fk(out.q[i], tip).translation - ways[tip][i].translation) < 1e-6
    hidden_steps(cell, out, read_rows(cell, ways), np.full(cell.dof, 3.1), _read(loosened))
    assert out.status.tolist() == ["converged", "discontinuous"]
    assert out.reason(1).startswith(f"{left}: ") and "hide" in out.reason(1)
    alone = cell.chain(left).solve_path(ways[left], q[cols], max_joint_step=3.1, **loosened)
    assert alone.status.tolist() == ["converged", "discontinuous"]
    middle = 0.5 * (ways[left][0].translation + ways[left][1].translation)
    there = cell.chain(left).solve(middle)  # the position halfway: out of reach
    assert not there.success and there.position_error > 0.01


def test_a_path_over_a_shared_torso_judges_the_step_after_a_jump():
    """TALOS, both hands: Q_A to Q_B hides a jump within max_joint_step 1.0; with a random
    configuration between them (a jump, row 1), the row after it reaches the same answer
    and must not be called converged: each row after a jump is judged too (a row whose
    step was left unjudged was a false success)."""
    robot = talos()
    q_a = np.array([-0.748, 0.175, 0.121, 0.789, 1.543, -2.103, -0.322, 0.946, -0.421, 0.11,
                    -1.892, -1.408, -0.186, 0.289, 0.965, 0.048])  # fmt: skip
    q_b = np.array([-1.309, -0.262, 0.524, 0.937, 0.812, -2.223, -0.36, 0.334, 0.001, -0.524,
                    -2.088, -1.378, -0.311, 0.445, 1.393, 0.698])  # fmt: skip
    q_j = robot.random_q(np.random.default_rng(4))
    for qs in ([q_a, q_b], [q_a, q_j, q_b]):
        ways = {tip: [robot.fk(q, tip) for q in qs] for tip in robot.tips}
        b = robot.solve_path(ways, q_a, max_joint_step=1.0)
        assert b.status.tolist()[-1] == "discontinuous", (len(qs), b.summary())


def _with(q: np.ndarray, cols: np.ndarray, part: np.ndarray) -> np.ndarray:
    """``q`` with its columns ``cols`` replaced by ``part``."""
    out = np.array(q, dtype=float)
    out[cols] = part
    return out


def test_a_loop_over_a_shared_torso_anchored_by_a_posture_returns_to_its_start():
    """TALOS, both hands along a circle of 5 cm radius in 40 waypoints back to the start:
    each followed step is the least joint motion onto the pose, which drifts along the
    self-motion (docs/paths.md: 0.044 rad after a lap); a posture preference at q0 brings
    the joints back onto q0, every answer on its poses by FK and every step within the
    bound."""
    robot = talos()
    union = robot._union
    q0 = robot.middle
    n = 40
    circle = [
        np.array([0.0, np.sin(2 * np.pi * k / n), 1 - np.cos(2 * np.pi * k / n)])
        for k in range(n + 1)
    ]
    ways = {
        tip: [
            pin.SE3(union.fk(q0, tip).rotation, union.fk(q0, tip).translation + 0.05 * c)
            for c in circle
        ]
        for tip in robot.tips
    }
    b = robot.solve_path(ways, q0, max_joint_step=0.1, prefer=armik.Posture(q0))
    assert b.success.all(), b.summary()
    assert np.abs(np.diff(np.vstack([q0, b.q]), axis=0)).max() <= 0.1 + 1e-12
    for i in range(n + 1):
        for tip in robot.tips:
            assert np.abs(pin.log6(ways[tip][i].actInv(union.fk(b.q[i], tip))).vector).max() <= 1e-6
    assert np.abs(b.q[-1] - q0).max() <= 1e-6


def test_rows_of_flat_poses_beside_position_only_are_refused_as_solve_refuses_them():
    # read as bare poses, the rows dropped the Pose tasks' rotation unseen under
    # position_only=True: every row a success with each tip's rotation 1.1 rad off
    from armik.errors import OptionError
    from tests.test_arms import dual_irb120

    left, right = "l_tool0", "r_tool0"
    cell = armik.load(dual_irb120(), tips=[left, right])
    q = cell.random_q(np.random.default_rng(8))
    turn = pin.SE3(pin.utils.rpyToMatrix(1.0, 0.5, 0.0), np.zeros(3))
    rows = [[armik.Pose(cell.fk(q, t) * turn, frame=t) for t in (left, right)]] * 2
    for call in (
        lambda: cell.solve(rows[0], q0=q, position_only=True),
        lambda: cell.solve_batch(rows, q0=q, position_only=True),
        lambda: cell.solve_path(rows, q, position_only=True),
    ):
        with pytest.raises(OptionError, match="position_only=True drops the rotation"):
            call()
