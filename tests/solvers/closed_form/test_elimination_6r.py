"""The 6R elimination (Raghavan-Roth): its equations' coefficients read by sampling, a cut
chosen per arm, and its answers against the 2-D search (the oracle) on random arms with
every axis random and on arms whose parallel axes rule out most cuts; every answer measured
by Pinocchio's FK here; a target it is unsure of handed to the search."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers.closed_form import elimination, elimination_6r, sixr

from .random_arms import load_arm, wrapped_distance


def _pose_error(arm, q, T) -> float:
    return float(np.linalg.norm(pin.log6(arm.fk(q).inverse() * T).vector))


def _fourteen(p, d):
    return np.r_[p, d, p @ p, p @ d, np.cross(p, d), (p @ p) * d - 2 * (p @ d) * p]


def _within(a, rows) -> bool:
    return any(wrapped_distance(a, b) < 1e-6 for b in rows)


@pytest.fixture(scope="module")
def arms():
    rng = np.random.default_rng(21)
    kinds = ["general"] * 4 + ["two_parallel", "two_intersecting"]
    return [load_arm(kind, rng) for kind in kinds]


def test_each_side_has_degree_one_in_each_joint():
    """Raghavan and Roth's property the sampling relies on: the 14 quantities of each side
    equal their fitted (s, c, 1) expansion at angles other than the samples."""
    rng = np.random.default_rng(3)
    arm = load_arm("general", rng)
    plan = elimination_6r.classify(arm.kinematics)
    chain = plan.chain
    R, pos = sixr.forward(chain.h, chain.p, chain.R_tip0, rng.uniform(-3, 3, 6))
    R, pos = np.array(R).reshape(3, 3), np.array(pos)
    for cut in (5, 4, 9):
        LH, LR, LT = np.empty((6, 3)), np.empty((6, 9)), np.empty((6, 3))
        elimination._loop(chain.h, chain.p, chain.R_tip0, tuple(R.ravel()), tuple(pos), cut,
                          LH, LR, LT)  # fmt: skip
        Lc, Rc = np.empty((14, 3, 3, 3)), np.empty((14, 3, 3))
        elimination._sides(LH, LR, LT, Lc, Rc)
        for _ in range(3):
            t = rng.uniform(-3, 3, 5)
            b = [np.array([np.sin(x), np.cos(x), 1.0]) for x in t]
            left = np.einsum("nijk,i,j,k->n", Lc, b[2], b[3], b[4])
            right = np.einsum("nij,i,j->n", Rc, b[0], b[1])
            # the same quantities, straight from the loop's rotations
            rot = [pin.exp3(LH[k] * t[k]) for k in range(5)]
            L = [LR[k].reshape(3, 3) for k in range(6)]
            pv = rot[2] @ (L[2] @ (rot[3] @ (L[3] @ (rot[4] @ LT[4]) + LT[3])) + LT[2])
            lv = rot[2] @ L[2] @ rot[3] @ L[3] @ rot[4] @ L[4] @ LH[5]
            o = -L[5].T @ LT[5]
            v = L[0].T @ (rot[0].T @ o - LT[0])
            pr = L[1].T @ (rot[1].T @ v - LT[1])
            lr = L[1].T @ rot[1].T @ L[0].T @ rot[0].T @ L[5].T @ LH[5]
            np.testing.assert_allclose(left, _fourteen(pv, lv), atol=1e-12)
            np.testing.assert_allclose(right, _fourteen(pr, lr), atol=1e-12)


def test_auto_takes_it_for_every_solution_only(arms):
    for arm in arms:
        plan = elimination_6r.classify(arm.kinematics)
        assert not isinstance(plan, str), plan
        T = arm.fk(arm.middle)
        assert arm.solve_all(T)[0].solver == "elimination_6r"
        assert arm.solve(T).solver == "dls"
    ur5 = armik.load("ur5")  # a closed form keeps its arms
    assert ur5.solve_all(ur5.fk(np.full(6, 0.3)))[0].solver == "three_parallel"


def test_not_a_6r_arm_is_refused_with_the_reason():
    assert elimination_6r.classify(armik.load("panda").kinematics) == (
        "the chain has 7 joints, this class needs 6"
    )


def test_the_same_solutions_as_the_search_every_one_verified(arms):
    rng = np.random.default_rng(8)
    found = checked = 0
    for arm in arms:
        for _ in range(4):
            q = arm.random_q(rng)
            T = arm.fk(q)
            ours = arm.solve_all(T, solver="elimination_6r")
            ok = [r.q for r in ours if r.success]
            for a in ok:  # every success reaches the target, within the limits, once
                assert _pose_error(arm, a, T) < 1e-9
                assert np.all(a >= arm.lower) and np.all(a <= arm.upper)
            for i, a in enumerate(ok):
                assert all(wrapped_distance(a, b) > 1e-6 for b in ok[i + 1 :])
            found += _within(q, ok)
            search = [r.q for r in arm.solve_all(T, solver="general_6r") if r.success]
            # the search can miss a solution, never find one the elimination lacks
            assert all(_within(s, ok) for s in search)
            checked += 1
    assert found == checked


def test_an_arm_with_parallel_axes_gets_a_regular_cut():
    """Axes 2 and 3 parallel leave M(x3) singular with joint 6 dropped (Raghavan and
    Roth's first choice): the plan takes another, and finds every search answer."""
    rng = np.random.default_rng(5)
    arm = load_arm("two_parallel", rng)
    plan = elimination_6r.classify(arm.kinematics)
    assert not isinstance(plan, str), plan
    chain = plan.chain
    K, state = np.empty((24, 24)), np.empty(elimination.SIZE)
    R, pos = sixr.forward(chain.h, chain.p, chain.R_tip0, rng.uniform(-3, 3, 6))
    R, pos = np.array(R).reshape(3, 3), np.array(pos)
    args = (chain.h, chain.p, chain.R_tip0, R, pos)
    pivot, _ = elimination.companion(*args, np.int64(plan.cut), K, state)
    assert pivot >= elimination.REGULAR
    for _ in range(4):
        q = arm.random_q(rng)
        T = arm.fk(q)
        ok = [r.q for r in arm.solve_all(T, solver="elimination_6r") if r.success]
        assert _within(q, ok)
        search = [r.q for r in arm.solve_all(T, solver="two_parallel") if r.success]
        assert all(_within(s, ok) for s in search)


def test_a_target_it_is_unsure_of_goes_to_the_search(arms, monkeypatch):
    arm = arms[4]  # axes 2 and 3 parallel: two_parallel's search
    T = arm.fk(arm.random_q(np.random.default_rng(2)))
    assert elimination_6r.applies(arm.kinematics) is None  # its cut chosen (and kept) first
    monkeypatch.setattr(elimination_6r, "_rows", lambda *a: (0, False, 0.0))
    got = arm.solve_all(T, solver="elimination_6r")
    want = arm.solve_all(T, solver="two_parallel")
    assert [r.reason for r in got] == [r.reason for r in want]
    np.testing.assert_array_equal([r.q for r in got], [r.q for r in want])


def test_the_search_adds_what_an_unsure_elimination_lacks(arms, monkeypatch):
    arm = arms[4]
    rng = np.random.default_rng(9)
    q = arm.random_q(rng)
    T = arm.fk(q)
    full = [r.q for r in arm.solve_all(T) if r.success]
    rows = elimination_6r._rows

    def half(plan, R, pos, q0, lower, upper, out):  # half its rows, and unsure
        n, _, regular = rows(plan, R, pos, q0, lower, upper, out)
        return n // 2, False, regular

    monkeypatch.setattr(elimination_6r, "_rows", half)
    results = arm.solve_all(T)
    got = [r.q for r in results if r.success]
    assert len(got) == len(full) and all(_within(a, got) for a in full)
    words = {r.reason.split(";")[0] for r in results if r.success}
    assert words == {elimination_6r.CLOSED_FORM, "one-dimensional search (axes 2 and 3 parallel)"}


def test_out_of_reach_is_no_success(arms):
    T = pin.SE3(np.eye(3), np.array([10.0, 0.0, 0.0]))
    results = arms[0].solve_all(T)
    assert results and not any(r.success for r in results)


@pytest.mark.parametrize("config", ["449", "433", "265", "164"])
def test_targets_next_to_folds_keep_their_configuration(config):
    """The two_parallel search's hardest targets (two solutions about to merge): solve_all
    (the elimination, the search behind it where it is unsure) finds the configuration."""
    from .test_search_1d import NEAR_FOLDS

    arm = armik.load_string(NEAR_FOLDS["urdf"], base="world", tip="tool")
    q = np.array(NEAR_FOLDS["configurations"][config])
    T = arm.fk(q)
    results = arm.solve_all(T)
    assert results[0].solver == "elimination_6r"
    ok = [r.q for r in results if r.success]
    assert _within(q, ok)
    assert all(_pose_error(arm, a, T) < 1e-9 for a in ok)


def test_a_polished_root_a_hair_past_a_limit_is_put_on_it():
    """The xArm 7 with joint 4 held, joint 2 on its lower limit at a singular pose (joint 5
    at 2 pi): Newton left the double root 3.3e-9 rad past the limit, failed as joint_limits;
    put on the limit, it is verified by forward kinematics."""
    a = armik.load("xarm7")
    q = np.array([5.4497, -2.059, 5.6913, 1.2957, 2 * np.pi, 1.5397, 5.8185])
    q[1] = a.lower[1]
    T = a.fk(q)
    found = [r for r in a.solve_all(T, hold={"joint4": float(q[3])}, q0=q) if r.success]
    on_limit = [r for r in found if r.q[1] == a.lower[1]]
    assert on_limit and wrapped_distance(on_limit[0].q, q) < 1e-6
    for r in found:
        assert a.within_limits(r.q) and _pose_error(a, r.q, T) < 1e-6


@pytest.mark.parametrize("held", ["panda_joint4", "panda_joint6"])
def test_a_family_of_solutions_is_flagged_singular(held):
    """The Panda with joint 2 at 0 (axes 1 and 3 in line: the target fixes only q1 + q3) and
    one joint held: the search's grid gave samples of the family, 5 degrees apart, each
    listed as a solution of its own and none flagged singular."""
    a = armik.load("panda")
    q = np.array([0.0, 0.0, 0.0, -np.pi / 2, np.pi / 2, np.pi, -np.pi / 2])
    T = a.fk(q)
    hold = {held: float(q[a.joint_names.index(held)])}
    found = [r for r in a.solve_all(T, hold=hold, q0=q) if r.success]
    assert len(found) > 1
    for r in found:
        assert abs(r.q[0] + r.q[2]) < 1e-6  # on the family
        assert r.singular and "family of solutions" in r.reason
    # a regular target of the same arm: nothing flagged
    q = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])
    regular = a.solve_all(a.fk(q), hold={held: float(q[a.joint_names.index(held)])})
    assert any(r.success for r in regular)
    assert not any(r.singular for r in regular)


def test_a_root_of_a_rank_deficient_pose_on_a_limit_is_put_on_it():
    """The Panda with joint 4 held at -pi/2, joint 1 on its upper limit, at a pose where the
    six joints left lose a rank (joint 6 at pi): Newton left the root 1.4e-7 rad past the
    limit (more than 1e-7), failed as joint_limits, and solve_all had no success."""
    a = armik.load("panda")
    q = np.array([a.upper[0], np.pi / 2, 0.0, -np.pi / 2, -np.pi / 2, np.pi, -np.pi / 2])
    T = a.fk(q)
    found = [r for r in a.solve_all(T, hold={"panda_joint4": float(q[3])}, q0=q) if r.success]
    assert any(wrapped_distance(r.q, q) < 1e-5 for r in found)
    for r in found:
        assert a.within_limits(r.q) and _pose_error(a, r.q, T) < 1e-6


@pytest.mark.parametrize("off", [5e-7, 9e-7])
def test_a_regular_root_past_a_limit_stays_past_it(off):
    """The Panda with joint 4 held, the target made with joint 1 ``off`` rad past its upper
    limit at a regular pose (the Jacobian far from singular): Newton leaves that root within
    1e-14, so it lies past the limit; it was put on the limit (sixr.POLISHED_SNAP, meant for
    double roots), an answer 3e-7 m off called a success (or, to tighter tolerances, failed
    as not converged)."""
    a = armik.load("panda")
    q = np.array([a.upper[0] + off, 0.4, 0.3, -np.pi / 2, 0.2, 1.9, 0.5])
    T = a.fk(q)
    found = a.solve_all(T, hold={"panda_joint4": float(q[3])}, q0=np.clip(q, a.lower, a.upper))
    nearest = min(found, key=lambda r: wrapped_distance(r.q, q))
    assert not nearest.success and nearest.status == armik.Status.JOINT_LIMITS
    assert wrapped_distance(nearest.q, q) < 1e-9
    for r in found:
        if r.success:
            assert a.within_limits(r.q) and _pose_error(a, r.q, T) < 1e-9


@pytest.mark.parametrize(
    "q",
    [
        [np.pi, 2.0944, -np.pi, -0.19198, np.pi, 2.295107653589793, np.pi],
        [np.pi, 2.0944, np.pi, 1.86751, np.pi, 2.295107653589793, -np.pi / 2],
        [-np.pi / 2, 0.0177, -np.pi / 2, 3.927, 0.0, 0.7243113267948965, np.pi],
    ],
)
def test_each_solution_of_a_multiple_root_is_found(q):
    """The xArm 7 with joint 7 held, joint 5 on 0 or pi: four solutions share q5 (a
    four-fold root; two of them joint 1 turned by pi, the shoulder's axes 5e-7 m from
    meeting). Inverse iteration gave mixtures that Newton took to three of them, and the
    search behind found none; read off M(x3)'s null space, every one is found."""
    a = armik.load("xarm7")
    q = np.array(q)
    assert a.within_limits(q)
    T = a.fk(q)
    hold = {"joint7": float(q[6])}
    results = a.solve_all(T, hold=hold)
    assert results[0].solver == "elimination_6r"
    ok = [r.q for r in results if r.success]
    assert _within(q, ok)
    for r in ok:
        assert a.within_limits(r) and _pose_error(a, r, T) < 1e-9
    assert a.solve(T, hold=hold).success
