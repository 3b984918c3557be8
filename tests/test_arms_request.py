"""What a call on several tips reads of its options is read once, at the facade, into an
``ArmsRequest`` (``armik.arms_request``): ``Arms.solve``, each row of a batch or a path,
``solve_all``'s search and a path's judge halfway solve a row from it
(``Arms._solve_row``), never through ``Arms.solve`` again, with the answers ``Arms.solve``
gives that row; and options given as one-shot iterators are read in full everywhere."""

from __future__ import annotations

import pickle

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.arms_request import read_request
from armik.constraints.base import Check, Constraint

from .test_arms import dual_irb120
from .test_arms_collision import dual


class Never(Constraint):
    """Holds no answer: a solve given it fails, its reason the check's."""

    def check(self, arm, Q):
        return Check(np.zeros(len(Q), dtype=bool), armik.Status.JOINT_LIMITS, lambda i: "never")


def _panda() -> armik.Arms:
    return armik.load("panda", tips=["panda_hand", "panda_link5"])  # joints 1-5 shared


def _cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])  # no joint shared


def _rows(robot: armik.Arms, n: int, seed: int) -> list[dict[str, pin.SE3]]:
    """``n`` rows of one reachable pose per tip."""
    Q = robot.random_q(np.random.default_rng(seed), n=n)
    return [{tip: robot.fk(q, tip) for tip in robot.tips} for q in Q]


def _related(robot: armik.Arms, rows: list[dict]) -> list[list]:
    """The rows as flat task lists: the first tip's pose, the second's relative to it."""
    a, b = robot.tips
    return [[armik.Pose(r[a], frame=a), armik.Relative(b, a, r[a].actInv(r[b]))] for r in rows]


def _refused(monkeypatch) -> None:
    """``Arms.solve`` raises from here on: a row that goes back through it fails."""

    def solve(self, *args, **kwargs):
        raise AssertionError("a row went back through Arms.solve")

    monkeypatch.setattr(armik.Arms, "solve", solve)


CASES = [  # (robot, rows as a batch takes them, options): each solved row by row
    ("panda", "poses", {}),
    ("panda", "poses", {"hold": {"panda_joint1": 0.2}, "iteration_budget": 2000}),
    ("cell", "related", {}),
    ("cell", "poses", {"prefer": lambda q: float(np.sum(q**2))}),  # a cost: row by row
]


@pytest.mark.parametrize(
    "robot, spelled, options", CASES, ids=["poses", "held", "relative", "cost"]
)
def test_a_batch_solves_each_row_from_the_request_as_solve_does(
    monkeypatch, robot, spelled, options
):
    """Each row of a batch solved row by row (a shared torso, a relative task, a cost of
    the whole configuration) is ``Arms.solve``'s answer for that row and seed, bit for bit,
    and none goes back through ``Arms.solve`` (there, in this process and on threads)."""
    arms = _panda() if robot == "panda" else _cell()
    rows = _rows(arms, 3, 4)
    seeds = arms.random_q(np.random.default_rng(5), n=len(rows))
    given = _related(arms, rows) if spelled == "related" else rows
    expected = [arms.solve(row, q0=q, **options) for row, q in zip(given, seeds)]
    batch = given if spelled == "related" else {t: [r[t] for r in rows] for t in arms.tips}
    _refused(monkeypatch)
    for workers in (1, 2):
        b = arms.solve_batch(batch, q0=seeds, workers=workers, chunk_size=1, **options)
        assert b.success.tolist() == [r.success for r in expected]
        np.testing.assert_array_equal(b.q, [r.q for r in expected])
        assert b.status.tolist() == [r.status.value for r in expected]


@pytest.mark.parametrize("robot, spelled", [("panda", "poses"), ("cell", "related")])
def test_a_path_solves_each_waypoint_from_the_request_as_solve_does(monkeypatch, robot, spelled):
    """Each waypoint of a path solved row by row is ``Arms.solve``'s answer for it from
    the previous answer, bit for bit; no row, and no solve halfway judging a step, goes
    back through ``Arms.solve``."""
    arms = _panda() if robot == "panda" else _cell()
    q = arms.random_q(np.random.default_rng(6))
    along = np.random.default_rng(7).uniform(-1.0, 1.0, arms.dof)  # a straight joint motion
    rows = [{tip: arms.fk(q + 0.03 * k * along, tip) for tip in arms.tips} for k in range(4)]
    given = _related(arms, rows) if spelled == "related" else rows
    expected, seed = [], q
    for row in given:
        r = arms.solve(row, q0=seed)
        expected.append(r)
        seed = r.q if r.success else seed
    waypoints = given if spelled == "related" else {t: [r[t] for r in rows] for t in arms.tips}
    _refused(monkeypatch)
    path = arms.solve_path(waypoints, q, max_joint_step=1.0)
    assert path.success.all(), path.summary()
    np.testing.assert_array_equal(path.q, [r.q for r in expected])


def test_rows_solved_again_and_solve_all_do_not_go_back_through_solve(monkeypatch):
    """Two UR5s, their tools close: a row whose chains' answers collide is solved again as
    ``Arms.solve`` solves it (the other combinations of the chains' answers), exactly its
    answer, without going back through it; ``solve_all``'s search likewise."""
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    rng = np.random.default_rng(1)
    rows = []
    for _ in range(12):  # both tools 8-30 cm apart between the arms, one orientation
        R, c = pin.exp3(rng.normal(size=3)), np.array([rng.uniform(0.2, 0.6), 0.0, 0.35])
        gap = np.array([0.0, rng.uniform(0.04, 0.15), 0.0])
        rows.append({"l_tool0": pin.SE3(R, c + gap), "r_tool0": pin.SE3(R, c - gap)})
    expected = [robot.solve(row, self_collision=True) for row in rows]
    clashed = [i for i, r in enumerate(expected) if r.status is armik.Status.COLLISION]
    assert clashed  # no combination of the chains' answers keeps clear there
    every = robot.solve_all(rows[clashed[0]], self_collision=True)
    _refused(monkeypatch)
    b = robot.solve_batch({t: [r[t] for r in rows] for t in robot.tips}, self_collision=True)
    assert b.success.tolist() == [r.success for r in expected]
    for i in clashed:  # solved again: the robot's answer, exactly
        assert b.status[i] == "collision" and b.reason(i) == expected[i].reason
        np.testing.assert_array_equal(b.q[i], expected[i].q)
    again = robot.solve_all(rows[clashed[0]], self_collision=True)
    np.testing.assert_array_equal([r.q for r in again], [r.q for r in every])


def test_the_request_is_read_once_and_travels():
    """The request of a call: its chains' options, the solver and preference, the
    descent's settings where the chains share joints; picklable (a batch's chunks carry
    it to other processes), the request of a call without options kept with the robot."""
    arms = _panda()
    request = read_request(arms, {"hold": {"panda_joint1": 0.2}, "solver": "dls"})
    assert request.solver == "dls" and request.prefer is None
    assert request.each == {tip: {"hold": {"panda_joint1": 0.2}} for tip in arms.tips}
    assert request.together is not None and request.together[0].hold == (("panda_joint1", 0.2),)
    again = pickle.loads(pickle.dumps(request))
    assert again.each == request.each and again.together[0] == request.together[0]
    assert read_request(arms, {}) is read_request(arms, {})
    with pytest.raises(armik.OptionError, match="unknown option 'max_iteration'"):
        read_request(arms, {"max_iteration": 3})


@pytest.mark.parametrize("robot", ["panda", "cell"])
def test_a_constraint_given_as_an_iterator_holds_on_every_route(robot):
    """A tip's constraints given as a one-shot iterator (``iter([c])``, a generator) were
    read by the first reader only: the chains' solves then held none, and an answer that
    violates the constraint was a success. Every route takes them in full now."""
    arms = _panda() if robot == "panda" else _cell()
    q = arms.random_q(np.random.default_rng(7))
    T = {tip: arms.fk(q, tip) for tip in arms.tips}
    tip = arms.tips[0]
    rows = {t: [X] for t, X in T.items()}
    calls = {
        "solve": lambda own: [arms.solve(T, constraints=own, iteration_budget=300)],
        "solve_all": lambda own: list(arms.solve_all(T, constraints=own, iteration_budget=300)),
        "solve_batch": lambda own: list(
            arms.solve_batch(rows, constraints=own, iteration_budget=300)
        ),
        "solve_path": lambda own: list(
            arms.solve_path(rows, q, constraints=own, iteration_budget=300)
        ),
    }
    for name, call in calls.items():
        for own in ({tip: [Never()]}, {tip: iter([Never()])}, {tip: (c for c in [Never()])}):
            results = call(own)
            assert results and not any(r.success for r in results), (name, own)


def test_a_held_joint_given_as_an_iterator_of_constraints_is_held():
    """``constraints=iter([armik.Hold(joint, value)])`` on several tips: the flat list was
    read by the check that refuses a user's own constraint there, and the joint went
    free; it is held now, on every route."""
    arms = _cell()
    q = arms.random_q(np.random.default_rng(8))
    T = {tip: arms.fk(q, tip) for tip in arms.tips}
    joint = arms.chain(arms.tips[0]).joint_names[0]
    j = arms.joint_names.index(joint)
    value = float(q[j]) + 0.3
    for given in ([armik.Hold(joint, value)], iter([armik.Hold(joint, value)])):
        r = arms.solve({arms.tips[1]: T[arms.tips[1]]}, constraints=given)
        assert r.success and r.q[j] == value, r.reason
    other = arms.tips[1]
    b = arms.solve_batch({other: [T[other]]}, constraints=iter([armik.Hold(joint, value)]))
    assert b.success[0] and b.q[0, j] == value


def test_a_servo_takes_obstacles_given_as_an_iterator_on_every_chain():
    """Two UR5s' servo, ``obstacles=iter([sphere])``: each chain's servo read the options
    in turn, and the second found the iterator spent (no obstacle); both keep it now."""
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    sphere = armik.Sphere(0.05, (0.0, 0.0, 3.0))
    for given in ([sphere], iter([sphere])):
        servo = robot.servo(robot.middle, obstacles=given)
        for tip in robot.tips:
            pairs = servo.servo(tip)._collisions.check.pair_names
            assert any("Sphere" in b for _, b in pairs), (tip, given)


class _Below(Constraint):
    """Joint 1 of its chain below 1 rad (a constraint of one tip)."""

    def check(self, arm, Q):
        return Check(np.asarray(Q)[:, 0] < 1.0, armik.Status.JOINT_LIMITS, lambda i: "joint 1")


def test_a_tips_constraint_over_shared_joints_travels_without_a_model():
    """A request holding a tip's own constraint over shared joints (``OnChain``) pickles
    without the chain's model: every chunk of a Dask batch carries the request, and each
    carried the chain's recipe (the whole URDF of an arm read from its text, 113 kB for
    TALOS) and rebuilt the chain on the worker. The constraint still holds."""
    with open(armik.load("panda").source) as f:  # read from its text: the recipe holds it
        arms = armik.load(f.read(), tips=["panda_hand", "panda_link5"])
    request = read_request(arms, {"constraints": {"panda_hand": [_Below()]}})
    blob = pickle.dumps(request)
    assert len(blob) < 4000, len(blob)
    assert b"ArmModel" not in blob and b"Recipe" not in blob
    rows = _rows(arms, 6, 3)
    by_tip = {tip: [row[tip] for row in rows] for tip in arms.tips}
    got = arms.solve_batch(by_tip, constraints={"panda_hand": [_Below()]}, iteration_budget=2000)
    assert got.success.any()
    assert (np.asarray(got.q)[got.success, 0] < 1.0).all()


def test_a_pose_read_at_the_facade_is_not_checked_again_by_a_chains_read(monkeypatch):
    """Each tip's pose is parsed (and checked) once at the facade; a chain's solve with
    options reads the request from it without checking its rotation again, as a
    ``Target`` built by hand is checked (3.6 such checks a solve, 75 Python calls)."""
    import armik.solve.read as read_module

    arms = _panda()
    rows = _rows(arms, 2, 5)

    def refused(R):
        raise AssertionError("a parsed pose checked again")

    monkeypatch.setattr(read_module, "is_rotation", refused)
    for row in rows:
        r = arms.solve(row, iteration_budget=2000)
        assert r.position_error is not None


@pytest.mark.parametrize("spelled", ["poses", "related", "cost"])
def test_solve_all_solves_each_chain_without_its_facade(monkeypatch, spelled):
    """``Arms.solve_all`` lists each chain's answers from the request (its options read
    once at the facade), not through each chain's ``Arm.solve_all`` again: the same
    answers, in the same order, as before it was taken away."""
    robot = _cell()
    row = _rows(robot, 1, 7)[0]
    target: object = _related(robot, [row])[0] if spelled == "related" else row
    options = {"prefer": lambda q: float(np.sum(q**2))} if spelled == "cost" else {}
    first = robot.solve_all(target, **options)
    assert len(first) > 1 and first[0].success

    def refused(self, *args, **kwargs):
        raise AssertionError("a chain solved through Arm.solve_all")

    monkeypatch.setattr(armik.Arm, "solve_all", refused)
    again = robot.solve_all(target, **options)
    np.testing.assert_array_equal([r.q for r in again], [r.q for r in first])
