"""The tip chosen when none is given: a gripper's tool frame beats its moving jaw."""

from __future__ import annotations

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
    """Two fixed leaves on the hand: no single tool frame, the old rules decide."""
    text = chain(
        *ARM,
        joint("tcp_fixed", "hand", "tcp", jtype="fixed"),
        joint("cam_fixed", "hand", "camera", jtype="fixed"),
        joint("jaw", "hand", "jaw_link"),
    )
    a = armik.load(write_urdf(tmp_path, text))
    assert (a.tip, a.dof) == ("jaw_link", 4)


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


def test_the_so101_drives_its_tool_frame():
    """example-robot-data's SO-101: five arm joints to gripper_frame_link; the jaw is off."""
    path = _erd_robot_dir() / "so_arm_description" / "urdf" / "so101.urdf"
    if not path.exists():
        pytest.skip(f"this example-robot-data has no SO-101 at {path}")
    a = armik.load(path)
    assert (a.tip, a.dof) == ("gripper_frame_link", 5)
    assert "gripper" not in a.joint_names and "'gripper'" in a.tip_reason
