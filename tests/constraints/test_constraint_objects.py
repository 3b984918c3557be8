"""Constraints as objects (armik.constraints): the joint limits, a held joint and
collisions, each a check over N answers and, for the limits and a held joint, the box of
every step. The old keywords and the objects are one problem; a list of tasks honours
them, a held joint on any arm."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.constraints.limits import JointLimits, on_limits
from armik.options import Options
from armik.solve.tasks import box_of
from armik.solvers.answers import Answers
from armik.status import Status
from armik.tolerances import LIMIT_TOL
from armik.verify.verdicts import Verdicts
from tests import conftest

BUDGET = {"iteration_budget": 4000}  # deterministic: no test depends on timing


def test_old_spellings_equal_the_objects():
    arm = conftest.arm("panda")
    rng = np.random.default_rng(3)
    wall = armik.Box((0.05, 0.6, 0.6), (0.25, 0.0, 0.5))
    for _ in range(4):
        T = arm.fk(arm.random_q(rng))
        q0 = arm.random_q(rng)
        old = arm.solve(T, q0=q0, hold={"panda_joint7": 0.4}, **BUDGET)
        new = arm.solve(T, q0=q0, constraints=[armik.Hold("panda_joint7", 0.4)], **BUDGET)
        assert np.array_equal(old.q, new.q) and old.reason == new.reason
        said = {"obstacles": [wall], "self_collision": True, "margin": 0.005}
        old = arm.solve(T, q0=q0, **said, **BUDGET)
        new = arm.solve(T, q0=q0, constraints=[armik.Collisions(**said)], **BUDGET)
        assert np.array_equal(old.q, new.q) and old.reason == new.reason
        assert old.status == new.status and old.extra.keys() == new.extra.keys()
        # coal's warm start may move the last bits of a distance between two queries
        assert old.extra["min_distance"] == pytest.approx(new.extra["min_distance"], abs=1e-12)
    targets = [arm.fk(arm.random_q(rng)) for _ in range(6)]
    old_b = arm.solve_batch(targets, obstacles=[wall], workers=1, progress=False, **BUDGET)
    new_b = arm.solve_batch(
        targets, constraints=armik.Collisions([wall]), workers=1, progress=False, **BUDGET
    )
    assert np.array_equal(old_b.q, new_b.q) and list(old_b.status) == list(new_b.status)


def test_options_give_their_constraints_back():
    wall = armik.HalfSpace((0, 0, 1), -0.1)
    opts = Options.from_kwargs({"hold": {"j2": None}, "obstacles": [wall], "margin": 0.01})
    assert opts.constraints == (
        JointLimits(),
        armik.Hold("j2"),
        armik.Collisions(obstacles=(wall,), margin=0.01),
    )
    again = Options.from_kwargs({"constraints": opts.constraints[1:]})
    assert again == opts
    assert Options().constraints == (JointLimits(),)


def test_constraints_said_twice_or_not_constraints_are_refused():
    arm = conftest.arm("panda")
    T = arm.fk(arm.middle)
    hold = armik.Hold("panda_joint7", 0.1)
    with pytest.raises(armik.OptionError, match="hold is given twice.*as an option"):
        arm.solve(T, constraints=[hold], hold={"panda_joint7": 0.2})
    with pytest.raises(armik.OptionError, match="panda_joint7 is held twice"):
        arm.solve(T, constraints=[hold, armik.Hold("panda_joint7", 0.2)])
    with pytest.raises(armik.OptionError, match="margin is given twice"):
        arm.solve(T, constraints=[armik.Collisions(self_collision=True)], margin=0.01)
    with pytest.raises(armik.OptionError, match="constraints holds.*'hold'"):
        arm.solve(T, constraints={"hold": 1})
    with pytest.raises(armik.OptionError, match="constraints holds.*None"):
        arm.solve(T, constraints=[None])


@pytest.mark.parametrize(
    "build, match",
    [
        (lambda: armik.Hold(3, 0.1), "joint must be a joint's name, got 3"),
        (lambda: armik.Hold("j", math.nan), "finite number.*nan"),
        (lambda: armik.Hold("j", "up"), "finite number.*'up'"),
        (lambda: armik.Hold("j", 10**400), "finite number"),  # beyond a float's range
        (lambda: armik.Collisions(margin=-0.1, self_collision=True), "margin.*-0.1"),
        (lambda: armik.Collisions(margin=0.1), "checks nothing"),
        (lambda: armik.Collisions(self_collision="yes"), "True or False, got 'yes'"),
        (lambda: armik.Collisions(obstacles="box"), "list of shapes"),
    ],
)
def test_bad_constraints_get_armik_errors(build, match):
    with pytest.raises(armik.InputError, match=match):
        build()


def test_a_held_joint_is_checked_against_the_arm():
    arm = conftest.model("ur5")
    with pytest.raises(armik.JointError, match="unknown joint 'elbow'.*shoulder_pan_joint"):
        armik.Hold("elbow", 0.1).at(arm, arm.middle)
    with pytest.raises(armik.JointError, match="outside joint 'elbow_joint'"):
        armik.Hold("elbow_joint", 9.0).at(arm, arm.middle)
    with pytest.raises(armik.OptionError, match="resolve it with Hold.at"):
        armik.Hold("elbow_joint").check(arm, arm.middle[None])
    locked = arm.with_locked({"elbow_joint": 0.25})
    with pytest.raises(armik.JointError, match="'elbow_joint' is locked at 0.25.*leave it out"):
        armik.Hold("elbow_joint", 0.25).at(locked, locked.middle)
    seed = arm.random_q(0)
    held = armik.Hold("elbow_joint").at(arm, seed)
    assert held.value == seed[2]
    lo, hi = box_of(arm, (JointLimits(), held))
    assert lo[2] == hi[2] == seed[2]
    assert np.array_equal(np.delete(lo, 2), np.delete(arm.lower, 2))


def test_checks_over_rows_agree_with_each_answer():
    arm = conftest.arm("panda")
    model = arm.kinematics
    rng = np.random.default_rng(7)
    Q = arm.random_q(rng, 12)
    Q[3, 1] = arm.upper[1] + 0.2  # one row outside the limits
    edges = Q.copy()
    edges[4, 0] = arm.lower[0] - 0.5 * LIMIT_TOL  # on the limit, within its tolerance
    edges[6, 2] = arm.upper[2] + 2.0 * LIMIT_TOL  # just beyond it
    edges[7, 5] = np.nan  # not a number: outside
    at_edges = JointLimits().check(model, edges)
    assert at_edges.ok.tolist() == [model.within_limits(q) for q in edges]
    assert at_edges.ok[4] and not at_edges.ok[6] and not at_edges.ok[7]
    limits = JointLimits().check(model, Q)
    assert limits.ok.tolist() == [model.within_limits(q) for q in Q]
    assert not limits.ok[3] and "panda_joint2" in limits.why(3)
    held = armik.Hold("panda_joint4", float(Q[5, 3])).check(model, Q)
    assert held.ok.tolist() == [i == 5 for i in range(12)]
    assert "'panda_joint4' at" in held.why(0)
    ball = armik.Sphere(0.15, (0.3, 0.0, 0.5))
    clear = armik.Collisions([ball], self_collision=True, margin=0.01).check(model, Q)
    for i, q in enumerate(Q):
        distance, pair = arm.min_distance(q, obstacles=[ball], self_collision=True)
        assert clear.extra(i)["closest_pair"] == pair
        assert clear.extra(i)["min_distance"] == pytest.approx(distance, abs=1e-12)  # coal
        assert clear.ok[i] == (distance >= 0.01)


def _two_verdicts(q: np.ndarray, success: bool) -> Verdicts:
    """Two answers at ``q``: the first a failure, the second as ``success`` says."""
    answers = Answers.of([q, q], [Status.NOT_CONVERGED, Status.CONVERGED], ["missed", "ok"], len(q))
    codes = [
        Status.NOT_CONVERGED.code,
        (Status.CONVERGED if success else Status.NOT_CONVERGED).code,
    ]
    return Verdicts(
        answers=answers,
        status=np.array(codes, dtype=np.int8),
        position_error=np.zeros(2),
        orientation_error=np.zeros(2),
        rotation=True,
        words=["missed", "ok"],
        tol_position=1e-5,
        tol_orientation=1e-4,
    )


def test_a_check_turns_only_successes_into_failures():
    model = conftest.model("panda")
    found = _two_verdicts(model.middle, True)
    found.checked(model, (armik.Hold("panda_joint1", 0.5),))
    assert found.success.tolist() == [False, False]
    assert found.status[0] == Status.NOT_CONVERGED.code and found.reason(0) == "missed"
    assert found.status[1] == Status.NOT_CONVERGED.code
    assert found.reason(1) == "joint 'panda_joint1' at 0, held at 0.5"
    kept = _two_verdicts(model.middle, True).checked(model, (armik.Hold("panda_joint1", 0.0),))
    assert kept.success.tolist() == [False, True]
    assert kept.reason(1).startswith("ok") and kept.reason(1).endswith(
        "joint 'panda_joint1' held at 0"
    )
    r = kept.result(1, "dls", 0.0)
    assert r.success and r.reason == kept.reason(1) and np.array_equal(r.q, model.middle)


def _looks_at(arm, q, point, within):
    T = arm.fk(q)
    sight = (np.asarray(point) - T.translation) / np.linalg.norm(point - T.translation)
    return math.acos(min(1.0, float(T.rotation[:, 2] @ sight))) <= within + 1e-6


def test_a_task_list_holds_a_joint_of_any_arm():
    """A 6-joint arm's position with its last joint held (the compiled path holds a joint
    of 7-joint arms only, so the task solver does, as a box row of its steps); a look-at on
    a Panda with joint 4 held. Each checked on the arm's FK."""
    ur5 = conftest.arm("ur5")
    rng = np.random.default_rng(11)
    for _ in range(5):
        p = ur5.fk(ur5.random_q(rng)).translation
        r = ur5.solve([armik.Position(p)], constraints=[armik.Hold("wrist_3_joint", 0.7)])
        assert r.success and r.solver == "tasks" and r.q[5] == 0.7
        assert np.linalg.norm(ur5.fk(r.q).translation - p) <= 1e-6
        assert "held at 0.7" in r.reason
    with pytest.raises(armik.OptionError, match=r"said as tasks \(armik.Pose"):
        ur5.solve(p, constraints=[armik.Hold("wrist_3_joint", 0.7)], weights=[1] * 6)
    panda = conftest.arm("panda")
    q = panda.random_q(rng)
    T = panda.fk(q)
    point = T.translation + 0.4 * T.rotation[:, 2]
    look = [armik.LookAt(point, (0, 0, 1), 0.02)]
    r = panda.solve(look, constraints=[armik.Hold("panda_joint4", -1.2)], **BUDGET)
    assert r.success and r.q[3] == -1.2 and _looks_at(panda, r.q, point, 0.02)


def test_a_task_list_keeps_clear_of_obstacles():
    """A look-at whose first answer would sit in a ball placed on it: the answer found
    keeps clear (by coal, through the arm's own query); a ball over the shoulder, which
    every configuration sinks into, leaves none: a collision naming its pair."""
    panda = conftest.arm("panda")
    q = panda.random_q(np.random.default_rng(2))
    T = panda.fk(q)
    point = T.translation + 0.4 * T.rotation[:, 2]
    look = [armik.LookAt(point, (0, 0, 1), 0.02)]
    model = panda.kinematics
    pin.framesForwardKinematics(model.model, model.data, model.to_pin(q))
    link4 = model.T_base_world * model.data.oMf[model.model.getFrameId("panda_link4")]
    elbow = link4.translation
    ball = armik.Sphere(0.08, elbow)
    assert panda.in_collision(q, obstacles=[ball])
    r = panda.solve(look, q0=q, constraints=[armik.Collisions([ball])], **BUDGET)
    assert r.success and not panda.in_collision(r.q, obstacles=[ball])
    assert _looks_at(panda, r.q, point, 0.02)
    assert r.extra["min_distance"] == pytest.approx(panda.min_distance(r.q, [ball])[0], abs=1e-12)
    assert r.extra["min_distance"] >= 0.0
    assert "collision-free" in r.reason
    over = armik.Sphere(0.7, (0.0, 0.0, 0.95))
    r = panda.solve(look, q0=q, obstacles=[over], iteration_budget=300)
    assert not r.success and r.status is Status.COLLISION
    assert "obstacles[0] (Sphere)" in r.reason and r.extra["min_distance"] < 0.0
    assert r.extra["min_distance"] == pytest.approx(panda.min_distance(r.q, [over])[0], abs=1e-12)


def test_a_failure_says_which_joints_its_best_rests_on_a_limit_of():
    """A descent that finds no answer often stops on a limit: the reason names it, with the
    limit's value, and nothing where no joint rests on one."""
    model = conftest.model("panda")
    q = model.middle.copy()
    q[1], q[5] = model.upper[1], model.lower[5]
    assert on_limits(model, q) == [
        f"panda_joint2 at its upper limit ({model.upper[1]:.6g} rad)",
        f"panda_joint6 at its lower limit ({model.lower[5]:.6g} rad)",
    ]
    q[1] -= 1e-6  # near, not on it
    assert on_limits(model, q) == [f"panda_joint6 at its lower limit ({model.lower[5]:.6g} rad)"]
    assert on_limits(model, model.middle) == []
    # "this point, pointing straight down" beyond the SO-101's wrist: it bends to its limit
    so101 = conftest.arm("so101")
    tasks = [armik.Position((0.2, 0.0, 0.1)), armik.Axis((0, 0, 1), (0, 0, -1), 0.0)]
    r = so101.solve(tasks, iteration_budget=2000, seed=0)
    assert not r.success and r.status == "not_converged"
    assert r.reason.endswith(", ".join(on_limits(so101.kinematics, r.q)))
    assert "the best found rests on wrist_flex at its upper limit" in r.reason
    b = so101.solve_batch([tasks], iteration_budget=2000, seed=0, workers=1, progress=False)
    assert np.array_equal(b.q[0], r.q) and b.reason(0).endswith(r.reason.rsplit("; ", 1)[1])


def test_two_collision_constraints_hold_together():
    """Two armik.Collisions: both scenes kept, either's self-collision, the larger margin;
    an answer clear of one scene but inside the other is refused."""
    arm = conftest.arm("ur5")
    q = arm.middle + 0.3
    T = arm.fk(q)
    at_tip = armik.Collisions(obstacles=[armik.Sphere(0.05, T.translation)])  # every answer
    far = armik.Collisions(obstacles=[armik.Sphere(0.05, (3, 3, 3))], margin=0.01)
    own = armik.Collisions(self_collision=True)
    for cons in ([at_tip, far], [far, at_tip], [own, at_tip]):
        r = arm.solve(T, q0=q, constraints=cons)
        assert r.status == armik.Status.COLLISION
        b = arm.solve_batch(T.homogeneous[None], q0=q, constraints=cons, progress=False)
        assert b.status[0] == armik.Status.COLLISION
    r = arm.solve(T, q0=q, constraints=[far, own])
    assert r.success and r.extra["min_distance"] >= 0.01
