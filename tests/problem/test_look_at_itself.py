"""A look-at with no line of sight is never a success: refused by name where the request
itself says so, failed by the verdict where an answer stands on the point."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from tests.conftest import arm as bundled


@pytest.mark.parametrize("holder", ["position", "pose"])
def test_a_frame_held_on_the_point_it_looks_at_is_refused(holder):
    panda = bundled("panda")
    T = panda.fk(panda.middle)
    p = T.translation
    there = armik.Position(p) if holder == "position" else armik.Pose(T)
    with pytest.raises(armik.TargetError, match="LookAt point"):
        panda.solve([there, armik.LookAt(p)])
    # a box to stand back in leaves a line of sight: no refusal
    panda.solve([armik.Position(p, bounds=(0.05,) * 3), armik.LookAt(p)], iteration_budget=50)


def test_an_answer_standing_on_the_point_is_no_success():
    panda = bundled("panda")
    q = panda.middle
    p = panda.fk(q).translation
    # the task's own measure and the compiled path's region measure refuse it
    assert not armik.LookAt(p).measure(panda.fk(q), 1e-6, 1e-6).within
    assert not panda.solve(armik.LookAt(p), q0=q, iteration_budget=1, max_restarts=0).success
    for solver in ("auto", "dls"):
        r = panda.solve(armik.LookAt(p), q0=q, solver=solver, iteration_budget=200)
        if r.success:  # only by looking at it from elsewhere
            assert np.linalg.norm(panda.fk(r.q).translation - p) > 1e-9


def test_the_keyword_look_at_of_the_targets_own_point_is_refused_by_name():
    """``solve(p, look_at=p, cone=...)``'s check (``refuse_looking_from_target``): the
    refusal of ``[Position(p), LookAt(p)]``, for one target or a batch's; a box or a freed
    position, another point or no look-at pass."""
    from armik.problem.problem import refuse_looking_from_target
    from armik.solve.read import options
    from armik.targets.aim import aim_of

    def asked(**given):  # (the target's aim, the options), as a call's keywords are read
        sight = {k: given.pop(k) for k in ("cone", "look_at") if k in given}
        return aim_of(**sight), options(given)

    p = np.array([0.4, 0.1, 0.5])
    looking = asked(cone=(0, 0, 1, 0.0), look_at=p)
    with pytest.raises(armik.TargetError, match=r"look_at point .* the target's position"):
        refuse_looking_from_target(p, *looking)
    with pytest.raises(armik.TargetError, match="target 1's position"):
        refuse_looking_from_target([p + 0.1, p], *looking)
    weighted = asked(cone=(0, 0, 1, 0.0), look_at=p, weights=(1,) * 6)
    with pytest.raises(armik.TargetError):
        refuse_looking_from_target(p, *weighted)
    for aim, opts in (
        asked(cone=(0, 0, 1, 0.0), look_at=p, bounds=(0.05,) * 3 + (0,) * 3),
        asked(cone=(0, 0, 1, 0.0), look_at=p, bounds=(np.inf,) * 3 + (0,) * 3),
        asked(cone=(0, 0, 1, 0.0), look_at=p, weights=(0, 0, 0, 1, 1, 1)),
        asked(cone=(0, 0, 1, 0.0), look_at=p + 0.1),
        asked(cone=(0, 0, 1, 0.0)),
    ):
        refuse_looking_from_target(p, aim, opts)


def test_the_keyword_look_at_of_its_own_point_is_refused_on_every_route():
    panda = bundled("panda")
    T = panda.fk(panda.middle)
    p = T.translation
    sight = {"look_at": p, "cone": (0, 0, 1, 0.0)}
    with pytest.raises(armik.TargetError, match="the target's position"):
        panda.solve(p, **sight)
    with pytest.raises(armik.TargetError, match="the target's position"):
        panda.solve_all(p, **sight)
    with pytest.raises(armik.TargetError, match="target 1's position"):
        panda.solve_batch([p + 0.05, p], workers=1, **sight)
    with pytest.raises(armik.TargetError, match="target 0's position"):
        panda.solve_path([p, p + 0.01], panda.middle, **sight)
    # another point: solved
    assert panda.solve(p, look_at=p + [0.0, 0.0, -0.3], cone=(0, 0, 1, 0.3)).success


def test_a_look_at_seeded_on_its_point_moves_off_it():
    # the compiled step measured no error on the point (any axis "looked at it") and claimed
    # convergence at once; it measures pi there, as the verdict does, and restarts
    panda = bundled("panda")
    q = panda.middle
    p = panda.fk(q).translation
    for solver in ("auto", "dls"):
        r = panda.solve(armik.LookAt(p), q0=q, solver=solver, iteration_budget=2000)
        assert r.success, r.reason
        assert np.linalg.norm(panda.fk(r.q).translation - p) > 1e-6


def test_a_box_too_small_to_stand_back_in_is_refused_as_no_box():
    """A box of 1e-7 m around the point looked at leaves the frame within 1e-6 m of it, as
    an exact position does: refused by name in both spellings; a box of 1e-4 m is taken."""
    ur5 = bundled("ur5")
    p = ur5.fk(ur5.random_q(2)).translation
    tiny = (1e-7,) * 3
    with pytest.raises(armik.TargetError, match=r"LookAt point .* box .* wider than 1e-06 m"):
        ur5.solve([armik.Position(p, bounds=tiny), armik.LookAt(p)])
    with pytest.raises(armik.TargetError, match=r"the target's position.* wider than 1e-06 m"):
        ur5.solve(p, look_at=p, cone=(0, 0, 1, 0.0), bounds=tiny + (0, 0, 0))
    r = ur5.solve([armik.Position(p, bounds=(1e-4,) * 3), armik.LookAt(p)], iteration_budget=2000)
    assert r.success, r.reason
    F = ur5.fk(r.q)
    sight = p - F.translation
    assert np.linalg.norm(sight) > 1e-6 and np.all(np.abs(sight) <= 1e-4 + 1e-6)
    assert float(F.rotation[:, 2] @ sight) >= np.linalg.norm(sight) * np.cos(1e-6)


def test_a_frame_within_a_micrometre_of_the_point_looks_at_nothing():
    """The measure refuses a frame standing within 1e-6 m of the point (the distance within
    which the request is refused: no line of sight), whatever the tolerances. It refused only
    within 1e-9 m: a secondary posture moved the task solver's answer 4e-8 to 8e-8 m from
    the point, called a success."""
    ur5 = bundled("ur5")
    q = ur5.middle
    T = ur5.fk(q)
    ahead = [T.translation + T.rotation[:, 2] * d for d in (5e-7, 2e-6)]  # along the tool's z
    for tol in (1e-6, 1e-9, 1e-3):
        assert not armik.LookAt(ahead[0]).measure(T, tol, 1e-6).within
        assert armik.LookAt(ahead[1]).measure(T, tol, 1e-6).within
    rng = np.random.default_rng(8)
    for _ in range(5):
        qt = ur5.random_q(rng)
        qt[0] = rng.uniform(-0.8, 0.8)
        p = ur5.fk(qt).translation
        tasks = [armik.Position(p, bounds=(0.05,) * 3), armik.LookAt(p)]
        r = ur5.solve(
            tasks, q0=ur5.middle, secondary=[armik.Posture(ur5.middle)], iteration_budget=2000
        )
        if r.success:
            F = ur5.fk(r.q)
            sight = p - F.translation
            assert np.linalg.norm(sight) > 1e-6, r.reason
            assert np.all(np.abs(sight) <= 0.05 + 1e-6)
            assert float(F.rotation[:, 2] @ sight) >= np.linalg.norm(sight) * np.cos(1e-6)


def test_the_compiled_verdict_refuses_a_tip_within_a_micrometre_of_its_point():
    """The compiled path's verdict (``armik.verify.region``) measures a look-at as
    ``LookAt.measure`` does: a tip within 1e-6 m of the point has no line of sight. It took
    one only within 1e-9 m: a seed 5e-7 m behind the point, its axis on it, was a success
    on ``solve``, ``solve_batch`` and ``solve_path`` where the task's own measure refuses
    it."""
    ur5 = bundled("ur5")
    for k in (1, 4):
        q = ur5.random_q(k)
        T = ur5.fk(q)
        point = T.translation + 5e-7 * T.rotation[:, 2]  # on the tool's z, 5e-7 m ahead
        look = armik.LookAt(point)
        assert not look.measure(T, 1e-6, 1e-6).within
        found = [ur5.solve([look], q0=q, solver=s, iteration_budget=200) for s in ("auto", "qp")]
        batch = ur5.solve_batch([[look], [look]], q0=q, workers=1, iteration_budget=200)
        found += [batch[i] for i in range(len(batch))]
        path = ur5.solve_path([[look], [look]], q, iteration_budget=200)
        found += [path[i] for i in range(len(path))]
        for r in found:
            F = ur5.fk(r.q)
            assert not r.success or look.measure(F, 1e-6, 1e-6).within, r.reason
            if not r.success and np.linalg.norm(point - F.translation) <= 1e-6:
                assert r.orientation_error == pytest.approx(np.pi)


def test_a_seed_within_a_micrometre_of_the_point_moves_off_it_and_finds_an_answer():
    """A seed whose tip stands 5e-7 m behind the point, its axis on it: the compiled rows
    measure pi there (no line of sight within ``SIGHT``, the verdict's distance) and restart,
    on ``solve`` and ``solve_batch``; the answer found looks at the point from more than a
    micrometre, by an FK of the test's own. The rows took it as aimed beyond 1e-9
    m and claimed convergence at once: a failure, no restart tried."""
    ur5 = bundled("ur5")
    for k in (1, 4):
        q = ur5.random_q(k)
        T = ur5.fk(q)
        point = T.translation + 5e-7 * T.rotation[:, 2]
        look = [armik.LookAt(point)]
        found = [ur5.solve(look, q0=q, solver=s, iteration_budget=2000) for s in ("auto", "qp")]
        batch = ur5.solve_batch([look, look], q0=q, workers=1, iteration_budget=2000)
        found += [batch[i] for i in range(len(batch))]
        for r in found:
            assert r.success, r.reason
            F = pin.SE3(ur5.fk(r.q))
            sight = point - F.translation
            distance = float(np.linalg.norm(sight))
            assert distance > 1e-6
            assert float(F.rotation[:, 2] @ sight) >= distance * np.cos(2e-6)
