"""Loading arms: the catalogue, joint types, limits, and every bad input named clearly."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import FrameError, JointError, URDFError
from armik.model.catalogue import entry

from ..conftest import ALL_ROBOTS, arm, two_link_urdf, write_urdf

EXPECTED_DOF = {
    "planar_2link": 2,
    "planar_3link": 3,
    "scara": 4,
    "panda": 7,
    "ur5": 6,
    "ur10": 6,
    "kinova": 6,
    "xarm7": 7,
    "z1": 6,
    "double_pendulum": 2,
    "abb_irb120": 6,
    "kuka_iiwa14": 7,
    "so101": 5,
}


def test_catalogue_lists_required_robots():
    names = armik.robots()
    for required in [
        "planar_2link",
        "planar_3link",
        "panda",
        "ur5",
        "ur10",
        "kinova",
        "xarm7",
        "z1",
    ]:
        assert required in names


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_every_bundled_robot_loads(name, rng):
    a = arm(name)
    assert a.dof == EXPECTED_DOF[name]
    assert len(a.joint_names) == a.dof == len(a.lower) == len(a.upper)
    q = a.random_q(rng)
    assert a.within_limits(q)
    assert a.jacobian(q).shape == (6, a.dof)
    assert isinstance(a.fk(q), pin.SE3)


def test_panda_fingers_locked_and_tip():
    a = arm("panda")
    assert a.tip == "panda_hand"
    assert not any("finger" in n for n in a.joint_names)


def test_kinova_continuous_joints_are_one_angle_each(rng):
    a = arm("kinova")
    assert a.model.nq == 9 and a.dof == 6
    cont = [i for i, t in enumerate(a.joint_types) if t == "continuous"]
    assert cont == [0, 3, 5]
    assert np.all(np.isinf(a.lower[cont])) and np.all(np.isinf(a.upper[cont]))
    q = a.random_q(rng)
    assert np.all(np.abs(q[cont]) <= math.pi)
    # an angle and the same angle plus 2 pi are the same pose
    q2 = q.copy()
    q2[0] += 2 * math.pi
    assert a.fk(q).isApprox(a.fk(q2), 1e-12)
    m = a.kinematics
    np.testing.assert_allclose(m.from_pin(m.to_pin(q)), q, atol=1e-15)


def test_prismatic_joint_of_the_scara(rng):
    a = arm("scara")
    i = a.kinematics.joint_index("quill")
    assert a.joint_types[i] == "prismatic"
    q = a.middle.copy()
    z0 = a.fk(q).translation[2]
    q[i] += 0.05
    assert a.fk(q).translation[2] == pytest.approx(z0 - 0.05, abs=1e-12)  # axis is -z


def test_load_from_path_with_base_tip_and_locked(tmp_path):
    path = write_urdf(tmp_path, two_link_urdf())
    a = armik.load(path, base="l1", tip="tip")
    assert a.dof == 1 and a.joint_names == ["j2"]
    b = armik.load(str(path), tip="tip", locked={})
    assert b.dof == 2


def test_locked_joint_upstream_of_base_sets_base_placement():
    # joint1 lies above the base link1, so it is locked; its value places the base.
    a = armik.load("planar_3link", base="link1", locked={"joint1": 0.5})
    assert a.joint_names == ["joint2", "joint3"]
    np.testing.assert_allclose(
        pin.log3(a.kinematics.T_world_base.rotation), [0, 0, 0.5], atol=1e-12
    )
    # the chain's own kinematics, in the base frame, do not depend on it
    b = armik.load("planar_3link", base="link1")
    assert a.fk(np.array([0.2, 0.3])).isApprox(b.fk(np.array([0.2, 0.3])), 1e-12)


def test_locked_joint_on_the_chain_is_a_fixed_transform(tmp_path):
    path = write_urdf(tmp_path, two_link_urdf())
    a = armik.load(path, tip="tip", locked={"j2": 0.3})
    assert a.joint_names == ["j1"] and a.kinematics.locked_on_chain == ("j2",)
    full = armik.load(path, tip="tip")
    assert a.fk([0.2]).isApprox(full.fk([0.2, 0.3]), 1e-12)
    b = armik.load(path, tip="l1", locked={"j2": 0.3})  # off the chain: not on it
    assert (
        b.joint_names == ["j1"]
        and b.kinematics.locked_on_chain == ()
        and dict(b.locked) == {"j2": 0.3}
    )


def test_panda_locked_finger_value_moves_nothing_on_hand():
    a = armik.load("panda", locked={"panda_finger_joint1": 0.02})
    assert a.dof == 7


@pytest.mark.parametrize(
    "content, match",
    [
        ("", "empty"),
        ("<robot name='x'><link name='a'>", "not well-formed"),
        ("<model/>", "not a URDF"),
    ],
)
def test_bad_files(tmp_path, content, match):
    with pytest.raises(URDFError, match=match):
        armik.load(write_urdf(tmp_path, content))


@pytest.mark.parametrize("source", ["", "  ", "\n"])
def test_empty_source_says_empty_not_directory(source):
    # Path("") is "."; an empty name (an unset variable) is not the current folder
    with pytest.raises(URDFError, match="source is empty") as info:
        armik.load(source)
    assert "directory" not in str(info.value)
    with pytest.raises(URDFError, match="source is empty"):
        armik.load(source, tips=["a", "b"])


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(URDFError, match="does not exist"):
        armik.load(tmp_path / "nope.urdf")
    with pytest.raises(URDFError, match="directory"):
        armik.load(tmp_path)
    with pytest.raises(URDFError, match="neither a bundled robot") as info:
        armik.load("no_such_robot")
    assert "did you mean" not in str(info.value)  # nothing close to suggest
    with pytest.raises(URDFError, match=r"did you mean 'panda'\? check the name"):
        armik.load("pand")
    with pytest.raises(URDFError, match=r"did you mean 'kuka_iiwa14'\?"):
        armik.load("kuka")
    with pytest.raises(armik.InputError, match=r"unknown robot 'pand': did you mean 'panda'\?"):
        entry("pand")
    with pytest.raises(URDFError, match="robot name or a path"):
        armik.load(42)


def test_lower_above_upper(tmp_path):
    text = two_link_urdf(limits2=(1.0, -1.0))
    with pytest.raises(URDFError, match="lower limit 1.0 > upper limit -1.0"):
        armik.load(write_urdf(tmp_path, text))


def test_unknown_frames_list_candidates(tmp_path):
    path = write_urdf(tmp_path, two_link_urdf())
    with pytest.raises(FrameError, match="unknown tip frame 'hand'.*'tip'") as info:
        armik.load(path, tip="hand")
    assert "tip" in info.value.candidates
    with pytest.raises(FrameError, match="unknown base frame"):
        armik.load(path, base="nowhere", tip="tip")


def test_tip_above_base_and_no_moving_joint(tmp_path):
    path = write_urdf(tmp_path, two_link_urdf())
    with pytest.raises(FrameError, match="not downstream"):
        armik.load(path, base="l2", tip="l1")
    with pytest.raises(FrameError, match="no moving joint"):
        armik.load(path, base="world", tip="base")


def test_bad_locked_name_lists_joints(tmp_path):
    path = write_urdf(tmp_path, two_link_urdf())
    with pytest.raises(JointError, match="'elbow' does not exist.*'j1'"):
        armik.load(path, tip="tip", locked={"elbow": 0.0})


def test_missing_meshes_do_not_matter(tmp_path):
    text = two_link_urdf().replace(
        '<link name="l1"/>',
        '<link name="l1"><visual><geometry><mesh filename="package://gone/l1.stl"/>'
        "</geometry></visual></link>",
    )
    a = armik.load(write_urdf(tmp_path, text), tip="tip")
    assert a.dof == 2


def test_mimic_joint_on_chain_follows_its_driver(tmp_path):
    limit = '<limit lower="-3.14159" upper="3.14159" effort="1" velocity="1"/>'
    text = two_link_urdf().replace(
        f'{limit}</joint>\n  <joint name="tool"',
        f'{limit}<mimic joint="j1" multiplier="1"/></joint>\n  <joint name="tool"',
    )
    assert "mimic" in text
    a = armik.load(write_urdf(tmp_path, text), tip="tip")
    assert a.joint_names == ["j1"] and [m.name for m in a.kinematics.mimics] == ["j2"]


def test_no_tip_with_several_leaves_lists_them(tmp_path):
    text = (
        two_link_urdf()
        .replace('<link name="tip"/>', '<link name="tip"/><link name="cam"/>')
        .replace(
            "</robot>",
            '<joint name="c" type="continuous"><parent link="l1"/><child link="cam"/></joint>'
            "</robot>",
        )
    )
    with pytest.raises(FrameError, match="leaf links.*'cam'.*") as box:
        armik.load(write_urdf(tmp_path, text))
    assert "pass tip=" in str(box.value)  # the Python argument; the CLI says --tip


def test_single_leaf_is_default_tip(tmp_path):
    a = armik.load(write_urdf(tmp_path, two_link_urdf()))
    assert a.tip == "tip" and a.base == "world"


def test_with_limits_and_errors():
    a = arm("planar_2link").with_limits({"joint2": (0.0, 1.0)})
    assert a.lower[1] == 0.0 and a.upper[1] == 1.0
    assert arm("planar_2link").lower[1] < 0  # original untouched
    with pytest.raises(JointError, match="not on this arm's chain"):
        arm("planar_2link").with_limits({"joint9": (0.0, 1.0)})


def test_jacobian_base_frame_matches_finite_differences(rng):
    a = arm("ur5")
    q = a.random_q(rng)
    J = a.jacobian(q, reference="base")
    h = 1e-6
    for i in range(a.dof):
        dq = np.zeros(a.dof)
        dq[i] = h
        Tp, Tm = a.fk(q + dq), a.fk(q - dq)
        v = (Tp.translation - Tm.translation) / (2 * h)
        w = pin.log3(Tp.rotation @ Tm.rotation.T) / (2 * h)
        np.testing.assert_allclose(J[:3, i], v, atol=1e-6)
        np.testing.assert_allclose(J[3:, i], w, atol=1e-6)


@pytest.mark.parametrize("value", ["abc", float("nan"), None])
def test_bad_locked_value(value):
    with pytest.raises(JointError, match="finite number"):
        armik.load("panda", locked={"panda_finger_joint1": value})


def test_with_limits_recomputes_the_reach():
    a = armik.load("scara")
    assert a.kinematics.reach > 0  # cached on the original first
    longer = a.with_limits({"quill": (0.0, 1.2)})
    assert longer.kinematics.reach > a.kinematics.reach + 0.5  # the quill travels 1 m more
    # a target 0.5 m below what the original quill reaches is not refused as out of reach
    q = np.array([0.3, -0.4, 0.7, 0.0])
    r = longer.solve(longer.fk(q).translation, solver="dls")
    assert r.success, r.reason


def test_repr_shows_the_tool_offset():
    a = armik.load("ur5", tip_offset=(0.0, 0.0, 0.12))
    assert "tip_offset=(0.0, 0.0, 0.12)" in repr(a)
    assert "tip_offset" not in repr(armik.load("ur5"))
