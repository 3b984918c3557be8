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


def _distances(X: pin.SE3, T: pin.SE3) -> tuple[float, float]:
    """The distances of X to T by Pinocchio: (m, rad)."""
    angle = float(np.linalg.norm(pin.log3(X.rotation.T @ T.rotation)))
    return float(np.linalg.norm(X.translation - T.translation)), angle


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
    X = a.fk(batch.q[0])  # 0.2 m along the free z: by Pinocchio, said as it is
    far, angle = _distances(X, targets[0])
    assert batch.position_error[0] == pytest.approx(far, abs=1e-12)
    assert batch[0].reason.endswith(f"the tip is {far:.3g} m, {angle:.3g} rad from the target")
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
    # rows solved one by one: the batch kept no aim, its summary measured "to the target";
    # a cone on a pose: its distance is the angle to the pose's rotation, the cone's
    # measure what the verdicts measured
    a = arm("ur5")
    targets = _targets(a, 2)[:2]
    options = {"cone": (0, 0, 1, 0.2), "prefer": "manipulability"}
    batch = a.solve_batch(targets, **run, **options)
    assert batch.region and batch.cone == 0.2 and batch.success.all()
    far, angle = _distances(a.fk(batch.q[0]), targets[0])
    assert batch.orientation_error[0] == pytest.approx(angle, abs=1e-12)
    said = f"the tip is {far:.3g} m, {angle:.3g} rad from the target; prefer=manipulability"
    assert said in batch[0].reason
    assert "the tip's axis within its cone of 0.2 rad" in batch[0].reason
    said = batch.summary().partition("largest distance to the target of the solved: ")[2]
    worst = batch.orientation_error.max()
    assert said.startswith(f"{batch.position_error.max():.2g} m, {worst:.2g} rad"), batch.summary()
    _same_words(a, targets, batch, **options)


def test_weights_and_bounds_summary_measures_from_the_target():
    a = arm("ur5")
    options = {"bounds": (0.01, 0.01, np.inf, 0.1, 0.1, 0.1), "weights": (1, 1, 1, 1, 1, 0.5)}
    batch = a.solve_batch(_targets(a, 2)[:2], **options)
    assert batch[0].reason.endswith(" rad from the target")
    assert "largest distance to the target of the solved" in batch.summary()


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
