"""A servo's start reads its tip's Jacobian at the samples of ``armik.servo.fixed`` once
per arm, for both the directions the tip never moves in and the Jacobian's ranks."""

from __future__ import annotations

import numpy as np

import armik
from armik.model.arm_model import ArmModel
from armik.servo import fixed


def test_the_tips_jacobian_is_sampled_once_per_arm(monkeypatch):
    arm = armik.load("planar_3link")
    calls = []
    original = ArmModel.jacobian

    def counted(self, *args, **kwargs):
        calls.append(1)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(ArmModel, "jacobian", counted)
    first = arm.servo(arm.middle)
    second = arm.servo(arm.middle)
    assert len(calls) <= fixed.SAMPLES + 1
    # a planar arm: its tip never leaves its plane; both servos read the same directions
    assert np.array_equal(first._cfg, second._cfg)
    assert fixed.never_moved(arm.kinematics)[0].trace() > 0.5
