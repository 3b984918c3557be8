"""Mimic joints on the chain: a URDF ``<mimic joint= multiplier= offset=>`` joint follows its
driver, q_mimic = multiplier * q_driver + offset.

``reduce.reduce_chain`` asks ``resolve`` what becomes of each mimic joint of the chain: it
follows a driver that moves on the chain (a ``Mimic``), or it is fixed (its driver is off
the chain or locked, or its multiplier is zero). ``follow`` turns the reduced model's
mimicking joints into Pinocchio mimic joints (``pin.transformJointIntoMimic``: one
configuration coordinate per driving joint, the mimic joint's Jacobian column folded into
its driver's), and ``driver_range`` is the driver's range that keeps the mimic joint within
its own limits.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from armik.errors import JointError, URDFError, did_you_mean, listing
from armik.model.urdf import URDFInfo
from armik.tolerances import LIMIT_TOL, MAX_LIMIT


class Mimic(NamedTuple):
    """A joint of the chain that follows another joint of the chain."""

    name: str
    driver: str
    multiplier: float
    offset: float  # rad or m


def resolve(
    full: pin.Model,
    info: URDFInfo,
    jid: int,
    moving: list[int],
    q_ref: np.ndarray,
    locked: Mapping[str, float],
) -> Mimic | float:
    """What the mimic joint ``jid`` of the chain becomes: a ``Mimic`` of a driver among
    ``moving`` (the chain's joints left free, base first), or the value (rad or m) it is
    fixed at: multiplier x the driver's value (``driver_value``) + offset, or the offset
    for a zero multiplier. Raises ``URDFError`` for a driver that is unknown or is itself a mimic
    joint (a cycle included), ``JointError`` for a pair Pinocchio cannot model."""
    name = full.names[jid]
    driver = info.mimic[name]
    multiplier, offset = info.mimic_factors.get(name, (1.0, 0.0))
    did = joint_id(full, driver)
    if driver not in info.joints or did is None:
        raise URDFError(
            f"joint {name!r} on the chain mimics {driver!r}, which is not a moving joint of "
            "the URDF: name an existing joint in its <mimic joint=...>, or remove the tag"
        )
    if driver in info.mimic:
        loop = [name, driver]
        while loop[-1] in info.mimic and loop[-1] not in loop[:-1]:
            loop.append(info.mimic[loop[-1]])  # ends: each step adds a new name or stops
        if loop[-1] in loop[:-1]:
            raise URDFError(
                f"the mimic joints {' -> '.join(repr(n) for n in loop)} form a cycle: "
                "no joint drives them; let one of them be an ordinary joint"
            )
        raise URDFError(
            f"joint {name!r} on the chain mimics {driver!r}, which itself mimics "
            f"{info.mimic[driver]!r}: make {name!r} mimic a joint that is not a mimic "
            "joint (multipliers and offsets compose)"
        )
    if multiplier == 0.0:
        return offset + 0.0
    if did not in moving:  # off the chain, or locked: fixed at its driver's value
        return multiplier * driver_value(full, q_ref, did, locked) + offset
    for j, role in ((jid, "mimic"), (did, "driver")):
        if full.joints[j].nq != 1:
            raise JointError(
                f"joint {name!r} mimics {driver!r}, and the {role} {full.names[j]!r} is "
                "continuous: armik follows revolute and prismatic mimic pairs only; lock "
                f"{name!r} (locked=) or give the {role} limits in the URDF",
                joint=name,
            )
    if moving.index(did) > moving.index(jid):
        raise JointError(
            f"joint {name!r} mimics {driver!r}, which comes after it on the chain: Pinocchio "
            "models a mimic joint after its driver only; lock it (locked=) or pick a tip "
            "before it",
            joint=name,
        )
    return Mimic(name, driver, float(multiplier), float(offset))


def off_chain_values(
    full: pin.Model,
    info: URDFInfo,
    moving: list[int],
    q_ref: np.ndarray,
    locked: Mapping[str, float],
) -> list[tuple[int, float]]:
    """(joint id, value) for the mimic joints off the chain: each is locked at multiplier x
    its driver's value (``driver_value``: its lock, or neutral) + offset, as a gripper's
    second finger follows the first. Left as they are: joints ``locked`` by name, and mimics of
    an unknown joint, of another mimic joint (readers differ there: yourdfpy takes the
    offset alone) or of a joint that moves on the chain (``moving``; off the chain they move
    nothing the solvers see)."""
    values = []
    for name, driver in info.mimic.items():
        jid, did = joint_id(full, name), joint_id(full, driver)
        if jid is None or name in locked or driver in info.mimic:
            continue
        if jid in moving or did is None or did in moving:
            continue
        multiplier, offset = info.mimic_factors.get(name, (1.0, 0.0))
        values.append((jid, multiplier * driver_value(full, q_ref, did, locked) + offset))
    return values


def across(chains: dict) -> None:
    """Refuse chains (tip -> ``ArmModel``, one URDF) where a mimic joint held fixed on one
    chain follows a driver that moves on another: that chain (alone, or in the chains' union)
    holds it at its driver's value in the reference configuration (``fixed_mimics``), while
    the robot's own configuration moves it with the driver, its tip elsewhere. Raises
    ``JointError`` naming the mimic joint, its driver, both tips and the ways round."""
    for tip, arm in chains.items():
        for name, value in (arm.chain.fixed_mimics or {}).items():
            driver = arm.info.mimic.get(name)
            multiplier, offset = arm.info.mimic_factors.get(name, (1.0, 0.0))
            if multiplier == 0.0:  # held at its offset whatever the driver does
                continue
            other = next((t for t, a in chains.items() if driver in a.joint_names), None)
            if other is None:
                continue
            raise JointError(
                f"joint {name!r} on the chain to {tip!r} mimics {driver!r} ({multiplier:g} x "
                f"{driver} + {offset:g}), which moves on the chain to {other!r}: the chain to "
                f"{tip!r} holds {name!r} fixed at {value:g}, where the robot moves it with "
                f"{driver!r}; armik does not solve tips coupled through a mimic joint: load one "
                f"tip (tip={tip!r} or tip={other!r}), or lock the driver (locked={{{driver!r}: "
                f"value}}, --lock {driver}=VALUE) so that both chains hold it",
                joint=name,
            )


def driver_value(
    model: pin.Model, q_ref: np.ndarray, jid: int, locked: Mapping[str, float]
) -> float:
    """The value (rad or m) of the driver ``jid`` that its mimic joints follow: the value it
    is locked at by name (``locked``), else its value in ``q_ref``. A continuous driver's
    lock is taken as given, turns included: ``q_ref`` holds only its cos and sin, and
    multiplier x (4 - 2 pi) + offset is not where ROS tools put the mimic joint of a driver
    at 4 rad."""
    name = model.names[jid]
    if name in locked:
        return float(locked[name])
    return joint_value(model, q_ref, jid)


def joint_id(model: pin.Model, name: str) -> int | None:
    """The id of the joint ``name`` of ``model``, or None: never joint 0, which Pinocchio
    names 'universe' whatever the URDF names its joints (``getJointId`` would find it)."""
    return next((j for j in range(1, model.njoints) if model.names[j] == name), None)


def joint_of(model: pin.Model, name: str) -> int:
    """``joint_id`` of a joint ``model`` has (``KeyError`` otherwise)."""
    jid = joint_id(model, name)
    if jid is None:
        raise KeyError(name)
    return jid


def joint_value(model: pin.Model, q: np.ndarray, jid: int) -> float:
    """The value (rad or m) of joint ``jid`` in the configuration ``q``."""
    joint = model.joints[jid]
    if joint.nq == 2:
        return math.atan2(q[joint.idx_q + 1], q[joint.idx_q])
    return float(q[joint.idx_q])


def follow(plain: pin.Model, mimics: tuple[Mimic, ...]) -> pin.Model:
    """``plain`` (the reduced model, every joint its own) with each mimic joint of
    ``mimics`` turned into a Pinocchio mimic joint of its driver."""
    model = plain
    for m in mimics:
        model = pin.transformJointIntoMimic(
            model, joint_of(model, m.driver), joint_of(model, m.name), m.multiplier, m.offset
        )
    return model


def driver_range(plain: pin.Model, info: URDFInfo, m: Mimic) -> tuple[float, float]:
    """The driver's values (rad or m) that keep the mimic joint ``m`` within its URDF limits:
    (limits - offset) / multiplier, in order for a negative multiplier; (-inf, inf) for a
    mimic joint without limits."""
    joint = plain.joints[joint_of(plain, m.name)]
    if joint.nq != 1 or m.name in info.unset_limits:
        return -math.inf, math.inf
    lo = float(plain.lowerPositionLimit[joint.idx_q])
    hi = float(plain.upperPositionLimit[joint.idx_q])
    lo = lo if lo >= -MAX_LIMIT else -math.inf
    hi = hi if hi <= MAX_LIMIT else math.inf
    a, b = (lo - m.offset) / m.multiplier, (hi - m.offset) / m.multiplier
    return (a, b) if a <= b else (b, a)


def check_locked_driver(
    full: pin.Model, info: URDFInfo, jid: int, value: float, locked: dict[str, float]
) -> None:
    """Refuse a driver locked by name (``locked``: joint -> value) that holds its mimic
    joint ``jid`` at ``value`` outside the mimic joint's own URDF limits: each answer would
    put that joint outside them. Raises ``JointError`` naming both joints and the driver's
    values that keep the mimic joint within its limits."""
    name = full.names[jid]
    driver = info.mimic.get(name)
    multiplier, offset = info.mimic_factors.get(name, (1.0, 0.0))
    if driver not in locked or multiplier == 0.0:
        return
    lo, hi = driver_range(full, info, Mimic(name, driver, multiplier, offset))
    if lo - LIMIT_TOL <= locked[driver] <= hi + LIMIT_TOL:
        return
    unit = "m" if info.joint_types.get(name) == "prismatic" else "rad"
    raise JointError(
        f"locking {driver!r} at {locked[driver]:g} holds its mimic joint {name!r} at "
        f"{value:g} {unit} ({multiplier:g} x {locked[driver]:g} + {offset:g}), outside the "
        f"URDF limits of {name!r}: lock {driver!r} within [{lo:g}, {hi:g}], or lock {name!r} "
        "too",
        joint=driver,
    )


def not_a_joint(arm, name: str) -> str:
    """Why ``name`` is no joint of ``arm`` (an ``ArmModel``), for its errors: a mimic joint
    of its chain follows its driver, a joint locked on it or a mimic joint fixed there is
    a fixed transform, any other name is not on the chain."""
    for m in arm.mimics:
        if m.name == name:
            return (
                f"mimics {m.driver!r} on this arm's chain ({m.multiplier:g} x {m.driver} + "
                f"{m.offset:g}): its value follows the driver's; name {m.driver!r}"
            )
    if name in arm.locked_on_chain:
        return f"is locked at {arm.locked[name]:g} on this arm's chain (locked=), a fixed transform"
    fixed = arm.chain.fixed_mimics or {}
    if name in fixed:
        return (
            f"mimics {arm.info.mimic.get(name)!r}, which does not move on this arm's chain: it "
            f"is held at {fixed[name]:g} there, a fixed transform"
        )
    close = did_you_mean(name, arm.joint_names).strip()
    return "is not on this arm's chain" + (f" ({close})" if close else "")


def joint_map(arm) -> tuple[tuple, list[int], tuple[np.ndarray, np.ndarray]]:
    """For the physical joints of ``arm.physical_model`` (the reduced model, mimic joints as
    joints of their own) and the driving joints ``arm.joint_names``: (driver, multiplier,
    offset), physical
    joint i taking multiplier[i] * q[driver[i]] + offset[i] (rad or m); the physical index of
    each driving joint; and the driving joints' ranges (lower, upper) that keep their mimic
    joints within limits (``driver_range``; -inf, inf without a mimic)."""
    plain, info, joint_names, mimics = arm.physical_model, arm.info, arm.joint_names, arm.mimics
    names = [plain.names[j] for j in range(1, plain.njoints)]
    following = {x.name: x for x in mimics}
    driver = np.empty(len(names), dtype=np.int64)
    multiplier, offset = np.ones(len(names)), np.zeros(len(names))
    for i, jname in enumerate(names):
        x = following.get(jname)
        driver[i] = joint_names.index(jname if x is None else x.driver)
        if x is not None:
            multiplier[i], offset[i] = x.multiplier, x.offset
    lo, hi = np.full(len(joint_names), -np.inf), np.full(len(joint_names), np.inf)
    for x in mimics:
        k = joint_names.index(x.driver)
        a, b = driver_range(plain, info, x)
        lo[k], hi[k] = max(lo[k], a), min(hi[k], b)
    driving = [names.index(jname) for jname in joint_names]
    return (driver, multiplier, offset), driving, (lo, hi)


def narrow(lower: np.ndarray, upper: np.ndarray, box, arm) -> tuple[np.ndarray, np.ndarray]:
    """The limits ``lower``, ``upper`` of ``arm``'s driving joints narrowed to ``box`` (from
    ``joint_map``); raises ``JointError`` naming the driver when nothing is left."""
    if not arm.mimics:
        return lower, upper
    lo, hi = np.maximum(lower, box[0]), np.minimum(upper, box[1])
    for k in np.flatnonzero(lo > hi):
        jname = arm.joint_names[k]
        names = [x.name for x in arm.mimics if x.driver == jname]
        raise JointError(
            f"the limits [{lower[k]:g}, {upper[k]:g}] of joint {jname!r} and those of its "
            f"mimic joints {listing(names)} leave it no value: widen them (in the URDF or "
            "with_limits) or lock the mimic joint (locked=)",
            joint=jname,
        )
    return lo, hi


def no_period(arm) -> list[bool]:
    """Per driving joint of ``arm``: True where 2 pi is no period of the pose, so that
    ``nearest_equivalent`` and the kernel leave its value alone: a prismatic joint, or a
    driver of mimic joints (they would move by multiplier x 2 pi)."""
    drivers = {x.driver for x in arm.mimics}
    return [bool(p) or n in drivers for n, p in zip(arm.joint_names, arm.prismatic)]


def travel(arm) -> float:
    """How far (m) the prismatic mimic joints of ``arm`` slide from the middle of their
    drivers' limits: |multiplier| x the driver's travel (for ``ArmModel.reach``)."""
    total = 0.0
    for x in arm.mimics:
        if arm.info.joint_types.get(x.name) == "prismatic":
            k = arm.joint_names.index(x.driver)
            mid = arm.middle[k]
            total += abs(x.multiplier) * max(abs(arm.lower[k] - mid), abs(arm.upper[k] - mid))
    return total


def reason(mimics: tuple[Mimic, ...]) -> str:
    """Why a closed form does not apply to a chain with the mimic joints ``mimics`` (one
    at least: its callers ask only for an arm with mimic joints)."""
    m = mimics[0]
    return (
        f"joint {m.name!r} mimics {m.driver!r} (multiplier {m.multiplier:g}, offset "
        f"{m.offset:g}); the closed forms need independent joints: use dls or qp"
    )
