"""The servo on an arm with a mimic joint: the mimic joint's velocity and acceleration
limits bind its driver, as its position limits do."""

from __future__ import annotations

import numpy as np

import armik
from armik.servo.limits import DEFAULT_ACCELERATION

DT = 0.002


def _urdf(multiplier: float) -> str:
    def joint(name, parent, child, z, axis, lo, hi, vel, extra=""):
        return (
            f'<joint name="{name}" type="revolute"><parent link="{parent}"/>'
            f'<child link="{child}"/><origin xyz="0 0 {z}"/><axis xyz="{axis}"/>'
            f'<limit lower="{lo}" upper="{hi}" effort="1" velocity="{vel}"/>{extra}</joint>'
        )

    mimic = f'<mimic joint="j2" multiplier="{multiplier}" offset="0.0"/>'
    return (
        '<robot name="mim"><link name="base"/><link name="l1"/><link name="l2"/>'
        '<link name="l3"/><link name="tool"/>'
        + joint("j1", "base", "l1", 0.3, "0 0 1", -3, 3, 2)
        + joint("j2", "l1", "l2", 0.1, "0 1 0", -2, 2, 2)
        + joint("j3", "l2", "l3", 0.4, "0 1 0", -1.5, 1.5, 0.2, mimic)
        + joint("j4", "l3", "tool", 0.3, "0 1 0", -2, 2, 2)
        + "</robot>"
    )


def _mimic_motion(rec, q0, multiplier):
    """The mimic joint's values' velocity and acceleration by finite differences."""
    j3 = multiplier * np.concatenate([[q0[1]], rec.q[:, 1]])
    v = np.diff(j3) / DT
    return v, np.diff(np.concatenate([[0.0], v])) / DT


def test_a_mimic_joints_velocity_and_acceleration_limits_bind_its_driver():
    for multiplier in (-0.5, 2.0):
        arm = armik.load(_urdf(multiplier), tip="tool")
        q0 = np.zeros(3)
        servo = arm.servo(q0, dt=DT)
        # the driver j2 at most the mimic's 0.2 rad/s (and 20 rad/s^2) over |multiplier|
        vmax, amax = servo.velocity_limits, servo.acceleration_limits
        assert vmax[1] == 0.2 / abs(multiplier) and vmax[0] == vmax[2] == 2.0
        assert amax[1] == min(DEFAULT_ACCELERATION, DEFAULT_ACCELERATION / abs(multiplier))
        target = arm.fk(np.array([0.0, 0.6 / abs(multiplier), 0.0])).translation
        rec = servo.track([target] * 400)
        v, a = _mimic_motion(rec, q0, multiplier)
        assert np.abs(v).max() <= 0.2 * (1 + 1e-9)
        assert np.abs(v).max() > 0.19  # it did move at its limit
        assert np.abs(a).max() <= DEFAULT_ACCELERATION * (1 + 1e-9)


def test_one_number_for_every_joint_is_the_mimic_joints_too():
    arm = armik.load(_urdf(2.0), tip="tool")
    servo = arm.servo(np.zeros(3), velocity_limits=1.0, acceleration_limits=8.0)
    np.testing.assert_array_equal(servo.velocity_limits, [1.0, 0.5, 1.0])
    np.testing.assert_array_equal(servo.acceleration_limits, [8.0, 4.0, 8.0])
    # one per driving joint: the mimic joint keeps its URDF's velocity and the default
    servo = arm.servo(np.zeros(3), velocity_limits=[1.0, 1.0, 1.0])
    np.testing.assert_array_equal(servo.velocity_limits, [1.0, 0.1, 1.0])
    assert servo.acceleration_limits[1] == DEFAULT_ACCELERATION / 2.0
