"""Self-collision pairs of two links a chain holds where it was cut (their joints off the
chain, or the base) that overlap at its neutral configuration: the model as loaded is in
collision there, which no answer of the chain's is to clear (one TALOS arm's chain holds
the other arm in the right leg). ``armik.constraints.collision`` leaves them out of the
check and names them, as MoveIt's setup assistant disables such pairs as "Default"."""

from __future__ import annotations

import coal
import pinocchio as pin

from armik.model import mimic_frames
from armik.model.arm_model import ArmModel


def held_overlaps(
    arm: ArmModel, geom: pin.GeometryModel, joints: list[int], pairs: tuple[tuple[int, int], ...]
) -> dict[tuple[int, int], float]:
    """Those of ``pairs`` (objects of ``geom``, the chain's cut geometry; ``joints``: each
    object's joint in the whole URDF's model) whose two objects no joint of the chain's own
    places and that overlap at the neutral configuration, and by how much (m)."""
    held = set(arm.chain.locked_joints) - set(mimic_frames.followers(arm))
    carried = [j == 0 or j in held for j in joints]
    both = [(a, b) for a, b in pairs if carried[a] and carried[b]]
    if not both:
        return {}
    data, gd = arm.model.createData(), pin.GeometryData(geom)
    pin.updateGeometryPlacements(arm.model, data, geom, gd, arm.to_pin(arm.neutral))
    found = {}
    for a, b in both:
        Ma, Mb = gd.oMg[a], gd.oMg[b]
        d = coal.distance(
            geom.geometryObjects[a].geometry,
            coal.Transform3s(Ma.rotation, Ma.translation),
            geom.geometryObjects[b].geometry,
            coal.Transform3s(Mb.rotation, Mb.translation),
            coal.DistanceRequest(),
            coal.DistanceResult(),
        )
        if d < 0:
            found[(a, b)] = -float(d)
    return found
