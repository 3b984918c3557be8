"""Numeric IK: round trips on every arm, Jacobians against finite differences, limits."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
import qpsolvers
from scipy import sparse

import armik
from armik.options import Options
from armik.solvers import registry
from armik.solvers.numeric import driver as numeric
from armik.solvers.numeric import pieces, qp
from armik.status import Status
from armik.targets.pose import parse_target

from ...conftest import SPATIAL, TOL, arm, model

NUMERIC = ["dls", "qp"]


@pytest.mark.parametrize("solver", NUMERIC)
@pytest.mark.parametrize("name", SPATIAL + ["scara", "planar_3link"])
def test_round_trip(name, solver):
    a = arm(name)
    rng = np.random.default_rng(7)
    for _ in range(8):
        q_true = a.random_q(rng)
        target = a.fk(q_true) if name != "planar_3link" else a.fk(q_true).translation
        r = a.solve(target, q0=a.middle, solver=solver)
        assert r.success, r
        T = a.fk(r.q)
        assert np.linalg.norm(T.translation - a.fk(q_true).translation) <= TOL["solve"]
        if name != "planar_3link":
            assert np.linalg.norm(pin.log6(T.actInv(a.fk(q_true))).angular) <= TOL["solve"]
        assert a.within_limits(np.asarray(r.q), tol=0.0)


def test_frame_jacobian_against_finite_differences(rng):
    a = model("kinova")  # continuous joints: steps through pin.integrate
    for _ in range(5):
        q = a.random_q(rng)
        J = a.jacobian(q)  # LOCAL
        qp_ = a.to_pin(q)
        T0 = a.fk_pin(qp_)
        h = 1e-6
        for i in range(a.dof):
            dv = np.zeros(a.dof)
            dv[i] = h
            Tp = a.fk_pin(pin.integrate(a.model, qp_, dv))
            Tm = a.fk_pin(pin.integrate(a.model, qp_, -dv))
            fd = (pin.log6(T0.actInv(Tp)).vector - pin.log6(T0.actInv(Tm)).vector) / (2 * h)
            np.testing.assert_allclose(J[:, i], fd, atol=TOL["fd_jacobian"])


def test_error_jacobian_against_finite_differences(rng):
    a = model("panda")
    target = parse_target(a.fk(a.random_q(rng)))
    pb = pieces.Problem.build(a, target, a.middle, Options())
    qp_ = a.to_pin(a.random_q(rng))
    s = pieces.evaluate(pb, qp_)
    h = 1e-6
    for i in range(a.dof):
        dv = np.zeros(a.dof)
        dv[i] = h
        ep = pieces.evaluate(pb, pin.integrate(a.model, qp_, dv)).e
        em = pieces.evaluate(pb, pin.integrate(a.model, qp_, -dv)).e
        # e decreases along A: de/dq = -A
        np.testing.assert_allclose(-(ep - em) / (2 * h), s.A[:, i], atol=1e-6)


@pytest.mark.parametrize("solver", NUMERIC)
def test_fixed_point_takes_no_iteration(solver, rng):
    a = arm("ur5")
    q = a.random_q(rng)
    r = a.solve(a.fk(q), q0=q, solver=solver)
    assert r.success and r.iterations <= 1 and np.allclose(r.q, q, atol=1e-9)


def test_qp_stays_inside_limits_near_limits():
    a = arm("panda")
    rng = np.random.default_rng(3)
    for _ in range(10):
        q_true = a.random_q(rng)
        j = rng.integers(a.dof)
        q_true[j] = a.upper[j] - 1e-4 if rng.random() < 0.5 else a.lower[j] + 1e-4
        r = a.solve(a.fk(q_true), q0=a.middle, solver="qp")
        assert r.success and a.within_limits(np.asarray(r.q), tol=0.0)


def test_qp_problem_has_the_expected_bounds(rng):
    a = model("panda")
    pb = pieces.Problem.build(a, parse_target(a.fk(a.random_q(rng))), a.middle, Options())
    q = a.random_q(rng)
    s = pieces.evaluate(pb, a.to_pin(q))
    problem = qp.build_problem(pb, s)
    assert isinstance(problem, qpsolvers.Problem)
    np.testing.assert_allclose(problem.lb, a.lower - q)
    np.testing.assert_allclose(problem.ub, a.upper - q)
    P = problem.P.toarray()
    np.testing.assert_allclose(P, P.T)
    assert np.all(np.linalg.eigvalsh(P) > 0)


def test_active_set_matches_qp_backend(rng):
    solved = 0
    for _ in range(200):
        A = rng.normal(size=(6, 7))
        H = A.T @ A + 1e-3 * np.eye(7)
        g = A.T @ rng.normal(size=6)
        lb, ub = -rng.uniform(0.0, 0.3, 7), rng.uniform(0.0, 0.3, 7)
        G = np.linalg.inv(H)
        dq = G @ g
        x = qp.active_set_guess(G, dq, lb, ub, dq)
        if x is None:
            continue
        solved += 1
        ref = qpsolvers.solve_qp(
            sparse.csc_matrix(H),
            -g,
            lb=lb,
            ub=ub,
            solver="osqp",
            eps_abs=1e-10,
            eps_rel=1e-10,
            max_iter=200000,
            raise_error=False,
        )
        ref = np.clip(ref, lb, ub)
        assert np.all(x >= lb - 1e-12) and np.all(x <= ub + 1e-12)
        assert 0.5 * x @ H @ x - g @ x <= 0.5 * ref @ H @ ref - g @ ref + 1e-9
    assert solved > 150  # the shortcut must do most of the work


def test_kinova_continuous_answer_nearest_q0(rng):
    a = arm("kinova")
    q_true = a.random_q(rng)
    q0 = q_true.copy()
    q0[0] += 2 * math.pi + 0.05  # a continuous joint wound one turn further
    q0 = np.clip(q0, a.lower, a.upper)
    r = a.solve(a.fk(q_true), q0=q0)
    assert r.success
    assert abs(r.q[0] - q0[0]) < math.pi  # the equivalent angle near q0, not in (-pi, pi]


@pytest.mark.parametrize("name", SPATIAL)
def test_out_of_workspace_is_a_result(name):
    a = arm(name)
    r = a.solve([5.0, 5.0, 5.0], timeout=0.01)
    assert not r.success and r.status in ("unreachable", "not_converged")
    assert np.all(np.isfinite(r.q)) and r.reason


def test_not_converged_within_budget_is_honest():
    a = arm("panda")
    # within the reach bound (0.99 m from the shoulder) but beyond the real reach (~0.86 m)
    p = a.kinematics.first_joint_origin + np.array([0.95, 0.0, 0.0])
    assert np.linalg.norm(p - a.kinematics.first_joint_origin) < a.kinematics.reach
    r = a.solve(p, timeout=0.01, solver="dls")
    assert not r.success and r.status == "not_converged" and "best found" in r.reason
    assert r.position_error > 1e-6 or (r.orientation_error or 0) > 1e-6


def test_solve_all_distinct_verified(rng):
    a = arm("ur5")
    T = a.fk(a.random_q(rng))
    results = a.solve_all(T, timeout=0.1, max_solutions=6)
    assert len(results) >= 2
    ok = [r for r in results if r.success]
    assert len(ok) == len(results)
    for i in range(len(ok)):
        for j in range(i):
            assert np.abs(ok[i].q - ok[j].q).max() > 1e-4


def test_position_only_and_free_tool_axis(rng):
    a = arm("panda")
    T = a.fk(a.random_q(rng))
    r = a.solve(T.translation)
    assert r.success and r.orientation_error is None
    r = a.solve(T, position_only=True)
    assert r.success and r.orientation_error is None
    turned = T * pin.SE3(pin.rpy.rpyToMatrix(0, 0, 2.0), np.zeros(3))
    r = a.solve(turned, weights=(1, 1, 1, 1, 1, 0))
    assert r.success
    z_goal, z_got = turned.rotation[:, 2], a.fk(r.q).rotation[:, 2]
    assert np.linalg.norm(z_goal - z_got) < 1e-5


@pytest.mark.parametrize("solver", NUMERIC)
@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_weights_freeing_position_and_rotation_axes(name, solver):
    """A free position axis with a free rotation axis (not its own): log6's linear rows
    mix the axes through the free rotation; these targets failed (0 to 1 of 30 solved)."""
    a = arm(name)
    rng = np.random.default_rng(21)
    for w in [(1, 1, 0, 0, 0, 1), (0, 1, 1, 1, 0, 0), (1, 0, 1, 0, 1, 1), (1, 1, 0, 1, 0, 0)]:
        for _ in range(6):
            T = a.fk(a.random_q(rng))
            r = a.solve(T, solver=solver, weights=w)
            assert r.success, (w, r.reason)
            Tq = a.fk(r.q)
            tip = Tq.rotation.T @ (T.translation - Tq.translation)  # tip frame, as measured
            assert np.abs(tip[np.array(w[:3]) > 0]).max() <= 1e-6  # the default tolerance


@pytest.mark.parametrize("solver", NUMERIC)
@pytest.mark.parametrize("name", ["panda", "xarm7"])
def test_uneven_weights_on_a_redundant_arm(name, solver):
    """Weights of 1 and 100 to 10^4: the null-space pull grew with the largest weight and
    held 7-joint arms off the light rows (3 to 27 of 40 solved)."""
    a = arm(name)
    rng = np.random.default_rng(22)
    for ratio in (100.0, 1e4):
        for _ in range(8):
            T = a.fk(a.random_q(rng))
            w = tuple(rng.choice([1.0, ratio], 6))
            r = a.solve(T, solver=solver, weights=w)
            assert r.success, (w, r.reason)


def test_weight_ratio_is_bounded():
    with pytest.raises(armik.errors.OptionError, match="times the smallest positive"):
        arm("ur5").solve([0.3, 0.2, 0.4], weights=(1e-3, 1, 1, 1, 1, 1e4))


def test_redundant_arm_prefers_solution_near_q0(rng):
    a = arm("panda")
    for _ in range(5):
        q_true = a.random_q(rng)
        q0 = np.clip(q_true + rng.normal(scale=0.1, size=a.dof), a.lower, a.upper)
        r = a.solve(a.fk(q_true), q0=q0)
        assert r.success and np.linalg.norm(r.q - q0) < np.linalg.norm(q_true - q0) + 0.2


def test_same_seed_same_answer(rng):
    a = arm("z1")
    T = a.fk(a.random_q(rng))
    q0 = a.random_q(rng)
    r1 = a.solve(T, q0=q0, seed=5)
    r2 = a.solve(T, q0=q0, seed=5)
    np.testing.assert_array_equal(r1.q, r2.q)


def test_clik_baseline_runs():
    a = arm("ur5")
    q = np.array([0.3, -1.2, 1.4, -1.0, 0.8, 0.2])
    r = a.solve(a.fk(q), q0=q + 0.05, solver="clik", timeout=0.5, max_iterations=1000)
    assert r.solver == "clik" and r.success


def test_prismatic_solution(rng):
    a = arm("scara")
    q_true = a.random_q(rng)
    r = a.solve(a.fk(q_true).translation, q0=a.middle)
    assert r.success
    i = a.kinematics.joint_index("quill")
    assert a.lower[i] <= r.q[i] <= a.upper[i]


def test_unconverged_never_success(monkeypatch):
    # A solver that lies about convergence is caught by the FK check.
    from armik.solvers.answers import one
    from armik.solvers.numeric import dls

    def liar(arm_, target, q0, opts, all_solutions):
        return one(q0 + 0.1, Status.CONVERGED, "trust me")

    import dataclasses

    spec = registry.get("dls")
    lying = dataclasses.replace(spec, run=liar, prepare_pose=None)  # the general path
    monkeypatch.setitem(registry._REGISTRY, "dls", lying)
    a = armik.load("ur5")  # a fresh arm: no solve prepared with the honest spec
    r = a.solve(a.fk(a.middle), solver="dls")
    assert not r.success and r.status == "not_converged" and "check failed" in r.reason
    assert dls  # the real module is untouched


def test_restart_seeds_cover_the_box_reproducibly():
    a = model("kinova")  # bounded and continuous joints
    s1 = pieces.RestartSeeds(a, 3)
    s2 = pieces.RestartSeeds(a, 3)
    pts = np.array([s1.next() for _ in range(600)])  # wraps around the 512-point table
    np.testing.assert_array_equal(pts[:10], [s2.next() for _ in range(10)])
    lo, hi = a.sampling_box()
    assert np.all(pts >= lo) and np.all(pts <= hi)
    # even coverage: every joint's range split in 8 bins gets 1/8 of the points, +-30 %
    for j in range(a.dof):
        counts = np.histogram(pts[:512, j], bins=8, range=(lo[j], hi[j]))[0]
        assert np.all(np.abs(counts - 64) <= 20)


def test_restart_seeds_past_the_table_are_new_points():
    """A search of more restarts than the table holds (1000 by default against 512 points,
    4 scored a restart) draws new points on each pass, turned by another rotation; the
    first pass is the table's own, as before."""
    a = model("kinova")
    seeds = pieces.RestartSeeds(a, 3)
    n = a.kernel_chain.flat.halton.shape[0]
    pts = np.array([seeds.next() for _ in range(3 * n)])
    lo, hi = a.sampling_box()
    assert np.all(pts >= lo) and np.all(pts <= hi)
    u = (a.kernel_chain.flat.halton + seeds.shift) % 1.0  # the first pass, as the table
    np.testing.assert_allclose(pts[:n], lo + (hi - lo) * u, rtol=0, atol=1e-12)
    for passes in (1, 2):  # no point of a later pass is one of an earlier pass's
        later = pts[passes * n : (passes + 1) * n]
        gaps = np.abs(later[:, None, :] - pts[None, : passes * n, :]).max(axis=2)
        assert gaps.min() > 1e-3
    for j in range(a.dof):  # and each pass covers the box as evenly as the first
        counts = np.histogram(pts[n : 2 * n, j], bins=8, range=(lo[j], hi[j]))[0]
        assert np.all(np.abs(counts - n / 8) <= 20)


def test_beyond_reach_returns_the_seed_at_once():
    a = arm("ur5")
    q0 = a.middle + 0.2
    r = a.solve([3.0, 0.0, 0.0], q0=q0)
    assert r.status == "unreachable" and "beyond the arm's reach" in r.reason
    np.testing.assert_array_equal(r.q, q0)
    assert r.iterations == 0


def test_halton_table_is_the_radical_inverse():
    table = numeric._halton(3, n=8)
    np.testing.assert_allclose(table[:4, 0], [1 / 2, 1 / 4, 3 / 4, 1 / 8])
    np.testing.assert_allclose(table[:4, 1], [1 / 3, 2 / 3, 1 / 9, 4 / 9])
    np.testing.assert_allclose(table[:4, 2], [1 / 5, 2 / 5, 3 / 5, 4 / 5])


def test_restart_pick_is_the_candidate_nearest_the_target(rng):
    a = model("panda")
    target = parse_target(a.fk(a.random_q(rng)))
    pb = pieces.Problem.build(a, target, a.middle, Options())
    picker = pieces.RestartSeeds(a, 5)
    plain = pieces.RestartSeeds(a, 5)
    for _ in range(3):
        picked = a.from_pin(picker.pick(pb))
        candidates = [plain.next() for _ in range(numeric.RESTART_CANDIDATES)]
        distances = [np.linalg.norm(a.fk(c).translation - target.position) for c in candidates]
        np.testing.assert_array_equal(picked, candidates[int(np.argmin(distances))])


def test_descent_stops_at_a_known_minimum(rng):
    a = model("ur5")
    q_star = a.random_q(rng)
    pb = pieces.Problem.build(a, parse_target(a.fk(q_star)), a.middle, Options())
    start = a.to_pin(q_star + 0.01)
    step = qp.make_step("osqp")
    *_, ok = pieces.descend(pb, start, step, 100, math.inf)
    assert ok  # on its own it converges to q_star ...
    # ... but told that an earlier attempt got stuck there, it gives up on the way
    s, its, ok = pieces.descend(pb, start, step, 100, math.inf, a.to_pin(q_star)[None, :])
    assert not ok and its < 5 and s.sq < numeric.CAREFUL_BELOW


@pytest.mark.parametrize("solver", NUMERIC)
@pytest.mark.parametrize(
    ("budget", "said"),
    [
        ({"max_restarts": 20}, "restart limit (max_restarts=20)"),
        ({"iteration_budget": 300}, "iteration budget (300 iterations"),
    ],
)
def test_a_batch_row_that_does_not_converge_says_why_as_solve_does(solver, budget, said):
    """What ended the search (the restart limit or the budget) and its best errors, in the
    words ``solve`` gives the same target from the same seed; a batch said "the time budget
    (..., at most N restarts)" whatever ended it."""
    a = arm("panda")
    hopeless = pin.SE3(pin.utils.rotate("x", 2.0), np.array([0.0, 0.0, -0.3]))
    rows = [a.fk(a.random_q(1)), hopeless]
    b = a.solve_batch(rows, solver=solver, seed=0, workers=1, progress=False, **budget)
    r = a.solve(hopeless, solver=solver, seed=0, **budget)
    assert b.success.tolist() == [True, False] and not r.success
    assert said in r.reason and b[1].reason == r.reason
    np.testing.assert_array_equal(b.q[1], r.q)
