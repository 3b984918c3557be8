"""Any frame by name, in the same words on one arm and on several tips: ``fk(q, frame=)``
and ``jacobian(q, frame=, reference=)``."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from tests.conftest import arm as bundled
from tests.conftest import frame_position


def _finite_differences(place, q: np.ndarray, reference: str, h: float = 1e-6) -> np.ndarray:
    """Columns of the frame's twist per joint, central differences of its placement:
    the LOCAL twist ``log6(T^-1 T')``, or its parts along the base axes."""
    T = place(q)
    J = np.zeros((6, len(q)))
    for k in range(len(q)):
        d = np.zeros(len(q))
        d[k] = h
        twist = pin.log6(place(q - d).inverse() * place(q + d)).vector / (2 * h)
        if reference == "base":
            R = T.rotation
            twist = np.concatenate([R @ twist[:3], R @ twist[3:]])
        J[:, k] = twist
    return J


@pytest.mark.parametrize("name, frame", [("ur5", "forearm_link"), ("panda", "panda_link4")])
@pytest.mark.parametrize("reference", ["local", "base"])
def test_a_frame_by_name(name, frame, reference):
    a = bundled(name)
    q = a.random_q(3)
    T = a.fk(q, frame=frame)
    np.testing.assert_allclose(T.translation, frame_position(a, q, frame), atol=1e-12)
    J = a.jacobian(q, frame=frame, reference=reference)
    fd = _finite_differences(lambda x: a.fk(x, frame=frame), q, reference)
    np.testing.assert_allclose(J, fd, atol=1e-6)


def test_the_tip_by_default_and_the_old_spelling():
    a = bundled("panda")
    q = a.random_q(4)
    assert a.fk(q, frame=a.tip).isApprox(a.fk(q), 1e-14)
    np.testing.assert_array_equal(a.jacobian(q, "base"), a.jacobian(q, reference="base"))
    np.testing.assert_array_equal(a.jacobian(q, "local"), a.jacobian(q, reference="local"))
    np.testing.assert_array_equal(a.jacobian(q), a.jacobian(q, frame=a.tip, reference="local"))


@pytest.mark.parametrize("several", [False, True])
def test_the_old_spelling_is_refused_where_a_frame_has_its_name(several):
    """The UR5 has a frame named ``base``: ``jacobian(q, frame="base")`` could mean it or
    the old spelling of ``reference="base"``; it answered the tip's Jacobian in the base's
    axes without a word. Refused by name, each meaning said apart."""
    a = armik.load("ur5", tips=["tool0", "forearm_link"]) if several else bundled("ur5")
    q = a.random_q(4)
    for spelled in ({"frame": "base"}, {}):
        with pytest.raises(armik.OptionError, match="names a frame of this arm") as e:
            a.jacobian(q, "base") if not spelled else a.jacobian(q, **spelled)
        assert "reference='base'" in str(e.value) and e.value.value == "base"
    J = a.jacobian(q, frame="base", reference="local")  # the frame itself: fixed to the base
    assert np.abs(J).max() == 0.0
    tip = a.tips[0] if several else a.tip
    direct = a.jacobian(q, frame=tip, reference="base")
    assert np.abs(direct).max() > 0.1


def test_bad_names_are_refused_by_name():
    a = bundled("ur5")
    with pytest.raises(armik.FrameError, match="forearm_link"):  # the list of frames
        a.fk(a.middle, frame="no_such_link")
    with pytest.raises(armik.OptionError, match="reference"):
        a.jacobian(a.middle, reference="world")


def test_several_tips_say_the_same():
    robot = armik.load("panda", tips=["panda_hand", "panda_link5"])
    q = robot.random_q(5)
    single = bundled("panda")
    q_hand = robot.split(q)["panda_hand"]
    assert robot.fk(q, frame="panda_link3").isApprox(single.fk(q_hand, frame="panda_link3"))
    J = robot.jacobian(q, frame="panda_hand", reference="base")
    cols = [robot.joint_names.index(n) for n in single.joint_names]
    np.testing.assert_allclose(J[:, cols], single.jacobian(q_hand, reference="base"), atol=1e-12)
    with pytest.raises(armik.FrameError):
        robot.fk(q, frame="no_such_link")


def test_a_path_starts_from_the_middle_without_q0():
    a = bundled("ur5")
    T = a.fk(a.middle + 0.1)
    line = [pin.SE3(T.rotation, T.translation + [0, 0.01 * k, 0]) for k in range(3)]
    path = a.solve_path(line)
    np.testing.assert_array_equal(path.q, a.solve_path(line, a.middle).q)


def test_a_name_a_joint_and_its_link_share_is_the_links_frame():
    """The SCARA's ``quill`` names a joint and its child link: Pinocchio holds a frame of
    each, at one placement; ``fk``, ``jacobian`` and a task read the link's, as ROS does."""
    scara = bundled("scara")
    q = scara.random_q(np.random.default_rng(4))
    model = scara.model
    data = model.createData()
    link = model.getFrameId("quill", pin.FrameType.BODY)
    pin.framesForwardKinematics(model, data, scara.kinematics.to_pin(q))
    T = scara.fk(q, "quill")
    assert T.isApprox(scara.kinematics.T_base_world * data.oMf[link], 1e-12)
    J = pin.computeFrameJacobian(model, data, scara.kinematics.to_pin(q), link, pin.LOCAL)
    np.testing.assert_allclose(scara.jacobian(q, frame="quill"), J, atol=1e-12)
    r = scara.solve([armik.Position(T.translation, frame="quill")])
    assert r.success, r.reason
    assert np.linalg.norm(scara.fk(r.q, "quill").translation - T.translation) < 1e-6


def test_a_name_of_frames_at_different_placements_is_refused_naming_them():
    from armik.model.frames import named

    model = bundled("scara").model.copy()
    elbow = model.getFrameId("elbow")
    joint = model.frames[model.getFrameId("quill", pin.FrameType.BODY)].parentJoint
    frame = pin.Frame("elbow", joint, elbow, pin.SE3.Identity(), pin.FrameType.BODY)
    model.addFrame(frame, False)
    with pytest.raises(armik.FrameError, match="'elbow' names 2 frames") as caught:
        named(model, "elbow")
    assert len(caught.value.candidates) == 2
    assert named(model, "link1") == model.getFrameId("link1")


def test_an_unknown_frame_names_the_closest(rng):
    ur5 = bundled("ur5")
    with pytest.raises(armik.FrameError, match=r"'wrist3_link' .*; closest: 'wrist_3_link'"):
        ur5.fk(ur5.random_q(rng), frame="wrist3_link")
    with pytest.raises(armik.FrameError, match=r"'wrist3_link' .*; closest: 'wrist_3_link'"):
        ur5.jacobian(ur5.random_q(rng), frame="wrist3_link")
    with pytest.raises(armik.FrameError) as caught:
        ur5.fk(ur5.middle, frame="nothing_like_it")
    assert "closest" not in str(caught.value) and "'tool0'" in str(caught.value)
