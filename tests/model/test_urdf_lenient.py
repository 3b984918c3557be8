"""URDFs as ROS reads them: what urdfdom's lenient XML parser (TinyXML2) accepts, armik
reads the same way with a warning naming the line; what it refuses, armik refuses.
Pinocchio (``buildModelFromXML``, urdfdom underneath) is the oracle."""

from __future__ import annotations

import re
import warnings
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import ArmikWarning, URDFError
from armik.model import urdf as urdf_mod
from armik.model.urdf import read_urdf_string, urdf_text

from ..conftest import write_urdf

LIMIT = 'effort="1" velocity="1"'

# line 3 holds the marker each case replaces; j3 is on lines 20-24, </robot> on 29
ARM = f"""<?xml version="1.0"?>
<robot name="lenient">
  <!-- LINE3 -->
  <link name="base"/>
  <link name="l1"/>
  <link name="l2"/>
  <link name="l3"/>
  <link name="tool"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" {LIMIT}/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" {LIMIT}/>
  </joint>
  <!-- J3 -->
  <joint name="j3" type="prismatic">
    <parent link="l2"/><child link="l3"/>
    <origin xyz="0.25 0 0"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.5" {LIMIT}/>
  </joint>
  <!-- J3 END -->
  <joint name="tool_joint" type="fixed">
    <parent link="l3"/><child link="tool"/><origin xyz="0.1 0 0"/>
  </joint>
</robot>
"""
assert ARM.splitlines()[2].strip() == "<!-- LINE3 -->"
assert ARM.splitlines()[19].strip() == '<joint name="j3" type="prismatic">'


def case(*pairs: tuple[str, str]) -> str:
    text = ARM
    for old, new in pairs:
        assert old in text
        text = text.replace(old, new)
    return text


LENIENT = {
    "nested comment": (
        case(("<!-- LINE3 -->", "<!-- old base <!-- was here --> kept -->")),
        "line 3: a comment nested in a comment",
    ),
    # the inner --> ends the comment for urdfdom: j3 is live, in Pinocchio and in armik
    "nested comment around a joint": (
        case(("<!-- J3 -->", "<!-- off <!-- note -->"), ("<!-- J3 END -->", "-->")),
        "line 19: a comment nested in a comment",
    ),
    "dashes in a comment": (
        case(("<!-- LINE3 -->", "<!-- ---------- arm ---------- -->")),
        "line 3: '--' inside a comment",
    ),
    "dashes in two comments": (
        case(("<!-- LINE3 -->", "<!-- a -- b -->"), ("<!-- J3 -->", "<!-- prismatic --->")),
        "lines 3, 19: '--' inside a comment",
    ),
    "undeclared xacro element": (
        case(("<!-- LINE3 -->", '<xacro:property name="reach" value="0.3"/>')),
        r"line 3: the prefix 'xacro' is used without xmlns:xacro declared \(<xacro:property>\)",
    ),
    "undeclared xacro attribute": (
        case(('<joint name="j2"', '<joint xacro:note="elbow" name="j2"')),
        r"line 14: the prefix 'xacro' is used without xmlns:xacro declared \(xacro:note\)",
    ),
    # urdfdom never reads a prefixed element, nor the link inside (else two root links)
    "undeclared prefix around a link": (
        case(("<!-- LINE3 -->", '<foo:group><link name="ghost"/></foo:group>')),
        "line 3: the prefix 'foo' is used",
    ),
    "bare ampersand": (
        case(('<robot name="lenient">', '<robot name="R&D arm">')),
        "line 2: a bare '&' or an undefined entity",
    ),
    "less-than in a value": (
        case(('<joint name="j2"', '<joint name="j<2"')),
        "line 14: a '<' inside an attribute value",
    ),
}


def pin_joints(model: pin.Model) -> list[tuple]:
    """Each joint's name, type, limits and placement, in the model's order."""
    out = []
    for j in range(1, model.njoints):
        i, n = model.idx_qs[j], model.nqs[j]
        out.append(
            (
                model.names[j],
                model.joints[j].shortname(),
                tuple(model.lowerPositionLimit[i : i + n]),
                tuple(model.upperPositionLimit[i : i + n]),
                tuple(np.round(model.jointPlacements[j].homogeneous.ravel(), 12)),
            )
        )
    return out


@pytest.mark.parametrize("name", list(LENIENT))
def test_what_urdfdom_reads_armik_reads_the_same(name):
    text, message = LENIENT[name]
    with pytest.raises(ET.ParseError):
        ET.fromstring(text)  # the strict parser refuses each of them
    oracle = pin.buildModelFromXML(text)
    with pytest.warns(ArmikWarning, match=re.escape("'<string>', ") + message):
        model, info = read_urdf_string(text)
    assert pin_joints(model) == pin_joints(oracle)
    assert any(re.search(message, note) for note in info.notes)  # armik info shows it
    assert info.name == oracle.name
    with pytest.warns(ArmikWarning):
        arm = armik.load_string(text)
    moving = [j for j in pin_joints(oracle) if j[1] != "JointModelFixed"]
    assert arm.joint_names == [j[0] for j in moving]
    np.testing.assert_array_equal(arm.lower, [j[2][0] for j in moving])
    np.testing.assert_array_equal(arm.upper, [j[3][0] for j in moving])
    assert arm.joint_types == ["revolute", "revolute", "prismatic"]
    assert arm.tip == "tool"
    q = np.array([0.3, -0.4, 0.2])
    data = oracle.createData()
    pin.framesForwardKinematics(oracle, data, q)
    T = data.oMf[oracle.getFrameId("tool")].homogeneous
    np.testing.assert_allclose(arm.fk(q).homogeneous, T, atol=1e-12)


def test_the_text_armik_keeps_is_well_formed():
    text = case(
        ("<!-- LINE3 -->", '<!-- a <!-- b --> c --><xacro:property name="x" value="1"/>'),
        ('<robot name="lenient">', '<robot name="R&D" xacro:a="1">'),
    )
    with pytest.warns(ArmikWarning):
        _, info = read_urdf_string(text)
    root = ET.fromstring(info.text)  # collision geometry is read from this text
    assert root.get("name") == "R&D" and not root.findall(".//{*}property")
    assert not any(key.startswith("{") for key in root.attrib)


def test_a_file_with_undeclared_xacro_tags_is_plain_urdf(tmp_path):
    """xacro itself refuses <xacro:...> without xmlns:xacro; urdfdom ignores the tags."""
    text = case(("<!-- LINE3 -->", '<xacro:property name="reach" value="0.3"/>'))
    path = write_urdf(tmp_path, text)
    with pytest.warns(ArmikWarning, match="line 3: the prefix 'xacro'"):
        arm = armik.load(path)
    assert arm.joint_names == ["j1", "j2", "j3"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # said when the arm was loaded: not again
        shown = urdf_text(path)  # the viewer's text
    assert ET.fromstring(shown).find("link").get("name") == "base"


def test_well_formed_files_take_the_strict_path_only(monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("the lenient reading ran on a well-formed file")

    monkeypatch.setattr(urdf_mod, "forgiving_parse", never)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ArmikWarning)
        model, info = read_urdf_string(ARM)
    assert info.text == ARM  # given to Pinocchio as written
    assert [j[0] for j in pin_joints(model)] == ["j1", "j2", "j3"]


REFUSED = {
    "mismatched tag": (case(("</robot>", "</robbot>")), r"mismatched tag: line 29"),
    # a forgiven comment does not hide the real error, nor shift its line
    "mismatched tag after a forgiven comment": (
        case(("<!-- LINE3 -->", "<!-- a -- b -->"), ("  </joint>\n  <!-- J3 END", "  </jont>\n")),
        r"mismatched tag: line 24",
    ),
    "unclosed comment": (case(("<!-- J3 END -->", "<!-- J3 END")), r"unclosed token: line 25"),
    "unclosed tag": (ARM.replace("</robot>", ""), r"no element found: line 30"),
    "duplicate attribute": (
        case(('<joint name="j2"', '<joint name="j2" name="k2"')),
        r"duplicate attribute: line 14",
    ),
}


@pytest.mark.parametrize("name", list(REFUSED))
def test_what_urdfdom_refuses_armik_refuses(name):
    text, message = REFUSED[name]
    with pytest.raises(ValueError, match="does not contain a valid URDF"):
        pin.buildModelFromXML(text)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ArmikWarning)  # nothing forgiven is said to be
        with pytest.raises(URDFError, match=r"not well-formed XML \(" + message):
            armik.load_string(text)


def test_a_nested_comment_can_make_a_file_urdfdom_refuses():
    # the inner --> ends the comment: the 'hidden' link is live, a second root link
    text = case(("<!-- LINE3 -->", '<!-- <!-- old --> <link name="spare"/> -->'))
    with pytest.raises(ValueError, match="does not contain a valid URDF"):
        pin.buildModelFromXML(text)
    with pytest.warns(ArmikWarning, match="line 3: a comment nested"):
        with pytest.raises(URDFError, match="exactly one root link.*'spare'"):
            read_urdf_string(text)
