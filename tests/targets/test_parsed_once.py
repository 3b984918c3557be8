"""A user's target is parsed once per solve, on every route: the stages below the door
take the parsed ``Target`` (``armik.targets.pose.parsed``), never the raw value again.

The parsers are counted by the targets each call reads (``parse_target`` one,
``parse_by_tip`` one per tip, ``parse_targets`` one per row; a ``TargetBatch`` read
already, none), wherever armik calls them: a route of several tips reads each of the
user's targets exactly once; a task's pose was read when the task was built."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
import armik.arms  # noqa: F401  (imported before the fixture patches its parsers)
import armik.targets.batch as batch_module
import armik.targets.pose as pose_module
from tests.conftest import arm as bundled
from tests.test_arms import dual_irb120


@pytest.fixture
def reads(monkeypatch):
    """How many targets the parsers read from every armik module that calls them, as
    ``reads()`` (the count since the last call, which starts it again)."""
    seen: list[int] = []
    originals = {
        "parse_target": (pose_module.parse_target, lambda value: 1),
        "parse_by_tip": (pose_module.parse_by_tip, len),
        "parse_targets": (
            batch_module.parse_targets,
            lambda value: 0 if isinstance(value, batch_module.TargetBatch) else len(value),
        ),
    }

    def counting(original, count):
        def parser(value, *args, **kwargs):
            seen.append(count(value))
            return original(value, *args, **kwargs)

        return parser

    wrapped = {name: counting(*given) for name, given in originals.items()}
    for module in list(sys.modules.values()):
        name = getattr(module, "__name__", "") or ""
        if not name.startswith("armik"):
            continue
        for parser, (original, _) in originals.items():
            # the batch parser's own reading of each row is its rows' count
            inside = name == "armik.targets.batch" and parser == "parse_target"
            if getattr(module, parser, None) is original and not inside:
                monkeypatch.setattr(module, parser, wrapped[parser])

    def count() -> int:
        found = sum(seen)
        seen.clear()
        return found

    return count


def _pose(name: str):
    a = bundled(name)
    return a, a.fk(a.middle + 0.1)


@pytest.mark.parametrize(
    "name, options",
    [
        ("ur5", {}),
        ("ur5", {"bounds": (0.01,) * 3 + (0.1,) * 3}),
        ("panda", {"obstacles": [armik.Sphere(0.05, (2.0, 2.0, 2.0))]}),
        ("panda", {"prefer": "manipulability", "iteration_budget": 300}),
        ("panda", {"hold": {"panda_joint7": 0.3}}),
        ("panda", {"hold": {"panda_joint7": 0.3, "panda_joint1": 0.1}}),  # the task solver
        ("panda", {"weights": (1, 1, 1, 1, 1, 0)}),
    ],
    ids=str,
)
def test_a_solve_parses_its_target_once(reads, name, options):
    a, T = _pose(name)
    reads()
    for target in (T, (T.translation, pin.Quaternion(T.rotation).coeffs())):
        a.solve(target, **options)
        assert reads() <= 1


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_solve_all_parses_once(reads, name):
    a, T = _pose(name)
    reads()
    a.solve_all(T)
    assert reads() <= 1


@pytest.mark.parametrize("name", ["ur5", "panda"])  # the Panda's global plan: swept rungs
def test_a_path_parses_each_waypoint_once_at_most(reads, name):
    a, T = _pose(name)
    line = [pin.SE3(T.rotation, T.translation + [0, 0.01 * k, 0]) for k in range(3)]
    reads()
    for plan in ("follow", "global"):
        a.solve_path(line, a.middle + 0.1, plan=plan)
        assert reads() <= len(line), plan


def test_a_batch_parses_each_target_once_at_most(reads):
    a = bundled("panda")
    T = a.fk_batch(a.random_q(0, n=4))
    reads()
    for given in (T, list(T)):
        a.solve_batch(given, workers=1, progress=False)
        assert reads() <= len(T)


def test_a_pose_read_already_is_not_read_again(reads):
    """A ``Pose`` task read its pose when it was built, and a ``Target`` is read: a solve
    reads neither again, where the compiled solver finds no answer (its verdict read the
    pose again from the 4x4 it was handed) nor where the task solver holds joints (its
    start read the task's pose again). A pose as given is read once."""
    ur5 = bundled("ur5")
    T = ur5.fk(ur5.middle + 0.1)
    inside = pin.SE3(T.rotation, 0.05 * T.translation)  # within reach, no answer
    task, target = armik.Pose(inside), armik.parse_target(inside)
    held = {ur5.joint_names[0]: 0.1, ur5.joint_names[1]: 0.2}  # two: the task solver's
    reads()
    for given in (task, [task], target):
        assert not ur5.solve(given).success
        assert reads() == 0
        assert not ur5.solve(given, hold=held, iteration_budget=300).success
        assert reads() == 0
    ur5.solve(inside)
    assert reads() == 1


def _talos() -> armik.Arms:
    """TALOS's two hands, whose chains share the torso's two joints."""
    robots = Path(armik.load("panda").source).parents[2]
    urdf = robots / "talos_data" / "robots" / "talos_reduced.urdf"
    return armik.load(urdf, tips=["gripper_left_base_link", "gripper_right_base_link"])


@pytest.mark.parametrize("robot", ["panda, two tips", "talos, shared torso"])
def test_several_tips_parse_their_targets_once(reads, robot):
    """The request's target, one pose per tip, is parsed in one call (the chains apart, and
    over the shared torso: one task per tip on the union), in each form a tip's pose takes."""
    if robot.startswith("panda"):
        arms = armik.load("panda", tips=["panda_hand", "panda_link5"])
    else:
        arms = _talos()
    q = arms.middle + 0.1
    placed = {tip: arms.fk(q, tip) for tip in arms.tips}
    spelled = {t: (T.translation, pin.Quaternion(T.rotation).coeffs()) for t, T in placed.items()}
    reads()
    for targets in (placed, spelled):
        r = arms.solve(targets, iteration_budget=3000)
        assert r.success, r.reason
        assert reads() == len(arms.tips)


ROBOTS = ["shared joints", "independent"]  # the Panda's hand and link 5; two IRB 120s


def _robot(kind: str) -> tuple[armik.Arms, np.ndarray]:
    """A robot of two tips and a configuration its targets are placed at."""
    if kind == "shared joints":
        robot = armik.load("panda", tips=["panda_hand", "panda_link5"])
        return robot, robot.middle + 0.1
    robot = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    return robot, robot.random_q(np.random.default_rng(3))


@pytest.mark.parametrize("kind", ROBOTS)
def test_every_solve_of_several_tips_reads_each_target_once(reads, kind):
    """One pose per tip: read once on every route of ``solve`` and ``solve_all`` (held
    joints, which a 5-joint chain holds by the task solver, a pose spelled as a position
    and a quaternion); tasks, a flat list of them and a relative task: their poses were
    read when they were built, none again. Before, a held joint read the chain's pose
    again, ``solve_all`` read the poses twice, a flat list read its poses again."""
    robot, q = _robot(kind)
    a, b = robot.tips
    T = {tip: robot.fk(q, tip) for tip in robot.tips}
    held = {robot.chain(b).joint_names[0]: float(q[robot.joint_names.index(
        robot.chain(b).joint_names[0])])}  # fmt: skip
    spelled = {t: (X.translation, pin.Quaternion(X.rotation).coeffs()) for t, X in T.items()}
    relative = armik.Relative(b, a, T[a].actInv(T[b]))
    pose_a, pose_b = armik.Pose(T[a], frame=a), armik.Pose(T[b], frame=b)  # read here
    reads()
    for call, read in (
        (lambda: robot.solve(T), 2),
        (lambda: robot.solve(T, q0=q), 2),
        (lambda: robot.solve(spelled, hold=held, iteration_budget=3000), 2),
        (lambda: robot.solve(T, prefer="nearest", q0=q), 2),
        (lambda: robot.solve_all(T), 2),
        (lambda: robot.solve_all(T, hold=held), 2),
        (lambda: robot.solve({a: pose_a, b: T[b].translation}), 1),
        (lambda: robot.solve([pose_a, pose_b]), 0),
        (lambda: robot.solve([pose_a, relative]), 0),
        (lambda: robot.solve([pose_a, relative], hold=held), 0),
        (lambda: robot.solve_all([pose_a, relative]), 0),
    ):
        call()
        assert reads() == read


@pytest.mark.parametrize("kind", ROBOTS)
def test_every_batch_and_path_of_several_tips_reads_each_target_once(reads, kind):
    """N rows per tip: each of the 2 N targets read once, in each tip's rows or each row,
    whether the rows are solved by each chain's own batch and path or row by row (held
    joints, a cost of the whole configuration); rows of tasks, a flat list each or with a
    relative task: none. Before, a path read every waypoint again to judge its steps, and
    rows solved again read theirs again."""
    robot, q = _robot(kind)
    a, b = robot.tips
    n = 3
    shifted = [pin.SE3(np.eye(3), np.array([0.0, 0.01 * k, 0.0])) for k in range(n)]
    way = {tip: [s * robot.fk(q, tip) for s in shifted] for tip in robot.tips}
    array = {tip: np.array([X.homogeneous for X in rows]) for tip, rows in way.items()}
    held = {robot.chain(b).joint_names[0]: None}
    cost = {"prefer": lambda x: float(np.sum(x**2))}
    reads()
    for call in (
        lambda: robot.solve_batch(way, workers=1, progress=False),
        lambda: robot.solve_batch(array, q0=q, workers=1, progress=False),
        lambda: robot.solve_batch(way, q0=q, hold=held, workers=1, progress=False),
        lambda: robot.solve_batch(way, q0=q, workers=1, progress=False, **cost),
        lambda: robot.solve_path(way, q),
        lambda: robot.solve_path(array, q, max_joint_step=0.5),
        lambda: robot.solve_path(way, q, hold=held),
    ):
        call()
        assert reads() == 2 * n
    flat = [[armik.Pose(way[a][k], frame=a), armik.Pose(way[b][k], frame=b)] for k in range(n)]
    related = [
        [armik.Pose(way[a][k], frame=a), armik.Relative(b, a, way[a][k].actInv(way[b][k]))]
        for k in range(n)
    ]
    reads()  # the tasks read their poses when built
    for rows in (flat, related):
        robot.solve_batch(rows, workers=1, progress=False)
        robot.solve_path(rows, q)
        assert reads() == 0


def test_a_tips_bad_target_is_named_by_its_tip():
    arms = armik.load("panda", tips=["panda_hand", "panda_link5"])
    with pytest.raises(armik.TargetError, match="tip 'panda_link5'.*NaN"):
        arms.solve({"panda_hand": arms.fk(arms.middle, "panda_hand"), "panda_link5": [np.nan] * 3})
