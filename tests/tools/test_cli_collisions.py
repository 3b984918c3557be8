"""armik solve and armik batch with --obstacles, --self-collision and --margin."""

from __future__ import annotations

import json

import numpy as np
import pytest

from armik import BatchResult
from armik.constraints.shapes_file import read_shapes
from tests.tools.cli_run import run

from ..conftest import arm

SCENE = [
    {"type": "halfspace", "normal": [0, 0, 1], "offset": 0},
    {"type": "box", "size": [0.2, 0.2, 0.3], "position": [0.45, -0.3, 0.15]},
]
XYZ = ["--xyz", "0.4", "0.2", "0.3", "--rpy", "3.1416", "0", "0"]


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(SCENE))
    return path


def test_solve_with_obstacles_prints_the_clearance_the_library_measures(capsys, scene):
    code, out, _ = run(capsys, "solve", "ur5", *XYZ, "--obstacles", scene, "--json")
    assert code == 0
    r = json.loads(out)["results"][0]
    ur5 = arm("ur5")
    d, pair = ur5.min_distance(np.array(r["q"]), read_shapes(scene))
    assert r["min_distance"] == pytest.approx(d, abs=1e-12) and tuple(r["closest_pair"]) == pair
    code, out, _ = run(capsys, "solve", "ur5", *XYZ, "--obstacles", scene, "--self-collision")
    assert code == 0
    line = next(x for x in out.splitlines() if "clearance:" in x)
    assert "closest pair" in line and " / " in line
    plain = run(capsys, "solve", "ur5", *XYZ)[1]
    assert "clearance" not in plain and "collision" not in plain


def test_margin_refuses_what_the_plain_answer_allows(capsys, scene):
    code, out, _ = run(capsys, "solve", "ur5", *XYZ, "--obstacles", scene, "--json")
    d = json.loads(out)["results"][0]["min_distance"]
    code, out, _ = run(
        capsys, "solve", "ur5", *XYZ, "--obstacles", scene, "--margin", d + 0.05, "--json"
    )
    for r in json.loads(out)["results"]:
        assert (r["success"] and r["min_distance"] >= d + 0.05) or r["status"] == "collision"


def test_yaml_obstacles_read_as_json(tmp_path, capsys, scene):
    pytest.importorskip("yaml")
    path = tmp_path / "scene.yaml"
    path.write_text(
        "- type: halfspace\n  normal: [0, 0, 1]\n  offset: 0\n"
        "- type: box\n  size: [0.2, 0.2, 0.3]\n  position: [0.45, -0.3, 0.15]\n"
    )
    a = run(capsys, "solve", "ur5", *XYZ, "--obstacles", path, "--json")[1]
    b = run(capsys, "solve", "ur5", *XYZ, "--obstacles", scene, "--json")[1]
    ra, rb = json.loads(a)["results"][0], json.loads(b)["results"][0]
    assert ra["q"] == rb["q"] and ra["closest_pair"] == rb["closest_pair"]


def test_batch_with_obstacles_saves_the_distances(tmp_path, capsys, scene):
    ur5 = arm("ur5")
    T = ur5.fk_batch(ur5.random_q(3, n=6))
    np.save(tmp_path / "t.npy", T)
    out = tmp_path / "o.npz"
    argv = ["batch", "ur5", tmp_path / "t.npy", "-o", out, "--workers", "1"]
    code, text, _ = run(capsys, *argv, "--obstacles", scene, "--self-collision")
    assert code == 0
    r = BatchResult.load(out)
    shapes = read_shapes(scene)
    for i in range(len(r)):
        d, pair = ur5.min_distance(r.q[i], shapes, self_collision=True)
        assert r.min_distance[i] == pytest.approx(d, abs=1e-12) and r.closest_pair(i) == pair
    if r.success.any():
        assert "smallest clearance of the solved" in text
    run(capsys, *argv)
    assert np.isnan(BatchResult.load(out).min_distance).all()


@pytest.mark.parametrize(
    "content, name, words",
    [
        ('[{"type": "box", "size": [-0.1, 0.2, 0.3]}]', "neg.json", "Box size"),
        ('[{"type": "sphere", "radius": 0.1, "center": [0, NaN, 0]}]', "nan.json", "finite"),
        ('[{"type": "mesh", "path": "/no/such/mesh.stl"}]', "mesh.json", "not an existing"),
        ("{not json", "bad.json", "not JSON"),
        ("- type: [", "bad.yaml", "not YAML"),
    ],
)
def test_bad_obstacles_files_exit_2_one_line(tmp_path, capsys, content, name, words):
    if name.endswith(".yaml"):
        pytest.importorskip("yaml")
    path = tmp_path / name
    path.write_text(content)
    code, _, err = run(capsys, "solve", "ur5", *XYZ, "--obstacles", path)
    assert code == 2 and words in err and len(err.strip().splitlines()) == 1


def test_margin_without_anything_to_check_names_the_flags(capsys):
    code, _, err = run(capsys, "solve", "ur5", *XYZ, "--margin", "0.01")
    assert code == 2 and "--obstacles or --self-collision" in err


MESHED = """<robot name="r"><link name="l0"/>
<link name="l1"><collision><geometry><mesh filename="package://parts/a.stl"/></geometry>
</collision></link><link name="l2"/><link name="l3"><collision><geometry>
<box size="0.1 0.1 0.1"/></geometry></collision></link>
<joint name="j1" type="revolute"><parent link="l0"/><child link="l1"/><origin xyz="0 0 0.1"/>
<axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.1 0 0.3"/>
<axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
<joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0.2 0 0.3"/>
<axis xyz="1 0 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint></robot>"""
FACES = [
    ("0 0 0", "0.05 0 0", "0 0.05 0"),
    ("0 0 0", "0 0.05 0", "0 0 0.05"),
    ("0 0 0", "0 0 0.05", "0.05 0 0"),
    ("0.05 0 0", "0 0 0.05", "0 0.05 0"),
]
FACETS = [
    "facet normal 0 0 0\nouter loop\n" + "".join(f"vertex {v}\n" for v in face) for face in FACES
]
TETRAHEDRON = "solid a\n" + "".join(f + "endloop\nendfacet\n" for f in FACETS) + "endsolid a\n"


def test_a_missing_mesh_names_the_way_the_command_line_has(tmp_path, capsys, monkeypatch):
    """The fix the command line can follow: ROS_PACKAGE_PATH (Pinocchio reads it), not
    Python's package_dirs=; with it set the mesh is found."""
    (tmp_path / "robot").mkdir()
    urdf = tmp_path / "robot" / "r.urdf"
    urdf.write_text(MESHED)
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    argv = ["solve", urdf, "--tip", "l3", "--xyz", "0.2", "0.1", "0.6", "--self-collision"]
    code, _, err = run(capsys, *argv)
    assert code == 2 and "parts/a.stl" in err
    assert "ROS_PACKAGE_PATH=DIR" in err and "package_dirs" not in err
    (tmp_path / "pkgs" / "parts").mkdir(parents=True)
    (tmp_path / "pkgs" / "parts" / "a.stl").write_text(TETRAHEDRON)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "pkgs"))
    code, _, err = run(capsys, *argv)
    assert "could not be read" not in err and code in (0, 1), err
