"""A look-at in the compiled path: alone, from a held position or from a box it lowers to
the cone around the line of sight (options ``cone`` and ``look_at``), which ``dls`` and
``qp`` solve in the kernel and the verdict measures as the ``LookAt`` task does; a box
around a position with an ``Axis``, to the cone around the direction itself (``toward``).
Every answer here is checked again by the tasks' own measures on the arm's FK."""

from __future__ import annotations

import math

import numpy as np
import pytest

import armik
from armik.problem.problem import Problem, lower
from armik.solve.read import options, read
from armik.targets.aim import Aim
from tests import conftest

BUDGET = {"iteration_budget": 3000}  # deterministic


def _holds(arm, tasks, q) -> bool:
    T = arm.fk(q)
    return all(t.measure(T, 1e-6, 1e-6).within for t in tasks)


def _look_targets(arm, rng, n, case):
    out = []
    for _ in range(n):
        T = arm.fk(arm.random_q(rng))
        point = T.translation + rng.uniform(0.2, 0.8) * T.rotation[:, 2]
        look = armik.LookAt(point + rng.uniform(-0.01, 0.01, 3), (0, 0, 1), 0.05)
        p = T.translation
        out.append(
            {
                "alone": [look],
                "held": [armik.Position(p), look],
                "box": [armik.Position(p + 0.002, bounds=(0.005, 0.005, 0.005)), look],
            }[case]
        )
    return out


def test_look_ats_lower_to_the_cone_around_the_line_of_sight():
    p, point = np.array([0.3, 0.1, 0.4]), np.array([0.6, 0.1, 0.0])
    look = armik.LookAt(point, (1, 0, 0), 0.1)
    T, said = lower(Problem((armik.Position(p), look)))
    assert said == {} and T.aim == Aim((1.0, 0.0, 0.0), 0.1, point=(0.6, 0.1, 0.0))
    # the target's rotation is not read (the cone's direction is the line of sight)
    assert np.array_equal(T.rotation, np.eye(3)) and np.array_equal(T.position, p)
    T, said = lower(Problem((look,)))
    assert said["bounds"] == (math.inf,) * 3 + (0.0,) * 3 and T.aim.point == tuple(point)
    T, said = lower(Problem((look, armik.Position(p, bounds=(0.01, 0.02, math.inf)))))
    assert said["bounds"] == (0.01, 0.02, math.inf, 0.0, 0.0, 0.0)
    assert np.array_equal(T.rotation, np.eye(3))  # the box in the base frame
    # looking at the very point it stands on: no line of sight, the task solver's
    assert lower(Problem((armik.Position(point), look))) is None


@pytest.mark.parametrize("case", ["alone", "held", "box"])
@pytest.mark.parametrize("robot", ["ur5", "panda", "so101"])
def test_look_ats_are_solved_in_the_kernel(robot, case):
    arm = conftest.arm(robot)
    targets = _look_targets(arm, np.random.default_rng(4), 20, case)
    for tasks in targets:
        r = arm.solve(tasks, q0=arm.middle, **BUDGET)
        assert r.success and r.solver == "dls", r.reason
        assert _holds(arm, tasks, r.q) and arm.within_limits(r.q)


def test_each_look_at_of_a_loop_looks_at_its_own_point():
    """The point is kept out of the remembered options (one validation and one plan for a
    loop): each answer must still look at its own point, not the first's."""
    arm = conftest.arm("ur5")
    targets = _look_targets(arm, np.random.default_rng(9), 12, "held")
    keys = {read(arm.kinematics, t, None, "auto", BUDGET).key for t in targets}
    assert len(keys) == 1
    for tasks in targets:
        r = arm.solve(tasks, **BUDGET)
        assert r.success and _holds(arm, tasks, r.q)
    qp = arm.solve(targets[0], solver="qp", **BUDGET)
    assert qp.success and qp.solver == "qp" and _holds(arm, targets[0], qp.q)


def test_batches_of_look_ats():
    """A camera moved about a spot 2 cm at a time, kept on one point: the rows lower alike
    and the compiled batch gives each row the answer a single solve gives (some of these
    positions cannot face the point: both fail them). Look-ats at many points (each
    reachable by construction) lower row by row, each solved in the kernel."""
    arm = conftest.arm("panda")
    rng = np.random.default_rng(6)
    T = arm.fk(arm.random_q(rng))
    point = T.translation + 0.4 * T.rotation[:, 2]
    rows = [
        [armik.Position(T.translation + rng.uniform(-0.02, 0.02, 3)), armik.LookAt(point)]
        for _ in range(30)
    ]
    b = arm.solve_batch(rows, workers=1, progress=False, **BUDGET)
    singles = [arm.solve(row, **BUDGET) for row in rows]
    assert b[0].solver == "dls" and b.success.sum() >= 20
    assert b.success.tolist() == [r.success for r in singles]
    assert all(_holds(arm, row, q) for row, q, ok in zip(rows, b.q, b.success) if ok)
    many = _look_targets(arm, rng, 12, "held")
    b = arm.solve_batch(many, workers=1, progress=False, **BUDGET)
    assert b.success.all() and all(r.solver == "dls" for r in b)
    assert all(_holds(arm, row, q) for row, q in zip(many, b.q))


@pytest.mark.parametrize("robot", ["ur5", "panda", "so101"])
def test_a_box_with_an_axis_is_solved_in_the_kernel(robot):
    """ "Within 5 mm of the spot, the tool within 0.05 rad of down-ish": built from a
    configuration, so an answer exists."""
    arm = conftest.arm(robot)
    rng = np.random.default_rng(14)
    for _ in range(20):
        T = arm.fk(arm.random_q(rng))
        p = T.translation + rng.uniform(-0.004, 0.004, 3)
        direction = T.rotation[:, 2] + rng.uniform(-0.02, 0.02, 3)
        tasks = [armik.Position(p, bounds=(0.005,) * 3), armik.Axis((0, 0, 1), direction, 0.05)]
        r = arm.solve(tasks, q0=arm.middle, **BUDGET)
        assert r.success and r.solver == "dls", r.reason
        assert _holds(arm, tasks, r.q) and arm.within_limits(r.q)


@pytest.mark.parametrize(
    "given, match",
    [
        ({"cone": (0, 0, 1, 0.1), "toward": (0, 0, 0)}, "toward must be a non-zero direction"),
        ({"cone": (0, 0, 1, 0.1), "look_at": (1, 0, 0), "toward": (0, 0, 1)}, "both say"),
        ({"toward": (0.0, 0.0, 1.0)}, "toward needs cone"),
        ({"look_at": (0.1, 0.2, 0.3)}, "look_at needs cone"),
        ({"cone": (0, 0, 1, 0.1), "look_at": (0.1, math.nan, 0.3)}, "look_at must be a point"),
        ({"cone": (0, 0, 1, 0.1), "look_at": (0.1, 0.2)}, r"look_at.*\(0\.1, 0\.2\)"),
    ],
)
def test_bad_look_at_options_get_armik_errors(given, match):
    with pytest.raises(armik.OptionError, match=match):
        options(given)
    with pytest.raises(armik.OptionError, match=match):
        conftest.arm("ur5").solve(np.eye(4), **given)
