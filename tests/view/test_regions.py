"""Tolerance regions in the viewer: a task list's box, fans and cones are drawn where and as
large as the tasks say, follow the gizmo when it is dragged, and go when the target is a
plain pose again."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.problem.tasks import cone
from armik.view import regions
from armik.view.nodes import wxyz_position

from ..conftest import arm

pytest.importorskip("viser")


@pytest.fixture(scope="module")
def viewer():
    v = armik.view(arm("abb_irb120"), port=0, open_browser=False)
    yield v
    v.close()


def drawn(viewer) -> dict:
    """The region nodes on the page, by name."""
    return {h.name: h for h in viewer._region_nodes}


def drag(viewer, T: pin.SE3, tip=None) -> None:
    wxyz, position = wxyz_position(T.homogeneous)
    viewer._dragged(SimpleNamespace(wxyz=tuple(wxyz), position=tuple(position)), tip)


def test_a_position_region_is_a_box_about_the_point_in_the_base_axes(viewer):
    a = viewer.arm
    p = a.fk(a.random_q(1)).translation
    r = viewer.set_target([armik.Position(p, bounds=(0.05, 0.02, math.inf))])
    assert r.success
    (box,) = viewer.regions
    assert isinstance(box, regions.BoxRegion) and box.name == "/regions/0/0/box"
    free = regions.FREE * viewer.robot.size  # a free axis: long, not infinite
    assert np.allclose(box.size, [0.1, 0.04, free]) and np.allclose(box.T[:3, 3], p)
    assert np.allclose(box.T[:3, :3], np.eye(3))  # Position's bounds are along the base axes
    node = drawn(viewer)["/regions/0/0/box"]
    assert np.allclose(node.dimensions, box.size) and np.allclose(node.position, p)
    assert node.opacity < 1  # translucent: the arm shows through
    # the gizmo sits on the point, in the tip's orientation
    assert np.allclose(viewer._gizmos[a.tip].position, p)


def test_a_pose_region_is_a_box_in_the_target_frame_and_a_fan_per_bounded_rotation(viewer):
    a = viewer.arm
    T = a.fk(a.random_q(2))
    task = armik.Pose(T, bounds=(0.01, 0.02, 0.0, 0.0, 0.0, 0.3))
    assert viewer.set_target([task]).success
    box, fan = viewer.regions
    assert box.name == "/regions/0/0/box" and fan.name == "/regions/0/0/fan_rz"
    thin = regions.THIN * viewer.robot.size  # a zero bound beside bounded ones: a plate
    assert np.allclose(box.size, [0.02, 0.04, thin])
    assert np.allclose(box.T, T.homogeneous)  # along the target's axes
    assert fan.about == 2 and fan.half_angle == pytest.approx(0.3)
    vertices, faces = regions.fan_mesh(fan)
    centre, arc = vertices[0], vertices[1:] - vertices[0]
    assert np.allclose(centre, T.translation, atol=1e-6)
    assert np.allclose(np.linalg.norm(arc, axis=1), fan.radius, atol=1e-6)
    # the x axis swung about z through +-0.3 rad, in the target's x-y plane
    x, y, z = T.rotation.T
    assert np.allclose(arc @ z, 0, atol=1e-6)
    angles = np.arctan2(arc @ y, arc @ x)
    assert angles.min() == pytest.approx(-0.3, abs=1e-6)
    assert angles.max() == pytest.approx(0.3, abs=1e-6)
    node = drawn(viewer)["/regions/0/0/fan_rz"]
    assert node.vertices.shape == vertices.shape and len(faces) == regions.SIDES


def test_a_free_rotation_is_a_whole_disc(viewer):
    a = viewer.arm
    T = a.fk(a.random_q(3))
    viewer.set_target([armik.Pose(T, weights=(1, 1, 1, 0, 1, 1))])  # rx free by its weight
    (fan,) = viewer.regions
    assert fan.name.endswith("fan_rx") and fan.half_angle == pytest.approx(math.pi)


def test_an_axis_region_is_a_cone_of_its_half_angle_at_the_tip(viewer):
    a = viewer.arm
    q = a.random_q(4)
    T = a.fk(q)
    down = np.array([0.0, 0.0, -1.0])
    r = viewer.set_target([armik.Position(T.translation), armik.Axis((0, 0, 1), down, 0.2)])
    assert r.success
    (c,) = viewer.regions  # the exact position has no region
    assert isinstance(c, regions.ConeRegion) and c.name == "/regions/0/1/cone"
    tip = a.fk(r.q)
    assert np.allclose(c.apex, tip.translation) and np.allclose(c.direction, down)
    assert c.half_angle == 0.2 and c.inside
    assert np.allclose(c.now, tip.rotation[:, 2])  # the tool's z now
    vertices, _ = regions.cone_mesh(c)
    sides = vertices[1:] - vertices[0]
    angles = [cone.angle(s / np.linalg.norm(s), down) for s in sides]
    assert np.allclose(angles, 0.2, atol=1e-6)
    assert np.allclose(np.linalg.norm(sides, axis=1), c.length, atol=1e-6)
    nodes = drawn(viewer)
    assert "/regions/0/1/cone" in nodes and "/regions/0/1/cone_now" in nodes
    assert np.array(nodes["/regions/0/1/cone_now"].colors).reshape(-1, 3)[0].tolist() == list(
        regions.INSIDE
    )


def test_a_look_at_region_is_the_cone_from_the_tip_to_the_point(viewer):
    a = viewer.arm
    T = a.fk(a.random_q(5))
    point = T.translation + T.rotation @ np.array([0.0, 0.0, 0.3])  # 0.3 m along the tool
    viewer.show(a.random_q(5))
    r = viewer.set_target([armik.Position(T.translation), armik.LookAt(point, within=0.1)])
    assert r.success
    mark, c = viewer.regions
    assert mark.name == "/regions/0/1/point" and np.allclose(mark.position, point)
    apex = a.fk(r.q).translation
    sight = point - apex
    assert np.allclose(c.apex, apex) and c.length == pytest.approx(np.linalg.norm(sight))
    assert np.allclose(c.direction, sight / np.linalg.norm(sight)) and c.half_angle == 0.1


def test_an_axis_outside_its_cone_is_drawn_red(viewer):
    a = viewer.arm
    q = a.random_q(11)
    T = a.fk(q)
    viewer.show(q)
    away = T.rotation[:, 0]  # the tool's x: a quarter turn from its z
    r = viewer.set_target([armik.Pose(T), armik.Axis((0, 0, 1), away, 0.1)], q0=q)
    assert not r.success  # the pose holds the z axis where the cone is not
    (c,) = viewer.regions
    assert not c.inside and np.allclose(c.now, T.rotation[:, 2])
    color = np.array(drawn(viewer)[f"{c.name}_now"].colors).reshape(-1, 3)[0]
    assert color.tolist() == list(regions.OUTSIDE)


def test_an_exact_axis_is_a_line(viewer):
    a = viewer.arm
    T = a.fk(a.random_q(6))
    viewer.set_target([armik.Position(T.translation), armik.Axis((0, 0, 1), T.rotation[:, 2])])
    (c,) = viewer.regions
    assert c.half_angle == 0.0
    assert drawn(viewer)[c.name].points.shape == (1, 2, 3)  # one segment, not a cone


def test_dragging_moves_the_anchor_and_keeps_the_bounds_and_other_tasks(viewer):
    a = viewer.arm
    q = a.random_q(7)
    T = a.fk(q)
    axis = armik.Axis((0, 0, 1), T.rotation[:, 2], 0.1)
    viewer.set_target([armik.Position(T.translation, bounds=(0.02, 0.02, 0.02)), axis], q0=q)
    moved = pin.SE3(T.rotation, T.translation + np.array([0.0, 0.03, 0.0]))
    drag(viewer, moved)
    position, kept = viewer.targets[a.tip]
    assert isinstance(position, armik.Position) and kept is axis
    assert np.allclose(position.p, moved.translation) and np.allclose(position.bounds, 0.02)
    assert viewer.result.success
    box = viewer.regions[0]
    assert np.allclose(box.T[:3, 3], moved.translation)
    assert np.allclose(drawn(viewer)[box.name].position, moved.translation)


def test_dragging_a_list_without_an_anchor_adds_a_position(viewer):
    a = viewer.arm
    q = a.random_q(8)
    T = a.fk(q)
    axis = armik.Axis((0, 0, 1), T.rotation[:, 2], 0.05)
    assert viewer.set_target([axis], q0=q).success
    drag(viewer, T)
    position, kept = viewer.targets[a.tip]
    assert isinstance(position, armik.Position) and np.allclose(position.p, T.translation)
    assert kept is axis and viewer.result.success


def test_a_plain_pose_takes_the_regions_away(viewer):
    a = viewer.arm
    T = a.fk(a.random_q(9))
    viewer.set_target([armik.Position(T.translation, bounds=(0.05, 0.05, 0.05))])
    assert viewer._region_nodes
    viewer.set_target(T)
    assert viewer.regions == [] and viewer._region_nodes == []


def test_a_task_on_another_frame_is_drawn_at_that_frame(viewer):
    a = viewer.arm
    r = viewer.set_target(a.fk(a.random_q(10)))
    elbow = "link_4"
    tasks = [armik.Pose(a.fk(r.q)), armik.Axis((1, 0, 0), (0, 0, 1), 0.5, frame=elbow)]
    viewer.set_target(tasks, q0=r.q)
    (c,) = viewer.regions
    m = a.kinematics
    d = m.data
    pin.forwardKinematics(a.model, d, m.to_pin(viewer.q))
    T_elbow = m.T_base_world * pin.updateFramePlacement(a.model, d, a.model.getFrameId(elbow))
    assert np.allclose(c.apex, T_elbow.translation) and np.allclose(c.now, T_elbow.rotation[:, 0])
