"""Collision checking: distances against an independent coal model, the pairs, SRDFs."""

from __future__ import annotations

import pickle
import re

import coal
import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.constraints.bounds import PREFIX
from armik.constraints.collision import arm_geometry, checker
from armik.model.catalogue import erd_share

from ..conftest import arm, model, write_urdf

TABLE = armik.HalfSpace((0, 0, 1), 0)
BOX = armik.Box((0.2, 0.3, 0.4), (0.45, 0.1, 0.2))
SPHERE = armik.Sphere(0.1, (0.3, -0.3, 0.5))


def _independent(a: armik.Arm, locked: dict):
    """The whole URDF's model and collision geometry, meshes as hulls, built here."""
    full = pin.buildModelFromUrdf(a.kinematics.source)
    geom = pin.buildGeomFromUrdf(
        full, a.kinematics.source, pin.COLLISION, package_dirs=[erd_share()]
    )
    hulls = []
    for o in geom.geometryObjects:
        if isinstance(o.geometry, coal.BVHModelBase):
            o.geometry.buildConvexHull(True, "Qt")
            hulls.append(o.geometry.convex)
        else:
            hulls.append(o.geometry)
    q_full = pin.neutral(full)
    for name, value in locked.items():
        q_full[full.joints[full.getJointId(name)].idx_q] = value
    return full, geom, hulls, q_full


def _distance(g1, T1: pin.SE3, g2, T2: pin.SE3) -> float:
    return coal.distance(
        g1,
        coal.Transform3s(T1.rotation, T1.translation),
        g2,
        coal.Transform3s(T2.rotation, T2.translation),
        coal.DistanceRequest(),
        coal.DistanceResult(),
    )


@pytest.mark.parametrize("name, locked", [("ur5", {}), ("panda", {"panda_finger_joint1": 0.03})])
def test_obstacle_distances_match_an_independent_coal_model(name, locked):
    a = armik.load(name, locked=locked)
    full, geom, hulls, q_full = _independent(a, locked)
    data = full.createData()
    shapes = (BOX, SPHERE)
    for q in a.random_q(7, n=15):
        for jname, value in zip(a.joint_names, q):
            q_full[full.joints[full.getJointId(jname)].idx_q] = value
        pin.forwardKinematics(full, data, q_full)
        pin.updateGeometryPlacements(full, data, geom, geom.createData())
        best = np.inf
        for o, hull in zip(geom.geometryObjects, hulls):
            if o.parentJoint == 0:
                continue  # fixed links: checked once, not per configuration
            T = data.oMi[o.parentJoint] * o.placement
            for s in shapes:
                best = min(best, _distance(hull, T, s.geometry(), s.placement()))
        d, pair = a.min_distance(q, obstacles=shapes)
        assert d == pytest.approx(best, abs=1e-9)
        assert pair[1].startswith("obstacles[")


def test_self_distances_match_an_independent_coal_model():
    a = arm("ur5")
    full, geom, hulls, q_full = _independent(a, {})
    g = arm_geometry(a.kinematics)
    data = full.createData()
    for q in a.random_q(3, n=10):
        pin.forwardKinematics(full, data, q)
        T = [data.oMi[o.parentJoint] * o.placement for o in geom.geometryObjects]
        expected = min(_distance(hulls[i], T[i], hulls[j], T[j]) for i, j in g.self_pairs)
        d, pair = a.min_distance(q, self_collision=True)
        assert d == pytest.approx(expected, abs=1e-6)  # EPA depths: to its tolerance
        assert pair[0] in g.links and pair[1] in g.links


def _link_pairs(a, which="self_pairs"):
    g = arm_geometry(a.kinematics)
    return {tuple(sorted((g.links[i], g.links[j]))) for i, j in getattr(g, which)}


def test_adjacent_and_rigidly_joined_links_are_not_pairs():
    ur5 = _link_pairs(arm("ur5"))
    chain = ["base_link", "shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link",
             "wrist_2_link", "wrist_3_link"]  # fmt: skip
    for a, b in zip(chain, chain[1:]):
        assert tuple(sorted((a, b))) not in ur5
    assert ("base_link", "forearm_link") in ur5
    panda = _link_pairs(arm("panda"))
    assert ("panda_hand", "panda_link7") not in panda  # joined by fixed joints
    assert ("panda_hand", "panda_link6") not in panda  # across joint 7
    assert ("panda_leftfinger", "panda_rightfinger") not in panda  # fingers locked: rigid
    assert ("panda_hand", "panda_link5") in panda


def test_an_srdf_disables_its_pairs_and_the_arm_pickles_with_it(tmp_path):
    path = tmp_path / "ur5.srdf"
    armik.collision.write_srdf([("base_link", "forearm_link")], path, robot="ur5")
    a = armik.load("ur5", srdf=path)
    assert ("base_link", "forearm_link") not in _link_pairs(a)
    assert ("base_link", "forearm_link") in _link_pairs(a, "candidates")
    assert len(_link_pairs(a)) == len(_link_pairs(arm("ur5"))) - 1
    copy = pickle.loads(pickle.dumps(a))
    assert (
        copy.kinematics.disabled_pairs
        == a.kinematics.disabled_pairs
        == {("base_link", "forearm_link")}
    )
    # a configuration folding the forearm onto the base: the pair is no longer reported
    for q in a.random_q(5, n=50):
        assert a.min_distance(q, self_collision=True)[1] != ("base_link", "forearm_link")


def test_srdf_errors_name_the_file_and_the_link(tmp_path):
    with pytest.raises(armik.CollisionError, match="not an existing file"):
        armik.load("ur5", srdf=tmp_path / "missing.srdf")
    bad = tmp_path / "bad.srdf"
    armik.collision.write_srdf([("base_link", "elbow")], bad)
    with pytest.raises(armik.CollisionError, match="'elbow'"):
        armik.load("ur5", srdf=bad)


def test_never_colliding_pairs_round_trip_through_an_srdf(tmp_path):
    a = arm("ur5")
    never = armik.collision.never_colliding_pairs(a, n=200)
    assert never and set(never) <= _link_pairs(a, "candidates")
    path = tmp_path / "never.srdf"
    armik.collision.write_srdf(never, path)
    b = armik.load("ur5", srdf=path)
    assert _link_pairs(b) == _link_pairs(a) - set(never)


def test_in_collision_and_margin():
    a = arm("ur5")
    q = a.random_q(11)
    d, _ = a.min_distance(q, obstacles=[BOX])
    assert a.in_collision(q, [BOX]) == (d < 0)
    assert a.in_collision(q, [BOX], margin=d + 1e-3)
    assert not a.in_collision(q, [BOX], margin=d - 1e-3) or d - 1e-3 < 0


@pytest.mark.parametrize("margin", [None, "1cm", float("nan"), -0.01, 10**400])
def test_in_collision_refuses_a_margin_that_is_no_distance(margin):
    # a NaN said "clear" of any overlap, a negative margin allowed one; None a TypeError
    a = arm("ur5")
    q = a.random_q(11)
    with pytest.raises(armik.OptionError, match="margin must be a distance"):
        a.in_collision(q, [BOX], margin=margin)


@pytest.mark.parametrize("flag", ["no", 1, None])
def test_min_distance_refuses_a_self_collision_that_is_no_bool(flag):
    # "no" read as true measured the self-collision pairs; as the constraint refuses it
    a = arm("ur5")
    with pytest.raises(armik.OptionError, match="self_collision must be True or False"):
        a.min_distance(a.middle, [BOX], self_collision=flag)
    with pytest.raises(armik.OptionError, match="self_collision must be True or False"):
        a.in_collision(a.middle, [BOX], self_collision=flag)


def test_a_table_under_the_base_is_accepted_an_obstacle_through_it_is_refused():
    a = arm("ur5")
    a.min_distance(a.middle, obstacles=[TABLE])  # the base sits 3 mm into its table
    with pytest.raises(armik.CollisionError, match="base_link.*never moves"):
        a.min_distance(a.middle, obstacles=[armik.Box((0.3, 0.3, 0.3))])


def test_an_arm_without_collision_geometry_says_so():
    a = arm("planar_2link")
    with pytest.raises(armik.CollisionError, match="no <collision> geometry"):
        a.solve([1.2, 0.5], obstacles=[armik.Sphere(0.1, (5, 5, 0))])
    with pytest.raises(armik.CollisionError, match="no <collision> geometry"):
        a.min_distance([0.0, 0.0], self_collision=True)


def test_an_arm_whose_moving_links_have_no_geometry_says_so(tmp_path):
    # geometry on the base alone: no pair a solve could keep apart, so a ball the upper
    # link passes through is refused by name, not called collision-free
    base = '<link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry>'
    text = _BARE_BASE_URDF.replace('<link name="base"/>', base + "</collision></link>")
    for link in ("l1", "l2", "l3"):
        text = re.sub(
            rf'<link name="{link}">.*?</link>', f'<link name="{link}"/>', text, flags=re.S
        )
    a = armik.load(write_urdf(tmp_path, text), tip="tool")
    ball = armik.Sphere(0.1, (0.0, 0.0, 0.55))
    with pytest.raises(armik.CollisionError, match=r"only on links that never move .*\(base\)"):
        a.solve(a.fk(a.middle).translation, obstacles=[ball])
    with pytest.raises(armik.CollisionError, match="only on links that never move"):
        a.min_distance(a.middle, self_collision=True)
    robot = armik.load(write_urdf(tmp_path, text), tips=["tool"])
    with pytest.raises(armik.CollisionError, match=r"only on links that never move .*\(base\)"):
        robot.min_distance(robot.middle, [ball])


def test_the_pairs_come_smallest_bound_first():
    a = model("panda")
    ch = checker(a, (TABLE, BOX, SPHERE), True)
    for q in a.random_q(5, n=20):
        bound, order, m = ch._ordered(q)
        assert m == min(PREFIX, len(bound)) and sorted(order.tolist()) == list(range(len(bound)))
        head = [(bound[k], k) for k in order[:m]]
        assert head == sorted(head)  # in order, ties in pair order
        assert (bound[order[m:]] >= bound[order[m - 1]]).all()


def test_a_check_past_the_ordered_pairs_still_finds_the_closest(monkeypatch):
    # none in order: every pair is looked at, none skipped wrongly
    a = model("panda")
    ch = checker(a, (TABLE, BOX), True)
    gd = pin.GeometryData(ch.model)
    ordered = ch._ordered
    monkeypatch.setattr(ch, "_ordered", lambda q: (*ordered(q)[:2], 0))
    for q in a.random_q(6, n=10):
        pin.updateGeometryPlacements(a.model, a.data, ch.model, gd, a.to_pin(q))
        k = pin.computeDistances(ch.model, gd)
        d, pair = ch.distance(q)
        assert d == pytest.approx(gd.distanceResults[k].min_distance, abs=1e-9)
        assert pair == ch.pair_names[k]


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_pair_bounds_never_exceed_coal_and_the_closest_pair_is_every_pairs(name):
    a = model(name)
    shapes = (
        TABLE,
        BOX,
        SPHERE,
        armik.Capsule(0.05, 0.3, (0.2, -0.2, 0.5)),
        armik.HalfSpace((-0.3, -1, 0), -0.5),  # oblique, its solid side away from the base
    )
    ch = checker(a, shapes, True)
    gd = pin.GeometryData(ch.model)
    for q in a.random_q(3, n=60):
        pin.updateGeometryPlacements(a.model, a.data, ch.model, gd, a.to_pin(q))
        k = pin.computeDistances(ch.model, gd)
        every = np.array([r.min_distance for r in gd.distanceResults])
        assert (every >= ch.bounds(q) - 1e-9).all()
        d, pair = ch.distance(q)
        assert d == pytest.approx(every[k], abs=1e-6) and pair == ch.pair_names[k]


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_each_capsule_holds_its_objects_points(name):
    # a capsule holding every point holds their hull: the bounds stay below coal's
    from armik.constraints.collision import _points

    a = model(name)
    g = arm_geometry(a)
    caps = checker(a, (), True)._capsule
    for o, cap in zip(g.model.geometryObjects, caps):
        p = _points(o.geometry) @ o.placement.rotation.T + o.placement.translation
        end0, end1, radius = cap[:3], cap[3:6], cap[6]
        d = end1 - end0
        s = np.clip((p - end0) @ d / max(d @ d, 1e-300), 0.0, 1.0)
        far = np.linalg.norm(p - (end0 + np.outer(s, d)), axis=1)
        assert (far <= radius).all()
        assert radius <= np.linalg.norm(p - p.mean(axis=0), axis=1).max() + 1e-9  # not loose


_LIMIT = 'effort="1" velocity="1"'
# a parallelogram's rod: a box on a link that a passive mimic joint off the chain turns
# with j2, beside the prismatic link l3 (the only two links with collision geometry)
_ROD_URDF = f"""<?xml version="1.0"?>
<robot name="rod">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="tool"/>
  <link name="l3"><collision><origin xyz="0 0 0.15"/>
    <geometry><box size="0.06 0.06 0.3"/></geometry></collision></link>
  <link name="rod"><collision><origin xyz="0 0 0.21"/>
    <geometry><box size="0.06 0.06 0.42"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" {_LIMIT}/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" {_LIMIT}/></joint>
  <joint name="j3" type="prismatic"><parent link="l2"/><child link="l3"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 0 1"/><limit lower="0" upper="0.3" {_LIMIT}/></joint>
  <joint name="tool_fix" type="fixed"><parent link="l3"/><child link="tool"/>
    <origin xyz="0 0 0.3"/></joint>
  <joint name="passive" type="revolute"><parent link="l1"/><child link="rod"/>
    <origin xyz="0.25 0 0.17"/><axis xyz="0 1 0"/><limit lower="-6" upper="6" {_LIMIT}/>
    <mimic joint="j2" multiplier="1.5" offset="-1.03"/></joint>
</robot>
"""


def test_never_colliding_pairs_place_a_passive_mimic_links_objects_by_its_driver(tmp_path):
    # sampled with the rod where its driver puts it, as every check measures it: a pair that
    # touches in the samples is not "never", or an SRDF written from it switches it off
    a = armik.load(write_urdf(tmp_path, _ROD_URDF), tip="tool")
    assert _link_pairs(a, "candidates") == {("l3", "rod")}
    touching = [q for q in a.random_q(0, n=50) if a.min_distance(q, self_collision=True)[0] < 0]
    assert touching  # the rod, turned by j2, hits l3 in some of the samples
    assert armik.collision.never_colliding_pairs(a, n=50, seed=0) == []


def test_a_passive_mimic_links_pairs_with_the_links_beside_it_are_checked(tmp_path):
    # the rod turns relative to l1 and l2 (its driver's rate times 1.5): a body of its own,
    # not welded to l1, so its pair with l2 is checked; measured against the whole model
    l2 = (
        '<link name="l2"><collision><origin xyz="0 0 0.2"/>'
        '<geometry><box size="0.06 0.06 0.4"/></geometry></collision></link>'
    )
    path = write_urdf(tmp_path, _ROD_URDF.replace('<link name="l2"/>', l2))
    a = armik.load(path, tip="tool")
    assert {("l2", "rod"), ("l3", "rod")} <= _link_pairs(a)
    full = pin.buildModelFromUrdf(str(path))
    data = full.createData()
    geom = pin.buildGeomFromUrdf(full, str(path), pin.COLLISION)
    objects = {full.frames[o.parentFrame].name: o for o in geom.geometryObjects}

    def placed(link):
        o = objects[link]
        M = data.oMi[o.parentJoint] * o.placement
        return o.geometry, coal.Transform3s(M.rotation, M.translation)

    crossing = 0
    for q in a.random_q(1, n=60):
        qf = pin.neutral(full)
        for name, value in zip(a.joint_names, q):
            qf[full.joints[full.getJointId(name)].idx_q] = value
        qf[full.joints[full.getJointId("passive")].idx_q] = 1.5 * q[1] - 1.03  # the mimic
        pin.forwardKinematics(full, data, qf)
        req, res = coal.DistanceRequest(), coal.DistanceResult()
        d = coal.distance(*placed("rod"), *placed("l2"), req, res)
        if d < 0:
            crossing += 1
            assert a.min_distance(q, self_collision=True)[0] <= d + 1e-6
    assert crossing  # the rod crosses l2 in some of the samples


_BARE_BASE_URDF = f"""<robot name="bare_base">
  <link name="base"/><link name="tool"/>
  <link name="l1"><collision><origin xyz="0 0 0.1"/>
    <geometry><box size="0.06 0.06 0.2"/></geometry></collision></link>
  <link name="l2"><collision><origin xyz="0 0 0.15"/>
    <geometry><box size="0.06 0.06 0.3"/></geometry></collision></link>
  <link name="l3"><collision><origin xyz="0 0 0.15"/>
    <geometry><box size="0.06 0.06 0.3"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" {_LIMIT}/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" {_LIMIT}/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" {_LIMIT}/></joint>
  <joint name="tool_fix" type="fixed"><parent link="l3"/><child link="tool"/>
    <origin xyz="0 0 0.3"/></joint>
</robot>
"""


def test_an_arm_deep_inside_a_half_space_is_in_collision(tmp_path):
    # a base without geometry: no link fixed to it refuses the plane. Its moving links,
    # 500 m inside, overlap the plane by that much, with their own pair (l1 and l3, its
    # bound below the plane's) measured beside it
    a = armik.load(write_urdf(tmp_path, _BARE_BASE_URDF), tip="tool")
    assert _link_pairs(a) == {("l1", "l3")}
    inside = armik.HalfSpace((0, 0, -1), 500.0)  # the solid z >= -500
    for q in a.random_q(2, n=5):
        alone, pair = a.min_distance(q, [inside])
        assert alone < -499 and pair[1] == "obstacles[0] (HalfSpace)"
        assert a.min_distance(q, [inside], self_collision=True) == (alone, pair)
    T = a.fk(a.middle)
    r = a.solve(T.translation, obstacles=[inside], self_collision=True)
    assert not r.success and r.status == armik.Status.COLLISION and r.min_distance < -499
