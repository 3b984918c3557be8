"""Solving with collisions checked: branches, the collision status, lying solvers, batches."""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers import registry
from armik.solvers.answers import one
from armik.status import Status

from ..conftest import arm

TABLE = armik.HalfSpace((0, 0, 1), 0)


def _elbow_sphere(a, q, radius=0.06):
    """A sphere around the elbow joint at ``q``, in the base frame."""
    a.fk(q)
    m = a.kinematics
    return armik.Sphere(radius, m.T_base_world.act(m.data.oMi[3].translation))


def test_an_obstacle_across_the_seeds_branch_forces_another_branch():
    ur5 = arm("ur5")
    found = 0
    for q in ur5.random_q(21, n=40):
        T = ur5.fk(q)
        plain = ur5.solve(T, q0=q)
        sphere = _elbow_sphere(ur5, q)
        every = ur5.solve_all(T, q0=q, obstacles=[sphere])
        free = [r for r in every if r.success]
        if not free or not ur5.in_collision(plain.q, [sphere]):
            continue
        r = ur5.solve(T, q0=q, obstacles=[sphere])
        assert r.success and r.branch != plain.branch
        assert not ur5.in_collision(r.q, [sphere])
        np.testing.assert_array_equal(r.q, free[0].q)  # the nearest free branch
        assert r.extra["min_distance"] >= 0 and r.extra["closest_pair"][1].startswith("obst")
        assert "collision-free: closest" in r.reason
        assert any(x.status == "collision" for x in every)
        found += 1
    assert found >= 5


@pytest.mark.parametrize("self_collision", [False, True])
def test_a_closed_form_runs_its_kernel_once_for_a_checked_answer(monkeypatch, self_collision):
    """Its branches come from one kernel run and are checked nearest first, also when the
    nearest collides (the plain solve's kernel and the search's were two runs)."""
    ur5 = arm("ur5")
    family = registry.get("three_parallel").run.__self__
    calls = []
    for name in ("kernel", "solve_into"):  # the general path's entry and the prepared one
        compiled = getattr(family, name)
        counted = (lambda f: lambda *a: calls.append(f) or f(*a))(compiled)
        monkeypatch.setattr(family, name, counted)
    colliding = 0
    for q in ur5.random_q(21, n=12):
        T = ur5.fk(q)
        sphere = _elbow_sphere(ur5, q)
        calls.clear()
        r = ur5.solve(T, q0=q, obstacles=[sphere], self_collision=self_collision)
        assert r.solver == "three_parallel" and len(calls) == 1, (r.reason, calls)
        colliding += r.success and not np.array_equal(r.q, ur5.solve(T, q0=q).q)
    assert colliding >= 3  # answers where the nearest branch collided


@pytest.mark.parametrize("name, solver", [("ur5", "auto"), ("panda", "dls")])
def test_a_target_reachable_only_in_collision_is_collision_naming_the_pair(name, solver):
    a = arm(name)
    T = a.fk(a.random_q(4))
    blob = armik.Sphere(0.05, T.translation)  # every answer puts the tip inside it
    r = a.solve(T, solver=solver, obstacles=[blob], timeout=0.01)
    assert not r.success and r.status == armik.Status.COLLISION
    assert "in collision" in r.reason and "obstacles[0] (Sphere)" in r.reason
    assert r.extra["min_distance"] < 0 and r.extra["closest_pair"][1] == "obstacles[0] (Sphere)"
    assert r.position_error < 1e-6  # reached, within the limits: only the collision fails
    budget = a.solve(T, solver=solver, obstacles=[blob], iteration_budget=300)
    assert budget.status == "collision" and budget.iterations <= 300 + 100


def test_numeric_solvers_restart_until_free():
    panda = arm("panda")
    rng = np.random.default_rng(5)
    restarted = 0
    for _ in range(30):
        q = panda.random_q(rng)
        T = panda.fk(q)
        plain = panda.solve(T)
        sphere = _elbow_sphere(panda, plain.q, 0.05)
        if panda.in_collision(q, [sphere]):
            continue  # the target's own configuration must stay free
        r = panda.solve(T, obstacles=[sphere], self_collision=False)
        assert r.success and not panda.in_collision(r.q, [sphere])
        restarted += r.restarts > plain.restarts
    assert restarted >= 3


def test_a_lying_solver_is_caught_by_the_collision_check(monkeypatch):
    ur5 = armik.load("ur5")  # a fresh arm: nothing prepared with the honest spec
    q_bad = ur5.random_q(8)
    T = ur5.fk(q_bad)
    box = armik.Sphere(0.08, T.translation)

    def liar(arm_, target, q0, opts, all_solutions):
        return one(q_bad.copy(), Status.CONVERGED, "trust me")

    lying = dataclasses.replace(registry.get("dls"), run=liar, prepare_pose=None)
    monkeypatch.setitem(registry._REGISTRY, "dls", lying)
    honest = ur5.solve(T, solver="dls")
    assert honest.success  # it does reach the pose
    r = ur5.solve(T, solver="dls", obstacles=[box], timeout=0.005)
    assert not r.success and r.status == "collision" and "obstacles[0]" in r.reason


def test_margin_refuses_near_misses():
    ur5 = arm("ur5")
    q = ur5.random_q(2)
    T = ur5.fk(q)
    r = ur5.solve(T, q0=q, obstacles=[TABLE])
    d = r.extra["min_distance"]
    assert r.success and d > 0
    tight = ur5.solve_all(T, q0=q, obstacles=[TABLE], margin=d + 1e-4)
    assert all(x.extra["min_distance"] >= d + 1e-4 for x in tight if x.success)
    assert not any(np.array_equal(x.q, r.q) and x.success for x in tight)


def test_collisions_off_keep_the_answers_and_the_prepared_path():
    ur5 = arm("ur5")
    T = ur5.fk(ur5.random_q(9))
    a = ur5.solve(T)
    b = ur5.solve(T, obstacles=[], self_collision=False)
    np.testing.assert_array_equal(a.q, b.q)
    assert a.reason == b.reason and "collision" not in a.reason and a.extra == {}


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_solve_batch_equals_a_loop_of_solve_with_obstacles(name, tmp_path):
    a = arm(name)
    obstacles = (TABLE, armik.Box((0.2, 0.2, 0.2), (0.45, 0.0, 0.3)))
    Q = a.random_q(13, n=12)
    T = a.fk_batch(Q)
    opts = dict(obstacles=obstacles, self_collision=True, iteration_budget=2000)
    res = a.solve_batch(T, q0=a.middle, progress=False, **opts)
    for i in range(len(T)):
        r = a.solve(T[i], q0=a.middle, **opts)
        assert res.status[i] == r.status.value
        np.testing.assert_array_equal(res.q[i], r.q)
        # coal's GJK starts from the last call's guess: the same q, the last bits may differ
        assert res.min_distance[i] == pytest.approx(r.min_distance, abs=1e-9)
        assert res.closest_pair(i) == r.closest_pair
        assert res[i].closest_pair == r.closest_pair
        if r.success:
            assert not a.in_collision(r.q, obstacles, self_collision=True)
            # the clearance in words, as the single solve's reason ends
            assert res.reason(i).endswith(r.reason.rsplit("; ", 1)[1])
    assert res.success.any() and np.isfinite(res.min_distance).all()
    loaded = armik.BatchResult.load(res.save(tmp_path / "r.npz"))
    np.testing.assert_array_equal(loaded.min_distance, res.min_distance)
    assert [loaded.reason(i) for i in range(len(T))] == [res.reason(i) for i in range(len(T))]
    assert [loaded.closest_pair(i) for i in range(len(T))] == [
        res.closest_pair(i) for i in range(len(T))
    ]
    plain = a.solve_batch(T[:3], progress=False, iteration_budget=2000)
    assert np.isnan(plain.min_distance).all() and plain.closest_pair(0) is None
    assert plain[0].min_distance is None


def test_solve_path_keeps_clear_of_an_obstacle():
    ur5 = arm("ur5")
    q = ur5.random_q(1)
    T = ur5.fk(q)
    line = [pin.SE3(T.rotation, T.translation + [0, 0.005 * k, 0]) for k in range(6)]
    box = armik.Box((0.05, 0.05, 0.05), T.translation + [0.0, 0.0, 0.6])
    if ur5.in_collision(q, [box]):
        pytest.skip("the start collides")
    path = ur5.solve_path(line, q, obstacles=[box])
    for i in np.flatnonzero(path.success):
        assert not ur5.in_collision(path.q[i], [box])
    assert path.success.all()


def test_a_folded_elbow_self_collides_and_is_never_a_success():
    ur5 = arm("ur5")
    rng = np.random.default_rng(0)
    caught = other_branch = 0
    for _ in range(12):
        q = ur5.random_q(rng)
        q[2] = rng.choice([-1.0, 1.0]) * rng.uniform(2.8, 3.1)  # the forearm folded back
        d, pair = ur5.min_distance(q, self_collision=True)
        if d >= 0:
            continue
        caught += 1
        assert "upper_arm_link" in pair or "forearm_link" in pair
        assert ur5.in_collision(q, self_collision=True)
        T = ur5.fk(q)
        plain = ur5.solve(T, q0=q)
        assert plain.success and np.allclose(plain.q, q, atol=1e-6)  # blind: the folded arm
        r = ur5.solve(T, q0=q, self_collision=True)
        if r.success:
            assert r.branch != plain.branch and r.min_distance >= 0
            assert not ur5.in_collision(r.q, self_collision=True)
            other_branch += 1
        else:
            assert r.status == "collision" and r.closest_pair is not None
            assert f"{r.closest_pair[0]} and {r.closest_pair[1]}" in r.reason
    assert caught >= 8 and other_branch >= 1


def test_paths_around_an_obstacle_go_round_it_or_say_where_they_cannot():
    panda = arm("panda")
    budget = dict(iteration_budget=3000)
    around = checked = 0
    for seed in range(40):
        q = panda.random_q(seed)
        T = panda.fk(q)
        line = [pin.SE3(T.rotation, T.translation + [0, 0.01 * k, 0]) for k in range(8)]
        plain = panda.solve_path(line, q, **budget)
        if not plain.success.all():
            continue
        panda.fk(plain.q[-1])  # a sphere beside the elbow at the end of the blind path
        sphere = armik.Sphere(0.06, panda.kinematics.data.oMi[4].translation + [0, 0.1, 0])
        hit = [panda.in_collision(x, [sphere]) for x in plain.q]
        if hit[0] or not any(hit):
            continue
        checked += 1
        path = panda.solve_path(line, q, obstacles=[sphere], **budget)
        previous = q
        for i in range(len(line)):
            if path.success[i]:
                assert not panda.in_collision(path.q[i], [sphere])
                assert np.abs(path.q[i] - previous).max() <= 0.5  # no silent jump
            else:
                assert path.status[i] in ("discontinuous", "collision")
            if path.success[i] or path.status[i] == "discontinuous":
                previous = path.q[i]
        around += bool(path.success.all())
    assert checked >= 4 and around >= 1


@pytest.mark.parametrize("solver", ["auto", "dls"])
def test_weighted_with_collisions_reports_the_true_distances(solver):
    """A weighted request with obstacles checked reports its true distances to the target
    and what its verdict measured beside them, as without obstacles."""
    ur5 = arm("ur5")
    q = ur5.random_q(4)
    T = ur5.fk(q)
    aside = pin.SE3(T.rotation, T.translation + np.array([0.0, 0.0, 0.05]))
    weights = (1, 1, 0, 1, 1, 1)  # z not measured: 5 cm off along it is a success
    far = [armik.Sphere(0.05, (3.0, 3.0, 3.0))]
    plain = ur5.solve(aside, q0=q, weights=weights, solver=solver)
    r = ur5.solve(aside, q0=q, weights=weights, solver=solver, obstacles=far)
    for got in (plain, r):
        assert got.success, got.reason
        true = np.linalg.norm(ur5.fk(got.q).translation - aside.translation)
        assert got.position_error == pytest.approx(true, abs=1e-9) and true > 0.01
        assert got.measured is not None and got.measured[0] < 1e-4
