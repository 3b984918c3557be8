"""A posture as a secondary task (``secondary=[armik.Posture(q_ref, weights)]``): the
compiled step's null-space pull goes toward ``q_ref`` instead of q0, each joint's share by
its weight (``nullspace_gain`` its strength). It steers where the task leaves joints free
and never decides a success."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.kernel.problem import pack_settings, unpack
from armik.options import Options
from armik.solvers.numeric.driver import DLS_STEP, settings
from tests import conftest

BUDGET = {"iteration_budget": 3000}  # deterministic: no test depends on timing


def test_the_posture_spells_an_option_and_comes_back():
    posture = armik.Posture([0.1, 0.2, 0.3], [1.0, 0.0, 2.0])
    opts = Options.from_kwargs({"secondary": [posture]})
    assert opts.posture == ((0.1, 0.2, 0.3), (1.0, 0.0, 2.0))
    assert opts == Options.from_kwargs({"posture": ((0.1, 0.2, 0.3), (1.0, 0.0, 2.0))})
    (back,) = opts.secondary
    assert back.q_ref.tolist() == [0.1, 0.2, 0.3] and back.weights.tolist() == [1.0, 0.0, 2.0]
    assert Options().secondary == ()


def test_bad_secondary_tasks_are_named():
    arm = conftest.arm("panda")
    p = arm.fk(arm.middle).translation
    posture = armik.Posture(arm.middle)
    with pytest.raises(armik.OptionError, match="secondary holds one armik.Posture"):
        arm.solve(p, secondary=["upright"])
    with pytest.raises(armik.OptionError, match="posture is given twice .by a secondary task and"):
        arm.solve(p, secondary=[posture, armik.Posture(arm.middle)])
    with pytest.raises(armik.OptionError, match="has 3 values, the arm 7 joints"):
        arm.solve(p, secondary=[armik.Posture([0.0, 0.0, 0.0])])
    with pytest.raises(armik.OptionError, match="posture must be .q_ref, weights."):
        arm.solve(p, posture=[0.0] * 7)


def test_the_kernel_settings_carry_the_posture():
    """Packed and unpacked: the reference and the weights (the largest 1); without a
    posture, empty (the pull toward q0 as before)."""
    posture = armik.Posture(np.arange(7) * 0.1, [2.0, 1, 1, 1, 1, 1, 0])
    for opts, ref, w in (
        (
            Options.from_kwargs({"secondary": [posture]}),
            np.arange(7) * 0.1,
            [1, 0.5, 0.5, 0.5, 0.5, 0.5, 0],
        ),
        (Options(), [], []),
    ):
        st = unpack(*pack_settings(settings(opts, True, 7, 1, DLS_STEP)))
        assert st.posture.tolist() == pytest.approx(list(ref), abs=0) and st.posture_w.tolist() == w
        assert st.look_point.shape == (3,)


def test_a_posture_steers_a_redundant_position_toward_it():
    """A Panda's positions (three task rows, four free joints), by dls and qp: each answer
    with the posture lies nearer its reference than the answer without, from the same start;
    both verified."""
    arm = conftest.arm("panda")
    rng = np.random.default_rng(1)
    q_ref = arm.middle.copy()
    posture = armik.Posture(q_ref)
    for solver in ("dls", "qp"):
        for _ in range(4):
            p = arm.fk(arm.random_q(rng)).translation
            q0 = arm.random_q(rng)
            plain = arm.solve(p, q0=q0, solver=solver, **BUDGET)
            pulled = arm.solve(p, q0=q0, solver=solver, secondary=[posture], **BUDGET)
            assert plain.success and pulled.success
            assert np.linalg.norm(pulled.q - q_ref) < np.linalg.norm(plain.q - q_ref)
            assert np.linalg.norm(arm.fk(pulled.q).translation - p) <= 1e-6


def test_a_posture_of_zero_weights_pulls_nothing_and_a_full_pose_has_no_null_space():
    arm = conftest.arm("panda")
    rng = np.random.default_rng(2)
    p = arm.fk(arm.random_q(rng)).translation
    q0 = arm.random_q(rng)
    none = armik.Posture(arm.middle, np.zeros(7))
    a = arm.solve(p, q0=q0, secondary=[none], **BUDGET)
    b = arm.solve(p, q0=q0, nullspace_gain=0.0, **BUDGET)
    assert np.array_equal(a.q, b.q)
    ur5 = conftest.arm("ur5")
    T = ur5.fk(ur5.random_q(rng))
    q0 = ur5.random_q(rng)
    plain = ur5.solve(T, q0=q0, solver="dls", **BUDGET)
    pulled = ur5.solve(T, q0=q0, solver="dls", secondary=[armik.Posture(ur5.middle)], **BUDGET)
    assert np.array_equal(plain.q, pulled.q)


def test_the_task_solver_follows_a_posture_in_the_tasks_null_space():
    """Two frames of a Panda (the tip's position, the elbow's within 2 cm): the task solver
    moves its answer toward the posture along what the tasks leave free, never below the
    answer without it, each answer verified by Pinocchio on both frames."""
    arm = conftest.arm("panda")
    rng = np.random.default_rng(3)
    q_ref = arm.middle.copy()
    nearer = 0
    for _ in range(4):
        q_true = arm.random_q(rng)
        tip = conftest.frame_position(arm, q_true, arm.tip)
        elbow = conftest.frame_position(arm, q_true, "panda_link4")
        tasks = [armik.Position(tip), armik.Position(elbow, bounds=[0.02] * 3, frame="panda_link4")]
        q0 = arm.random_q(rng)
        plain = arm.solve(tasks, q0=q0, **BUDGET)
        pulled = arm.solve(tasks, q0=q0, secondary=[armik.Posture(q_ref)], **BUDGET)
        assert plain.success and pulled.success, (plain.reason, pulled.reason)
        assert "secondary posture: cost" in pulled.reason
        assert np.linalg.norm(conftest.frame_position(arm, pulled.q, arm.tip) - tip) <= 1e-6
        assert np.all(
            np.abs(conftest.frame_position(arm, pulled.q, "panda_link4") - elbow) <= 0.02 + 1e-6
        )
        d_plain, d_pulled = (float(((r.q - q_ref) ** 2).sum()) for r in (plain, pulled))
        assert d_pulled <= d_plain + 1e-9
        nearer += d_pulled < d_plain - 1e-6
    assert nearer >= 3


@pytest.mark.parametrize("solver", ["auto", "dls", "three_parallel"])
def test_a_secondary_posture_of_another_arm_is_refused_whichever_solver_runs(solver):
    # a closed form reads no posture; the request still is the user's mistake
    ur5 = conftest.arm("ur5")
    T = ur5.fk(ur5.random_q(1))
    bad = [armik.Posture([0.0] * 5)]
    with pytest.raises(armik.OptionError, match="has 5 values, the arm 6 joints"):
        ur5.solve(T, solver=solver, secondary=bad)
    with pytest.raises(armik.OptionError, match="has 5 values, the arm 6 joints"):
        ur5.solve_batch([T, T], solver=solver, secondary=bad, workers=1)


def _two_frames(arm, rng):
    """A Panda task list only the task solver takes: the tip's position, the elbow's
    within 10 cm, from a random configuration."""
    q_true = arm.random_q(rng)
    tip = conftest.frame_position(arm, q_true, arm.tip)
    elbow = conftest.frame_position(arm, q_true, "panda_link4")
    return [armik.Position(tip), armik.Position(elbow, bounds=[0.1] * 3, frame="panda_link4")]


def test_with_prefer_as_well_the_preference_decides_the_move_along_the_null_space():
    """docs/preferences.md: a task list follows a secondary posture A once its tasks hold,
    and with ``prefer=armik.Posture(B)`` as well the preference decides that move. The
    move followed A, the preference only scored its end: the answer was A's, farther
    from B than the plain answer on some targets. Each answer verified on both frames."""
    arm = conftest.arm("panda")
    rng = np.random.default_rng(4)
    A = arm.middle.copy()
    B = arm.middle + np.array([1.2, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0])
    lower = 0
    for _ in range(4):
        tasks = _two_frames(arm, rng)
        kw = dict(q0=arm.middle, secondary=[armik.Posture(A)], **BUDGET)
        toward_a = arm.solve(tasks, **kw)
        both = arm.solve(tasks, prefer=armik.Posture(B), **kw)
        assert toward_a.success and both.success, (toward_a.reason, both.reason)
        tip, elbow = tasks[0].p, tasks[1].p
        assert np.linalg.norm(conftest.frame_position(arm, both.q, arm.tip) - tip) <= 1e-6
        off = np.abs(conftest.frame_position(arm, both.q, "panda_link4") - elbow)
        assert np.all(off <= 0.1 + 1e-6)
        cost_a, cost_both = (float(((r.q - B) ** 2).sum()) for r in (toward_a, both))
        assert both.score == pytest.approx(cost_both, abs=1e-9)
        assert cost_both <= cost_a + 1e-9
        lower += cost_both < cost_a - 1e-3
    assert lower >= 3


def test_prefer_on_a_task_list_gives_the_task_solver_the_whole_budget():
    """The task solver's one answer is scored, nothing else searched: it ran on the share
    of the budget a search of many answers gathers with (half the iterations), and lists
    it solved without ``prefer=`` failed with it. The same answer with or without."""
    arm = conftest.arm("ur5")
    rng = np.random.default_rng(8)
    for _ in range(6):
        q = arm.random_q(rng)
        T = arm.fk(q)
        forearm = conftest.frame_position(arm, q, "forearm_link")
        tasks = [
            armik.Position(T.translation, bounds=(0.01,) * 3),
            armik.LookAt(T.translation + 0.4 * T.rotation[:, 2], (0, 0, 1), 0.02),
            armik.Position(forearm, bounds=(0.05,) * 3, frame="forearm_link"),
        ]
        plain = arm.solve(tasks, q0=arm.middle, iteration_budget=600)
        ranked = arm.solve(tasks, q0=arm.middle, iteration_budget=600, prefer="manipulability")
        assert ranked.success == plain.success, (plain.reason, ranked.reason)
        if plain.success:
            np.testing.assert_allclose(ranked.q, plain.q, atol=1e-12)
