"""Reading URDFs (issue items 1, 2, 5, 9, 10, 13-17): every file either loads into the arm
it describes or is refused with an ``ArmikError`` that names the joint or link, the value
and the fix."""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import textwrap
import warnings

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import ArmikWarning, FrameError, URDFError
from armik.model import urdf as urdf_mod

from ..conftest import write_urdf
from ..urdf_cases import arm3, chain, joint


def load_text(tmp_path, text: str, name: str = "robot.urdf", **kw) -> armik.Arm:
    return armik.load(write_urdf(tmp_path, text, name), **kw)


# -- 1. degenerate axes are refused, others normalised -----------------------------------


@pytest.mark.parametrize(
    "axis",
    [
        "<axis/>",
        '<axis xyz="0 0 0"/>',
        '<axis xyz="0 0 -0"/>',
        '<axis xyz="1e-200 1e-200 1e-200"/>',
        '<axis xyz="nan 0 1"/>',
        '<axis xyz="inf 0 0"/>',
        '<axis xyz="0 1"/>',
        '<axis xyz="0 one 0"/>',
    ],
)
def test_degenerate_axis_is_refused_naming_the_joint(tmp_path, axis):
    text = arm3().replace('<axis xyz="0 1 0"/><limit', f"{axis}<limit", 1)
    assert axis in text
    with pytest.raises(URDFError, match="joint 'j2'.*axis") as info:
        load_text(tmp_path, text)
    assert "xyz" in str(info.value)


def test_huge_and_tilted_axes_are_normalised_and_fk_stays_rigid(tmp_path, rng):
    with pytest.warns(ArmikWarning, match="'j2'.*norm 1e\\+300"):
        big = load_text(tmp_path, arm3(axis2="1e300 0 0"), "big.urdf")
    unit = load_text(tmp_path, arm3(axis2="1 0 0"), "unit.urdf")
    with pytest.warns(ArmikWarning, match="'j2'.*norm 5"):
        tilted = load_text(tmp_path, arm3(axis2="0 3 4"), "tilted.urdf")
    tilted_unit = load_text(tmp_path, arm3(axis2="0 0.6 0.8"), "tilted_unit.urdf")
    for _ in range(20):
        q = rng.uniform(-2, 2, 3)
        for a, b in ((big, unit), (tilted, tilted_unit)):
            T = a.fk(q)
            R = T.rotation
            assert np.abs(R.T @ R - np.eye(3)).max() < 1e-12
            assert np.abs(T.homogeneous - b.fk(q).homogeneous).max() < 1e-12


def test_a_nearly_unit_axis_warns_with_a_norm_that_is_not_one(tmp_path):
    # six digits of (1, 2, 3) / sqrt(14): norm 0.9999999, which "%.6g" printed as 1
    axis = "0.267261 0.534522 0.801784"
    norm = math.hypot(*map(float, axis.split()))
    with pytest.warns(ArmikWarning, match="'j2'") as seen:
        a = load_text(tmp_path, arm3(axis2=axis))
    for text in [str(w.message) for w in seen] + list(a.info.notes):
        said = float(re.search(r"norm ([0-9.e+-]+)", text).group(1))
        assert said != 1.0 and abs(said - norm) < 1e-9, text


# -- 2. non-unit prismatic axis: the ROS reading, said out loud ---------------------------


def test_non_unit_prismatic_axis_reads_as_unit_with_a_warning(tmp_path):
    text = arm3(
        axis2="0 0 2",
        jtype2="prismatic",
        limit2=('<limit lower="-0.5" upper="0.5" effort="1" velocity="1"/>'),
    )
    with pytest.warns(ArmikWarning, match=r"joint 'j2'.*norm 2\b.*yourdfpy"):
        a = load_text(tmp_path, text)
    p0 = a.fk([0.0, 0.0, 0.0]).translation
    p1 = a.fk([0.0, 0.2, 0.0]).translation
    np.testing.assert_allclose(p1 - p0, [0, 0, 0.2], atol=1e-12)  # 0.2 m, not 0.4
    assert any("'j2'" in n and "norm 2" in n for n in a.info.notes)


# -- 5. equal limits: 0 0 means "not given", anything else pins the joint ----------------


def test_equal_nonzero_limits_pin_the_joint(tmp_path, rng):
    pinned = '<limit lower="0.5" upper="0.5" effort="1" velocity="1"/>'
    a = load_text(tmp_path, arm3(limit2=pinned))
    assert a.lower[1] == a.upper[1] == 0.5
    assert a.random_q(rng)[1] == 0.5 and a.middle[1] == 0.5
    for solver in ("dls", "qp"):
        for k in range(5):
            q = np.array([rng.uniform(-2, 2), 0.5, rng.uniform(-2, 2)])
            r = a.solve(a.fk(q).translation, solver=solver, q0=[0.1, 0.5, 0.1], seed=k)
            assert r.success and r.q[1] == 0.5, (solver, r.reason)
    # A target that needs j2 away from 0.5 is not reached by moving it anyway.
    target = a.fk([0.3, -1.0, 0.4]).translation
    free = load_text(tmp_path, arm3(), "free.urdf")
    assert free.solve(target).success
    r = a.solve(target, timeout=0.02)
    assert not r.success or r.q[1] == 0.5


def test_zero_zero_limits_mean_not_given_with_a_warning(tmp_path):
    text = arm3(limit2='<limit lower="0" upper="0" effort="1" velocity="1"/>')
    with pytest.warns(ArmikWarning, match="'j2'.*lower = upper = 0.*unlimited"):
        a = load_text(tmp_path, text)
    assert a.lower[1] == -np.inf and a.upper[1] == np.inf
    assert any("'j2'" in n for n in a.info.notes)


def test_huge_limits_mean_free_with_a_warning(tmp_path, rng):
    text = arm3().replace('lower="-2" upper="2"', 'lower="-1e16" upper="1e308"', 1)
    with pytest.warns(ArmikWarning, match="'j1' has lower and upper limit.*no limit"):
        a = load_text(tmp_path, text)
    assert a.lower[0] == -np.inf and a.upper[0] == np.inf and a.upper[1] == 2
    assert np.isfinite(a.random_q(rng)).all()
    q = np.array([2.5, 0.3, -0.4])
    r = a.solve(a.fk(q), solver="qp")
    assert r.success, r.reason


SAFETY = '<safety_controller k_position="100" k_velocity="10" {}/>'


def test_soft_limits_of_a_safety_controller_bound_the_joint_as_moveit_reads_them(tmp_path):
    # TIAGo's arm_1_joint: <limit> [0, 2.749], soft limits [0.07, 2.679]; MoveIt and
    # trac_ik bound it by both, the controller holds it there
    limit = '<limit lower="-2" upper="2" effort="1" velocity="1"/>'
    soft = SAFETY.format('soft_lower_limit="-0.5" soft_upper_limit="3"')
    a = load_text(tmp_path, arm3(limit2=limit + soft))
    assert (a.lower[1], a.upper[1]) == (-0.5, 2.0) and (a.lower[0], a.upper[0]) == (-2, 2)
    assert any("'j2'" in n and "safety_controller" in n for n in a.info.notes)
    q = np.array([0.3, -1.0, 0.4])  # j2 within <limit>, outside the soft limits
    assert not a.within_limits(q)
    r = a.solve(a.fk(q))
    assert not r.success or r.q[1] >= -0.5 - 1e-9
    with pytest.raises(armik.JointError, match="'j2'.*outside its URDF limits"):
        load_text(tmp_path, arm3(limit2=limit + soft), "locked.urdf", locked={"j2": -1.0})
    # a soft limit not written is 0, as urdfdom reads it for MoveIt and trac_ik
    one_side = SAFETY.format('soft_upper_limit="1.5"')
    b = load_text(tmp_path, arm3(limit2=limit + one_side), "one.urdf")
    assert (b.lower[1], b.upper[1]) == (0.0, 1.5)


def test_soft_limits_that_narrow_to_zero_pin_the_joint_and_do_not_free_it(tmp_path):
    """lower = upper = 0 in <limit> means no limits given; soft limits that narrow real
    limits to [0, 0] pin the joint there, as MoveIt reads them."""
    for hard, soft in (("-1", "1"), ("0", "2")):
        limit = f'<limit lower="{hard}" upper="{soft}" effort="1" velocity="1"/>'
        pinned = SAFETY.format('soft_lower_limit="0" soft_upper_limit="0"')
        a = load_text(tmp_path, arm3(limit2=limit + pinned), f"pinned{hard}.urdf")
        assert (a.lower[1], a.upper[1]) == (0.0, 0.0)
        q = np.array([0.3, 2.5, 0.4])  # j2 past every limit the file writes
        assert not a.within_limits(q)
        r = a.solve(a.fk(q))
        assert not r.success or abs(r.q[1]) <= 1e-9


def test_soft_limits_that_leave_no_value_are_refused_naming_the_joint(tmp_path):
    limit = '<limit lower="-2" upper="2" effort="1" velocity="1"/>'
    soft = SAFETY.format('soft_lower_limit="2.5" soft_upper_limit="3"')
    with pytest.raises(URDFError, match="'j2'.*safety_controller.*leave no value"):
        load_text(tmp_path, arm3(limit2=limit + soft))


# -- 9. names shared by a link and a joint ------------------------------------------------


def test_link_and_joint_with_one_name_survive_locking():
    a = armik.load("scara", base="link1")  # the joint "quill" and the link "quill"
    assert a.joint_names == ["elbow", "quill", "tool_roll"]
    q = np.array([0.4, 0.1, 0.3])
    r = a.solve(a.fk(q))
    assert r.success, r.reason
    full = armik.load("scara")
    T_world_tip = full.fk(np.array([0.2, *q]))
    T_world_link1 = full.model.frames[full.model.getFrameId("link1", pin.BODY)]
    assert T_world_link1 is not None
    # The quill link is a valid tip too: the link (BODY) frame is meant.
    b = armik.load("scara", tip="quill")
    assert b.dof == 3
    assert np.isfinite(T_world_tip.translation).all()


def test_link_named_universe_and_tip_named_like_a_joint(tmp_path):
    text = chain(
        joint("universe_joint", "universe", "l1"),
        joint("l2", "l1", "l2", xyz="0.3 0 0"),  # joint named like its child link
        joint("j3", "l2", "tool", xyz="0.2 0 0"),
        joint("side", "l1", "cam", jtype="fixed"),
    )
    a = load_text(tmp_path, text, tip="l2", base="l1")
    assert a.dof == 1 and a.joint_names == ["l2"]
    r = a.solve(a.fk([0.7]).translation)
    assert r.success, r.reason


def test_a_joint_named_universe_locks_at_its_value(tmp_path, rng):
    # Pinocchio's joint 0 is "universe": looked up by name, the lock went there and the
    # URDF's joint stayed at 0, its arm 0.5 rad off the robot
    text = chain(joint("universe", "base", "l1"), joint("j2", "l1", "tool", xyz="0.3 0 0"))
    a = load_text(tmp_path, text, locked={"universe": 0.5})
    free = load_text(tmp_path, text, "free.urdf")
    assert a.joint_names == ["j2"] and a.locked == {"universe": 0.5}
    for q in rng.uniform(-1, 1, (3, 1)):
        assert a.fk(q).isApprox(free.fk([0.5, q[0]]), 1e-12)
    with pytest.raises(armik.JointError, match="locked joint 'universe' does not exist"):
        load_text(tmp_path, chain(joint("j1", "base", "l1")), "none.urdf", locked={"universe": 0})


def test_locked_joint_named_like_a_link(tmp_path):
    # As in example-robot-data's ANYmal C: link "RH_KFE" is the parent of joint "RH_KFE".
    text = chain(
        joint("hip", "base", "thigh"),
        joint("knee", "thigh", "shank", xyz="0.3 0 0", axis='<axis xyz="0 1 0"/>'),
        joint("foot_fixed", "shank", "foot", jtype="fixed", xyz="0.3 0 0"),
        joint("other_fixed", "base", "knee2", jtype="fixed", xyz="0 0.2 0"),
        joint("knee2", "knee2", "other_shank", xyz="0.3 0 0"),
        joint("tip_fixed", "other_shank", "other_foot", jtype="fixed", xyz="0.2 0 0"),
    )
    a = load_text(tmp_path, text, tip="foot", locked={"knee2": 0.4})
    assert a.joint_names == ["hip", "knee"]
    assert a.solve(a.fk([0.3, -0.5])).success
    b = load_text(tmp_path, text, tip="other_foot")
    assert b.joint_names == ["knee2"] and {f for f in b.frames() if "\x00" in f} == set()


# -- 10. deep trees are refused before Pinocchio's parser could crash ---------------------


def deep_chain(n: int, moving_every: int = 1) -> str:
    """A chain n links deep, one joint in ``moving_every`` revolute, the others fixed."""
    return chain(
        *(
            joint(
                f"j{i}", f"l{i}", f"l{i + 1}", "revolute" if i % moving_every == 0 else "fixed",
                xyz="0 0 0.01",
            )
            for i in range(n)
        )
    )  # fmt: skip


def test_tree_deeper_than_the_limit_is_refused(tmp_path):
    with pytest.raises(URDFError, match=f"more than {urdf_mod.MAX_DEPTH} links deep"):
        urdf_mod.read_urdf_string(deep_chain(urdf_mod.MAX_DEPTH + 5))


def test_a_huge_file_of_fixed_links_after_the_tip_is_refused_by_the_depth_limit(tmp_path):
    # 45 000 fixed links hanging after a 2-link arm's tip (about 5 MB): refused by the depth
    # limit, naming where the tree gets too deep. Reading it took 28 s while the links'
    # names were checked against a list (quadratic); a set makes it linear, 1.8 s here.
    arm = chain(
        joint("j1", "base", "l1", xyz="0 0 0.1"),
        joint("j2", "l1", "tip", xyz="0.5 0 0"),
    )
    n = 45_000
    hanging = "".join(
        f'<link name="f{i}"/><joint name="fj{i}" type="fixed"><parent link="'
        f'{"tip" if i == 0 else f"f{i - 1}"}"/><child link="f{i}"/></joint>'
        for i in range(n)
    )
    text = arm.replace("</robot>", hanging + "</robot>")
    assert len(text) > 4_000_000
    with pytest.raises(URDFError, match=f"more than {urdf_mod.MAX_DEPTH} links deep.*'f9"):
        armik.load(write_urdf(tmp_path, text), tip="tip")


def test_deep_tree_parses_on_a_small_thread_stack(tmp_path):
    # 600 links crashed Pinocchio's parser on a 512 kB thread stack (measured at 300);
    # armik parses on a thread of its own with a large stack. In a subprocess: a crash
    # must not take the test run down.
    path = write_urdf(tmp_path, deep_chain(600, moving_every=3))  # 200 moving joints
    code = textwrap.dedent(
        f"""
        import threading
        from armik.model.urdf import read_urdf
        out = []
        threading.stack_size(512 * 1024)
        t = threading.Thread(target=lambda: out.append(read_urdf({str(path)!r})[0].njoints))
        t.start(); t.join()
        print(out[0])
        """
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stderr[-500:]
    assert done.stdout.strip() == "201"


def test_more_moving_joints_than_pinocchio_data_can_hold_are_refused_by_count(tmp_path):
    """A URDF of 300 moving joints, chain or tree: a ``URDFError`` naming the count and
    the fix, where Pinocchio's data (about 1.8 GB a copy) ended the process; a tree of as
    many links with the joints past the limit fixed still loads."""
    n = urdf_mod.MAX_MOVING + 44
    with pytest.raises(URDFError, match=f"has {n} moving joints.*up to 256.*fixed"):
        urdf_mod.read_urdf_string(deep_chain(n))
    star = chain(*(joint(f"j{i}", "l0", f"b{i}") for i in range(n)))
    with pytest.raises(URDFError, match=f"has {n} moving joints"):
        urdf_mod.read_urdf_string(star)
    model = urdf_mod.read_urdf_string(deep_chain(n, moving_every=2))[0]
    assert model.nv == (n + 1) // 2


# -- 13. files that are not files -------------------------------------------------------


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="needs /dev/zero")
def test_device_is_refused():
    with pytest.raises(URDFError, match="not a regular file"):
        armik.load("/dev/zero")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs named pipes")
def test_named_pipe_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "robot.urdf"
    os.mkfifo(fifo)
    with pytest.raises(URDFError, match="not a regular file"):
        armik.load(fifo)


def test_file_size_cap(tmp_path, monkeypatch):
    path = write_urdf(tmp_path, arm3())
    monkeypatch.setattr(urdf_mod, "MAX_FILE_BYTES", 100)
    with pytest.raises(URDFError, match="above the"):
        armik.load(path)


# -- 14. the parser's reasons, named ------------------------------------------------------


@pytest.mark.parametrize(
    "edit, words",
    [
        (lambda t: t.replace('name="j3"', 'name="j1"'), ["two joints named 'j1'", "unique"]),
        (
            lambda t: t.replace('<link name="l3"/>', '<link name="l3"/><link name="l3"/>'),
            ["two links named 'l3'"],
        ),
        (
            lambda t: t.replace(
                '<limit lower="-2" upper="2" effort="1" velocity="1"/></joint><joint name="j3"',
                '</joint><joint name="j3"',
            ),
            ["joint 'j2'", "no <limit>", "continuous"],
        ),
        (lambda t: t.replace('xyz="0.25 0 0"', 'xyz="0.25 0 nan"'), ["joint 'j3'", "'nan'"]),
        (lambda t: t.replace('xyz="0.25 0 0"', 'xyz="0.25 0 1x"'), ["joint 'j3'", "'1x'"]),
        (lambda t: t.replace('xyz="0.25 0 0"', 'xyz="0.25 0"'), ["joint 'j3'", "3 numbers"]),
        (
            lambda t: t.replace('upper="2" effort="1"', 'upper="2"', 1),
            ["joint 'j1'", "no effort"],
        ),
        (lambda t: t.replace('xyz="0.2 0 0"', 'xyz="1e308 0 0"'), ["'tool_joint'", "1e308"]),
        (lambda t: t.replace('type="revolute"', 'type="hinge"', 1), ["'j1'", "'hinge'"]),
        (lambda t: t.replace('<child link="l2"/>', '<child link="l9"/>'), ["'l9'", "not a <link>"]),
        (
            lambda t: t.replace('<child link="l3"/>', '<child link="l2"/>'),
            ["'l2'", "child of two joints"],
        ),
    ],
)
def test_parser_errors_name_the_element_and_value(tmp_path, edit, words):
    text = edit(arm3())
    assert text != arm3()
    with pytest.raises(URDFError) as info:
        load_text(tmp_path, text)
    message = str(info.value)
    for word in words:
        assert word in message, message
    assert "not a valid URDF model" not in message and "\n" not in message


def test_default_namespace_is_read_like_urdfdom_reads_it(tmp_path):
    text = arm3().replace('<robot name="chain">', '<robot name="chain" xmlns="http://x.org/urdf">')
    assert load_text(tmp_path, text).dof == 3


def test_urdfdom_reason_is_captured_when_armik_does_not_know_it(tmp_path, capfd):
    text = arm3().replace('<robot name="chain">', "<robot>")  # urdfdom needs a robot name
    with pytest.raises(URDFError, match="Pinocchio could not build") as info:
        load_text(tmp_path, text)
    message = str(info.value)
    assert "No name given for the robot" in message and "\n" not in message
    assert "No name" not in capfd.readouterr().err  # taken from stderr, not left there


# -- 15. xacro ------------------------------------------------------------------------


XACRO = """<?xml version="1.0"?>
<robot name="xarm2" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="len" value="0.4"/>
  <xacro:macro name="rev" params="name parent child x">
    <joint name="${name}" type="revolute"><parent link="${parent}"/><child link="${child}"/>
      <origin xyz="${x} 0 0"/><axis xyz="0 0 1"/>
      <limit lower="${-pi/2}" upper="${pi/2}" effort="1" velocity="1"/></joint>
  </xacro:macro>
  <link name="base"/><link name="a"/><link name="b"/>
  <xacro:rev name="j1" parent="base" child="a" x="0"/>
  <xacro:rev name="j2" parent="a" child="b" x="${len}"/>
</robot>
"""


def test_xacro_is_expanded_when_the_package_is_installed(tmp_path):
    a = load_text(tmp_path, XACRO, "arm.urdf.xacro")
    assert a.dof == 2 and a.name == "xarm2"
    np.testing.assert_allclose(a.upper, [np.pi / 2] * 2, atol=1e-12)
    np.testing.assert_allclose(a.fk([0, 0]).translation, [0.4, 0, 0], atol=1e-12)


def test_xacro_that_cannot_be_expanded_says_so(tmp_path):
    text = XACRO.replace('value="0.4"', 'value="${undefined_length}"')
    with pytest.raises(URDFError, match="could not expand it.*undefined_length.*xacro "):
        load_text(tmp_path, text, "arm.xacro")


def test_expressions_in_a_plain_urdf_are_expanded_only_when_needed(tmp_path):
    text = arm3().replace('xyz="0.25 0 0"', 'xyz="${0.5 / 2} 0 0"')
    a = load_text(tmp_path, text)  # fails as URDF ('${0.5' is no number): expanded
    np.testing.assert_allclose(a.fk([0, 0, 0]).translation, [0.45, 0, 0.4], atol=1e-12)
    # A stray ${...} where nobody reads it (a comment, as in example-robot-data's xArm 7)
    # leaves the file as it is.
    plain = arm3().replace("<link", "<!-- ${prefix}link --><link", 1)
    assert load_text(tmp_path, plain, "plain.urdf").dof == 3


def test_xacro_without_the_package_says_how_to_expand_it(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "xacro", None)  # import xacro -> ImportError
    with pytest.raises(URDFError, match="xacro file.*xacro .*> robot.urdf"):
        load_text(tmp_path, XACRO, "arm.urdf")  # detected from the text, not the suffix
    text = arm3().replace('xyz="0.25 0 0"', 'xyz="${0.5 / 2} 0 0"')
    with pytest.raises(URDFError, match="joint 'j3'.*if it is a xacro file"):
        load_text(tmp_path, text, "expr.urdf")


# -- 16. default tip, 17. name ---------------------------------------------------------


def ur_like(with_tool0: bool = True) -> str:
    joints = [
        joint("world_joint", "world", "base_link", jtype="fixed"),
        joint("base_fixed", "base_link", "base", jtype="fixed"),
        joint("j1", "base_link", "l1"),
        joint("j2", "l1", "l2", xyz="0.3 0 0"),
        joint("ee_fixed", "l2", "ee_link", jtype="fixed"),
    ]
    if with_tool0:
        joints.append(joint("tool0_fixed", "l2", "tool0", jtype="fixed", xyz="0.1 0 0"))
    return chain(*joints, name="ur_like")


def test_default_tip_tool0_by_rep199(tmp_path):
    a = load_text(tmp_path, ur_like(), "whatever_file.urdf")
    assert a.tip == "tool0" and "REP 199" in a.tip_reason
    assert a.name == "ur_like"  # 17: <robot name>, not the file name


def test_ur_description_loads_without_a_tip():
    from armik.model.catalogue import entry

    a = armik.load(entry("ur5").urdf_path())  # leaves: base, ee_link, tool0
    assert a.tip == "tool0" and a.dof == 6 and a.name == "ur5"


def test_default_tip_fixed_leaves_on_one_link_give_that_link(tmp_path):
    a = load_text(tmp_path, ur_like(with_tool0=False).replace("ee_link", "tcp"))
    assert a.tip == "tcp" and "longest chain" in a.tip_reason
    text = ur_like(with_tool0=False).replace(
        "</robot>",
        joint("cam_fixed", "l2", "camera", jtype="fixed").replace(
            "<joint", '<link name="camera"/><joint'
        )
        + "</robot>",
    )
    b = load_text(tmp_path, text, "two.urdf")
    assert b.tip == "l2" and "'camera'" in b.tip_reason and "'ee_link'" in b.tip_reason


def test_unknown_frame_suggests_close_names():
    with pytest.raises(FrameError, match="closest: 'tool0'") as info:
        armik.load("ur5", tip="tool")
    assert "tool0" in info.value.candidates


def test_bundled_names_stay_catalogue_names():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert armik.load("double_pendulum").name == "double_pendulum"


def test_revolute_limits_in_degrees_load_with_a_warning_naming_them(tmp_path):
    """``<limit lower="-170" upper="170">`` on a revolute joint, degrees by mistake: ROS
    loads it, and so does armik, but it loaded silently a joint of 27 turns each way."""
    text = arm3(limit2='<limit lower="-170" upper="120" effort="1" velocity="1"/>')
    with pytest.warns(ArmikWarning) as said:
        a = load_text(tmp_path, text)
    words = [str(w.message) for w in said if "four turns" in str(w.message)]
    assert len(words) == 1, [str(w.message) for w in said]
    assert "'j2'" in words[0] and "[-170, 120] rad" in words[0] and "radians" in words[0]
    assert f'lower="{math.radians(-170):.6g}" upper="{math.radians(120):.6g}"' in words[0]
    assert (a.lower[1], a.upper[1]) == (-170.0, 120.0)  # loaded as written, as ROS does
    assert words[0] in a.info.notes
    # four turns each way and less, another joint type, or a huge value: no such word
    for limit2, jtype2 in (
        ('<limit lower="-25" upper="25" effort="1" velocity="1"/>', "revolute"),
        ('<limit lower="-170" upper="170" effort="1" velocity="1"/>', "prismatic"),
        ('<limit lower="-1e16" upper="2" effort="1" velocity="1"/>', "revolute"),
    ):
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            load_text(tmp_path, arm3(limit2=limit2, jtype2=jtype2), f"{jtype2}{limit2[14:17]}.urdf")
        assert not [w for w in said if "four turns" in str(w.message)], limit2
