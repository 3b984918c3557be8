"""A result's position_error and orientation_error are the true distances of its tip to the
target, whatever the request measured for its verdict (weights, a region); that measure is
``measured``, beside them (``armik.verify.distances``)."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik

from ..conftest import arm


def _distances(a, q, T: pin.SE3) -> tuple[float, float]:
    """The tip's distance to ``T`` by Pinocchio's FK: (m, rad)."""
    X = a.fk(q)
    return (
        float(np.linalg.norm(X.translation - T.translation)),
        float(np.linalg.norm(pin.log3(X.rotation.T @ T.rotation))),
    )


def _off(a, seed: int, shift) -> pin.SE3:
    T = a.fk(a.random_q(np.random.default_rng(seed)))
    return pin.SE3(T.rotation, T.translation + np.asarray(shift, dtype=float))


@pytest.mark.parametrize("solver", ["auto", "dls", "qp"])
def test_weights_that_free_the_position_report_the_true_distance(solver):
    """The issue's case: weights (0, 0, 0, 1, 1, 1) on a UR5 target 0.3 m away from any
    reachable one report the tip's real distance, not the weighted error of 0."""
    ur5 = arm("ur5")
    T = _off(ur5, 1, (0.3, 0.2, 0.1))
    r = ur5.solve(T, weights=(0, 0, 0, 1, 1, 1), solver=solver)
    assert r.success, r.reason
    pos, ori = _distances(ur5, r.q, T)
    assert r.position_error == pytest.approx(pos, abs=1e-12)
    assert r.orientation_error == pytest.approx(ori, abs=1e-9)
    assert r.position_error > 0.01  # the position is free: the tip is not at the target
    measured_pos, measured_ori = r.measured
    assert measured_pos <= 1e-6 and measured_ori <= 1e-6
    assert f"{pos:.3g} m" in r.reason and "weighted" in r.reason


def test_a_bounded_pose_reports_its_distance_to_the_target():
    panda = arm("panda")
    T = _off(panda, 2, (0.04, -0.03, 0.0))
    r = panda.solve(T, bounds=(0.05,) * 3 + (0.2,) * 3)
    assert r.success, r.reason
    pos, ori = _distances(panda, r.q, T)
    assert (r.position_error, r.orientation_error) == pytest.approx((pos, ori), abs=1e-9)
    assert r.measured[0] <= 1e-6 and r.measured[1] <= 1e-6  # inside the region
    assert f"the tip is {pos:.3g} m, {ori:.3g} rad from the target" in r.reason


def test_every_answer_of_solve_all_and_each_route_report_the_same():
    """The prepared plan and the general path (a seed spelled as a tuple of numpy floats
    takes the general one) give equal fields; every answer of solve_all its distances."""
    ur5 = arm("ur5")
    T = _off(ur5, 3, (0.2, 0.0, 0.1))
    w = (0, 0, 0, 1, 1, 1)
    fast = ur5.solve(T, q0=ur5.middle, weights=w)
    general = ur5.solve(T, q0=tuple(np.float64(v) for v in ur5.middle), weights=w)
    assert np.array_equal(fast.q, general.q)
    assert (fast.position_error, fast.orientation_error) == pytest.approx(
        (general.position_error, general.orientation_error), abs=1e-12
    )
    assert fast.measured == pytest.approx(general.measured, abs=1e-12)
    every = ur5.solve_all(T, weights=w)
    assert len(every) > 1
    for r in every:
        pos, ori = _distances(ur5, r.q, T)
        assert r.position_error == pytest.approx(pos, abs=1e-12) and r.measured is not None


def test_a_batch_keeps_both_columns_and_saves_them(tmp_path):
    ur5 = arm("ur5")
    poses = [_off(ur5, s, (0.1 * s, 0.0, 0.05)) for s in range(4)]
    b = ur5.solve_batch(poses, weights=(0, 0, 0, 1, 1, 1), workers=1)
    for i, T in enumerate(poses):
        pos, _ = _distances(ur5, b.q[i], T)
        assert b.position_error[i] == pytest.approx(pos, abs=1e-12)
        assert b.measured[i, 0] <= 1e-6 and b[i].measured == pytest.approx(tuple(b.measured[i]))
        assert "weighted" in b.reason(i)
    back = armik.BatchResult.load(b.save(tmp_path / "b.npz"))
    np.testing.assert_array_equal(back.measured, b.measured)


def test_a_plain_request_measures_the_distances_themselves():
    ur5 = arm("ur5")
    T = _off(ur5, 5, (0.0, 0.0, 0.0))
    r = ur5.solve(T)
    assert r.measured is None and "weighted" not in r.reason
    b = ur5.solve_batch([T], workers=1)
    assert np.isnan(b.measured).all() and b[0].measured is None


@pytest.mark.parametrize(
    "options",
    [
        {"bounds": (0.02, 0.02, 0.02, 0.1, 0.1, math.inf)},
        {"bounds": (0.02,) * 3 + (0.1,) * 3, "weights": (1, 1, 1, 1, 1, 0.5)},
        {"cone": (0.0, 0.0, 1.0, 0.1)},
    ],
)
def test_the_prepared_plan_and_the_general_path_agree_on_a_region(options):
    panda = arm("panda")
    T = _off(panda, 6, (0.03, 0.01, -0.02))
    fast = panda.solve(T, q0=panda.middle, **options)
    general = panda.solve(T, q0=tuple(np.float64(v) for v in panda.middle), **options)
    assert fast.success and np.array_equal(fast.q, general.q)
    assert (fast.position_error, fast.orientation_error) == pytest.approx(
        (general.position_error, general.orientation_error), abs=1e-12
    )
    assert fast.measured == pytest.approx(general.measured, abs=1e-12)
    assert fast.reason == general.reason


@pytest.mark.parametrize("solver", ["auto", "dls"])
def test_weights_that_free_the_rotation_report_the_true_angle_on_every_route(solver):
    """Rotation weights all 0 on a full pose: the verdict measures the position only, and
    ``orientation_error`` is still the tip's angle to the target's rotation (Pinocchio's
    FK), the same from ``solve``, ``solve_all`` and ``solve_batch``."""
    a = arm("ur5")
    T = a.fk(a.random_q(np.random.default_rng(2)))
    w = (1, 1, 1, 0, 0, 0)
    r = a.solve(T, weights=w, solver=solver)
    assert r.success and r.orientation_error is not None
    assert r.orientation_error == pytest.approx(_distances(a, r.q, T)[1], abs=1e-9)
    for x in a.solve_all(T, weights=w, solver=solver):
        assert x.orientation_error == pytest.approx(_distances(a, x.q, T)[1], abs=1e-9)
    b = a.solve_batch(T.homogeneous[None], weights=w, solver=solver, workers=1)
    assert b[0].orientation_error == pytest.approx(r.orientation_error, abs=1e-9)


def test_the_task_solver_reports_the_distance_to_a_region_centre():
    """A box around a point that the task solver answers (its centre's compiled answer
    out of the box's reach or off it): ``position_error`` is the tip's distance to the
    point by Pinocchio's FK, the region's measure (0 inside) kept as ``measured``."""
    a = arm("panda")
    model = a.kinematics.model
    data = model.createData()
    tip = model.getFrameId(a.tip)
    seen = 0
    for seed in range(40, 56):
        c = a.fk(a.random_q(seed)).translation + 0.02
        r = a.solve([armik.Position(c, bounds=(0.03, 0.03, 0.03))], q0=a.middle)
        pin.framesForwardKinematics(model, data, r.q)
        assert r.position_error == pytest.approx(np.linalg.norm(data.oMf[tip].translation - c))
        if r.solver == "tasks":
            seen += 1
            assert r.success and r.measured[0] == 0.0 and r.position_error > 0.0
    assert seen  # the route under test was taken


def test_a_solved_batch_of_positions_in_a_box_says_inside_the_region_as_solve_does():
    """A position target has no orientation to measure (NaN in a batch's arrays): a solved
    row's reason says "inside the region", as ``solve``'s result for the same target."""
    panda = arm("panda")
    q0 = panda.random_q(np.random.default_rng(3))
    p = panda.fk(q0).translation + (0.03, 0.0, 0.0)  # outside the box around q0's tip
    options = dict(q0=q0, bounds=(0.01, 0.01, 0.01, 0.0, 0.0, 0.0))
    one = panda.solve(p, **options)
    many = panda.solve_batch([p, p], **options)
    assert one.success and many.success.all(), (one.reason, many.summary())
    assert not math.isnan(many.measured[0, 0])  # measured apart: the box's own measure
    for i in range(2):
        assert "inside the region" in many.reason(i) and many.reason(i) == one.reason
        assert many[i].reason == one.reason


def test_the_plain_dictionary_of_a_result_keeps_what_its_verdict_measured():
    """``as_dict`` (what ``--json`` prints) holds ``measured`` beside the distances where
    the verdict measured apart, and no such key where it measured the distances."""
    ur5 = arm("ur5")
    T = _off(ur5, 4, (0.004, 0.0, 0.0))
    boxed = ur5.solve(T, bounds=(0.01,) * 6)
    weighted = ur5.solve(T, weights=(1, 1, 1, 1, 1, 0))
    for r in (boxed, weighted, ur5.solve_batch([T, T], bounds=(0.01,) * 6)[1]):
        assert r.success and r.measured is not None, r.reason
        d = r.as_dict()
        assert d["measured"] == list(r.measured) and d["position_error"] == r.position_error
    assert "measured" not in ur5.solve(T).as_dict()


def test_a_batch_summary_calls_the_distances_of_a_region_or_weights_distances():
    """A batch measured apart reports distances to the target: its summary says so, with
    what the verdicts measured, where it said "largest error" of a 0.003 m distance inside
    a box of 0.01 m."""
    ur5 = arm("ur5")
    T = _off(ur5, 4, (0.003, 0.0, 0.0))
    boxed = ur5.solve_batch([T, T], bounds=(0.01,) * 6)
    weighted = ur5.solve_batch([T, T], weights=(1, 1, 1, 1, 1, 0))
    plain = ur5.solve_batch([T, T])
    assert boxed.success.all() and weighted.success.all() and plain.success.all()
    line = boxed.summary()
    assert "largest error" not in line and "distance to the target" in line
    assert f"{boxed.position_error.max():.2g} m" in line and "verdicts measured at most" in line
    assert "distance to the target" in weighted.summary()
    assert "largest error of the solved" in plain.summary()
