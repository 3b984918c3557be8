"""The general 6R solver (the 2-D search): any 6R chain classified, "auto" choosing it only
where no closed form fits, every answer verified by Pinocchio, and the configuration that made
the target among ``solve_all``'s answers on random arms with every axis random."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers.closed_form import general_6r
from armik.status import Status

from ...analytic_urdfs import six_r


def _fmt(v) -> str:
    return " ".join(repr(float(x)) for x in v)


def random_arm_urdf(rng: np.random.Generator) -> str:
    """A 6R arm with random unit axes through random points and random fixed transforms
    before joint 1 and after joint 6."""
    joints, prev = [], np.zeros(3)
    for _ in range(6):
        c = rng.uniform(-0.4, 0.4, size=3)
        h = rng.normal(size=3)
        joints.append((_fmt(c - prev), "0 0 0", _fmt(h / np.linalg.norm(h))))
        prev = c
    return six_r(
        joints,
        mount_xyz=_fmt(rng.uniform(-1, 1, size=3)),
        mount_rpy=_fmt(rng.uniform(-3, 3, size=3)),
        tool_xyz=_fmt(rng.uniform(-0.2, 0.2, size=3)),
        tool_rpy=_fmt(rng.uniform(-3, 3, size=3)),
    )


def _wrapped(a, b) -> float:
    return float(np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))).max())


def _pose_error(arm, q, T) -> float:
    return float(np.linalg.norm(pin.log6(arm.fk(q).inverse() * T).vector))


@pytest.fixture(scope="module")
def arms():
    rng = np.random.default_rng(11)
    return [
        armik.load_string(random_arm_urdf(rng), base="world", tip="tool") for _ in range(5)
    ], rng


def test_any_6r_arm_is_classified_and_auto_picks_it_last(arms):
    for arm in arms[0]:
        geo = general_6r.classify(arm.kinematics)
        assert not isinstance(geo, str), geo
        assert geo.description == "general 6R (2-D search)"
        T = arm.fk(arm.middle)
        # a search: auto takes it for every solution, a numeric solver for one answer
        assert arm.solve_all(T)[0].solver == "elimination_6r"  # the elimination goes first
        assert arm.solve_all(T, solver="general_6r")[0].solver == "general_6r"
        assert arm.solve(T).solver == "dls"
    # arms a closed form fits keep it
    assert armik.load("ur5").solve(armik.load("ur5").fk(np.full(6, 0.3))).solver == (
        "three_parallel"
    )
    irb = armik.load("abb_irb120")
    assert irb.solve(irb.fk(np.full(6, 0.3))).solver == "spherical"


def test_not_a_6r_arm_is_refused_with_the_reason():
    why = general_6r.classify(armik.load("panda").kinematics)
    assert why == "the chain has 7 joints, this class needs 6"
    with pytest.raises(armik.errors.SolverError, match="7 joints"):
        armik.load("panda").solve(armik.load("panda").fk(np.zeros(7)), solver="general_6r")


def test_random_arms_every_solution_verified_and_complete(arms):
    arm_list, rng = arms
    found = 0
    for arm in arm_list:
        for _ in range(3):
            q = arm.random_q(rng)
            T = arm.fk(q)
            results = arm.solve_all(T, solver="general_6r")
            ok = [r for r in results if r.success]
            assert ok and all(r.solver == "general_6r" for r in results)
            for r in ok:
                assert _pose_error(arm, r.q, T) < 1e-9
                assert np.all(r.q >= arm.lower) and np.all(r.q <= arm.upper)
            for i, a in enumerate(ok):  # distinct answers
                for b in ok[i + 1 :]:
                    assert _wrapped(a.q, b.q) > 1e-6
            assert [r.branch for r in results] == [str(k) for k in range(len(results))]
            found += min(_wrapped(r.q, q) for r in ok) < 1e-6
    assert found == 15


def test_same_solutions_as_the_closed_form_on_a_ur5():
    arm = armik.load("ur5")
    rng = np.random.default_rng(4)
    for _ in range(4):
        T = arm.fk(arm.random_q(rng))
        closed = [r.q for r in arm.solve_all(T, solver="three_parallel") if r.success]
        if any(r.singular for r in arm.solve_all(T, solver="three_parallel")):
            continue
        search = [r.q for r in arm.solve_all(T, solver="general_6r") if r.success]
        assert len(search) == len(closed)
        for q in closed:
            assert min(_wrapped(q, s) for s in search) < 1e-7


def test_solve_is_the_nearest_verified_answer(arms):
    arm = arms[0][1]
    rng = np.random.default_rng(2)
    T = arm.fk(arm.random_q(rng))
    q0 = arm.random_q(rng)
    every = [r for r in arm.solve_all(T, q0=q0, solver="general_6r") if r.success]
    one = arm.solve(T, q0=q0, solver="general_6r")
    assert one.success and one.solver == "general_6r"
    nearest = min(every, key=lambda r: np.linalg.norm(r.q - q0))
    np.testing.assert_allclose(one.q, nearest.q, atol=1e-12)


def test_out_of_reach_is_no_success(arms):
    arm = arms[0][0]
    T = pin.SE3(np.eye(3), np.array([10.0, 0.0, 0.0]))
    results = arm.solve_all(T)
    assert results and not any(r.success for r in results)
    assert results[0].status is Status.UNREACHABLE
    assert np.isfinite(results[0].q).all()


def test_a_search_that_finds_nothing_hands_over_to_dls(arms, monkeypatch):
    arm = arms[0][2]
    rng = np.random.default_rng(6)
    q = arm.random_q(rng)
    T = arm.fk(q)
    monkeypatch.setattr(general_6r, "THRESHOLD", -1.0)  # no seed at all
    results = arm.solve_all(T, solver="general_6r", iteration_budget=2000)
    assert results[0].success and results[0].solver == "general_6r"
    assert results[0].reason.startswith(general_6r.SEARCH_FAILED + "; dls: ")
    assert _pose_error(arm, results[0].q, T) < 1e-6
