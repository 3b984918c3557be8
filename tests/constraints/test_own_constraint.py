"""A constraint of the user's own, written by CONTRIBUTING's recipe (a ``Constraint`` with
a ``check`` and nothing more), holds on every route: no answer that violates it is a
success, and its status and reason are the check's."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.constraints.base import Check, Constraint
from tests.conftest import arm as bundled

ELBOW = -1.0  # the Panda's joint 4 must stay above this (rad)


class ElbowUp(Constraint):
    """Joint 4 above ``ELBOW``: what the Panda's starting configurations below violate
    (written as the issue that found the gap wrote it: ``said`` spells no option)."""

    def said(self):
        return {}

    def check(self, arm, Q):
        return Check(Q[:, 3] > ELBOW, armik.Status.JOINT_LIMITS, lambda i: "elbow below -1")


class ShoulderSide(Constraint):
    """Joint 2 of a UR5 below zero: half of its closed form's branches break it (``check``
    alone: the recipe's least)."""

    def check(self, arm, Q):
        return Check(Q[:, 1] < 0.0, armik.Status.JOINT_LIMITS, lambda i: "shoulder above 0")


Q_BENT = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])  # joint 4 at -2: violates ElbowUp


def _targets(n: int):
    """Panda poses reached with joint 4 well below ``ELBOW``, and those configurations."""
    rng = np.random.default_rng(7)
    qs = [Q_BENT + rng.uniform(-0.1, 0.1, 7) for _ in range(n)]
    panda = bundled("panda")
    return [panda.fk(q) for q in qs], qs


def _honest(results) -> None:
    """No success violates the constraint; a failure for it says so."""
    checked = 0
    for r in results:
        if r.success:
            assert r.q[3] > ELBOW, (r.q, r.reason)
        elif r.q[3] <= ELBOW and r.reason == "elbow below -1":
            assert r.status is armik.Status.JOINT_LIMITS
            checked += 1
    return checked


@pytest.mark.parametrize("constraint, name", [(ElbowUp(), "panda"), (ShoulderSide(), "ur5")])
def test_the_check_over_rows_is_each_answers_own(constraint, name):
    """The recipe's first test: the check of many rows at once says of each row what it
    says of that row alone, its reason too (a check that read the rows as one, or another
    row's values, would differ)."""
    arm = bundled(name)
    Q = arm.random_q(np.random.default_rng(3), n=40)
    kin = arm.kinematics
    together = constraint.check(kin, Q)
    ok = np.asarray(together.ok, dtype=bool)
    assert ok.any() and not ok.all()
    for i in range(len(Q)):
        alone = constraint.check(kin, Q[i : i + 1])
        assert bool(np.asarray(alone.ok)[0]) == ok[i]
        if not ok[i]:
            assert together.why(i) == alone.why(0)
            assert together.status is alone.status


@pytest.mark.parametrize(
    "how",
    [
        {},
        {"solver": "dls"},
        {"solver": "qp"},
        {"solver": "swept"},
        {"prefer": "manipulability"},
        {"hold": {"panda_joint7": 0.6}},
        {"obstacles": [armik.Sphere(0.1, (2.0, 2.0, 2.0))]},
        {"weights": (1, 1, 1, 1, 1, 0)},
        {"bounds": (1e-3, 1e-3, 1e-3, 0.01, 0.01, 0.01)},
    ],
    ids=str,
)
def test_solve_never_calls_a_violating_answer_a_success(how):
    panda = bundled("panda")
    targets, qs = _targets(4)
    results = [
        panda.solve(T, q0=q, constraints=[ElbowUp()], iteration_budget=400, **how)
        for T, q in zip(targets, qs)
    ]
    _honest(results)
    # without the constraint, these starts give the bent answers it refuses
    plain = panda.solve(targets[0], q0=qs[0], iteration_budget=400, **how)
    assert plain.success and plain.q[3] <= ELBOW


def test_solve_all_judges_every_branch():
    panda = bundled("panda")
    targets, qs = _targets(3)
    for T, q in zip(targets, qs):
        found = panda.solve_all(T, q0=q, constraints=[ElbowUp()])
        _honest(found)
        assert any(r.reason == "elbow below -1" for r in found)  # some branch broke it


def test_a_closed_form_returns_the_nearest_branch_that_holds():
    """The check is part of the search: the nearest branch that breaks it gives way to
    the nearest that holds."""
    ur5 = bundled("ur5")
    q = np.array([0.4, 0.6, -1.2, 0.3, 1.1, -0.5])  # joint 2 above 0: the nearest breaks it
    T = ur5.fk(q)
    plain = ur5.solve(T, q0=q)
    assert plain.success and plain.q[1] > 0.0
    r = ur5.solve(T, q0=q, constraints=[ShoulderSide()])
    assert r.success and r.q[1] < 0.0
    every = ur5.solve_all(T, q0=q)
    holding = [a for a in every if a.success and a.q[1] < 0.0]
    nearest = min(holding, key=lambda a: np.linalg.norm(a.q - q))
    np.testing.assert_allclose(r.q, nearest.q, atol=1e-12)
    # a prepared plan for the plain options is not taken for the constrained ones
    again = ur5.solve(T, q0=q, constraints=(ShoulderSide(),))
    assert again.success and again.q[1] < 0.0


@pytest.mark.parametrize("workers", [1, 2])
def test_solve_batch_on_one_and_two_workers(workers):
    panda = bundled("panda")
    targets, qs = _targets(6)
    res = panda.solve_batch(
        np.array([T.homogeneous for T in targets]),
        q0=np.array(qs),
        constraints=[ElbowUp()],
        workers=workers,
        iteration_budget=400,
    )
    assert _honest(res[i] for i in range(len(res))) > 0


class BaseAhead(Constraint):
    """Joint 1 of a UR5 above zero: a branch breaking it passes at its turn by 2 pi."""

    def check(self, arm, Q):
        return Check(Q[:, 0] > 0.0, armik.Status.JOINT_LIMITS, lambda i: "base behind 0")


@pytest.mark.parametrize("workers", [1, 2])
def test_a_closed_form_batch_row_is_the_solve_of_that_row(workers):
    """A row's nearest branch that passes the check only turned by 2 pi gives way to the
    nearest branch that passes as it is, as in ``solve``."""
    ur5 = bundled("ur5")
    targets = [ur5.fk(q) for q in ur5.random_q(5, n=4)]
    own = [BaseAhead()]
    res = ur5.solve_batch(
        np.array([T.homogeneous for T in targets]), constraints=own, workers=workers
    )
    turned = 0
    for i, T in enumerate(targets):
        r = ur5.solve(T, constraints=own)
        assert res.success[i] == r.success
        np.testing.assert_allclose(res.q[i], r.q, atol=1e-12)
        plain = ur5.solve(T)
        turned += plain.q[0] <= 0.0 and plain.q[0] + 2 * np.pi < ur5.upper[0]
    assert turned > 0  # some row's nearest branch passes only turned


class BaseAhead60(Constraint):
    """Joint 1 within 60 degrees of 0 at any turn (``check`` alone): no turn by 2 pi of
    an answer that breaks it passes."""

    def check(self, arm, Q):
        return Check(np.cos(Q[:, 0]) > 0.5, armik.Status.JOINT_LIMITS, lambda i: "base aside")


def test_a_numeric_answer_the_check_refuses_restarts_within_the_budget():
    """A numeric solve whose first answer breaks the check runs again from random
    configurations, as the collision retry does, where it gave up at the first; a batch's
    row is that solve; ``max_restarts=0`` keeps the first run's refusal."""
    ur5 = bundled("ur5")
    own = [BaseAhead60()]
    BUDGET = {"iteration_budget": 5000}  # deterministic: counted, not timed
    Q = ur5.random_q(3, n=6)
    Q[:, 0] = np.linspace(-0.9, 0.9, len(Q))  # each position has an answer that holds it
    positions = [ur5.fk(q).translation for q in Q]
    refused = 0
    for p in positions:
        plain = ur5.solve(p)
        assert plain.success and plain.solver == "dls"
        if np.cos(plain.q[0]) > 0.5:
            continue
        refused += 1
        r = ur5.solve(p, constraints=own, **BUDGET)
        assert r.success and np.cos(r.q[0]) > 0.5 and r.restarts > 0, r.reason
        assert np.linalg.norm(ur5.fk(r.q).translation - p) < 1e-6
        once = ur5.solve(p, constraints=own, max_restarts=0, **BUDGET)
        assert not once.success and once.reason == "base aside" and once.restarts == 0
    assert refused > 0
    res = ur5.solve_batch(np.array(positions), constraints=own, workers=1, **BUDGET)
    for i, p in enumerate(positions):
        r = ur5.solve(p, constraints=own, **BUDGET)
        assert res.success[i] == r.success
        np.testing.assert_allclose(res.q[i], r.q, atol=1e-12)


def test_a_closed_form_giving_one_answer_goes_on_to_the_branches_that_hold():
    """``spin_joint``'s one answer (its nearest branch) refused by the check gives way to
    the nearest branch that holds it, as ``solve_all`` lists them, where the solve
    failed."""
    ur5 = bundled("ur5")
    q = ur5.random_q(2)
    q[0] = 0.2
    T = ur5.fk(q)
    start = ur5.middle.copy()
    start[0] = 2.5
    spin = {"bounds": (0, 0, 0, 0, 0, np.inf)}
    plain = ur5.solve(T, q0=start, **spin)
    assert plain.success and plain.solver == "spin_joint" and np.cos(plain.q[0]) <= 0.5
    r = ur5.solve(T, q0=start, constraints=[BaseAhead60()], **spin)
    assert r.success and r.solver == "spin_joint" and np.cos(r.q[0]) > 0.5, r.reason
    holding = [a for a in ur5.solve_all(T, q0=start, constraints=[BaseAhead60()], **spin)]
    nearest = min((a for a in holding if a.success), key=lambda a: np.linalg.norm(a.q - start))
    np.testing.assert_allclose(r.q, nearest.q, atol=1e-9)


@pytest.mark.parametrize("plan", ["follow", "global"])
def test_solve_path(plan):
    ur5 = bundled("ur5")
    q = np.array([0.4, 0.6, -1.2, 0.3, 1.1, -0.5])
    T = ur5.fk(q)
    line = [pin.SE3(T.rotation, T.translation + [0, 0.005 * k, 0]) for k in range(4)]
    path = ur5.solve_path(line, q, constraints=[ShoulderSide()], plan=plan)
    for i in range(len(path)):
        r = path[i]
        assert not r.success or r.q[1] < 0.0, (i, r.q)


def test_a_task_list():
    panda = bundled("panda")
    targets, qs = _targets(2)
    for T, q in zip(targets, qs):
        tasks = [armik.Position(T.translation), armik.Axis((0, 0, 1), T.rotation[:, 2], 0.05)]
        _honest([panda.solve(tasks, q0=q, constraints=[ElbowUp()], iteration_budget=400)])


def test_several_tips_refuse_what_they_cannot_honour():
    robot = armik.load("panda", tips=["panda_hand", "panda_link5"])
    q = robot.middle
    targets = {"panda_hand": robot.fk(q, "panda_hand"), "panda_link5": robot.fk(q, "panda_link5")}
    with pytest.raises(armik.OptionError, match="ElbowUp"):
        robot.solve(targets, constraints=[ElbowUp()])


def test_several_tips_over_shared_joints_take_a_constraint_by_tip():
    # one model of both chains (the task solver): the tip's check reads its chain's joints;
    # where no answer holds it, the failure is the check's own, naming the tip
    robot = armik.load("panda", tips=["panda_hand", "panda_link5"])
    targets, qs = _targets(3)
    refused = 0
    for T, q in zip(targets, qs):
        elbow = robot.fk(q, "panda_link5")  # fixes joints 1 to 4 nearly: joint 4 at -2
        goal = {"panda_hand": T, "panda_link5": elbow}
        own = {"panda_hand": [ElbowUp()]}
        r = robot.solve(goal, q0=q, constraints=own, iteration_budget=3000)  # not timed
        assert not r.success, r.q
        if r.reason.endswith("panda_hand: elbow below -1"):
            assert r.status is armik.Status.JOINT_LIMITS
            refused += 1
    assert refused > 0
    bent = Q_BENT.copy()
    bent[3] = -0.5  # a pose whose elbow holds it: no answer refused that holds it
    r = robot.solve(
        {"panda_hand": robot.fk(bent, "panda_hand")},
        constraints={"panda_hand": ElbowUp()},
        iteration_budget=3000,
    )
    assert r.success and r.q[3] > ELBOW, r.reason
    with pytest.raises(armik.OptionError, match="unknown tip 'hand'"):
        robot.solve({"panda_hand": targets[0]}, constraints={"hand": [ElbowUp()]})
    with pytest.raises(armik.OptionError, match="armik.Hold and armik.Collisions go in"):
        robot.solve(
            {"panda_hand": targets[0]}, constraints={"panda_hand": [armik.Hold("panda_joint1")]}
        )


def test_independent_chains_take_a_constraint_by_tip_on_every_route():
    from tests.test_arms import dual_irb120

    cell = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])

    class Below(Constraint):  # the right arm's joint 2 below a value: some branches break it
        def check(self, arm, Q):
            return Check(Q[:, 1] < LIMIT, armik.Status.JOINT_LIMITS, lambda i: "joint 2 above")

    right = cell.chain("r_tool0")
    LIMIT = 0.2
    own = {"r_tool0": [Below()]}
    rng = np.random.default_rng(3)
    answers = []
    for _ in range(4):
        q = cell.random_q(rng)
        T = {t: cell.fk(q, t) for t in cell.tips}
        answers += [cell.solve(T, constraints=own), *cell.solve_all(T, constraints=own)]
        rows = {t: [T[t], T[t]] for t in cell.tips}
        for workers in (1, 2):  # in this process, and on forked ones
            batch = cell.solve_batch(rows, constraints=own, workers=workers, chunk_size=1)
            answers += [batch[i] for i in range(2)]
        path = cell.solve_path(rows, q, constraints=own)
        answers += [path[i] for i in range(2)]
    successes = [r for r in answers if r.success]
    assert successes and len(successes) < len(answers)
    for r in successes:
        assert cell.split(r.q)["r_tool0"][1] < LIMIT, r.reason
        assert np.allclose(right.fk(cell.split(r.q)["r_tool0"]).translation,
                           cell.fk(r.q, "r_tool0").translation)  # fmt: skip


def test_with_collisions_checked_a_check_refusing_the_answer_restarts_too():
    """With obstacles checked, a numeric answer a user's check refuses (clear of every
    obstacle) restarts as a colliding one does. (The first run's refusal restarted before
    too, in the plain solve the collision search starts from; a restart's refusal is
    ``test_a_restart_refused_by_the_check_goes_on_among_obstacles``.)"""
    ur5 = bundled("ur5")
    far = [armik.Sphere(0.05, (3.0, 3.0, 3.0))]  # never near: only the check refuses
    BUDGET = {"iteration_budget": 5000}
    Q = ur5.random_q(3, n=6)
    Q[:, 0] = np.linspace(-0.9, 0.9, len(Q))
    refused = 0
    for q in Q:
        p = ur5.fk(q).translation
        plain = ur5.solve(p, obstacles=far, **BUDGET)
        assert plain.success
        if np.cos(plain.q[0]) > 0.5:
            continue
        refused += 1
        r = ur5.solve(p, obstacles=far, constraints=[BaseAhead60()], **BUDGET)
        assert r.success and np.cos(r.q[0]) > 0.5 and r.restarts > 0, r.reason
        assert np.linalg.norm(ur5.fk(r.q).translation - p) < 1e-6
        assert r.extra["min_distance"] > 1.0
    assert refused > 0


@pytest.mark.parametrize("k", [2, 3, 8, 12, 13])
def test_a_restart_refused_by_the_check_goes_on_among_obstacles(k):
    """Collisions and a user's check together: a restart's answer clear of the box but
    refused by the check goes on to the next start (one search), where the search ended
    there and the solve failed although answers that hold both exist."""
    ur5 = bundled("ur5")
    box = armik.Box((0.3, 0.3, 0.3), (0.35, 0.25, 0.4))
    q = ur5.random_q(k)
    q[0] = np.random.default_rng(k).uniform(-0.9, 0.9)  # an answer with the base ahead
    p = ur5.fk(q).translation
    r = ur5.solve(p, obstacles=[box], constraints=[BaseAhead60()], iteration_budget=5000, seed=k)
    assert r.success, r.reason
    assert np.cos(r.q[0]) > 0.5 and r.extra["min_distance"] >= 0.0
    assert np.linalg.norm(ur5.fk(r.q).translation - p) < 1e-6


def test_the_restarts_of_several_tips_take_a_few_attempts_a_chain_where_no_answer_holds():
    # each restart's start solved each chain on the whole budget again: a check no answer
    # holds ran 147 607 times for one target on a budget of 3000 iterations (37 s)
    calls = []

    class Counted(ElbowUp):
        def check(self, arm, Q):
            calls.append(len(Q))
            return super().check(arm, Q)

    robot = armik.load("panda", tips=["panda_hand", "panda_link5"])
    (T,), (q,) = _targets(1)
    goal = {"panda_hand": T, "panda_link5": robot.fk(q, "panda_link5")}
    r = robot.solve(goal, q0=q, constraints={"panda_hand": [Counted()]}, iteration_budget=3000)
    assert not r.success and r.reason.endswith("elbow below -1")
    assert r.restarts > 10  # the descent did restart
    # a start: each chain at most 4 attempts; the first start and the verdicts aside
    assert len(calls) <= 12 * (r.restarts + 1), (len(calls), r.restarts)


def test_the_restarts_starts_keep_a_budget_given_as_one(monkeypatch):
    # 3 restarts were added as max_restarts beside budget=Budget(restarts=...): every
    # chain's start solve was refused ("given twice") and each restart began at random
    robot = armik.load("panda", tips=["panda_hand", "panda_link5"])
    refused = []
    solve_chain = type(robot)._solve_chain

    def recorded(self, *args):
        try:
            return solve_chain(self, *args)
        except armik.ArmikError as error:
            refused.append(error)
            raise

    monkeypatch.setattr(type(robot), "_solve_chain", recorded)
    (T,), (q,) = _targets(1)
    goal = {"panda_hand": T, "panda_link5": robot.fk(q, "panda_link5")}
    budget = armik.Budget(iterations=3000, restarts=20)
    r = robot.solve(goal, q0=q, constraints={"panda_hand": [ElbowUp()]}, budget=budget)
    assert not r.success and r.restarts > 0
    assert refused == []


class WrapsInPlace(Constraint):
    """Holds every answer, but writes into the ``Q`` it is given: joint 1 wrapped into
    [0, 2 pi) in place, a normalisation a user may write before comparing angles."""

    def check(self, arm, Q):
        Q[:, 0] = np.mod(Q[:, 0], 2.0 * np.pi)
        return Check(np.ones(len(Q), dtype=bool), armik.Status.JOINT_LIMITS, lambda i: "never")


@pytest.mark.parametrize("how", [{}, {"solver": "dls"}, {"solver": "swept"}], ids=str)
def test_a_check_writing_into_its_answers_changes_no_answer(how):
    """A check is given a copy of the answers: the ones it wrote into were reported as they
    were measured no more (joint 1 of a Panda at -0.5 turned to 5.8, outside its limits,
    called a success on ``solve`` and ``solve_all``)."""
    panda = bundled("panda")
    q = Q_BENT.copy()
    q[0] = -0.5  # the answer nearest q0 has joint 1 below 0: the check's wrap moves it
    T = panda.fk(q)
    found = [panda.solve(T, q0=q, constraints=[WrapsInPlace()], **how)]
    found += list(panda.solve_all(T, q0=q, constraints=[WrapsInPlace()], **how))
    assert any(r.success and r.q[0] < 0.0 for r in found)
    for r in found:
        if r.success:
            F = panda.fk(r.q)
            assert panda.within_limits(r.q), r.q
            assert np.linalg.norm(F.translation - T.translation) <= 1e-6
            assert np.linalg.norm(pin.log3(T.rotation.T @ F.rotation)) <= 1e-6
