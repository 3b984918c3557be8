"""A frame that hangs from a mimic joint off the chain whose driver moves on the chain (a
parallelogram's passive link): ``fk(q, frame=...)`` and ``jacobian(q, frame=...)`` move it
with its driver, as yourdfpy and robot_state_publisher do; the chain's model holds it fixed."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

import armik

from ..conftest import write_urdf

LIMIT = 'effort="1" velocity="1"'
URDF = f"""<?xml version="1.0"?>
<robot name="passive">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="tool"/>
  <link name="rod"/><link name="rod_end"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" {LIMIT}/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.1" rpy="0.2 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" {LIMIT}/></joint>
  <joint name="j3" type="prismatic"><parent link="l2"/><child link="l3"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 0 1"/><limit lower="0" upper="0.3" {LIMIT}/></joint>
  <joint name="tool_fix" type="fixed"><parent link="l3"/><child link="tool"/>
    <origin xyz="0 0 0.1"/></joint>
  <joint name="passive" type="revolute"><parent link="l1"/><child link="rod"/>
    <origin xyz="0.05 0 0.1" rpy="0 0.3 0"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" {LIMIT}/>
    <mimic joint="j2" multiplier="-0.8" offset="0.25"/></joint>
  <joint name="slide" type="prismatic"><parent link="rod"/><child link="rod_end"/>
    <origin xyz="0 0 0.2"/><axis xyz="1 0 0"/><limit lower="-1" upper="1" {LIMIT}/>
    <mimic joint="j3" multiplier="2" offset="0.01"/></joint>
</robot>
"""


@pytest.fixture
def setup(tmp_path):
    path = write_urdf(tmp_path, URDF)
    return armik.load(path, tip="tool"), yourdfpy.URDF.load(str(path), load_meshes=False)


def _reference(arm, robot, q, frame):
    values = dict(zip(arm.joint_names, q))  # yourdfpy moves the mimic joints itself
    robot.update_cfg(np.array([values.get(n, 0.0) for n in robot.actuated_joint_names]))
    return robot.get_transform(frame_to=frame, frame_from=arm.base)


@pytest.mark.parametrize("frame", ["rod", "rod_end", "l2", "tool"])
def test_frames_below_a_passive_mimic_joint_follow_its_driver(setup, rng, frame):
    arm, robot = setup
    assert arm.joint_names == ["j1", "j2", "j3"]
    for _ in range(10):
        q = arm.random_q(rng)
        want = _reference(arm, robot, q, frame)
        np.testing.assert_allclose(arm.fk(q, frame=frame).homogeneous, want, atol=1e-12)


@pytest.mark.parametrize("reference", ["base", "local"])
@pytest.mark.parametrize("frame", ["rod", "rod_end"])
def test_their_jacobian_is_the_derivative_of_that_pose(setup, rng, frame, reference):
    arm, robot = setup
    h = 1e-6
    for _ in range(5):
        q = arm.random_q(rng)
        J = arm.jacobian(q, frame=frame, reference=reference)
        R = _reference(arm, robot, q, frame)[:3, :3]
        for i in range(arm.dof):
            up, down = q.copy(), q.copy()
            up[i] += h
            down[i] -= h
            Tu, Td = _reference(arm, robot, up, frame), _reference(arm, robot, down, frame)
            v = (Tu[:3, 3] - Td[:3, 3]) / (2 * h)
            w = pin.log3(Tu[:3, :3] @ Td[:3, :3].T) / (2 * h)
            if reference == "local":
                v, w = R.T @ v, R.T @ w
            np.testing.assert_allclose(J[:, i], np.concatenate([v, w]), atol=1e-7)


def test_a_passive_mimic_joint_locked_by_name_stays_at_its_value(tmp_path, rng):
    path = write_urdf(tmp_path, URDF)
    arm = armik.load(path, tip="tool", locked={"passive": 0.5})
    robot = yourdfpy.URDF.load(str(path), load_meshes=False)
    held = (0.5 - 0.25) / -0.8  # the j2 at which yourdfpy puts the passive joint at 0.5
    for _ in range(5):
        q = arm.random_q(rng)
        at_held = q.copy()
        at_held[1] = held
        l1_rod = arm.fk(q, frame="l1").inverse() * arm.fk(q, frame="rod")
        want = _reference(arm, robot, at_held, "l1")
        want = np.linalg.inv(want) @ _reference(arm, robot, at_held, "rod")
        np.testing.assert_allclose(l1_rod.homogeneous, want, atol=1e-12)


def test_collision_objects_below_a_passive_mimic_joint_follow_its_driver(tmp_path, rng):
    """A box on the passive rod is checked where the rod is (its driver turned), not where
    the reference value left it: a sphere on the rod's end at q touches it, one where the
    rod would be at the reference value does not, and the distance past the box's end is
    measured on yourdfpy's placement of the rod."""
    box = (
        '<collision><origin xyz="0 0 0.1"/>'
        '<geometry><box size="0.02 0.02 0.2"/></geometry></collision>'
    )
    text = URDF.replace('<link name="rod"/>', f'<link name="rod">{box}</link>')
    path = write_urdf(tmp_path, text)
    arm = armik.load(path, tip="tool")
    robot = yourdfpy.URDF.load(str(path), load_meshes=False)
    for _ in range(5):
        q = arm.random_q(rng)
        end = _reference(arm, robot, q, "rod")  # the rod's frame, as ROS places it
        centre = (end @ np.array([0.0, 0.0, 0.1, 1.0]))[:3]  # the box's centre
        held = arm.fk(arm.middle, frame="rod").act(np.array([0.0, 0.0, 0.1]))
        if np.linalg.norm(held - centre) < 0.2:
            continue  # the rod where it would be held: too near to tell apart
        assert arm.in_collision(q, obstacles=[armik.Sphere(0.02, centre)])
        assert not arm.in_collision(q, obstacles=[armik.Sphere(0.02, held)])
        beyond = (end @ np.array([0.0, 0.0, 0.3, 1.0]))[:3]  # 0.1 past the box's end
        d, pair = arm.min_distance(q, obstacles=[armik.Sphere(0.05, beyond)])
        assert pair[0] == "rod" and d == pytest.approx(0.1 - 0.05, abs=1e-6)
