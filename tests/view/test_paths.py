"""Paths side by side (``Viewer.play_paths``, ``armik view --path``): a ghost per plan at the
waypoint the slider picks, each plan's trace, its discontinuous waypoints marked, and bad
input refused with the fix."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.tools.cli.main import main
from armik.view.nodes import wxyz_position
from armik.view.viewer import Viewer

from ..conftest import arm
from ..test_arms import dual_irb120

pytest.importorskip("viser")

N = 60


def spin() -> tuple[np.ndarray, list[pin.SE3]]:
    """The UR5's tool spun one and a half turns about its axis (docs/paths.md): following
    meets wrist 3's limit two thirds of the way, the global plan goes through."""
    ur5 = arm("ur5")
    q = ur5.middle.copy()
    q[4] = 1.0
    T0 = ur5.fk(q)
    turn = [pin.exp3(np.array([0.0, 0.0, 3 * math.pi * k / (N - 1)])) for k in range(N)]
    return q, [T0 * pin.SE3(R, np.zeros(3)) for R in turn]


@pytest.fixture(scope="module")
def plans():
    ur5 = arm("ur5")
    q, poses = spin()
    follow = ur5.solve_path(poses, q, max_joint_step=0.3)
    planned = ur5.solve_path(poses, None, max_joint_step=0.3, plan="global")
    assert (follow.status == "discontinuous").any() and planned.success.all()
    return {"follow": follow, "global": planned}


@pytest.fixture(scope="module")
def viewer():
    v = armik.view(arm("ur5"), port=0, open_browser=False)
    yield v
    v.close()


def test_a_ghost_per_plan_steps_with_the_slider(viewer, plans):
    player = viewer.play_paths(plans)
    assert viewer.paths is player and player.n == N
    assert not viewer._arm_nodes.visible  # the ghosts are the arms now
    follow = plans["follow"]
    jump = int(np.flatnonzero(follow.status == "discontinuous")[0])
    assert player.flagged["follow"].tolist() == np.flatnonzero(~follow.success).tolist()
    assert player.flagged["global"].size == 0
    for i in (0, jump, N - 1):
        player.show(i)
        assert player.index == i and player.slider.value == i
        for k, ((ghost, label), (name, batch)) in enumerate(zip(player._ghosts, plans.items())):
            poses = viewer.robot.poses(batch.q[i])
            for frame, T in zip(ghost._frames, poses):
                wxyz, position = wxyz_position(T)
                assert np.allclose(frame.position, position) and np.allclose(frame.wxyz, wxyz)
            assert label.text == f"{name}: {batch.status[i]}"
            lift = [0.0, 0.0, 0.06 * k * viewer.robot.size]  # labels stacked, not on each other
            assert np.allclose(label.position, viewer.arm.fk(batch.q[i]).translation + lift)
    assert player.texts["follow"].value.startswith(f"{N}/{N} ")
    player.show(jump)
    assert player.texts["follow"].value.startswith(f"{jump + 1}/{N} discontinuous (")
    assert player.texts["global"].value == f"{jump + 1}/{N} converged"


def test_the_traces_and_the_jumps_are_drawn_at_the_tips(viewer, plans):
    player = viewer.play_paths(plans)
    follow = plans["follow"]
    jumps = np.flatnonzero(follow.status == "discontinuous")
    nodes = {n.name: n for n in player._nodes}
    assert {"/paths/0/trace", "/paths/1/trace", "/paths/0/jumps"} <= set(nodes)
    assert "/paths/1/jumps" not in nodes  # the global plan has none
    tips = np.array([viewer.arm.fk(q).translation for q in follow.q])
    assert np.allclose(nodes["/paths/0/jumps"].points, tips[jumps], atol=1e-6)
    assert nodes["/paths/0/trace"].points.shape == (N - 1, 2, 3)
    assert np.allclose(nodes["/paths/0/trace"].points[:, 0], tips[:-1], atol=1e-6)


def test_playing_again_replaces_the_paths_and_show_brings_the_arm_back(viewer, plans):
    first = viewer.play_paths(plans)
    second = viewer.play_paths({"global": plans["global"]}, fps=1000)  # walks, then stays
    assert first._ghosts == [] and first._nodes == []
    assert viewer.paths is second and second.index == N - 1
    viewer.show(viewer.arm.middle)
    assert viewer._arm_nodes.visible
    second.remove()
    assert second._ghosts == []


def test_bad_paths_are_refused_with_the_fix(viewer, plans):
    follow = plans["follow"]
    with pytest.raises(armik.InputError, match="mapping of names"):
        viewer.play_paths([follow])
    with pytest.raises(armik.InputError, match="BatchResult of solve_path"):
        viewer.play_paths({"follow": follow.q})
    with pytest.raises(armik.InputError, match="same waypoints"):
        viewer.play_paths({"follow": follow, "short": follow[:10]})
    with pytest.raises(armik.InputError, match="of the robot shown"):
        viewer.play_paths({"planar": arm("planar_2link").solve_batch(np.zeros((2, 2)))})
    with pytest.raises(armik.InputError, match="at most 8"):
        viewer.play_paths({str(k): follow for k in range(9)})
    with pytest.raises(armik.OptionError, match="fps"):
        viewer.play_paths(plans, fps=0)
    player = viewer.play_paths(plans)
    with pytest.raises(armik.InputError, match="0..59"):
        player.show(N)
    # a waypoint that is no whole number, a rate that is no number > 0: armik's errors
    for bad in (2.5, "3", True):
        with pytest.raises(armik.InputError, match=f"waypoint {bad!r} is not one of 0..59"):
            player.show(bad)  # type: ignore[arg-type]
    player.show(np.int64(3))
    assert player.index == 3
    for fps in (0, "fast", math.nan):
        with pytest.raises(armik.OptionError, match="fps must be a number > 0"):
            player.play(fps=fps)  # type: ignore[arg-type]
    assert player.index == 3  # refused before walking


@pytest.fixture
def served(monkeypatch):
    """What ``armik view`` served: its viewer, caught where it would wait for Ctrl-C."""
    seen: list[Viewer] = []
    monkeypatch.setattr(Viewer, "wait", lambda self: seen.append(self))
    return seen


def test_view_path_shows_both_plans(tmp_path, capsys, served, plans):
    q, poses = spin()
    waypoints = tmp_path / "spin.npy"
    np.save(waypoints, np.array([T.homogeneous for T in poses]))
    args = ["view", "ur5", "--path", str(waypoints), "--max-joint-step", "0.3", "--port", "0"]
    q0 = ["--q0", *map(str, q)]
    assert main([*args, "--plan", "follow", *q0, "--no-browser"]) == 0
    (viewer,) = served
    assert list(viewer.paths.paths) == ["follow"]
    got = viewer.paths.paths["follow"]
    assert np.array_equal(got.q, plans["follow"].q)
    assert main([*args, "--no-browser"]) == 0  # both plans, global from any branch
    assert list(served[1].paths.paths) == ["follow", "global"]
    assert np.array_equal(served[1].paths.paths["global"].q, plans["global"].q)
    out = capsys.readouterr().out
    assert "armik: global: 60/60 waypoints" in out and "failed at [" in out


def test_view_tips_shows_the_whole_robot(tmp_path, capsys, served):
    urdf = tmp_path / "cell.urdf"
    urdf.write_text(dual_irb120())
    assert main(["view", str(urdf), "--tips", "l_tool0", "r_tool0", "--port", "0",
                 "--no-browser"]) == 0  # fmt: skip
    (viewer,) = served
    assert viewer.robot.tips == ("l_tool0", "r_tool0") and set(viewer._gizmos) == {
        "l_tool0",
        "r_tool0",
    }
    # --tip repeated, as info and solve take several tips, is the same
    assert main(["view", str(urdf), "--tip", "l_tool0", "--tip", "r_tool0", "--port", "0",
                 "--no-browser"]) == 0  # fmt: skip
    assert served[1].robot.tips == ("l_tool0", "r_tool0")
    code = main(["view", str(urdf), "--tip", "l_tool0", "--tip", "r_tool0", "--path", "x.npy",
                 "--port", "0", "--no-browser"])  # fmt: skip
    assert code == 2
    assert "--path takes the waypoints of one tip, got 2 tips" in capsys.readouterr().err
