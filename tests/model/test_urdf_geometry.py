"""``<collision>`` elements urdfdom cannot read (it logs them and drops the shape, so an
obstacle through the link was no collision) are refused when the URDF is read, naming the
link, the value and the fix; well-formed ones load and are seen by the checks."""

from __future__ import annotations

import pytest

import armik
from armik.errors import URDFError

JOINT = (
    '<joint name="{0}" type="revolute"><parent link="{1}"/><child link="{2}"/>'
    '<origin xyz="{3}"/><axis xyz="0 0 1"/>'
    '<limit lower="-2" upper="2" effort="1" velocity="1"/></joint>'
)
GOOD = '<box size="0.3 0.05 0.05"/>'


def two_links(shape: str, version: str = "") -> str:
    def link(name: str, geometry: str) -> str:
        return (
            f'<link name="{name}"><collision><origin xyz="0.15 0 0"/>'
            f"<geometry>{geometry}</geometry></collision></link>"
        )

    return (
        f'<robot name="r"{version}><link name="l0"/>'
        + link("l1", shape)
        + link("l2", GOOD)
        + JOINT.format("j1", "l0", "l1", "0 0 0")
        + JOINT.format("j2", "l1", "l2", "0.3 0 0")
        + "</robot>"
    )


@pytest.mark.parametrize(
    "shape, words",
    [
        ('<box size="0.3 0.05"/>', "box size='0.3 0.05': expected 3 numbers"),
        ('<cylinder radius="0.05"/>', "<cylinder> without length"),
        ('<sphere radius="x"/>', "sphere radius='x'"),
        ("<sphere/>", "<sphere> without radius"),
        ("<mesh/>", "<mesh> without filename"),
        ('<mesh filename="a.stl" scale="1 1"/>', "mesh scale='1 1'"),
        ("", "without a shape in its <geometry>"),
        ('<cone radius="0.1" length="0.1"/>', "shape <cone>"),
        ('<capsule radius="0.05" length="0.3"/>', 'needs <robot version="1.1">'),
    ],
)
def test_a_collision_shape_urdfdom_drops_is_refused_naming_the_link(shape, words):
    with pytest.raises(URDFError, match="link 'l1'") as info:
        armik.load_string(two_links(shape))
    assert words in str(info.value)


def test_well_formed_collision_shapes_load_and_are_seen():
    ball = armik.Sphere(center=(0.15, 0.0, 0.0), radius=0.05)  # through l1 at q1 = 0
    arm = armik.load_string(two_links(GOOD))
    assert arm.in_collision([0.0, 1.0], obstacles=[ball])
    assert not arm.in_collision([1.5, 1.0], obstacles=[ball])
    for shape in ('<cylinder radius="0.05" length="0.3"/>', '<sphere radius="0.1"/>'):
        assert armik.load_string(two_links(shape)).in_collision([0.0, 1.0], obstacles=[ball])
    capsule = '<capsule radius="0.05" length="0.3"/>'
    assert armik.load_string(two_links(capsule, ' version="1.1"')).dof == 2
