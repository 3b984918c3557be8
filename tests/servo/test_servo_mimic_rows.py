"""The servo's collision rows on a link below a mimic joint off the chain whose driver
moves on it (a parallelogram's rod): placed where the robot puts it at every tick, its
rows the derivatives of its distances, on one chain and over a shared torso. Measured by
coal on the URDF's shapes placed by Pinocchio's whole model, the mimic set by hand."""

from __future__ import annotations

import coal
import numpy as np
import pinocchio as pin
import pytest

import armik

from ..conftest import write_urdf

DT = 0.002
_LIMIT = 'effort="1" velocity="2"'


def _arm(s: str, y: float) -> str:
    def box(size: str) -> str:
        return (
            f'<collision><origin xyz="0 0 0.15"/><geometry><box size="{size}"/></geometry>'
            "</collision>"
        )

    return f"""
  <link name="{s}_l1">{box("0.04 0.04 0.26")}</link>
  <link name="{s}_l2">{box("0.04 0.04 0.26")}</link>
  <link name="{s}_tool"/><link name="{s}_rod">{box("0.03 0.03 0.3")}</link>
  <joint name="{s}_j1" type="revolute"><parent link="torso"/><child link="{s}_l1"/>
    <origin xyz="0 {y} 0.2"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" {_LIMIT}/></joint>
  <joint name="{s}_j2" type="revolute"><parent link="{s}_l1"/><child link="{s}_l2"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" {_LIMIT}/></joint>
  <joint name="{s}_fix" type="fixed"><parent link="{s}_l2"/><child link="{s}_tool"/>
    <origin xyz="0 0 0.3"/></joint>
  <joint name="{s}_passive" type="revolute"><parent link="{s}_l1"/><child link="{s}_rod"/>
    <origin xyz="0.1 0 0.05"/><axis xyz="0 1 0"/><limit lower="-6" upper="6" {_LIMIT}/>
    <mimic joint="{s}_j2" multiplier="1.2" offset="0.1"/></joint>"""


# a torso with two arms, each with a rod that a passive mimic joint off the chain turns
# with the elbow (j2), and a rod hung from the base that turns with the torso
URDF = f"""<?xml version="1.0"?>
<robot name="rods">
  <link name="base"/><link name="torso"/>
  <joint name="torso_j" type="revolute"><parent link="base"/><child link="torso"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" {_LIMIT}/></joint>
{_arm("l", 0.3)}
{_arm("r", -0.3)}
  <link name="brod"><collision><origin xyz="0 0 0.15"/>
    <geometry><box size="0.03 0.03 0.3"/></geometry></collision></link>
  <joint name="b_passive" type="revolute"><parent link="base"/><child link="brod"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-6" upper="6" {_LIMIT}/>
    <mimic joint="torso_j" multiplier="1" offset="0"/></joint>
</robot>
"""


class Whole:
    """The URDF's whole model, each passive joint at 1.2 x its driver + 0.1."""

    def __init__(self, path) -> None:
        self.model = pin.buildModelFromUrdf(str(path))
        self.data = self.model.createData()
        self.geom = pin.buildGeomFromUrdf(self.model, str(path), pin.COLLISION)

    def rod(self, names, q, link="l_rod") -> tuple[coal.CollisionGeometry, coal.Transform3s]:
        values = dict(zip(names, q))
        values.update({f"{s}_passive": 1.2 * values.get(f"{s}_j2", 0.0) + 0.1 for s in "lr"})
        values["b_passive"] = values["torso_j"]
        qf = pin.neutral(self.model)
        for name, v in values.items():
            qf[self.model.joints[self.model.getJointId(name)].idx_q] = v
        pin.forwardKinematics(self.model, self.data, qf)
        (o,) = [o for o in self.geom.geometryObjects if o.name.startswith(link)]
        M = self.data.oMi[o.parentJoint] * o.placement
        return o.geometry, coal.Transform3s(M.rotation, M.translation)


def _ball() -> tuple[armik.Sphere, tuple]:
    """A sphere where the left rod's end is with the elbow at 0.5 rad: in its sweep."""
    a = 1.2 * 0.5 + 0.1
    centre = np.array([0.1 + 0.3 * np.sin(a), 0.3, 0.55 + 0.3 * np.cos(a)])
    return armik.Sphere(0.03, tuple(centre)), (
        coal.Sphere(0.03),
        coal.Transform3s(np.eye(3), centre),
    )


def _nearest(whole: Whole, names, Q, shape, link="l_rod") -> float:
    request = coal.DistanceRequest()
    return min(
        coal.distance(*whole.rod(names, q, link), *shape, request, coal.DistanceResult()) for q in Q
    )


@pytest.mark.parametrize("tips", [["l_tool"], ["l_tool", "r_tool"]])
def test_a_rod_turned_by_a_mimic_joint_is_kept_at_the_margin(tmp_path, tips):
    """The elbow led to 0.8 rad sweeps the rod through the sphere; the servo (one chain, or
    over the shared torso) keeps the rod the margin from it at every tick."""
    path = write_urdf(tmp_path, URDF)
    robot = armik.load(path, tips=tips) if len(tips) > 1 else armik.load(path, tip=tips[0])
    names = robot.joint_names
    q0 = np.zeros(len(names))
    goal = q0.copy()
    goal[names.index("l_j2")] = 0.8
    if len(tips) > 1:
        target = {t: robot.fk(goal, t).translation for t in tips}
    else:
        target = robot.fk(goal).translation
    ball, shape = _ball()
    whole = Whole(path)
    free = robot.servo(q0, dt=DT, velocity_limits=1.0).track([target] * 800)
    assert _nearest(whole, names, free.q, shape) < 0.0  # the rod passes through it
    servo = robot.servo(q0, dt=DT, velocity_limits=1.0, obstacles=[ball], margin=0.01)
    rec = servo.track([target] * 800)
    assert _nearest(whole, names, rec.q, shape) >= 0.01 - 1e-4
    assert "obstacle" in set(rec.status.tolist())


def test_a_rods_row_is_the_derivative_of_its_distance_over_a_shared_torso(tmp_path):
    """The rod's row over the union's joints: its normal on the witness point's Jacobian,
    each mimic joint folded into its driver times its multiplier, is the derivative of the
    rod's distance to the sphere (central differences along random directions)."""
    path = write_urdf(tmp_path, URDF)
    robot = armik.load(path, tips=["l_tool", "r_tool"])
    names = robot.joint_names
    ball, shape = _ball()
    servo = robot.servo(np.zeros(len(names)), dt=DT, obstacles=[ball], margin=0.01)
    rows = servo._union._collisions
    q = np.zeros(len(names))
    q[names.index("l_j2")] = 0.35  # the rod 2-3 cm from the sphere
    q[names.index("torso_j")] = 0.05
    C = rows.at(q)
    assert len(C) == 1 and 0.01 < rows.nearest < 0.06
    whole = Whole(path)
    request = coal.DistanceRequest()
    request.gjk_tolerance = 1e-12

    def d(qq):
        return coal.distance(*whole.rod(names, qq), *shape, request, coal.DistanceResult())

    assert abs(d(q) - rows.nearest) < 1e-9  # placed where the whole model puts it
    rng = np.random.default_rng(0)
    h = 1e-6
    for _ in range(5):
        u = rng.normal(size=len(names))
        u /= np.linalg.norm(u)
        slope = (d(q + h * u) - d(q - h * u)) / (2 * h)
        assert abs(C[0, :-1] @ u - slope) < 1e-5 * max(1.0, abs(slope))


def test_a_rod_hung_from_the_base_turned_by_the_shared_torso_is_kept_at_the_margin(tmp_path):
    """The rod on the base turns with the torso, which both chains share: the servo over
    the torso pairs it with the sphere its sweep passes through (the chains' cut models
    hang it on the base, as if it never moved)."""
    path = write_urdf(tmp_path, URDF)
    robot = armik.load(path, tips=["l_tool", "r_tool"])
    names = robot.joint_names
    q0 = np.zeros(len(names))
    goal = q0.copy()
    goal[names.index("torso_j")] = 0.7
    target = {t: robot.fk(goal, t).translation for t in robot.tips}
    centre = np.array([0.3 + 0.3 * np.sin(0.5), 0.0, 0.3 * np.cos(0.5)])  # at torso 0.5
    ball = armik.Sphere(0.03, tuple(centre))
    shape = (coal.Sphere(0.03), coal.Transform3s(np.eye(3), centre))
    whole = Whole(path)
    free = robot.servo(q0, dt=DT, velocity_limits=1.0).track([target] * 800)
    assert _nearest(whole, names, free.q, shape, "brod") < 0.0
    servo = robot.servo(q0, dt=DT, velocity_limits=1.0, obstacles=[ball], margin=0.01)
    rec = servo.track([target] * 800)
    assert _nearest(whole, names, rec.q, shape, "brod") >= 0.01 - 1e-4
    assert "obstacle" in set(rec.status.tolist())
