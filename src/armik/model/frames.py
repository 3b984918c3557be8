"""Any frame of an arm's model by name: its placement in the base frame and its Jacobian,
the same words on one arm (``Arm.fk(q, frame=...)``) and on several tips (``Arms``).

A frame is named by ``frame``, the axes its Jacobian is expressed in by ``reference``
("local": the frame's own; "base": the base frame's, at the frame's origin). The old
spelling ``jacobian(q, "base")`` (the tip's Jacobian in base axes) still means that when
``reference`` is not given and the arm has no frame of that name: ``frame_and_reference``
reads it.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from armik.errors import FrameError, OptionError, closest, listing, warn
from armik.model import mimic_frames
from armik.model.limit_units import degrees_note

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel

REFERENCES = ("local", "base")


def frame_id(arm: ArmModel, frame: str | None) -> int:
    """The Pinocchio frame index of ``frame`` (None or the tip: the tip's, its offset
    included; a name a joint and a link share: ``named``); a ``FrameError`` listing the
    arm's frames for a name the model lacks."""
    if frame is None or frame == arm.tip:
        return arm.tip_frame_id
    if isinstance(frame, str) and arm.model.existFrame(frame):
        return named(arm.model, frame)
    names = arm.frames()
    close = closest(frame, names)
    hint = f"closest: {listing(close)}; " if close else ""
    raise FrameError(
        f"frame {frame!r} is not a frame of arm {arm.name!r}; {hint}its frames: {listing(names)}",
        frame=str(frame),
        candidates=close or names,
    )


def named(model: pin.Model, name: str) -> int:
    """The index of the frame ``name`` of ``model`` (one it has). A URDF may give a joint
    and a link one name (the bundled SCARA's ``quill``), and Pinocchio then holds a frame
    of each: the link's (a ``BODY`` frame) is the one meant, as ROS tools read a frame's
    name, and the joint's frame is placed where its child link is. Where the frames of a
    name are not all at that one placement, a ``FrameError`` names them."""
    found = [i for i, f in enumerate(model.frames) if f.name == name]
    if len(found) == 1:
        return found[0]
    frames = [model.frames[i] for i in found]
    bodies = [i for i, f in zip(found, frames) if f.type == pin.FrameType.BODY]
    first = frames[0]
    same = all(
        f.parentJoint == first.parentJoint and f.placement.isApprox(first.placement, 1e-12)
        for f in frames
    )
    if len(bodies) == 1 and same:
        return bodies[0]
    kinds = [f"{name} ({f.type.name.lower()}, on joint {f.parentJoint})" for f in frames]
    raise FrameError(
        f"frame {name!r} names {len(found)} frames of the model at different placements: "
        f"{listing(kinds)}; name a frame one of them alone has",
        frame=name,
        candidates=kinds,
    )


def owner(chains: Mapping[str, ArmModel], frame: str) -> str:
    """The tip of the first of ``chains`` (tip -> model) whose joints move ``frame``, else
    of the first that has it (a frame fixed to the common base); ``frame`` itself where
    none has it (a tip is its own chain's). Each chain's model holds every frame of the
    robot, the other chains' joints locked: only the chain that moves a frame places it."""
    if frame in chains:
        return frame
    having = [tip for tip, arm in chains.items() if arm.model.existFrame(str(frame))]
    moving = (tip for tip in having if moves(chains[tip], frame))
    return next(moving, having[0] if having else frame)


def moves(arm: ArmModel, frame: str) -> bool:
    """Whether some joint of ``arm`` moves its frame ``frame`` (one the model has)."""
    model = arm.model
    return bool(model.frames[named(model, str(frame))].parentJoint != 0)


def frame_and_reference(
    frame: str | None, reference: str | None, model: pin.Model
) -> tuple[str | None, str]:
    """(frame, reference) of a Jacobian call on ``model``: ``frame="local"`` or ``"base"``
    without a ``reference`` is the old spelling of the tip's Jacobian in those axes; an
    ``OptionError`` where ``model`` also has a frame of that name (the UR5's ``base``)."""
    if reference is None:
        if frame in REFERENCES:
            if model.existFrame(frame):
                raise OptionError(
                    f"{frame!r} names a frame of this arm and is the old spelling of "
                    f"reference={frame!r} (the tip's Jacobian in those axes): say which, "
                    f"jacobian(q, reference={frame!r}) or jacobian(q, frame={frame!r}, "
                    "reference='local')",
                    option="frame",
                    value=frame,
                )
            return None, frame  # type: ignore[return-value]
        return frame, "local"
    if reference not in REFERENCES:
        raise OptionError(
            f"reference must be 'local' or 'base', got {reference!r}",
            option="reference",
            value=reference,
        )
    return frame, reference


def placement(arm: ArmModel, q: object, frame: str | None = None) -> pin.SE3:
    """``T_base_frame`` at joint values ``q`` (rad, m): the tip's by default."""
    q = in_radians(arm, q, "fk")
    if frame is None or frame == arm.tip:
        return arm.fk_pin(arm.to_pin(q))
    fid = frame_id(arm, frame)
    whole = mimic_frames.full_frame(arm, frame)
    if whole is not None:
        return mimic_frames.placement(arm, q, whole)
    pin.framesForwardKinematics(arm.model, arm.data, arm.to_pin(q))
    return arm.T_base_world * arm.data.oMf[fid]


def in_radians(arm: ArmModel, q: object, what: str) -> np.ndarray:
    """``q`` checked (``ArmModel.check_q``), with an ``ArmikWarning`` where a value reads as
    degrees (``limit_units.degrees_note``). A value merely outside the limits is said by
    nothing: fk and the Jacobian need no limits (a workspace study, limits a URDF has
    wrong); but no joint with limits holds a value beyond them and four turns, and the pose
    of one, taken for a target, would carry the mistake on unsaid."""
    q = arm.check_q(q)
    note = degrees_note(q, arm)
    if note:
        shown = ", ".join(f"{v:g}" for v in q.tolist())
        warn(f"{what} at q [{shown}]{note}")
    return q


def jacobian(
    arm: ArmModel, q: object, frame: str | None = None, reference: str | None = None
) -> np.ndarray:
    """The 6 x dof Jacobian of ``frame`` (the tip's by default), rows (vx, vy, vz, wx,
    wy, wz): its twist in its own axes (``reference="local"``) or in the base frame's
    axes at its origin (``"base"``). Zero columns for joints that do not move it."""
    frame, reference = frame_and_reference(frame, reference, arm.model)
    if frame is None or frame == arm.tip:
        return arm.jacobian(in_radians(arm, q, "jacobian"), reference)
    fid = frame_id(arm, frame)
    kind = pin.LOCAL if reference == "local" else pin.LOCAL_WORLD_ALIGNED
    whole = mimic_frames.full_frame(arm, frame)
    if whole is not None:
        J = mimic_frames.jacobian(arm, in_radians(arm, q, "jacobian"), whole, kind)
    else:
        qp = arm.to_pin(in_radians(arm, q, "jacobian"))
        J = pin.computeFrameJacobian(arm.model, arm.data, qp, fid, kind).reshape(6, arm.dof)
    if reference == "local":
        return J.copy()
    R = arm.T_base_world.rotation
    return np.vstack([R @ J[:3], R @ J[3:]])
