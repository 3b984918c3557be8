"""SRDF files read as MoveIt reads them: the pairs each element exempts, checked against
the pairs the self-collision check then measures."""

from __future__ import annotations

import pytest

import armik
from armik.constraints.collision import arm_geometry

from ..conftest import arm

CHAIN = ("base_link", "shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link",
         "wrist_2_link", "wrist_3_link")  # fmt: skip


def _pairs(a) -> set[tuple[str, str]]:
    g = arm_geometry(a.kinematics)
    return {tuple(sorted((g.links[i], g.links[j]))) for i, j in g.self_pairs}


def _srdf(tmp_path, body: str):
    path = tmp_path / "ur5.srdf"
    path.write_text(f'<?xml version="1.0"?>\n<robot name="ur5">\n{body}\n</robot>\n')
    return path


def test_a_link_without_default_collisions_keeps_only_its_enabled_pairs(tmp_path):
    every = _pairs(arm("ur5"))
    with_wrist = {p for p in every if "wrist_3_link" in p}
    assert ("base_link", "wrist_3_link") in with_wrist and len(with_wrist) > 2
    path = _srdf(
        tmp_path,
        '<disable_default_collisions link="wrist_3_link"/>\n'
        '<enable_collisions link1="wrist_3_link" link2="base_link"/>\n'
        '<enable_collisions link1="forearm_link" link2="wrist_3_link"/>\n'
        '<disable_collisions link1="forearm_link" link2="wrist_3_link" reason="Never"/>',
    )
    a = armik.load("ur5", srdf=path)
    # enabled again: base_link; enabled and disabled: disabled, as MoveIt's matrix sets it last
    assert {p for p in _pairs(a) if "wrist_3_link" in p} == {("base_link", "wrist_3_link")}
    assert {p for p in _pairs(a) if "wrist_3_link" not in p} == every - with_wrist
    # the exempt pairs are never the closest measured, wherever the wrist folds
    for q in a.random_q(3, n=30):
        pair = a.min_distance(q, self_collision=True)[1]
        assert "wrist_3_link" not in pair or pair == ("base_link", "wrist_3_link")


def test_names_are_read_without_their_spaces_and_only_the_robots_children(tmp_path):
    path = _srdf(
        tmp_path,
        '<disable_collisions link1=" base_link " link2="forearm_link\n"/>\n'
        '<group name="arm"><disable_collisions link1="base_link" link2="wrist_1_link"/></group>',
    )
    pairs = _pairs(armik.load("ur5", srdf=path))
    assert ("base_link", "forearm_link") not in pairs
    assert ("base_link", "wrist_1_link") in pairs  # inside a <group>: no pair MoveIt reads


@pytest.mark.parametrize(
    "body, named",
    [
        ('<disable_default_collisions link="gripper"/>', "<disable_default_collisions> names"),
        ('<enable_collisions link1="base_link" link2="elbow"/>', "<enable_collisions> names"),
        ("<disable_default_collisions/>", "names link None"),
    ],
)
def test_an_unknown_link_of_any_element_is_named(tmp_path, body, named):
    with pytest.raises(armik.CollisionError) as info:
        armik.load("ur5", srdf=_srdf(tmp_path, body))
    assert named in str(info.value) and "not a link of the URDF" in str(info.value)


@pytest.mark.parametrize("pairs", [[("base_link",)], ["ab"], [3]])
def test_write_srdf_refuses_what_is_no_pair_of_links(tmp_path, pairs):
    with pytest.raises(armik.CollisionError, match="pairs of link names"):
        armik.collision.write_srdf(pairs, tmp_path / "x.srdf")


@pytest.mark.parametrize("pairs", [None, 5, "ab"])
def test_write_srdf_refuses_what_is_no_list_of_pairs(tmp_path, pairs):
    with pytest.raises(armik.CollisionError, match="a list of pairs of link names"):
        armik.collision.write_srdf(pairs, tmp_path / "x.srdf")
    assert not (tmp_path / "x.srdf").exists()


def test_write_srdf_names_a_path_it_cannot_write(tmp_path):
    with pytest.raises(armik.CollisionError, match="cannot write the SRDF .*no/such/folder"):
        armik.collision.write_srdf([("base_link", "elbow")], tmp_path / "no/such/folder/x.srdf")
    for path in (None, 3):  # 3 would be a file descriptor to open
        with pytest.raises(armik.CollisionError, match="path must be a file path"):
            armik.collision.write_srdf([("base_link", "elbow")], path)


def test_never_colliding_pairs_refuses_a_seed_that_is_no_whole_number():
    with pytest.raises(armik.CollisionError, match="seed must be a whole number"):
        armik.collision.never_colliding_pairs(arm("ur5"), n=3, seed="x")
