"""Obstacles in their plain (JSON) form, read into the shapes collisions and the viewer use."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import armik
from armik.constraints.shapes_file import as_shapes, read_shapes


def test_plain_shapes_and_their_checks(tmp_path):
    path = tmp_path / "obstacles.json"
    path.write_text(json.dumps([
        {"type": "box", "size": [0.2, 0.2, 0.4], "position": [0.5, 0, 0.2],
         "quaternion": [0, 0, 0, 2]},
        {"type": "sphere", "radius": 0.1, "center": [0.3, 0.3, 0.5]},
        {"type": "cylinder", "radius": 0.05, "length": 0.5, "pose": np.eye(4).tolist()},
        {"type": "halfspace", "normal": [0, 0, 1], "offset": 0},
    ]))  # fmt: skip
    box, sphere, cylinder, table = read_shapes(path)
    assert box == armik.Box((0.2, 0.2, 0.4), (0.5, 0, 0.2))  # the quaternion normalised
    assert sphere == armik.Sphere(0.1, (0.3, 0.3, 0.5))
    assert cylinder == armik.Cylinder(0.05, 0.5)
    assert table == armik.HalfSpace((0, 0, 1), 0.0)
    turned = as_shapes([{"type": "box", "size": [1, 1, 1], "quaternion": [0, 0, 1, 1]}])[0]
    np.testing.assert_allclose(turned.T[:3, 0], [0, 1, 0], atol=1e-12)  # 90 deg about z
    assert as_shapes([box, {"type": "sphere", "radius": 1}]) == [box, armik.Sphere(1.0)]


@pytest.mark.parametrize(
    "bad, words",
    [
        ([{"type": "cone"}], "'type' must be one of 'box', 'sphere'"),
        ([{"type": "box"}], "needs 'size'"),
        ([{"type": "box", "size": [1, 1]}], "Box size must be 3"),
        ([{"type": "box", "size": [1, 1, 0]}], "size"),
        ([{"type": "sphere", "radius": 1, "centre": [0, 0, 0]}], "unknown keys ['centre']"),
        ([{"type": "box", "size": [1, 1, 1], "quaternion": [0, 0, 0, 0]}], "zero length"),
        (
            [{"type": "box", "size": [1, 1, 1], "pose": np.eye(4).tolist(), "position": [0, 0, 0]}],
            "not both",
        ),
        ([3], "give a shape"),
        ([{"type": ["box"], "size": [1, 1, 1]}], "'type' must be one of"),
        ([{"type": "box", "size": [1, 1, 1], 1: 2, "foo": 3}], "unknown keys [1, 'foo']"),
        ([{"type": "sphere", "radius": 10**400}], "Sphere radius"),
        ([{"type": "box", "size": [1, 1, 1], "position": [10**400, 0, 0]}], "position must be 3"),
        ({"type": "sphere", "radius": 1}, "list of shapes"),
    ],
)
def test_bad_shapes_name_the_problem(bad, words):
    with pytest.raises(armik.CollisionError) as info:
        as_shapes(bad)
    assert words in str(info.value)


def test_obstacles_file_errors(tmp_path):
    with pytest.raises(armik.InputError, match="cannot read"):
        read_shapes(tmp_path / "missing.json")
    (tmp_path / "x.json").write_text("{not json")
    with pytest.raises(armik.InputError, match="not JSON"):
        read_shapes(tmp_path / "x.json")
    (tmp_path / "y.json").write_text('{"type": "sphere"}')
    with pytest.raises(armik.InputError, match="list of shapes"):
        read_shapes(tmp_path / "y.json")


def test_a_meshs_relative_path_is_read_beside_the_obstacles_file(tmp_path, monkeypatch):
    scene = tmp_path / "scene"
    scene.mkdir()
    corners = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    faces = [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)]
    body = "".join(
        "facet normal 0 0 0\nouter loop\n"
        + "".join("vertex {} {} {}\n".format(*corners[k]) for k in f)
        + "endloop\nendfacet\n"
        for f in faces
    )
    (scene / "fixture.stl").write_text(f"solid t\n{body}endsolid t\n")
    (scene / "cell.json").write_text('[{"type": "mesh", "path": "fixture.stl"}]')
    monkeypatch.chdir(tmp_path)  # no fixture.stl here: read from the working folder, none
    (mesh,) = read_shapes(Path("scene") / "cell.json")
    assert mesh.path == str((scene / "fixture.stl").resolve())
    with pytest.raises(armik.CollisionError, match="not an existing file"):
        as_shapes([{"type": "mesh", "path": "fixture.stl"}])  # in memory: the working folder


@pytest.mark.parametrize("big", [1e308, 1e200])
def test_a_quaternion_of_huge_entries_is_its_rotation(big):
    """A quaternion whose squares overflow is the rotation it spells, as the same one of
    ordinary entries: it normalised to (0, 0, 0, 0), whose matrix is the identity, and the
    obstacle stood unturned, where a check measured distances to a box the file did not
    place."""
    huge = as_shapes([{"type": "box", "size": [1, 2, 3], "quaternion": [0, 0, big, big]}])[0]
    plain = as_shapes([{"type": "box", "size": [1, 2, 3], "quaternion": [0, 0, 1, 1]}])[0]
    np.testing.assert_allclose(huge.T, plain.T, atol=1e-15)
    np.testing.assert_allclose(huge.T[:3, 0], [0, 1, 0], atol=1e-12)  # 90 deg about z
