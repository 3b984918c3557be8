"""Obstacles: validation with errors that name the value and the fix; coal conversion."""

from __future__ import annotations

import math
import pickle

import coal
import numpy as np
import pinocchio as pin
import pytest

import armik


def test_every_shape_converts_to_its_coal_geometry(tmp_path):
    T = pin.SE3(pin.utils.rpyToMatrix(0.1, 0.2, 0.3), np.array([0.1, 0.2, 0.3]))
    cases = [
        (armik.Box((0.1, 0.2, 0.3), T), coal.Box),
        (armik.Box((0.1, 0.2, 0.3), T.homogeneous), coal.Box),
        (armik.Box((0.1, 0.2, 0.3), (0.1, 0.2, 0.3)), coal.Box),
        (armik.Sphere(0.2, (1, 2, 3)), coal.Sphere),
        (armik.Capsule(0.05, 0.4), coal.Capsule),
        (armik.Cylinder(0.05, 0.4, T), coal.Cylinder),
        (armik.HalfSpace((0, 0, 2), 1.0), coal.Halfspace),
    ]
    for shape, kind in cases:
        assert isinstance(shape.geometry(), kind)
        hash(shape)
    assert cases[0][0] == cases[1][0]  # the same pose given two ways
    np.testing.assert_allclose(cases[0][0].T, T.homogeneous)
    assert armik.Sphere(0.2, (1, 2, 3)).placement().translation.tolist() == [1, 2, 3]
    assert armik.Box((0.1, 0.2, 0.3)).geometry().halfSide.tolist() == pytest.approx(
        [0.05, 0.1, 0.15]
    )
    half = armik.HalfSpace((0, 0, 2), 1.0)
    assert half.normal == (0, 0, 1) and half.offset == 0.5  # normalised: z <= 0.5
    stl = tmp_path / "tetra.stl"
    stl.write_text(
        "solid t\n"
        + "".join(
            f"facet normal 0 0 0\nouter loop\n{a}\n{b}\n{c}\nendloop\nendfacet\n"
            for a, b, c in [
                ("vertex 0 0 0", "vertex 1 0 0", "vertex 0 1 0"),
                ("vertex 0 0 0", "vertex 0 1 0", "vertex 0 0 1"),
                ("vertex 0 0 0", "vertex 0 0 1", "vertex 1 0 0"),
                ("vertex 1 0 0", "vertex 0 1 0", "vertex 0 0 1"),
            ]
        )
        + "endsolid t\n"
    )
    hull = armik.Mesh(stl, scale=0.5).geometry()
    assert isinstance(hull, coal.ConvexBase) and hull.num_points == 4


@pytest.mark.parametrize(
    "build, match",
    [
        (lambda: armik.Box((-0.1, 0.2, 0.3)), r"Box size must be .*> 0.*-0.1"),
        (lambda: armik.Box((0.1, 0.2)), "3 full side lengths"),
        (lambda: armik.Box((0.1, 0.2, math.nan)), "Box size"),
        (lambda: armik.Box((0.1, 0.2, 0.3), np.full((4, 4), np.nan)), "pose must be finite"),
        (lambda: armik.Box((0.1, 0.2, 0.3), [0, math.nan, 0]), "pose must be finite"),
        (lambda: armik.Box((0.1, 0.2, 0.3), 2 * np.eye(4)), "not a rotation"),
        (lambda: armik.Box((0.1, 0.2, 0.3), "here"), "not a pose"),
        (lambda: armik.Sphere(0.0, (0, 0, 0)), "Sphere radius"),
        (lambda: armik.Sphere(0.1, (0, 0)), "Sphere center must be 3"),
        (lambda: armik.Capsule(0.1, -1.0), r"Capsule length must be .*>= 0"),
        (lambda: armik.Cylinder("thin", 1.0), "Cylinder radius"),
        (lambda: armik.HalfSpace((0, 0, 0), 0), "normal must not be zero"),
        (lambda: armik.HalfSpace((0, 0, 1), math.inf), "offset must be a finite"),
        (lambda: armik.Mesh("/no/such/mesh.stl"), "not an existing file"),
        (lambda: armik.Mesh(__file__, scale=-1), "Mesh scale must be a factor > 0"),
        # an int beyond a float's range (JSON reads one from 400 digits)
        (lambda: armik.Sphere(10**400), "Sphere radius"),
        (lambda: armik.Sphere(0.1, (10**400, 0, 0)), "Sphere center must be 3"),
        (lambda: armik.Box((0.1, 0.2, 0.3), (10**400, 0, 0)), "not a pose"),
        (lambda: armik.HalfSpace((0, 0, 1), 10**400), "offset must be a finite"),
        # no order (a set), or keys (a dict): sides in whichever order they iterate
        (lambda: armik.Box({0.5, 0.1, 0.3}), "3 full side lengths .* in that order"),
        (lambda: armik.Box({0.5: "x", 0.1: "y", 0.3: "z"}), "in that order"),
        # numpy's True, refused as True is, not a side of 1 m
        (lambda: armik.Box((np.True_, 0.1, 0.1)), "Box size must be"),
        (lambda: armik.Sphere(np.True_), "Sphere radius"),
        (lambda: armik.HalfSpace((0, 0, 1), np.True_), "offset must be a finite"),
    ],
)
def test_bad_shapes_are_refused_naming_the_value(build, match):
    with pytest.raises(armik.CollisionError, match=match) as info:
        build()
    assert isinstance(info.value, armik.OptionError) and isinstance(info.value, ValueError)


def test_bad_collision_options_are_refused():
    ur5 = armik.load("ur5")
    T = ur5.fk(ur5.middle)
    with pytest.raises(armik.CollisionError, match=r"obstacles\[1\] is 3"):
        ur5.solve(T, obstacles=[armik.Sphere(0.1, (2, 2, 2)), 3])
    with pytest.raises(armik.CollisionError, match="list of shapes"):
        ur5.solve(T, obstacles="table")
    with pytest.raises(armik.OptionError, match="margin must be"):
        ur5.solve(T, obstacles=[armik.Sphere(0.1, (2, 2, 2))], margin=-0.1)
    with pytest.raises(armik.OptionError, match="margin must be"):  # beyond a float's range
        ur5.solve(T, obstacles=[armik.Sphere(0.1, (2, 2, 2))], margin=10**400)
    with pytest.raises(armik.OptionError, match="checks nothing"):
        ur5.solve(T, margin=0.01)
    with pytest.raises(armik.OptionError, match="self_collision must be True or False"):
        ur5.solve(T, self_collision="yes")


def test_a_shape_s_plain_form_given_as_obstacles_is_named_as_such():
    # a mapping is not read as its keys ("obstacles[0] is 'type', not a shape")
    ur5 = armik.load("ur5")
    T = ur5.fk(ur5.middle)
    plain = {"type": "sphere", "radius": 0.1, "center": [2, 2, 2]}
    with pytest.raises(armik.CollisionError, match=r"list of shapes .*got \{'type'") as info:
        ur5.solve(T, obstacles=plain)
    assert "obstacles[0]" not in str(info.value)
    with pytest.raises(armik.CollisionError, match=r"obstacles\[0\] .* plain form.*as_shapes"):
        ur5.solve(T, obstacles=[plain])


def _stl(path, triangles) -> str:
    """An ASCII STL of ``triangles`` (each three (x, y, z) vertices) at ``path``."""
    path.write_text(
        "solid s\n"
        + "".join(
            "facet normal 0 0 0\nouter loop\n"
            + "".join(f"vertex {x} {y} {z}\n" for x, y, z in t)
            + "endloop\nendfacet\n"
            for t in triangles
        )
        + "endsolid s\n"
    )
    return str(path)


TRIANGLE = [((0, 0, 0), (0.1, 0, 0), (0, 0.1, 0))]
SQUARE = [((0, 0, 0), (1, 0, 0), (1, 1, 0)), ((0, 0, 0), (1, 1, 0), (0, 1, 0))]  # flat
LINE = [((0, 0, 0), (1, 0, 0), (2, 0, 0)), ((0, 0, 0), (2, 0, 0), (3, 0, 0))]


@pytest.mark.parametrize(
    "triangles, given",
    [
        (TRIANGLE, "3 vertices"),
        (SQUARE, "4 vertices, all in one plane"),
        (LINE, "4 vertices, all on one line"),
    ],
)
def test_a_mesh_that_is_no_solid_is_refused_where_it_is_built(tmp_path, triangles, given):
    """coal's convex hull raised its own ValueError on fewer than 4 vertices, and ended the
    process (a segmentation fault) on 4 or more in one plane or line."""
    path = _stl(tmp_path / "flat.stl", triangles)
    with pytest.raises(armik.CollisionError, match=f"has {given}: a collision mesh needs 4 or"):
        armik.Mesh(path)


def test_a_robots_collision_mesh_that_is_no_solid_is_named_with_its_link(tmp_path):
    """A URDF's collision mesh of 3 vertices: coal's ValueError from a solve under
    self_collision; an armik error naming the mesh and its link."""
    mesh = _stl(tmp_path / "l1.stl", TRIANGLE)
    lim = '<limit lower="-3" upper="3" effort="1" velocity="1"/>'
    xml = (
        '<robot name="pk"><link name="base"/><link name="l1"><collision><geometry>'
        f'<mesh filename="{mesh}"/></geometry></collision></link><link name="l2"/>'
        '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>'
        f'<origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>{lim}</joint>'
        '<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>'
        f'<origin xyz="0.3 0 0"/><axis xyz="0 1 0"/>{lim}</joint></robot>'
    )
    a = armik.load_string(xml, tip="l2")
    with pytest.raises(armik.CollisionError, match=r"mesh '.*l1.stl' of link 'l1' .* 3 vertices"):
        a.solve([0.3, 0.0, 0.1], self_collision=True)


def _tetra(corner, size: float) -> list:
    """A tetrahedron's four faces, its right-angled corner at ``corner``."""
    o = np.asarray(corner, dtype=float)
    x, y, z = (o + size * e for e in np.eye(3))
    return [(o, x, y), (o, y, z), (o, z, x), (x, y, z)]


def test_a_mesh_is_the_file_as_it_was_read(tmp_path):
    # a scan's hull rewritten to one file: the new armik.Mesh is not the old one, and the
    # old one keeps the shape it read, on the arm that measured it, on a new arm and in a
    # copy pickled to a worker
    panda = armik.load("panda")
    q = panda.random_q(1, n=1)[0]
    elbow = panda.fk(q, "panda_link4").translation
    path = tmp_path / "scan.stl"
    far = armik.Mesh(_stl(path, _tetra((5.0, 5.0, 5.0), 0.1)))
    before = panda.min_distance(q, [far])[0]
    assert before > 5.0
    near = armik.Mesh(_stl(path, _tetra(elbow - 0.1, 0.3)))  # around the elbow now
    d, pair = panda.min_distance(q, [near])
    assert d < 0 and pair[1] == "obstacles[0] (Mesh)"
    assert near != far and near.path == far.path and near.digest != far.digest
    r = panda.solve(panda.fk(q), q0=q, obstacles=[near], max_restarts=0)
    assert r.status == "collision" and "obstacles[0] (Mesh)" in r.reason, r.reason
    other = panda.with_limits({"panda_joint1": (-2.0, 2.0)})
    copy = pickle.loads(pickle.dumps(far))
    assert copy == far and np.array_equal(copy.vertices, far.vertices)
    for arm, mesh in ((panda, far), (other, far), (panda, copy)):
        assert arm.min_distance(q, [mesh])[0] == pytest.approx(before, abs=1e-12)
    assert armik.Mesh(path) == near
