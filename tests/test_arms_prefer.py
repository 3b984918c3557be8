"""A preference on two IRB 120s that share no joint (``armik.arms_prefer``): a callable
cost takes the robot's whole configuration, as over shared joints; the robot's answer
carries its score (the whole configuration's), in ``solve``, ``solve_all`` and
``solve_batch`` alike, and ``solve_all`` lists the robot's answers best first by it. Held
values checked against the robot before any chain's batch runs."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import armik
from armik.errors import JointError, OptionError, TargetError
from armik.problem.scores import limit_margin

from .test_arms import dual_irb120


@pytest.fixture(scope="module")
def cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])


def _targets(cell, seed: int) -> dict:
    q = cell.random_q(np.random.default_rng(seed))
    return {tip: cell.fk(q, tip) for tip in cell.tips}


def test_a_cost_takes_the_whole_configuration_and_gets_the_best_combination(cell):
    """A cost coupling the chains (their first joints alike, the right one near 1) is
    called with the robot's 12 joints and ranks the combinations of the chains' answers:
    the answer is the best of every combination of each chain's branches, its score the
    cost of its q."""
    goal = _targets(cell, 0)
    lengths = set()

    def cost(q):
        lengths.add(len(q))
        return float((q[0] - q[6]) ** 2 + (q[6] - 1.0) ** 2)

    r = cell.solve(goal, prefer=cost)
    assert r.success and lengths == {12}
    assert r.score == pytest.approx(cost(r.q), abs=1e-12)
    left = [x.q for x in cell.chain("l_tool0").solve_all(goal["l_tool0"]) if x.success]
    right = [x.q for x in cell.chain("r_tool0").solve_all(goal["r_tool0"]) if x.success]
    best = min(cost(np.r_[a, b]) for a, b in itertools.product(left, right))
    assert r.score <= best + 1e-9
    for tip, own in r.extra["results"].items():  # the cost is the whole q's: each chain's too
        assert own.score == r.score, tip
    b = cell.solve_batch({tip: [T] for tip, T in goal.items()}, prefer=cost)
    assert b.success.all() and b.score[0] == pytest.approx(r.score, abs=1e-9)
    with pytest.raises(OptionError, match="IndexError") as caught:
        cell.solve(goal, prefer=lambda q: float(q[20]))
    assert "raised OptionError" not in str(caught.value)  # the cost's own error, once


def test_a_named_preference_gives_the_robot_its_whole_configuration_s_score(cell):
    goal = _targets(cell, 1)
    q0 = cell.random_q(np.random.default_rng(2))
    posture = armik.Posture(q0, np.linspace(0.5, 2.0, 12))
    r = cell.solve(goal, q0=q0, prefer=posture)
    assert r.success
    assert r.score == pytest.approx(float(posture.weights @ (r.q - q0) ** 2), abs=1e-9)
    r = cell.solve(goal, q0=q0, prefer="nearest")
    assert r.score == pytest.approx(float(np.linalg.norm(r.q - q0)), abs=1e-9)
    r = cell.solve(goal, prefer="limits")
    margin = min(limit_margin(cell.chain(t).kinematics, q) for t, q in cell.split(r.q).items())
    assert r.score == pytest.approx(-margin, abs=1e-12)
    b = cell.solve_batch({tip: [T, T] for tip, T in goal.items()}, prefer="limits")
    np.testing.assert_allclose(b.score, [r.score, r.score], atol=1e-12)
    assert np.isnan(cell.solve_batch({tip: [T] for tip, T in goal.items()}).score).all()


def test_solve_all_lists_the_robot_s_answers_best_first_by_its_score(cell):
    goal = _targets(cell, 3)
    posture = armik.Posture(np.zeros(12))
    every = cell.solve_all(goal, prefer=posture)
    scores = [x.score for x in every]
    assert len(every) > 4 and all(x.success for x in every)
    assert scores == sorted(scores)
    for x in every:
        assert x.score == pytest.approx(float(np.sum(x.q**2)), abs=1e-9)
    assert every[0].score == pytest.approx(cell.solve(goal, prefer=posture).score, abs=1e-9)
    limits = [x.score for x in cell.solve_all(goal, prefer="limits")]
    assert limits == sorted(limits) and None not in limits
    cost = [x.score for x in cell.solve_all(goal, prefer=lambda q: float(abs(q[0] + q[6])))]
    assert cost == sorted(cost) and len(cost) == len(every)


def test_a_path_of_independent_chains_refuses_a_cost_of_the_whole_configuration(cell):
    goal = _targets(cell, 4)
    ways = {tip: [T, T] for tip, T in goal.items()}
    with pytest.raises(OptionError, match="Posture over robot.joint_names") as caught:
        cell.solve_path(ways, cell.middle, prefer=lambda q: float(q[0]))
    assert caught.value.option == "prefer"


def test_a_batch_checks_held_values_against_the_robot_before_any_chain_runs(cell, monkeypatch):
    def ran(*args, **kwargs):
        raise AssertionError("a chain's batch ran before the held values were checked")

    monkeypatch.setattr(type(cell.chain("l_tool0")), "solve_batch", ran)
    rows = {tip: np.zeros((2, 3)) for tip in cell.tips}
    with pytest.raises(JointError, match="outside joint 'r_joint_1'"):
        cell.solve_batch(rows, hold={"r_joint_1": 100.0})
    with pytest.raises(TargetError, match=r"shape \(2, 5\)"):  # the second tip's rows
        cell.solve_batch({"l_tool0": rows["l_tool0"], "r_tool0": np.zeros((2, 5))})
    monkeypatch.undo()
    # held at q0's value, q0 outside the limits: clipped into them first, as one arm's
    # seed, and held there
    q0 = np.tile(cell.middle, (2, 1))
    j = cell.joint_names.index("r_joint_2")
    q0[1, j] = 10.0
    with pytest.warns(armik.ArmikWarning, match="row 1 outside the joint limits was clipped"):
        b = cell.solve_batch(rows, q0=q0, hold={"r_joint_2": None})
    assert b.q[1, j] == cell.upper[j]
