"""Joints of an arm locked within the arm's own limits: the chain cut again from the URDF's
model the arm was cut from, each locked value checked against the limits ``with_limits``
gave the joint (wider or narrower than the URDF's). ``armik.loading.Recipe`` builds an arm
with every joint ``with_limits`` reached left free, gives it its limits, then locks those
joints here."""

from __future__ import annotations

from collections.abc import Mapping

from armik.model.arm_model import ArmModel


def relocked(
    arm: ArmModel, locked: Mapping[str, float], limits: Mapping[str, tuple[float, float]]
) -> ArmModel:
    """``arm`` with the joints of ``locked`` (name -> rad or m) it leaves free locked too,
    their values checked against ``limits`` (name -> (lower, upper), rad or m) where it
    names them (a joint off the chain too: another chain's, on several tips), else against
    the URDF's; the joints left free given ``limits``. Raises ``JointError`` as
    ``armik.load`` does."""
    new = {name: value for name, value in locked.items() if name not in arm.locked}
    if new:
        chain = arm.chain
        out = ArmModel(
            chain.full,
            arm.info,
            name=arm.name,
            base=arm.base,
            tip=arm.tip,
            locked={**arm.locked, **new},
            tip_offset=arm.tip_offset,
            source=arm.source,
            limits=limits,
        )
        out.package_dirs, out.disabled_pairs = arm.package_dirs, arm.disabled_pairs
        out.tip_reason = arm.tip_reason
        arm = out
    free = {name: pair for name, pair in limits.items() if name in arm.joint_names}
    return arm.with_limits(free) if free else arm
