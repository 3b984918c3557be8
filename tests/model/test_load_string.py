"""URDFs given as text (ROS 2's robot_description): load_string, and load given XML."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import armik
from armik.errors import FrameError, OptionError, URDFError

from ..conftest import arm


@pytest.fixture(scope="module")
def ur5_xml() -> str:
    return open(arm("ur5").source).read()


def test_text_loads_as_the_file_does(ur5_xml):
    from_file = armik.load(arm("ur5").source)
    for a in (armik.load_string(ur5_xml), armik.load("\n  " + ur5_xml)):
        assert a.joint_names == from_file.joint_names
        assert (a.tip, a.tip_reason, a.name) == (from_file.tip, from_file.tip_reason, "ur5")
        assert a.source == "<string>"
        q = a.random_q(np.random.default_rng(1))
        np.testing.assert_array_equal(a.fk(q).homogeneous, from_file.fk(q).homogeneous)
        assert a.solve(a.fk(q)).success


def test_text_takes_the_load_arguments_and_pickles_with_them(ur5_xml):
    a = armik.load_string(
        ur5_xml, base="base_link", tip="wrist_3_link", tip_offset=(0, 0, 0.1)
    ).with_limits({"shoulder_pan_joint": (-1.0, 1.0)})
    b = pickle.loads(pickle.dumps(a))
    assert (b.base, b.tip, b.kinematics.tip_offset) == (
        "base_link",
        "wrist_3_link",
        (0.0, 0.0, 0.1),
    )
    assert b.lower[0] == -1.0 and b.upper[0] == 1.0
    q = a.random_q(np.random.default_rng(2))
    np.testing.assert_array_equal(a.fk(q).homogeneous, b.fk(q).homogeneous)


def test_bad_text_and_names_are_one_line_armik_errors(ur5_xml):
    with pytest.raises(URDFError, match="not well-formed XML"):
        armik.load("<robot name='r'><link name='a'/>")
    with pytest.raises(URDFError, match="the URDF's text"):
        armik.load_string(b"<robot/>")
    with pytest.raises(URDFError, match="neither a bundled robot nor|neither a bundled robot"):
        armik.load("x" * 5000)  # too long a name for the file system: no OSError
    with pytest.raises(URDFError, match="does not exist"):
        armik.load("/no/such/robot.urdf")
    with pytest.raises(FrameError, match="unknown tip frame 'hand'"):
        armik.load_string(ur5_xml, tip="hand")
    with pytest.raises(OptionError, match="not an existing folder"):
        armik.load_string(ur5_xml, package_dirs=["/no/such/folder"])


def test_package_dirs_are_kept(tmp_path, ur5_xml):
    a = armik.load_string(ur5_xml, package_dirs=[tmp_path])
    assert a.kinematics.package_dirs == (str(tmp_path.resolve()),)
    assert pickle.loads(pickle.dumps(a)).kinematics.package_dirs == a.kinematics.package_dirs
    assert armik.load("ur5").kinematics.package_dirs == ()


def test_a_path_given_as_the_text_points_to_load(tmp_path):
    """load_string(path): the path named as a path and armik.load as the fix, not the XML
    blamed; a missing file too when its name ends in .urdf."""
    source = arm("ur5").source
    for given in (source, str(tmp_path / "robot.urdf"), "arm.xacro"):
        with pytest.raises(URDFError, match="a file's path, not the URDF's XML") as info:
            armik.load_string(given)
        assert f"armik.load({given!r})" in str(info.value)
        assert "\n" not in str(info.value)
    with pytest.raises(URDFError, match="not well-formed XML"):
        armik.load_string("robot")  # neither XML nor a path: the XML is what is wrong
