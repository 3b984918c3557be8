"""A batch row says what ``solve`` says of the same target: its reason and its solver."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.constraints.base import Check, Constraint

from ..conftest import arm


def _targets(a: armik.Arm, n: int) -> list[pin.SE3]:
    poses = [a.fk(a.random_q(k)) for k in range(n)]
    return [*poses, pin.SE3(poses[0].rotation, poses[0].translation * 5)]  # out of reach


def _same_words(a: armik.Arm, targets, batch: armik.BatchResult, **options) -> None:
    for i, t in enumerate(targets):
        r = a.solve(t, **options)
        assert (batch[i].success, batch[i].reason) == (r.success, r.reason), i
        assert batch[i].solver == r.solver, i


@pytest.mark.parametrize(
    "run",
    [
        {},
        {"workers": 2},
        {"backend": "serial"},
        {"backend": "processes", "workers": 2, "chunk_size": 2},
    ],
)
def test_a_spin_solved_by_the_last_joint_says_its_angle(run):
    # spin_joint: each success's words name the spin its last joint turned through
    a = arm("ur5")
    targets = _targets(a, 3)
    options = {"bounds": (0, 0, 0, 0, 0, np.inf)}
    batch = a.solve_batch(targets, **run, **options)
    assert batch.solver == "spin_joint" and batch.success[:-1].all()
    assert "turned by the last joint" in batch[0].reason
    _same_words(a, targets, batch, **options)


def test_weights_and_bounds_say_the_distance_as_solve_does(tmp_path):
    a = arm("ur5")
    t = a.fk(a.random_q(1))
    targets = [pin.SE3(t.rotation, t.translation + [0.003, 0, 0]), *_targets(a, 2)]
    options = {"bounds": (0.01, 0.01, np.inf, 0.1, 0.1, 0.1), "weights": (1, 1, 1, 1, 1, 0.5)}
    batch = a.solve_batch(targets, **options)
    assert batch.success[:-1].all()
    assert batch[0].reason.endswith("from the region's centre, free components apart")
    _same_words(a, targets, batch, **options)
    loaded = armik.BatchResult.load(batch.save(tmp_path / "weighted.npz"))
    assert [loaded.reason(i) for i in range(len(batch))] == [r.reason for r in batch]
    assert [r.reason for r in batch[1:]] == [batch.reason(i) for i in range(1, len(batch))]


def test_a_preference_names_the_solver_solve_names():
    """Each row names the solver of its answer; the batch that solver, ranked."""
    a = arm("ur5")
    targets = _targets(a, 2)
    batch = a.solve_batch(targets, prefer="manipulability")
    solver = a.solve(targets[0], prefer="manipulability").solver
    assert solver != "auto" and batch.solver == f"{solver}, prefer"  # the batch: ranked
    _same_words(a, targets, batch, prefer="manipulability")
    on_threads = a.solve_batch(targets, prefer="manipulability", backend="threads", chunk_size=2)
    assert on_threads.solver == batch.solver and on_threads[2].solver == solver


@pytest.mark.parametrize("run", [{}, {"backend": "threads", "chunk_size": 1}])
def test_a_cone_ranked_by_a_preference_is_a_region_in_the_summary_too(run):
    # rows solved one by one: the batch kept no aim, its summary measured "to the target"
    a = arm("ur5")
    targets = _targets(a, 2)[:2]
    options = {"cone": (0, 0, 1, 0.2), "prefer": "manipulability"}
    batch = a.solve_batch(targets, **run, **options)
    assert batch.region and batch.cone == 0.2 and batch.success.all()
    assert "from the region's centre" in batch[0].reason
    said = batch.summary().partition("largest distances of the solved: the tip ")[2]
    assert " m from the region's centre, its axis " in said, batch.summary()
    assert said.partition(" (")[0].endswith(" rad from its direction"), batch.summary()
    _same_words(a, targets, batch, **options)


def test_weights_and_bounds_summary_measures_from_the_regions_centre():
    a = arm("ur5")
    options = {"bounds": (0.01, 0.01, np.inf, 0.1, 0.1, 0.1), "weights": (1, 1, 1, 1, 1, 0.5)}
    batch = a.solve_batch(_targets(a, 2)[:2], **options)
    assert batch[0].reason.endswith("from the region's centre, free components apart")
    assert "largest distance to the region's centre of the solved" in batch.summary()


class ElbowAbove(Constraint):
    """The Panda's joint 4 above -2 rad: some rows' answers then come from dls, others from
    swept, under a preference."""

    def check(self, arm, Q):
        return Check(Q[:, 3] > -2.0, armik.Status.JOINT_LIMITS, lambda i: "elbow below -2")


@pytest.mark.parametrize("run", [{}, {"backend": "threads", "chunk_size": 3}])
def test_rows_of_several_solvers_each_name_their_own(run):
    a = arm("panda")
    targets = [a.fk(a.random_q(k)) for k in range(8)]
    options = {"prefer": "manipulability", "constraints": [ElbowAbove()]}
    options.update(iteration_budget=1500, seed=3)
    batch = a.solve_batch(targets, **run, **options)
    assert batch.solver == "auto, prefer" and {r.solver for r in batch} == {"dls", "swept"}
    _same_words(a, targets, batch, **options)
    picked = batch[[3, 0]]
    assert [r.solver for r in picked] == [batch[3].solver, batch[0].solver]


def test_a_batch_ranked_by_a_preference_keeps_its_successes_words_apart_from_failures():
    """Rows solved one by one (``prefer=``): a success's words are in ``said``, only the
    failures' in ``reasons``, as a compiled batch's."""
    a = arm("ur5")
    targets = _targets(a, 2)[:2] + [pin.SE3(np.eye(3), np.array([3.0, 0.0, 0.0]))]
    batch = a.solve_batch(targets, prefer="manipulability", workers=1)
    assert batch.success.tolist() == [True, True, False]
    assert set(batch.reasons) == {2} and set(batch.said) == {0, 1}
    assert batch.reason(0) == a.solve(targets[0], prefer="manipulability").reason
