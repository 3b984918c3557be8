"""The arm's body: the URDF's visuals with package:// resolved, the stick figure when they
are missing (one warning naming the mesh), and poses that follow Pinocchio's FK."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import armik
from armik.model.arm_model import ArmModel
from armik.view.scene import arm_body, resolve
from armik.view.stick import skeleton

from ..conftest import model, two_link_urdf, write_urdf

trimesh = pytest.importorskip("trimesh")


def _with_visual(geometry: str, material: str = "") -> str:
    """The 2R test arm with one visual on its second link."""
    visual = f"<visual><origin xyz='0.4 0 0'/><geometry>{geometry}</geometry>{material}</visual>"
    return two_link_urdf().replace('<link name="l2"/>', f'<link name="l2">{visual}</link>')


def _load(path) -> ArmModel:
    """The arm model of the URDF at ``path`` (what the viewer's modules take)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return armik.load(str(path), tip="tip").kinematics


def _body(a: ArmModel):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        body = arm_body(a)
    return body, [w for w in caught if issubclass(w.category, armik.ArmikWarning)]


def test_urdf_without_visuals_is_a_stick_figure_without_warning():
    body, caught = _body(model("planar_2link"))
    assert body.kind == "stick" and caught == []
    assert "no visual geometry" in body.note
    names = {p.link for p in body.parts}
    assert {"joint1", "joint2", "axis of joint1", "axis of joint2", "link to the tip"} <= names


def test_missing_meshes_fall_back_with_one_warning_naming_the_mesh(tmp_path):
    urdf = _with_visual("<mesh filename='package://nowhere/meshes/forearm.stl'/>")
    urdf = urdf.replace(
        '<link name="l1"/>',
        "<link name='l1'><visual><geometry><mesh filename='meshes/upper.dae'/></geometry>"
        "</visual></link>",
    )
    body, caught = _body(_load(write_urdf(tmp_path, urdf)))
    assert body.kind == "stick"
    assert len(caught) == 1, [str(w.message) for w in caught]
    message = str(caught[0].message)
    assert "meshes/upper.dae" in message and "not found" in message
    assert "1 more meshes missing" in message and "stick figure" in message


def test_package_urls_resolve_among_the_urdfs_ancestors(tmp_path):
    pkg = tmp_path / "my_arm_description"
    (pkg / "meshes").mkdir(parents=True)
    (pkg / "urdf").mkdir()
    trimesh.creation.box(extents=(0.1, 0.2, 0.3)).export(pkg / "meshes" / "forearm.stl")
    urdf = _with_visual(
        "<mesh filename='package://my_arm_description/meshes/forearm.stl' scale='2 2 2'/>",
        "<material name='red'><color rgba='1 0 0 1'/></material>",
    )
    path = write_urdf(pkg / "urdf", urdf)
    assert resolve("package://my_arm_description/meshes/forearm.stl", path) == (
        pkg / "meshes" / "forearm.stl"
    )
    body, caught = _body(_load(path))
    assert body.kind == "meshes" and caught == []
    (part,) = body.parts
    assert part.link == "l2"
    assert np.allclose(part.mesh.extents, (0.2, 0.4, 0.6))  # scaled by the URDF's 2
    assert tuple(part.mesh.visual.face_colors[0]) == (255, 0, 0, 255)


def test_package_path_from_ros_package_path(tmp_path, monkeypatch):
    share = tmp_path / "share"
    (share / "pkg_b" / "meshes").mkdir(parents=True)
    mesh = share / "pkg_b" / "meshes" / "m.stl"
    trimesh.creation.icosphere().export(mesh)
    (tmp_path / "elsewhere").mkdir()
    elsewhere = tmp_path / "elsewhere" / "robot.urdf"
    assert resolve("package://pkg_b/meshes/m.stl", elsewhere) is None
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(share))
    assert resolve("package://pkg_b/meshes/m.stl", elsewhere) == mesh
    assert resolve(f"file://{mesh}", elsewhere) == mesh
    assert resolve("../share/pkg_b/meshes/m.stl", elsewhere) is not None
    assert resolve("package://pkg_b", elsewhere) is None  # no path inside the package


def test_primitives_become_parts_in_their_links_frame(tmp_path):
    a = _load(write_urdf(tmp_path, _with_visual("<box size='0.8 0.1 0.1'/>")))
    body, caught = _body(a)
    assert body.kind == "meshes" and caught == []
    q = np.array([0.3, -0.7])
    (T,) = body.poses(a, q)
    # the box's centre is 0.4 m along link 2, whose frame sits at the elbow
    elbow = np.array([np.cos(0.3), np.sin(0.3), 0.0])
    along = np.array([np.cos(-0.4), np.sin(-0.4), 0.0])
    assert np.allclose(T[:3, 3], elbow + 0.4 * along, atol=1e-12)


@pytest.mark.parametrize("name", ["planar_2link", "scara", "abb_irb120", "panda"])
def test_stick_figure_follows_the_arms_fk(name):
    a = model(name)
    q = a.random_q(3)
    sk = skeleton(a, q)
    assert len(sk.points) == a.dof + 2
    assert np.allclose(sk.points[-1], a.fk(q).translation, atol=1e-12)
    assert np.allclose(np.linalg.norm(sk.axes, axis=1), 1.0)
    body = arm_body(a)
    poses = body.poses(a, q)
    assert poses.shape == (len(body.parts), 4, 4)
    assert np.allclose(poses[:, 3], [0, 0, 0, 1])


def test_bundled_meshes_are_found():
    body, caught = _body(model("panda"))
    assert body.kind == "meshes" and caught == []
    assert {"panda_link0", "panda_link7", "panda_hand"} <= {p.link for p in body.parts}


def test_a_mesh_obstacle_is_drawn_as_the_hull_its_collisions_measure(tmp_path):
    """The viewer draws an ``armik.Mesh`` from the vertices it kept when it was made, as
    its collisions measure it, not from its file as it is now."""
    from armik.view.scenery import draw_obstacle

    from ..constraints.test_shapes import _stl, _tetra

    path = tmp_path / "scan.stl"
    mesh = armik.Mesh(_stl(path, _tetra((2.0, 2.0, 2.0), 0.1)))
    _stl(path, _tetra((3.0, 2.0, 2.0), 0.1))  # the file written again

    class Scene:
        def add_mesh_simple(self, name, vertices, faces, **kw):
            self.vertices = np.asarray(vertices)

    scene = Scene()
    draw_obstacle(scene, "/obstacle", mesh)
    assert np.allclose(np.sort(scene.vertices, axis=0), np.sort(mesh.vertices, axis=0))
