"""Reading URDFs (issue items 1, 2, 5, 9, 16, 17): every file either loads into the arm
it describes or is refused with an ``ArmikError`` that names the joint or link, the value
and the fix."""

from __future__ import annotations

import math
import pickle
import re
import warnings

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import ArmikWarning, FrameError, URDFError

from ..conftest import load_text
from ..urdf_cases import arm3, chain, joint

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


def said_norms(texts: list[str]) -> list[float]:
    return [float(re.search(r"norm ([0-9.e+-]+)", t).group(1)) for t in texts if "norm" in t]


def test_a_unit_axis_rounded_to_six_digits_is_normalised_with_a_note_only(tmp_path, rng):
    """Six digits of (1, 2, 3) / sqrt(14), norm 0.9999999 (romeo.urdf's hands: 0.9999998),
    warned 'non-unit axis' on every such joint. It is normalised as before, said by a note
    whose norm is not printed as 1 ("%.6g" printed 0.9999999 as 1)."""
    axis = "0.267261 0.534522 0.801784"
    norm = math.hypot(*map(float, axis.split()))
    with warnings.catch_warnings():
        warnings.simplefilter("error", ArmikWarning)
        a = load_text(tmp_path, arm3(axis2=axis))
    notes = [n for n in a.info.notes if "'j2'" in n and "axis" in n]
    assert len(notes) == 1 and "rounded" in notes[0], a.info.notes
    assert [abs(said - norm) < 1e-9 and said != 1.0 for said in said_norms(notes)] == [True]
    unit = " ".join(repr(float(v) / norm) for v in axis.split())
    exact = load_text(tmp_path, arm3(axis2=unit), "unit.urdf")
    for _ in range(10):  # normalised: the rotation about the written axis made unit
        q = rng.uniform(-2, 2, 3)
        assert np.abs(a.fk(q).homogeneous - exact.fk(q).homogeneous).max() < 1e-12


@pytest.mark.parametrize("scale", [1.0 - 2e-5, 1.0 + 2e-5])
def test_an_axis_beyond_rounding_warns_with_a_norm_that_is_not_one(tmp_path, scale):
    """2e-5 off unit is no rounding of six digits: the warning stays, its norm exact."""
    axis = " ".join(f"{v * scale:.9f}" for v in (0.6, 0.0, 0.8))
    norm = math.hypot(*map(float, axis.split()))
    with pytest.warns(ArmikWarning, match="'j2' has a non-unit axis") as seen:
        a = load_text(tmp_path, arm3(axis2=axis))
    texts = [str(w.message) for w in seen] + [n for n in a.info.notes if "'j2'" in n]
    assert len(said_norms(texts)) == 2 and "ROS reading" in texts[-1], texts
    assert all(said != 1.0 and abs(said - norm) < 1e-9 for said in said_norms(texts)), texts


def test_romeos_hands_load_without_an_axis_warning():
    """Six warnings 'non-unit axis ... norm 0.9999998076' for romeo.urdf, tip LHand."""
    from importlib.metadata import distribution

    share = distribution("example-robot-data").locate_file("cmeel.prefix/share")
    path = share / "example-robot-data/robots/romeo_description/urdf/romeo.urdf"
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        a = armik.load(str(path), tip="LHand")
    assert not [w for w in seen if "axis" in str(w.message)], [str(w.message) for w in seen]
    assert sum("rounded to its digits" in n for n in a.info.notes) == 6, a.info.notes


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


def test_what_reading_a_urdf_notes_is_said_at_load_not_again_when_the_arm_is_rebuilt(tmp_path):
    """An arm is rebuilt from its URDF when it is unpickled (a worker process) and by
    ``with_locked``; the notes of the first reading (degrees, limits of 0 0, a non-unit axis)
    are said once, at ``load``, and the rebuilt arm carries the same ``info.notes``."""
    text = arm3(limit2='<limit lower="-170" upper="120" effort="1" velocity="1"/>')
    text = text.replace('<limit lower="-2" upper="2"', '<limit lower="0" upper="0"', 1)
    text = text.replace('<axis xyz="0 0 1"/>', '<axis xyz="0 0 1.0001"/>', 1)
    for load in (lambda: load_text(tmp_path, text), lambda: armik.load_string(text)):
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            a = load()
        first = sorted(str(w.message) for w in said if issubclass(w.category, ArmikWarning))
        assert len(first) == 3, first  # degrees, 0 0, the axis
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            again = [pickle.loads(pickle.dumps(a)), a.with_locked({"j3": 0.1})]
        assert [str(w.message) for w in said] == []
        for b in again:
            assert b.info.notes == a.info.notes and len(a.info.notes) >= 3
