"""``prefer=`` on an arm without a closed form (the xArm7: the numeric search, then the
self-motion descent): the nearest answer against independent dls solves from starts near
q0, the descent's end a stationary point, the starts near q0, the search's determinism."""

from __future__ import annotations

import math
import time

import numpy as np
import pinocchio as pin
import pytest

from armik.problem.scores import Nearest
from armik.solve import prefer_near
from armik.solve.nullspace import descend

from .. import conftest


def _nearest_turn(arm, q, q0):
    """``q`` with each joint turned by whole turns of 2 pi to lie nearest q0 within the
    limits (by enumeration, not by the library's rounding)."""
    out = np.array(q, dtype=float)
    for i, (lo, hi) in enumerate(zip(arm.lower, arm.upper)):
        if not (math.isfinite(lo) and math.isfinite(hi)):
            continue
        values = [q[i] + 2 * math.pi * k for k in range(-3, 4)]
        out[i] = min((v for v in values if lo <= v <= hi), key=lambda v: abs(v - q0[i]))
    return out


def _null_projector(arm, q):
    J = arm.jacobian(q)
    return np.eye(arm.dof) - np.linalg.pinv(J) @ J


def test_the_nearest_is_no_farther_than_the_best_of_dls_from_starts_near_q0():
    """On fixed xArm7 targets with a deterministic budget, prefer="nearest" is no farther
    from q0 than the best of 24 independent dls descents from perturbations of q0 of
    growing size (each at its nearest 2 pi variant). Gathering 16 answers from uniform
    restarts and moving only the best along the self-motion lost on the first target."""
    arm = conftest.arm("xarm7")
    rng = np.random.default_rng(34)
    for _ in range(12):
        T = arm.fk(arm.random_q(rng))
        q0 = arm.random_q(rng)
        r = arm.solve(T, q0=q0, prefer="nearest", iteration_budget=2000)
        assert r.success and np.allclose(arm.fk(r.q).homogeneous, T.homogeneous, atol=1e-6)
        best = math.inf
        for j in range(24):
            start = q0 + rng.normal(scale=0.05 * (j + 1), size=arm.dof)
            s = arm.solve(T, q0=np.clip(start, arm.lower, arm.upper), solver="dls", max_restarts=0)
            if s.success:
                best = min(best, float(np.linalg.norm(_nearest_turn(arm, s.q, q0) - q0)))
        assert np.linalg.norm(r.q - q0) <= best + 1e-9
        assert r.extra["score"] == pytest.approx(np.linalg.norm(r.q - q0), abs=1e-12)


def test_the_descent_ends_where_the_distance_is_stationary_along_the_self_motion():
    """From a verified answer, the descent for "nearest" ends where q - q0 is orthogonal to
    the self-motion (the projected gradient vanishes), the pose held and no farther."""
    arm = conftest.arm("xarm7")
    rng = np.random.default_rng(5)
    for _ in range(4):
        q = arm.random_q(rng)
        T = arm.fk(q)
        q0 = np.clip(q + rng.normal(scale=0.4, size=arm.dof), arm.lower, arm.upper)
        moved = descend(arm.kinematics, q, T, Nearest(), q0, budget=math.inf)
        assert np.linalg.norm(moved - q0) < np.linalg.norm(q - q0)
        assert np.linalg.norm(_null_projector(arm, moved) @ (moved - q0)) <= 1e-6
        assert np.abs(pin.log6(arm.fk(moved).inverse() * T).vector).max() <= 1e-9
        assert arm.within_limits(moved)


def test_the_starts_near_q0_grow_from_q0_to_the_whole_range():
    arm = conftest.arm("xarm7")
    q0 = arm.random_q(8)
    starts = prefer_near.near_starts(arm.kinematics, q0, np.random.default_rng(0))
    drawn = np.array([next(starts) for _ in range(prefer_near.NEAR_STARTS)])
    half = np.minimum((arm.upper - arm.lower) / 2.0, math.pi)
    assert (np.abs(drawn[0] - q0) <= prefer_near.NEAR_FIRST * half + 1e-12).all()
    assert all(arm.within_limits(q) for q in drawn)
    spread = np.abs(drawn - q0).max(axis=1)
    assert spread[-8:].mean() > 5.0 * spread[:8].mean()


def test_the_search_is_deterministic_and_solve_all_is_ranked():
    arm = conftest.arm("xarm7")
    T = arm.fk(arm.random_q(21))
    q0 = arm.random_q(22)
    one = arm.solve(T, q0=q0, prefer="nearest", iteration_budget=1000)
    two = arm.solve(T, q0=q0, prefer="nearest", iteration_budget=1000)
    assert np.array_equal(one.q, two.q)
    ranked = arm.solve_all(T, q0=q0, prefer="nearest", iteration_budget=1000, max_solutions=6)
    scores = [r.extra["score"] for r in ranked]
    assert all(r.success for r in ranked) and 1 < len(ranked) <= 6
    assert scores == sorted(scores) and scores[0] == pytest.approx(one.extra["score"])


def test_the_starts_count_as_restarts_and_spend_their_share_of_the_iterations():
    """near_answers runs at most max_restarts starts, and with an iteration budget stops
    once the starts have spent their share of it."""
    from armik.options import Options

    arm = conftest.arm("xarm7")
    T = arm.fk(arm.random_q(31))
    calls = []

    def solve_from(start):
        calls.append(start)
        return arm.solve(T, q0=start, solver="dls", max_restarts=0)

    opts = Options(max_restarts=3, timeout=10.0)
    prefer_near.near_answers(arm.kinematics, solve_from, arm.middle, opts, time.perf_counter())
    assert len(calls) == 3
    calls.clear()
    opts = Options(iteration_budget=40)  # the starts' share: 20 iterations
    prefer_near.near_answers(arm.kinematics, solve_from, arm.middle, opts, 0.0)
    assert 1 <= len(calls) <= 20


@pytest.mark.parametrize("score", ["nearest", "limits", "manipulability"])
def test_a_position_target_on_a_redundant_arm_is_ranked_not_refused(score):
    """A position on a 7-joint arm with a preference: every answer reaches the point by
    Pinocchio's own FK, ranked by its score (the swept search and the self-motion descent
    hold a full pose only, so they step aside)."""
    arm = conftest.arm("panda")
    point = np.array([0.4, 0.1, 0.5])
    model = arm.kinematics.model
    data = model.createData()
    tip = model.getFrameId(arm.tip)
    found = arm.solve_all(point, prefer=score)
    assert found and all(r.success for r in found)
    for r in found:
        pin.framesForwardKinematics(model, data, r.q)
        assert np.linalg.norm(data.oMf[tip].translation - point) <= 1e-6
    scores = [r.extra["score"] for r in found]
    assert scores == sorted(scores)
    one = arm.solve(point, prefer=score)
    assert one.success and one.extra["score"] == scores[0]


@pytest.mark.parametrize("name", ["panda", "kuka_iiwa14"])
def test_solve_all_with_a_preference_lists_every_answer_once_best_first(name):
    """With ``prefer=`` on a redundant arm the answers of the search are ranked with every
    answer ``solve_all`` finds (the Panda listed 2 of 16), and a copy of an answer the
    descent moved a little is not listed beside it (two answers 1.6e-5 rad apart were)."""
    from armik.kernel.descent import DUPLICATE_TOL

    arm = conftest.arm(name)
    rng = np.random.default_rng(11)
    q = [arm.random_q(rng) for _ in range(4)][-1]
    T = arm.fk(q)
    plain = [r for r in arm.solve_all(T, q0=q, iteration_budget=20000) if r.success]
    ranked = [r for r in arm.solve_all(T, q0=q, iteration_budget=20000, prefer="nearest")
              if r.success]  # fmt: skip
    assert len(ranked) >= len(plain)
    for i, a in enumerate(ranked):
        for b in ranked[:i]:
            assert np.abs(a.q - b.q).max() >= DUPLICATE_TOL
    scores = [r.extra["score"] for r in ranked]
    assert scores == sorted(scores) and scores[0] == pytest.approx(0.0, abs=1e-9)


def test_the_preference_stages_clock_starts_after_their_kernels_are_loaded(monkeypatch):
    # a process's first call loads (or compiles) the kernels its stages run; were that in
    # the stages' shared time, the first call would gather fewer starts than every later
    # one and answer differently. Each request is run once first, then the clock starts.
    from armik.solve import preferred

    events: list = []
    load, near = preferred._load, prefer_near.near_answers

    def loading(arm, req):
        load(arm, req)
        events.append(("loaded", req.every))

    def gathering(arm, solve_from, middle, opts, clock):
        events.append(("clock", clock <= time.thread_time()))
        return near(arm, solve_from, middle, opts, clock)

    monkeypatch.setattr(preferred, "_load", loading)
    monkeypatch.setattr(prefer_near, "near_answers", gathering)
    xarm = conftest.arm("xarm7")  # numeric: solve_all's answers, then starts near q0
    T = xarm.fk(xarm.middle + 0.2)
    r = xarm.solve(T, prefer="manipulability")
    assert r.success, r.reason
    assert events[:2] == [("loaded", True), ("loaded", False)] and events[2][0] == "clock"
    assert preferred._LOADED(xarm.kinematics)  # once per arm and options: not again
    events.clear()
    xarm.solve(T, prefer="manipulability")
    assert [e[0] for e in events] == ["loaded", "loaded", "clock"]
