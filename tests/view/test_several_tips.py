"""Several tips in the viewer (``armik.view(armik.load(..., tips=[...]))``): the whole robot
drawn once where Pinocchio's FK of the whole URDF puts each link, a gizmo per tip, every
tip solved at once as ``Arms.solve`` solves it, and each tip's errors in the panel."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.view.nodes import wxyz_position
from armik.view.robot import Robot

from ..conftest import whole_placements
from ..test_arms import dual_irb120

pytest.importorskip("viser")

LIMIT = '<limit lower="-2.5" upper="2.5" effort="1" velocity="1"/>'
ORIGINS = {"base": (0, 0, 0), "torso": (0, 0, 0.2), "upper": (0.15, 0, 0), "fore": (0.125, 0, 0)}


def torso_urdf(torso: str) -> str:
    """A base, a torso on joint ``torso_yaw`` of type ``torso`` (revolute: shared by both
    chains; fixed: none shared) and two 2-joint arms, every link a box."""

    def link(name: str, size: str, at: str) -> str:
        return (f'<link name="{name}"><visual><origin xyz="{at}"/><geometry>'
                f'<box size="{size}"/></geometry></visual></link>')  # fmt: skip

    def joint(name: str, kind: str, parent: str, child: str, at: str, axis: str) -> str:
        limit = LIMIT if kind == "revolute" else ""
        return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/>'
                f'<child link="{child}"/><origin xyz="{at}"/><axis xyz="{axis}"/>{limit}'
                "</joint>")  # fmt: skip

    at = {name: " ".join(map(str, xyz)) for name, xyz in ORIGINS.items()}
    parts = [link("base", "0.3 0.3 0.1", at["base"]), link("torso", "0.1 0.1 0.4", at["torso"]),
             joint("torso_yaw", torso, "base", "torso", "0 0 0.05", "0 0 1")]  # fmt: skip
    for side, y in (("l", 0.15), ("r", -0.15)):
        parts += [
            link(f"{side}_upper", "0.3 0.05 0.05", at["upper"]),
            joint(f"{side}_shoulder", "revolute", "torso", f"{side}_upper", f"0 {y} 0.4", "0 1 0"),
            link(f"{side}_fore", "0.25 0.04 0.04", at["fore"]),
            joint(f"{side}_elbow", "revolute", f"{side}_upper", f"{side}_fore", "0.3 0 0", "0 1 0"),
            f'<link name="{side}_tool"/>',
            joint(
                f"{side}_tool_joint", "fixed", f"{side}_fore", f"{side}_tool", "0.25 0 0", "1 0 0"
            ),
        ]
    return '<robot name="torso_arms">' + "".join(parts) + "</robot>"


@pytest.fixture(scope="module")
def cell():
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])


@pytest.fixture
def viewer(cell):
    v = armik.view(cell, port=0, open_browser=False)
    yield v
    v.close()


@pytest.mark.parametrize("torso", ["revolute", "fixed"])
def test_every_link_is_drawn_once_where_the_whole_urdf_puts_it(torso):
    urdf = torso_urdf(torso)
    robot = armik.load(urdf, tips=["l_tool", "r_tool"])
    assert robot.shared == (("torso_yaw",) if torso == "revolute" else ())
    view = Robot(robot)
    assert view.body.kind == "meshes"
    links = sorted(p.link for p in view.body.parts)
    assert links == ["base", "l_fore", "l_upper", "r_fore", "r_upper", "torso"]
    full = pin.buildModelFromXML(urdf)
    data = full.createData()
    for seed in range(3):
        q = robot.random_q(seed)
        whole_placements(full, data, robot.joint_names, q)
        for part, T in zip(view.body.parts, view.poses(q)):
            link = data.oMf[full.getFrameId(part.link)].homogeneous
            # each box's pose: by the chains' FK, and by the whole URDF's at its origin
            origin = np.eye(4)
            origin[:3, 3] = ORIGINS[part.link.split("_")[-1]]
            assert np.allclose(T, link @ origin, atol=1e-9), part.link


def test_the_stick_figures_of_chains_sharing_no_joint_share_their_base(cell):
    view = Robot(cell)
    per_chain = [len(b.parts) for b in view._bodies]
    assert view.body.kind == "stick"
    assert len(view.body.parts) == sum(per_chain) - 1  # the base disc, drawn once
    assert view.joint_names == cell.joint_names and view.dof == 12


def test_set_target_is_arms_solve_and_the_panel_shows_each_tip(viewer, cell):
    q = cell.random_q(7)
    targets = {"l_tool0": cell.fk(q, "l_tool0"), "r_tool0": cell.fk(q, "r_tool0").translation}
    r = viewer.set_target(targets)
    want = cell.solve(targets, q0=cell.middle)
    assert r.success and np.array_equal(r.q, want.q) and r.solver == want.solver
    assert np.array_equal(viewer.q, r.q)
    for tip in cell.tips:
        pos, ori = r.extra["errors"][tip]
        row = viewer.panel.tip_errors[tip].value
        assert row == f"{pos:.3g}, {'-' if ori is None else f'{ori:.3g}'}"
        assert np.allclose(viewer._tip_frames[tip].position, cell.fk(r.q, tip).translation)
    # the pose's gizmo on the pose, the position's on the position in the tip's orientation
    T_l = targets["l_tool0"]
    assert np.allclose(viewer._gizmos["l_tool0"].position, T_l.translation)
    assert np.allclose(viewer._gizmos["r_tool0"].position, targets["r_tool0"])
    assert viewer._marks["l_tool0"].color == (40, 170, 70)


def test_dragging_one_gizmo_solves_every_tip(viewer, cell):
    q = cell.random_q(8)
    T_l = cell.fk(q, "l_tool0")
    viewer.set_target({"l_tool0": T_l})  # the right tip has no target yet
    moved = cell.fk(q + 0.05, "r_tool0")  # reachable: a small move of every joint
    seed = viewer.q
    wxyz, position = wxyz_position(moved.homogeneous)
    viewer._dragged(SimpleNamespace(wxyz=tuple(wxyz), position=tuple(position)), "r_tool0")
    assert set(viewer.targets) == {"l_tool0", "r_tool0"}
    assert viewer.targets["l_tool0"] is T_l
    want = cell.solve(dict(viewer.targets), q0=seed)
    assert viewer.result.success and np.array_equal(viewer.result.q, want.q)
    assert np.allclose(cell.fk(viewer.q, "r_tool0").homogeneous, moved.homogeneous, atol=1e-9)


def test_a_failed_tip_is_marked_and_named(viewer, cell):
    q = cell.random_q(9)
    far = pin.SE3(np.eye(3), np.array([0.0, -3.0, 0.5]))
    before = viewer.q
    r = viewer.set_target({"l_tool0": cell.fk(q, "l_tool0"), "r_tool0": far})
    assert not r.success and np.array_equal(viewer.q, before)
    assert viewer._marks["r_tool0"].color == (220, 50, 50)
    assert viewer._marks["l_tool0"].color == (40, 170, 70)
    assert viewer.panel.tip_errors["r_tool0"].value.endswith("(failed)")
    assert "r_tool0" in viewer.panel.reason.value
    # the next answer leaves the right tip out: its row holds no numbers of the failed one
    r = viewer.set_target({"l_tool0": cell.fk(q, "l_tool0")})
    assert r.success and "r_tool0" not in r.extra["errors"]
    assert viewer.panel.tip_errors["r_tool0"].value == "no target"
    assert viewer._marks["r_tool0"].color == (40, 170, 70)


def test_task_lists_per_tip_draw_each_tips_regions(viewer, cell):
    q = cell.random_q(10)
    p = cell.fk(q, "r_tool0").translation
    r = viewer.set_target({"l_tool0": cell.fk(q, "l_tool0"),
                           "r_tool0": [armik.Position(p, bounds=(0.03, 0.03, 0.03))]})  # fmt: skip
    assert r.success
    (box,) = viewer.regions
    assert box.name == "/regions/1/0/box" and np.allclose(box.T[:3, 3], p)


def test_play_walks_a_path_of_every_joint(viewer, cell):
    q0 = cell.random_q(11)
    ways = {tip: [cell.fk(q0 + 0.02 * k, tip) for k in range(4)] for tip in cell.tips}
    path = cell.solve_path(ways, q0, max_joint_step=0.3)
    assert path.success.all()
    viewer.play(path, fps=1000)
    assert np.array_equal(viewer.q, path.q[-1])


def test_bad_input_names_the_tips(viewer, cell):
    with pytest.raises(armik.InputError, match="several tips"):
        viewer.set_target(cell.fk(cell.middle, "l_tool0"))
    with pytest.raises(armik.FrameError, match="l_tool0"):
        viewer.set_target({"nope": cell.fk(cell.middle, "l_tool0")})
    with pytest.raises(armik.OptionError, match="12 finite numbers"):
        viewer.show(np.zeros(6))
    with pytest.raises(armik.InputError, match="tips="):
        armik.view([cell], port=0, open_browser=False)
    assert "tips=['l_tool0', 'r_tool0']" in repr(viewer)


def test_the_panel_has_no_ghosts_box_for_several_tips(viewer):
    assert not viewer.panel.ghosts.visible  # solve_all is one arm's


def test_chains_sharing_a_torso_are_solved_together():
    robot = armik.load(torso_urdf("revolute"), tips=["l_tool", "r_tool"])
    q = robot.random_q(12)
    targets = {tip: robot.fk(q, tip).translation for tip in robot.tips}
    with armik.view(robot, port=0, open_browser=False) as v:
        r = v.set_target(targets)
        assert r.success, r.reason
        for tip in robot.tips:  # the torso turned both arms: each tip where it was asked
            assert np.allclose(robot.fk(v.q, tip).translation, targets[tip], atol=1e-6)
            assert np.allclose(v._tip_frames[tip].position, targets[tip], atol=1e-6)


def test_a_preference_the_shared_joints_refuse_is_said_in_the_panel():
    """manipulability over a shared torso is refused (one tip's measure): the panel says
    why, the dropdown and the solves stay with the preference there was."""
    robot = armik.load(torso_urdf("revolute"), tips=["l_tool", "r_tool"])
    q = robot.random_q(13)
    targets = {tip: robot.fk(q, tip).translation for tip in robot.tips}
    with armik.view(robot, port=0, open_browser=False) as v:
        assert v.set_target(targets).success
        event = SimpleNamespace(client=object(), target=SimpleNamespace(value="manipulability"))
        v.panel.prefer.value = "manipulability"  # a browser's choice sets it, then calls them
        for callback in v.panel.prefer._impl.update_cb:
            callback(event)
        assert "prefer" not in v.options and v.panel.prefer.value == "none"  # put back
        assert v.panel.message.value == "prefer 'manipulability' refused"
        assert "shared by several tips" in v.panel.reason.value
        assert v.set_target(targets).success  # the next solve is not refused
