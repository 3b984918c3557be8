"""fk_checks (several answers of one target: the compiled FK, errors and limits in one call)
against Pinocchio's placements measured by the same compiled errors (``pose_checks``), to
1e-12; and solve_all's errors against a log6 of Pinocchio's FK computed here."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.kernel.measure import check_frame, fk_check_frame, fk_checks, pose_checks

from ..conftest import ALL_ROBOTS, arm

EXACT = 1e-12  # the compiled FK against Pinocchio's


def _pinocchio(a: armik.Arm, Q: np.ndarray, H: np.ndarray, w, measure: int) -> np.ndarray:
    """(position error, orientation error, within) of each row of Q, from Pinocchio's
    placements (world frame, mapped by T_base_world in the compiled check)."""
    m = a.kinematics
    placements = []
    for q in Q:
        pin.forwardKinematics(m.model, m.data, m.to_pin(q))
        placements.append(pin.updateFramePlacement(m.model, m.data, m.tip_frame_id).homogeneous)
    frame = check_frame(
        m.T_base_world.rotation, m.T_base_world.translation, w, measure, m.lower, m.upper
    )
    out = np.empty((len(Q), 3))
    pose_checks(frame, np.array(placements), H, np.ascontiguousarray(Q), out)
    return out


def _compiled(a: armik.Arm, Q: np.ndarray, H: np.ndarray, w, measure: int) -> np.ndarray:
    m = a.kinematics
    out = np.full((len(Q), 3), -1.0)
    fk_checks(*m.kernel_chain.flat, fk_check_frame(w, measure, m.lower, m.upper), H, Q, out)
    return out


@pytest.mark.parametrize("name", ALL_ROBOTS)
@pytest.mark.parametrize(
    "w, measure",
    [
        (np.ones(6), 2),  # the pose
        (np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0]), 0),  # the position only
        (np.array([1.0, 0.0, 1.0, 1.0, 1.0, 0.0]), 3),  # weighted axes
    ],
)
def test_fk_checks_is_pinocchio_row_by_row(name, w, measure):
    a = arm(name)
    rng = np.random.default_rng(11)
    Q = a.random_q(rng, n=24)
    limited = np.isfinite(a.upper)
    Q[::3, limited] = a.upper[limited] + 0.1  # rows outside the limits
    H = a.fk(a.random_q(rng)).homogeneous
    H[:3, 3] += 0.05  # a target no row reaches: errors of centimetres and radians
    got, want = _compiled(a, Q, H, w, measure), _pinocchio(a, Q, H, w, measure)
    np.testing.assert_allclose(got[:, :2], want[:, :2], rtol=0, atol=EXACT)
    np.testing.assert_array_equal(got[:, 2], want[:, 2])
    if limited.any():
        assert 0 < got[:, 2].sum() < len(Q)  # both within and outside the limits
    if measure & 2 == 0:
        assert np.isnan(got[:, 1]).all()


def test_fk_checks_reads_the_first_values_of_longer_rows_and_refuses_nan():
    a = arm("ur5")
    Q = a.random_q(np.random.default_rng(2), n=6)
    H = a.fk(Q[0]).homogeneous
    packed = np.zeros((6, 11))  # a closed form's packed rows: q, then flags and codes
    packed[:, :6] = Q
    packed[:, 6:] = 7.0
    frame = fk_check_frame(np.ones(6), 2, a.lower, a.upper)
    rows, plain = np.empty((6, 3)), np.empty((6, 3))
    fk_checks(*a.kinematics.kernel_chain.flat, frame, H, packed, rows)
    fk_checks(*a.kinematics.kernel_chain.flat, frame, H, Q, plain)
    np.testing.assert_array_equal(rows, plain)
    assert rows[0, 0] < 1e-12 and rows[0, 1] < 1e-12 and rows[0, 2] == 1.0
    Q[1, 3] = np.nan
    fk_checks(*a.kinematics.kernel_chain.flat, frame, H, Q, plain)
    assert np.isnan(plain[1, 0]) and plain[1, 2] == 0.0


@pytest.mark.parametrize("name", ["ur5", "abb_irb120", "kinova"])
def test_solve_all_errors_are_pinocchio_distances(name):
    # Each result's errors, from the compiled FK, against the distances of Pinocchio's
    # placement computed here: the same numbers to 1e-12, successes and failures alike.
    a = arm(name)
    m = a.kinematics
    rng = np.random.default_rng(4)
    seen = 0
    for _ in range(6):
        T = a.fk(a.random_q(rng))
        for r in a.solve_all(T):
            pin.forwardKinematics(m.model, m.data, m.to_pin(r.q))
            tip = m.T_base_world * pin.updateFramePlacement(m.model, m.data, m.tip_frame_id)
            assert abs(r.position_error - np.linalg.norm(T.translation - tip.translation)) < EXACT
            angle = np.linalg.norm(pin.log3(tip.rotation.T @ T.rotation))
            assert abs(r.orientation_error - angle) < EXACT
            assert r.success == (
                a.within_limits(r.q) and r.position_error <= 1e-6 and r.orientation_error <= 1e-6
            )
            seen += 1
    assert seen >= 12
