"""A URDF armik cannot take: each refusal names the joint or link, the value and the fix."""

from __future__ import annotations

import pytest

import armik
from armik.errors import JointError, URDFError

LIMIT = 'lower="-2" upper="2" effort="1" velocity="1"'


def chain(*joints: tuple[str, str], extra: str = "") -> str:
    """Links l0 .. ln joined by joints j1 .. jn, each (type, the rest of its XML)."""
    parts = ['<robot name="r"><link name="l0"/>']
    for i, (kind, rest) in enumerate(joints, 1):
        parts.append(
            f'<link name="l{i}"/><joint name="j{i}" type="{kind}"><parent link="l{i - 1}"/>'
            f'<child link="l{i}"/><origin xyz="0 0 0.3"/>{rest}</joint>'
        )
    return "".join(parts) + extra + "</robot>"


def turning(axis: str = "0 1 0", limit: str = LIMIT) -> tuple[str, str]:
    return ("revolute", f'<axis xyz="{axis}"/><limit {limit}/>')


def test_a_joint_of_several_freedoms_names_the_base_or_tip_that_leaves_it_out():
    """A floating joint under the arm: base= the link below it, which then loads; a planar
    joint within the chain: that base, or tip= the link above it."""
    text = chain(("floating", ""), turning(), turning("1 0 0"), turning("0 0 1"))
    with pytest.raises(JointError, match=r"'j1' \(floating, JointModelFreeFlyer\)") as info:
        armik.load_string(text, tip="l4")
    assert str(info.value).endswith("base='l1'")
    assert armik.load_string(text, base="l1", tip="l4").joint_names == ["j2", "j3", "j4"]
    text = chain(turning(), ("planar", '<axis xyz="0 0 1"/>'), turning("1 0 0"))
    with pytest.raises(JointError, match="'j2' \\(planar.*base='l2', or .* tip='l1'"):
        armik.load_string(text, tip="l3")


@pytest.mark.parametrize(
    "extra, words",
    [
        ('<link name="stray"/>', "link 'stray' is in no joint; remove it, or attach it"),
        ('<link name="a"/><link name="b"/>', "links 'a', 'b' are in no joint; remove them"),
        (
            '<link name="m0"/><link name="m1"/><joint name="k" type="fixed">'
            '<parent link="m0"/><child link="m1"/></joint>',
            "found ['l0', 'm0'], each the root of its own tree: join them with a joint",
        ),
    ],
)
def test_two_root_links_name_them_and_what_to_do(extra, words):
    with pytest.raises(URDFError, match="exactly one root link") as info:
        armik.load_string(chain(turning(), turning(), extra=extra), tip="l2")
    assert words in str(info.value)


@pytest.mark.parametrize("key", ["velocity", "effort"])
def test_a_negative_velocity_or_effort_limit_is_named(key):
    """Pinocchio refuses it without naming the joint ("min_velocity are greater than
    max_velocity"); on a fixed joint, which Pinocchio builds, it stays as it was."""
    limit = LIMIT.replace(f'{key}="1"', f'{key}="-1"')
    with pytest.raises(URDFError) as info:
        armik.load_string(chain(turning(), turning("1 0 0", limit)), tip="l2")
    text = str(info.value)
    assert "joint 'j2'" in text and f'<limit {key}="-1"> is negative' in text
    assert "without the minus sign" in text and "Pinocchio" not in text
    fixed = chain(turning(), turning("1 0 0"), ("fixed", f"<limit {limit}/>"))
    assert armik.load_string(fixed, tip="l3").dof == 2


def test_a_joint_without_a_type_says_the_attribute_is_missing():
    text = chain(turning(), turning()).replace('name="j2" type="revolute"', 'name="j2"')
    with pytest.raises(URDFError, match="joint 'j2' in '<string>' has no type attribute") as info:
        armik.load_string(text, tip="l2")
    assert 'type="revolute"' in str(info.value) and "None" not in str(info.value)
