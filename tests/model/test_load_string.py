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


XACRO = """<?xml version="1.0"?><robot name="xa" xmlns:xacro="http://www.ros.org/wiki/xacro">
<xacro:macro name="tool" params="parent"><link name="tool"/>
<joint name="tj" type="fixed"><parent link="${parent}"/><child link="tool"/>
<origin xyz="0 0 0.2"/></joint></xacro:macro>
<link name="base"/><link name="l1"/><link name="l2"/>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0"/>
<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
<xacro:tool parent="l2"/>
</robot>"""


def test_xacro_text_is_refused_with_the_way_to_expand_it(tmp_path):
    """load_string reads plain URDF: a xacro text is refused naming the way to expand it,
    where its macros were skipped as urdfdom skips unknown tags (no 'tool' link: another
    tip, silently) and its ${...} was refused as a number alone."""
    with pytest.raises(URDFError, match=r"is xacro \(<xacro:\.\.\.> tags\): load_string reads"):
        armik.load_string(XACRO)
    with pytest.raises(URDFError, match=r"is xacro"):
        armik.load(XACRO)  # the text given to load: the same reader
    start, end = XACRO.index("<xacro:macro"), XACRO.index("</xacro:macro>") + 14
    expression = (XACRO[:start] + XACRO[end:]).replace('<xacro:tool parent="l2"/>', "")
    expression = expression.replace("0.3 0 0", "${0.1*3} 0 0")
    with pytest.raises(URDFError, match=r"'\$\{0.1\*3\}' is not a finite number.*holds xacro's"):
        armik.load_string(expression)
    # in comments, or with the prefix undeclared, the tags are no xacro: plain URDF
    commented = XACRO.replace(XACRO[start:end], f"<!-- {XACRO[start:end]} -->")
    commented = commented.replace('<xacro:tool parent="l2"/>', '<!-- <xacro:tool parent="l2"/> -->')
    assert armik.load_string(commented).tip == "l2"
    plain = XACRO.replace(' xmlns:xacro="http://www.ros.org/wiki/xacro"', "")
    with pytest.warns(armik.ArmikWarning, match="without xmlns:xacro declared"):
        assert armik.load_string(plain).tip == "l2"
    path = tmp_path / "arm.urdf.xacro"  # a file: expanded (the xacro package installed)
    path.write_text(XACRO)
    assert armik.load(str(path)).tip == "tool"
