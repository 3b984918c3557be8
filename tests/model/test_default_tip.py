"""The tip chosen when none is given: a gripper's tool frame beats its moving jaw."""

from __future__ import annotations

import warnings

import pytest

import armik
from armik.errors import FrameError
from armik.model.catalogue import _erd_robot_dir

from ..conftest import write_urdf
from ..urdf_cases import chain, joint

ARM = (
    joint("j1", "base", "l1"),
    joint("j2", "l1", "l2", xyz="0.3 0 0", axis='<axis xyz="0 1 0"/>'),
    joint("j3", "l2", "hand", xyz="0.3 0 0", axis='<axis xyz="0 1 0"/>'),
)


def test_a_tool_frame_beside_a_jaw_is_the_tip(tmp_path):
    text = chain(
        *ARM,
        joint("tcp_fixed", "hand", "tcp", jtype="fixed", xyz="0.1 0 0"),
        joint("jaw", "hand", "jaw_link", xyz="0.05 0 0"),
    )
    a = armik.load(write_urdf(tmp_path, text))
    assert (a.tip, a.dof) == ("tcp", 3)
    assert "'jaw'" in a.tip_reason and "tool frame 'tcp'" in a.tip_reason


def test_two_fingers_and_a_tool_frame(tmp_path):
    text = chain(
        *ARM,
        joint("tcp_fixed", "hand", "tcp", jtype="fixed"),
        joint("finger1", "hand", "f1", jtype="prismatic", axis='<axis xyz="0 1 0"/>'),
        joint("finger2", "hand", "f2", jtype="prismatic", axis='<axis xyz="0 -1 0"/>'),
    )
    a = armik.load(write_urdf(tmp_path, text))
    assert a.tip == "tcp" and "'finger1', 'finger2'" in a.tip_reason


def test_no_tool_frame_when_it_is_a_choice(tmp_path):
    """Two fixed leaves on the hand and a last joint named as no gripper's: no single tool
    frame, the old rules decide."""
    text = chain(
        *ARM,
        joint("tcp_fixed", "hand", "tcp", jtype="fixed"),
        joint("cam_fixed", "hand", "camera", jtype="fixed"),
        joint("spin", "hand", "spinner"),
    )
    a = armik.load(write_urdf(tmp_path, text))
    assert (a.tip, a.dof) == ("spinner", 4)


TWO_FIXED = (
    joint("tcp_fixed", "hand", "tcp", jtype="fixed"),
    joint("cam_fixed", "hand", "camera", jtype="fixed"),
)


@pytest.mark.parametrize("fixed", [(), TWO_FIXED], ids=["no fixed leaf", "two fixed leaves"])
@pytest.mark.parametrize(
    "jaw, link", [("jaw", "jaw_link"), ("gripper", "moving"), ("j4", "gripperMover")]
)
def test_a_jaw_named_so_leaves_the_hand_as_the_tip(tmp_path, fixed, jaw, link):
    """No single tool frame on the hand: a last joint named as a gripper's jaw (by its
    joint's or its link's name) is left off, and the hand is the tip."""
    text = chain(*ARM, *fixed, joint(jaw, "hand", link, xyz="0.05 0 0"))
    a = armik.load(write_urdf(tmp_path, text))
    assert (a.tip, a.dof) == ("hand", 3)
    assert "the hand 'hand'" in a.tip_reason and f"'{jaw}'" in a.tip_reason


@pytest.mark.parametrize("jaw", ["j1", "gripper"])
def test_one_moving_joint_from_the_base_is_the_arm_not_a_jaw(tmp_path, jaw):
    """A single moving joint from the base beside a fixed leaf (a camera mount): the joint
    is the arm, its link the tip. The gripper rule took the base for a hand and its fixed
    leaf (or the base itself) for the tip: a chain with no moving joint, refused."""
    text = chain(
        joint(jaw, "base", "l1"),
        joint("l1_l2", "l1", "l2", jtype="fixed", xyz="0.3 0 0"),
        joint("cam_fixed", "base", "camera", jtype="fixed"),
    )
    a = armik.load(write_urdf(tmp_path, text))
    assert (a.tip, a.dof, a.joint_names) == ("l2", 1, [jaw])
    assert a.tip_reason.endswith("(1 moving joint)"), a.tip_reason  # not "1 moving joints"


def test_a_finger_robot_keeps_its_last_joint(tmp_path):
    """'finger' names no jaw: a finger robot's last joint is part of its chain."""
    text = chain(*ARM, joint("finger_lower_joint", "hand", "finger_lower_link"))
    a = armik.load(write_urdf(tmp_path, text))
    assert (a.tip, a.dof) == ("finger_lower_link", 4)
    assert "(4 moving joints)" in a.tip_reason, a.tip_reason


def test_a_jaw_with_a_joint_below_is_part_of_the_arm(tmp_path):
    """A 'jaw' followed by another moving joint is more arm: the longest chain wins."""
    text = chain(
        *ARM,
        joint("tcp_fixed", "hand", "tcp", jtype="fixed"),
        joint("j4", "hand", "l4"),
        joint("j5", "l4", "l5"),
    )
    a = armik.load(write_urdf(tmp_path, text))
    assert (a.tip, a.dof) == ("l5", 5)


def test_tied_chains_from_two_links_still_ask(tmp_path):
    text = chain(
        joint("j1", "base", "l1"),
        joint("a", "l1", "la"),
        joint("b", "base", "l2"),
        joint("c", "l2", "lb"),
    )
    with pytest.raises(FrameError, match="pass tip="):
        armik.load(write_urdf(tmp_path, text))


@pytest.mark.parametrize(
    "relpath, tip, dof, jaw",
    [
        ("so_arm_description/urdf/so100.urdf", "gripper", 5, "gripper"),
        ("z1_description/urdf/z1.urdf", "gripperStator", 6, "jointGripper"),
        (
            "talos_data/robots/talos_left_arm.urdf",
            "gripper_left_base_link",
            6,  # arm_left_2 to 7: its file starts at arm_left_1_link
            "gripper_left_joint",
        ),
    ],
)
def test_arms_whose_jaw_hangs_from_the_hand_drive_the_hand(relpath, tip, dof, jaw):
    """example-robot-data's SO-100 (no tool frame: the 'gripper' link holds the fixed jaw),
    Z1 and TALOS arm: the gripper joint is off the arm, as the catalogue's Z1 and the
    several-tips TALOS examples choose it."""
    path = _erd_robot_dir() / relpath
    if not path.exists():
        pytest.skip(f"this example-robot-data has no {path}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", armik.ArmikWarning)
        a = armik.load(path)
    assert (a.tip, a.dof) == (tip, dof)
    assert jaw not in a.joint_names and f"'{jaw}'" in a.tip_reason


def test_the_so101_drives_its_tool_frame():
    """example-robot-data's SO-101: five arm joints to gripper_frame_link; the jaw is off."""
    path = _erd_robot_dir() / "so_arm_description" / "urdf" / "so101.urdf"
    if not path.exists():
        pytest.skip(f"this example-robot-data has no SO-101 at {path}")
    a = armik.load(path)
    assert (a.tip, a.dof) == ("gripper_frame_link", 5)
    assert "gripper" not in a.joint_names and "'gripper'" in a.tip_reason
