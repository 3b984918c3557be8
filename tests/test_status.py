import pickle

import numpy as np
import pytest

import armik
from armik.result import IKResult
from armik.status import FAILURE_RANK, Status


def test_status_reads_as_its_word_and_round_trips_its_code():
    for s in Status:
        assert s == s.value and str(s) == s.value
        assert Status.from_code(s.code) is s
    assert sorted(FAILURE_RANK, key=FAILURE_RANK.get)[0] is Status.JOINT_LIMITS
    assert Status.CONVERGED not in FAILURE_RANK


def test_a_status_from_a_bad_word_is_an_armik_error_naming_the_statuses():
    with pytest.raises(armik.OptionError, match="status 'ok' is none of armik's statuses") as e:
        armik.Status("ok")
    assert "'converged', 'unreachable'" in str(e.value) and e.value.value == "ok"
    with pytest.raises(armik.OptionError, match="did you mean 'converged'"):
        armik.Status("CONVERGED")
    with pytest.raises(armik.InputError, match="status None"):
        armik.Status(None)
    assert armik.Status("collision") is armik.Status.COLLISION


def test_unknown_status_word_is_refused_with_the_list():
    with pytest.raises(ValueError, match="'converged', 'unreachable'"):
        Status.parse("done")
    with pytest.raises(ValueError, match="not_converged"):
        IKResult(
            q=[0.0],
            success=False,
            status="maybe",
            reason="",
            solver="dls",
            iterations=0,
            position_error=0.0,
            orientation_error=None,
            time=0.0,
        )


def test_result_status_is_the_enum_and_dict_keeps_the_word():
    r = armik.load("planar_2link").solve([1.2, 0.5])
    assert r.status is Status.CONVERGED and r.as_dict()["status"] == "converged"


def test_arm_pickles_as_its_recipe():
    arm = armik.load("ur5", tip="wrist_3_link", tip_offset=(0.0, 0.0, 0.1))
    arm = arm.with_limits({"shoulder_pan_joint": (-1.0, 1.0)})
    copy = pickle.loads(pickle.dumps(arm))
    assert copy.tip == arm.tip and copy.joint_names == arm.joint_names
    np.testing.assert_array_equal(copy.lower, arm.lower)
    np.testing.assert_array_equal(copy.upper, arm.upper)
    q = arm.random_q(3)
    assert copy.fk(q).isApprox(arm.fk(q), 1e-14)
    assert len(pickle.dumps(arm)) < 1000  # the recipe, not the model


def test_arm_pickles_with_locked_joints_and_base():
    arm = armik.load("panda", locked={"panda_finger_joint1": 0.01})
    copy = pickle.loads(pickle.dumps(arm))
    q = arm.random_q(1)
    assert copy.fk(q).isApprox(arm.fk(q), 1e-14)
