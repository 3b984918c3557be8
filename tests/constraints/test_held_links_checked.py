"""A chain cut from a bigger robot holds the links off the chain where it was cut; those its
own joints carry still move against the rest. One TALOS arm's chain holds the other arm
in the right leg at the upright torso, and the torso moves it out: ``self_collision``
checks that pair on every answer, so no success leaves the held hand in the leg (coal on
the whole URDF, placed here by Pinocchio)."""

from __future__ import annotations

import coal
import numpy as np
import pinocchio as pin

import armik
from armik.model.catalogue import erd_share

TALOS = "example-robot-data/robots/talos_data/robots/talos_reduced.urdf"


def test_a_held_hand_the_torso_moves_is_kept_out_of_the_leg():
    share = erd_share()
    urdf = f"{share}/{TALOS}"
    srdf = f"{share}/example-robot-data/robots/talos_data/srdf/talos.srdf"
    arm = armik.load(urdf, tip="gripper_left_base_link", srdf=srdf)
    model = pin.buildModelFromUrdf(urdf)
    geom = pin.buildGeomFromUrdf(model, urdf, pin.COLLISION, package_dirs=[share])
    links = [model.frames[o.parentFrame].name for o in geom.geometryObjects]
    shapes = []
    for o in geom.geometryObjects:
        s = o.geometry
        if isinstance(s, coal.BVHModelBase):
            s.buildConvexHull(True, "Qt")
            s = s.convex
        shapes.append(s)
    leg = [i for i, n in enumerate(links) if n == "leg_right_3_link"]
    hand = [i for i, n in enumerate(links) if n.startswith(("gripper_right", "wrist_right"))]

    def gap(q_chain) -> float:  # the right hand's distance to the right leg
        q = pin.neutral(model)
        for name, v in zip(arm.joint_names, q_chain):
            q[model.joints[model.getJointId(name)].idx_q] = v
        data, gd = model.createData(), pin.GeometryData(geom)
        pin.updateGeometryPlacements(model, data, geom, gd, q)
        M = [coal.Transform3s(m.rotation, m.translation) for m in gd.oMg]
        return min(
            coal.distance(shapes[a], M[a], shapes[b], M[b], coal.DistanceRequest(),
                          coal.DistanceResult())
            for a in leg for b in hand
        )  # fmt: skip

    assert gap(np.zeros(arm.dof)) < -0.05  # the model as cut: the held hand in the leg
    rng = np.random.default_rng(0)
    lo, hi = arm.lower, arm.upper
    solved = 0
    for _ in range(300):
        q = np.zeros(arm.dof)
        q[:2] = rng.uniform(lo[:2], hi[:2])  # the torso, which moves the held hand
        q[2:] = 0.3 * rng.uniform(lo[2:], hi[2:])
        if gap(q) > -0.06:
            continue
        r = arm.solve(arm.fk(q), q0=q, self_collision=True)
        if r.success:
            solved += 1
            assert gap(r.q) >= 0.0, (q[:2].tolist(), gap(r.q))
        if solved == 2:
            break
    assert solved == 2
