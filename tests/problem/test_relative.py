"""``armik.Relative``: one frame's pose in another's. Its Jacobian against finite
differences through ``pin.integrate``, its measure against a hand-built pose, and solves
on one arm, on two arms sharing no joint (the reference chain first, then the other to a
pose in the base: exact) and on TALOS's shared torso, each checked on Pinocchio's model of
the whole URDF."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import FrameError, TargetError
from armik.model.arm_model import ArmModel

from ..conftest import arm as bundled
from ..conftest import model
from ..test_arms import dual_irb120

H = 1e-6


def placed(a: ArmModel, qp: np.ndarray, frames: list[str]) -> list:
    """Each frame's (T_base_frame, LOCAL Jacobian) at Pinocchio's ``qp`` on the arm model."""
    data = a.model.createData()
    pin.computeJointJacobians(a.model, data, qp)
    out = []
    for f in frames:
        i = a.model.getFrameId(f)
        T = a.T_base_world * pin.updateFramePlacement(a.model, data, i)
        out.append((T, pin.getFrameJacobian(a.model, data, i, pin.LOCAL)))
    return out


def test_the_jacobian_matches_finite_differences():
    a = model("panda")
    rng = np.random.default_rng(8)
    frames = [a.tip, "panda_link4"]
    for bounds in (None, (0.01, 0.0, np.inf, 0.05, 0.0, 0.02)):
        q_t = a.random_q(rng)
        T_t = placed(a, a.to_pin(q_t), frames)
        task = armik.Relative(a.tip, "panda_link4", T_t[1][0].actInv(T_t[0][0]), bounds=bounds)
        for _ in range(3):
            qp = a.to_pin(a.random_q(rng))
            T, J = task.placement(placed(a, qp, frames))
            analytic = task.jacobian(T, J)
            columns = []
            for i in range(a.dof):
                dv = np.zeros(a.model.nv)
                dv[i] = H
                plus = task.residual(
                    task.placement(placed(a, pin.integrate(a.model, qp, dv), frames))[0]
                )
                minus = task.residual(
                    task.placement(placed(a, pin.integrate(a.model, qp, -dv), frames))[0]
                )
                columns.append((plus - minus) / (2 * H))
            np.testing.assert_allclose(analytic, np.array(columns).T, atol=2e-6)


def test_the_measure_is_the_pose_in_the_reference_frame():
    T_ref, T_rel = pin.SE3.Random(), pin.SE3.Random()
    task = armik.Relative("hand", "camera", T_rel)
    T, J = task.placement([(T_ref * T_rel, None), (T_ref, None)])
    assert J is None and T.isApprox(T_rel, 1e-12)
    moved = T_ref * T_rel * pin.SE3(np.eye(3), np.array([0.003, 0.0, 0.0]))
    e = task.measure(task.placement([(moved, None), (T_ref, None)])[0], 1e-6, 1e-6)
    assert not e.within and e.position == pytest.approx(0.003, abs=1e-12)
    assert e.orientation == pytest.approx(0.0, abs=1e-12)


def test_one_arm_holds_its_tool_in_a_frame_of_its_own():
    a = bundled("panda")
    rng = np.random.default_rng(2)
    for _ in range(5):
        q = a.random_q(rng)
        (T_tip, _), (T_4, _) = placed(a.kinematics, a.kinematics.to_pin(q), [a.tip, "panda_link4"])
        task = armik.Relative(a.tip, "panda_link4", T_4.actInv(T_tip))
        r = a.solve([task], iteration_budget=3000)
        assert r.success, r.reason
        (T_tip, _), (T_4, _) = placed(
            a.kinematics, a.kinematics.to_pin(r.q), [a.tip, "panda_link4"]
        )
        err = pin.log6(task.pose.T.inverse() * T_4.actInv(T_tip)).vector
        assert np.abs(err).max() <= 2e-6


def full_placements(urdf_xml: str, names, q, frames) -> dict:
    """The frames' placements on Pinocchio's model of the whole URDF (an independent read)."""
    full = pin.buildModelFromXML(urdf_xml)
    data = full.createData()
    qf = pin.neutral(full)
    for name, value in zip(names, q):
        qf[full.joints[full.getJointId(name)].idx_q] = value
    pin.framesForwardKinematics(full, data, qf)
    return {f: data.oMf[full.getFrameId(f)].copy() for f in frames}


@pytest.fixture(scope="module")
def cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])


def test_two_arms_sharing_no_joint_hold_a_box(cell):
    """The left hand at a pose, the right at a pose in the left's frame (within bounds)."""
    rng = np.random.default_rng(4)
    xml = dual_irb120()
    tips = list(cell.tips)
    for _ in range(10):
        q = cell.random_q(rng)
        T_l, T_r = cell.fk(q, "l_tool0"), cell.fk(q, "r_tool0")
        grip = armik.Relative("r_tool0", "l_tool0", T_l.actInv(T_r), bounds=(0, 0, 0, 0, 0, 0.1))
        r = cell.solve({"l_tool0": T_l, "r_tool0": grip})
        assert r.success, r.reason
        assert "l_tool0 by spherical" in r.reason  # each chain by its closed form
        got = full_placements(xml, cell.joint_names, r.q, tips)
        assert np.abs(pin.log6(T_l.inverse() * got["l_tool0"]).vector).max() <= 2e-6
        twist = grip.pose.twist(got["l_tool0"].actInv(got["r_tool0"]))
        assert np.abs(twist[:5]).max() <= 2e-6 and abs(twist[5]) <= 0.1 + 1e-6


def test_frames_placed_relative_to_each_other_are_solved_together(cell):
    """Each hand relative to the other (a cycle): no chain can go first; the left hand's
    pose alone (the right's free) too, where the right cannot reach from the left's seed."""
    rng = np.random.default_rng(6)
    q = cell.random_q(rng)
    T_l, T_r = cell.fk(q, "l_tool0"), cell.fk(q, "r_tool0")
    rel = T_l.actInv(T_r)
    targets = {
        "l_tool0": armik.Relative("l_tool0", "r_tool0", rel.inverse()),
        "r_tool0": armik.Relative("r_tool0", "l_tool0", rel),
    }
    r = cell.solve(targets, iteration_budget=3000)
    assert r.success, r.reason
    got = full_placements(dual_irb120(), cell.joint_names, r.q, cell.tips)
    err = pin.log6(rel.inverse() * got["l_tool0"].actInv(got["r_tool0"])).vector
    assert np.abs(err).max() <= 2e-6
    assert (r.q >= cell.lower - 1e-9).all() and (r.q <= cell.upper + 1e-9).all()


def test_a_relative_pose_over_a_shared_torso():
    robots = Path(armik.load("panda").source).parents[2]
    urdf = robots / "talos_data" / "robots" / "talos_reduced.urdf"
    tips = ["gripper_left_base_link", "gripper_right_base_link"]
    robot = armik.load(urdf, tips=tips)
    rng = np.random.default_rng(5)
    xml = urdf.read_text()
    solved = 0
    for _ in range(10):
        q = robot.random_q(rng)
        T = full_placements(xml, robot.joint_names, q, tips)
        rel = T[tips[0]].actInv(T[tips[1]])
        r = robot.solve(
            {tips[0]: T[tips[0]], tips[1]: armik.Relative(tips[1], tips[0], rel)},
            iteration_budget=3000,
        )
        if not r.success:
            continue
        solved += 1
        got = full_placements(xml, robot.joint_names, r.q, tips)
        assert np.abs(pin.log6(T[tips[0]].inverse() * got[tips[0]]).vector).max() <= 2e-6
        assert (
            np.abs(pin.log6(rel.inverse() * got[tips[0]].actInv(got[tips[1]])).vector).max() <= 2e-6
        )
        assert set(r.extra["errors"]) == set(tips)
    assert solved >= 9


def test_bad_relative_input_is_named(cell):
    with pytest.raises(TargetError, match="both are 'a'"):
        armik.Relative("a", "a", pin.SE3.Identity())
    with pytest.raises(TargetError, match="two frame names"):
        armik.Relative(None, "a", pin.SE3.Identity())  # type: ignore[arg-type]
    with pytest.raises(FrameError, match="unknown tips \\['camera'\\]"):
        cell.solve({"r_tool0": armik.Relative("r_tool0", "camera", pin.SE3.Identity())})
    with pytest.raises(TargetError, match="its own tasks"):
        cell.solve({"r_tool0": armik.Relative("l_tool0", "r_tool0", pin.SE3.Identity())})
