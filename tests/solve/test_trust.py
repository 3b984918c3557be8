"""No verdict stronger than its proof: a reachable target is never called unreachable, a
search's miss is not the last word of "auto", and "auto" takes a search for every solution
only (``registry.choose``)."""

from __future__ import annotations

import dataclasses
import os
import warnings

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik import reasons
from armik.solvers import registry
from armik.solvers.closed_form import elimination_6r, sixr, sixr_answers
from armik.status import Status
from armik.targets.pose import parse_target
from armik.tools.cli import main

from .. import conftest

RTB = os.path.join(
    os.path.dirname(__file__), "..", "data", "rtb"
)  # rtb-data's URDFs (README there)
IRB140 = os.path.join(RTB, "abb_irb140_description", "urdf", "irb140.urdf")


@pytest.fixture(scope="module")
def irb140() -> armik.Arm:
    return armik.load(IRB140, tip="tool0")


def test_the_irb140_is_a_searched_arm(irb140):
    """The arm this file is about: its family is a search; auto takes the elimination (and
    the search behind it) for solve_all."""
    T = irb140.fk(irb140.random_q(0))
    assert registry.why_not("two_parallel", irb140.kinematics) is None
    every = registry.choose("auto", irb140.kinematics, None, None, every=True).name
    assert every == "elimination_6r"
    assert registry.choose("auto", irb140.kinematics).name == "dls"
    assert irb140.solve_all(T)[0].solver == "elimination_6r"


def test_auto_solves_every_reachable_irb140_target(irb140):
    rng = np.random.default_rng(140)
    Q = np.array([irb140.random_q(rng) for _ in range(200)])
    poses = np.array([irb140.fk(q).homogeneous for q in Q])
    statuses = [irb140.solve(H).status for H in poses]
    assert statuses.count(Status.CONVERGED) == len(poses), statuses
    batch = irb140.solve_batch(poses, workers=1, progress=False)
    assert batch.success.all(), batch.status[~batch.success]
    for H in poses[:40]:
        every = irb140.solve_all(H)
        assert every[0].success, every[0].reason


REAL_ARMS = {  # every 6R arm of rtb-data and example-robot-data a search applies to
    "irb140": (IRB140, "tool0"),
    "irb140QT": (os.path.join(RTB, "abb_irb140_description", "urdf", "irb140QT.urdf"), "tool0"),
    "kr16": (os.path.join(RTB, "kuka_description", "kuka_kr16", "urdf", "kr16_2.urdf"), "tool0"),
    "kr120": (
        os.path.join(RTB, "kuka_description", "kuka_kr120", "urdf", "kr120r2500pro.urdf"),
        "tool0",
    ),
    "puma560": (
        os.path.join(RTB, "unimation_puma560_description", "urdf", "puma560_robot.urdf"),
        "link7",
    ),
    "kinova": ("kinova", None),
    "ur5": ("ur5", None),
    "ur10": ("ur10", None),
    "z1": ("z1", None),
    "abb_irb120": ("abb_irb120", None),
}


def _wrapped(a):
    return np.remainder(a + np.pi, 2.0 * np.pi) - np.pi


@pytest.mark.parametrize("name", sorted(REAL_ARMS))
def test_the_searches_find_every_generating_configuration_on_real_arms(name):
    """Each one-dimensional search (and the elimination) that applies to a real arm: the
    configuration that made an FK target is among solve_all's answers (modulo 2 pi), every
    time; and auto's one answer is a success."""
    source, tip = REAL_ARMS[name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        arm = armik.load(source, tip=tip) if tip else armik.load(source)
    searches = [
        s
        for s in ("two_parallel", "two_intersecting", "elimination_6r")
        if registry.why_not(s, arm.kinematics) is None
    ]
    assert searches, f"no search applies to {name}"
    rng = np.random.default_rng(36)
    for _ in range(30):
        q = arm.random_q(rng)
        T = arm.fk(q)
        assert arm.solve(T).success
        for search in searches:
            found = [r.q for r in arm.solve_all(T, solver=search) if r.success]
            assert any(np.abs(_wrapped(x - q)).max() < 1e-6 for x in found), (search, q)


def test_the_cli_exits_0_on_a_reachable_irb140_target(irb140, capsys):
    T = irb140.fk(irb140.random_q(3))
    xyz = [f"{v:.12g}" for v in T.translation]
    rpy = [f"{v:.12g}" for v in pin.rpy.matrixToRpy(T.rotation)]
    code = main(["solve", IRB140, "--tip", "tool0", "--xyz", *xyz, "--rpy", *rpy, "--json"])
    assert code == 0, capsys.readouterr()


def _searched_arms():
    """Arms on which each search is registered to apply: (solver name, arm)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        locked = armik.load("panda", locked={"panda_joint1": 0.3})  # general_6r
    return [("two_parallel", armik.load(IRB140, tip="tool0")), ("general_6r", locked)]


def test_auto_takes_no_search_for_one_answer():
    """For every registered search and an arm it applies to, one answer goes elsewhere."""
    searches = [registry.get(name) for name in registry.solvers()]
    searches = [s for s in searches if not s.complete]
    assert {s.name for s in searches} >= {"two_parallel", "two_intersecting", "general_6r"}
    for name, arm in _searched_arms():
        assert registry.why_not(name, arm.kinematics) is None
        one = registry.choose("auto", arm.kinematics)
        assert one.complete and one.name != name
        # every solution: the elimination, the search behind it
        assert registry.choose("auto", arm.kinematics, every=True).name == "elimination_6r"


@pytest.mark.parametrize("robot", ["planar_2link", "ur5", "panda", "abb_irb120", "irb140"])
def test_no_solver_calls_a_reachable_target_unreachable(robot, irb140):
    """Every solver that applies, on FK targets of random configurations within the
    limits: whatever it fails to find, it never claims the target out of reach."""
    arm = irb140 if robot == "irb140" else conftest.arm(robot)
    rng = np.random.default_rng(7)
    targets = [arm.fk(arm.random_q(rng)) for _ in range(8)]
    if robot == "planar_2link":
        targets = [T.translation[:2].copy() for T in targets]
    for name in registry.solvers():
        if (
            registry.why_not(name, arm.kinematics, parse_target(targets[0], arm.kinematics))
            is not None
        ):
            continue
        for T in targets:
            opts = {"iteration_budget": 300} if registry.get(name).kind == "numeric" else {}
            # solve_all's later rows speak of their own branch ("too far" for this elbow);
            # its first row is the call's verdict
            for r in [arm.solve(T, solver=name, **opts), arm.solve_all(T, solver=name, **opts)[0]]:
                assert r.status is not Status.UNREACHABLE, (name, r.reason)


def test_a_search_miss_is_not_converged_unless_beyond_reach():
    """The claim of a search's 'found nothing' row, and of the same row beyond reach."""
    row = np.zeros((1, 11))
    row[0, 6], row[0, 8] = sixr.LS, sixr.NOT_FOUND
    missed = sixr_answers.of_rows(row, "two_parallel", "search")
    assert len(missed) == 1 and missed.status(0) is Status.NOT_CONVERGED
    assert "does not show" in missed.reason(0)
    far = sixr_answers.of_rows(row, "two_parallel", "search", reasons.beyond_reach(3.0, 1.0))
    assert far.status(0) is Status.UNREACHABLE and "beyond the arm's reach" in far.reason(0)
    row[0, 8] = sixr.TOO_FAR  # a complete closed form's verdict is a proof
    too_far = sixr_answers.of_rows(row, "three_parallel", "closed form")
    assert too_far.status(0) is Status.UNREACHABLE


def test_auto_goes_on_to_the_numeric_solver_when_a_search_verifies_nothing(irb140, monkeypatch):
    """solve_all with auto: a search that finds nothing hands over, and says so."""
    spec = registry.get("two_parallel")

    def finds_nothing(arm, target, q0, opts, all_solutions):
        row = np.zeros((1, 11))
        row[0, :6] = q0
        row[0, 6], row[0, 8] = sixr.LS, sixr.NOT_FOUND
        return sixr_answers.of_rows(row, "two_parallel", "search")

    blind = dataclasses.replace(spec, run=finds_nothing, prepare_pose=None)
    monkeypatch.setitem(registry._REGISTRY, "two_parallel", blind)
    monkeypatch.setattr(
        registry, "_BY_PRIORITY", [blind if s is spec else s for s in registry._BY_PRIORITY]
    )
    monkeypatch.setattr(registry, "generation", registry.generation + 1)  # no old plans
    assert elimination_6r.applies(irb140.kinematics) is None  # its cut chosen first
    monkeypatch.setattr(elimination_6r, "_rows", lambda *a: (0, False, 0.0))  # unsure: search
    T = irb140.fk(irb140.random_q(5))
    (named,) = irb140.solve_all(T, solver="two_parallel")
    assert named.status is Status.NOT_CONVERGED and not named.success
    (auto,) = irb140.solve_all(T)
    assert auto.success and auto.solver == "dls"
    assert auto.reason.startswith("elimination_6r (a search, not a proof) found no solution")
