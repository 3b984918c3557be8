"""Building the reduced chain: the base and tip frames looked up, the default tip chosen,
every joint off the chain locked, the tool offset added.

``reduce_chain`` turns Pinocchio's model of the whole URDF into the model of one chain from
a base frame to a tip frame; ``armik.model.arm_model.ArmModel`` is built on it.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from armik.errors import FrameError, JointError, OptionError, URDFError, closest, listing
from armik.model import mimic as _mimic
from armik.model.default_tip import default_tip
from armik.model.mimic import Mimic
from armik.model.urdf import URDFInfo
from armik.model.value_checks import NOT_NUMBERS, locked_value
from armik.tolerances import MAX_LENGTH, MAX_LIMIT

log = logging.getLogger(__name__)

_FRAME_PREFERENCE = (pin.BODY, pin.OP_FRAME, pin.FIXED_JOINT, pin.JOINT, pin.SENSOR)


@dataclass(frozen=True)
class ReducedChain:
    """The chain's Pinocchio model and what was decided building it."""

    model: pin.Model
    base: str
    tip: str
    tip_reason: str  # how the tip was chosen ("given" when it was)
    tip_frame_id: int  # the tip frame, or the tool frame ``tip_offset`` added after it
    tip_offset: tuple[float, float, float] | None  # m, in the tip frame
    T_world_base: pin.SE3  # constant: the base frame's own joint is locked
    locked: dict[str, float]  # every joint locked by value, on or off the chain (rad or m)
    locked_on_chain: tuple[str, ...]  # those between the base and the tip, base first
    # how the chain was cut from the whole URDF's model, to cut its collision geometry alike
    full: pin.Model
    locked_joints: tuple[int, ...]
    q_ref: np.ndarray
    # mimic joints: those that follow a driver on the chain (``model`` holds them as
    # Pinocchio mimic joints, ``plain`` as joints of their own), those fixed at a value
    mimics: tuple[Mimic, ...]
    plain: pin.Model
    fixed_mimics: dict[str, float] | None


def reduce_chain(
    full: pin.Model,
    info: URDFInfo,
    locked: Mapping[str, float],
    limits: Mapping[str, tuple[float, float]],
    *,
    name: str,
    base: str | None,
    tip: str | None,
    tip_offset: tuple[float, float, float] | None,
) -> ReducedChain:
    """The chain of ``full`` from ``base`` (default: the URDF's root link) to ``tip``
    (default: ``default_tip``). Every joint off the chain is locked at ``locked``'s value or
    its neutral one; a joint of the chain named in ``locked`` becomes a fixed transform at
    that value (rad or m), and the chain keeps the other joints. Raises ``FrameError`` or
    ``JointError`` naming the frame or joint: an unknown locked joint, a locked value that is
    not finite or lies outside the joint's limits (``limits``' (lower, upper) where it names
    the joint, the arm's own from ``with_limits``; else the URDF's), every joint of the
    chain locked."""
    frames = [f.name for f in full.frames if f.name != "universe"]
    base = base if base is not None else info.root_link
    base_id = lookup_frame(full, base, "base", frames)
    if tip is None:
        tip, tip_reason = default_tip(info, base)
        log.info("arm %r: tip %r, %s", name, tip, tip_reason)
    else:
        tip_reason = "given"
    tip_id = lookup_frame(full, tip, "tip", frames)

    base_joint = full.frames[base_id].parentJoint
    tip_joint = full.frames[tip_id].parentJoint
    tip_support = list(full.supports[tip_joint])
    if base_joint not in tip_support:
        raise FrameError(
            f"tip {tip!r} is not downstream of base {base!r}: no chain leads "
            "from the base to the tip; swap them or pick frames on one branch",
            frame=tip,
            candidates=frames,
        )
    path = list(tip_support[tip_support.index(base_joint) + 1 :])
    if not path:
        raise FrameError(
            f"the chain from {base!r} to {tip!r} has no moving joint: "
            "pick a tip further from the base",
            frame=tip,
            candidates=frames,
        )

    q_ref = pin.neutral(full)
    values: dict[str, float] = {}
    for jname, value in locked.items():
        jid = _locked_joint(full, jname)
        number = locked_value(full, info, jid, value, limits.get(jname))
        set_joint(full, q_ref, jid, number)
        values[jname] = number
    held = [j for j in path if full.names[j] in values]
    chain = [j for j in path if j not in held]
    if not chain:
        names = [full.names[j] for j in held]
        raise JointError(
            f"locking {listing(names)} leaves no moving joint on the chain from {base!r} to "
            f"{tip!r}: leave at least one of them free, or pick another base or tip",
            joint=names[0],
            candidates=names,
        )
    for j in chain:
        if full.joints[j].nv != 1:
            raise _many_dof(full, info, j, j == chain[0])
    mimics, fixed = _chain_mimics(full, info, chain, q_ref, values)
    for j, value in _mimic.off_chain_values(full, info, chain, q_ref, values):
        _mimic.check_locked_driver(full, info, j, value, values)
        set_joint(full, q_ref, j, value)
    for jname, value in fixed.items():
        _mimic.check_locked_driver(full, info, _mimic.joint_of(full, jname), value, values)
    if fixed:
        chain = [j for j in chain if full.names[j] not in fixed]
        if not chain:
            raise JointError(
                f"the chain from {base!r} to {tip!r} has no moving joint once its mimic "
                f"joints {listing(fixed)} are fixed: pick another base or tip",
                joint=next(iter(fixed)),
            )
    # Every joint off the chain, and the chain's locked joints, become fixed transforms at
    # their value in q_ref.
    to_lock = [j for j in range(1, full.njoints) if j not in chain]
    model = reduce_model(full, to_lock, q_ref) if to_lock else full.copy()

    tip_frame = frame_id(model, tip)
    if tip_offset is not None:
        frame = model.frames[tip_frame]
        placement = frame.placement * pin.SE3(np.eye(3), np.asarray(tip_offset, float))
        tip_frame = model.addFrame(
            pin.Frame(tip + "_tool", frame.parentJoint, tip_frame, placement, pin.OP_FRAME)
        )
    plain = model  # the mimic model keeps its frames, the tool frame included
    if mimics:
        model = _mimic.follow(plain, mimics)

    # The base frame's own joint is locked, so its world placement is a constant.
    data_full = full.createData()
    pin.framesForwardKinematics(full, data_full, q_ref)
    return ReducedChain(
        model=model,
        base=base,
        tip=tip,
        tip_reason=tip_reason,
        tip_frame_id=tip_frame,
        tip_offset=None if tip_offset is None else _three(tip_offset),
        T_world_base=data_full.oMf[base_id].copy(),
        locked=values,
        locked_on_chain=tuple(full.names[j] for j in held),
        full=full,
        locked_joints=tuple(to_lock),
        q_ref=q_ref,
        mimics=mimics,
        plain=plain,
        fixed_mimics=fixed,
    )


def _many_dof(full: pin.Model, info: URDFInfo, j: int, first: bool) -> JointError:
    """A joint of several degrees of freedom (floating, planar) on the chain: the base
    below it (its child link) or, past the first joint, a tip above it is the fix."""
    jname, joint = full.names[j], full.joints[j]
    xml = info.joints.get(jname)
    kind = f"{xml.type}, {joint.shortname()}" if xml is not None else joint.shortname()
    fix = "load the arm from below it"
    if xml is not None:
        fix = f"load the arm from the link below it, base={xml.child!r}"
        if not first:
            fix += f", or up to the link above it, tip={xml.parent!r}"
    return JointError(
        f"joint {jname!r} ({kind}) has {joint.nv} degrees of freedom; armik solves "
        f"revolute, continuous and prismatic joints: {fix}",
        joint=jname,
    )


def _chain_mimics(
    full: pin.Model,
    info: URDFInfo,
    chain: list[int],
    q_ref: np.ndarray,
    locked: Mapping[str, float],
) -> tuple[tuple[Mimic, ...], dict[str, float]]:
    """The mimic joints of ``chain``: those that follow a driver on it, and those fixed at a
    value (written into ``q_ref``, to be locked there). See ``armik.model.mimic.resolve``."""
    mimics: list[Mimic] = []
    fixed: dict[str, float] = {}
    for j in chain:
        if full.names[j] in info.mimic:
            got = _mimic.resolve(full, info, j, chain, q_ref, locked)
            if isinstance(got, Mimic):
                mimics.append(got)
            else:
                set_joint(full, q_ref, j, got)
                fixed[full.names[j]] = got
    return tuple(mimics), fixed


def _locked_joint(full: pin.Model, jname: str) -> int:
    """The id of the locked joint ``jname``; raises ``JointError`` listing the joints."""
    jid = _mimic.joint_id(full, jname)
    if jid is None:
        all_joints = list(full.names)[1:]
        close = closest(jname, all_joints)
        hint = f"does not exist; closest: {listing(close)}; " if close else "does not exist; "
        if any(f.name == jname and f.type == pin.FIXED_JOINT for f in full.frames[1:]):
            hint = "is a fixed joint: it has no value to lock; the moving "
        message = f"locked joint {jname!r} {hint}joints: {listing(all_joints)}"
        raise JointError(message, joint=jname, candidates=all_joints)
    return jid


def frame_id(model: pin.Model, name: str) -> int:
    """The id of frame ``name``, a link's frame before a joint's of the same name; raises
    ``KeyError`` (``getFrameId`` would return ``nframes`` for an unknown name)."""
    for ftype in _FRAME_PREFERENCE:
        if model.existFrame(name, ftype):
            return model.getFrameId(name, ftype)
    raise KeyError(name)


def lookup_frame(full: pin.Model, name: str, role: str, frames: list[str]) -> int:
    try:
        return frame_id(full, name)
    except KeyError:
        close = closest(name, frames)
        hint = f"closest: {listing(close)}; " if close else ""
        shown = (
            f"frames: {listing(frames)}"
            if len(frames) <= 40
            else (f"'armik info <robot> --frames' lists all {len(frames)} frames")
        )
        raise FrameError(
            f"unknown {role} frame {name!r}; {hint}{shown}",
            frame=name,
            candidates=close or frames,
        ) from None


def check_frames(base: object, tip: object, source: str) -> None:
    """A ``URDFError`` for an empty source (an unset variable, say), which as a path would
    read as the current folder '.'; a ``FrameError`` for a base or tip given as anything
    but a frame name."""
    if not source.strip():
        raise URDFError(
            f"the source is empty ({source!r}): give a bundled robot name (armik.robots()), "
            "a path to a URDF file, or the URDF's XML",
            path=source,
        )
    for role, value in (("base", base), ("tip", tip)):
        if value is not None and not isinstance(value, str):
            raise FrameError(
                f"{role} must be a frame name (a str), got {value!r}; "
                f"'armik info {source} --frames' lists the frames",
                frame=str(value),
            )


def check_locked(locked: object) -> dict[str, float] | None:
    if locked is None:
        return None
    if not isinstance(locked, Mapping):
        raise JointError(
            f"locked must map joint names to values (rad or m), e.g. {{'finger': 0.0}}; "
            f"got {locked!r}",
            joint=str(locked),
        )
    for key in locked:
        if not isinstance(key, str):
            raise JointError(
                f"locked must map joint names (str) to values, got the key {key!r}",
                joint=str(key),
            )
    return dict(locked)


def check_offset(offset: object) -> tuple[float, float, float] | None:
    """``tip_offset`` as 3 finite floats (m); raises ``OptionError`` otherwise."""
    if offset is None:
        return None
    fix = "give 3 finite numbers (x, y, z) in metres in the tip frame"
    if isinstance(offset, (str, bytes)):
        raise OptionError(
            f"tip_offset must be numbers, got {offset!r}: {fix}", option="tip_offset", value=offset
        )
    try:
        arr = np.asarray(offset)
        if np.iscomplexobj(arr):
            raise TypeError
        arr = arr.astype(float)
    except (TypeError, ValueError, OverflowError):
        raise OptionError(
            f"tip_offset must be numbers, got {offset!r}: {fix}", option="tip_offset", value=offset
        ) from None
    if arr.shape != (3,):
        raise OptionError(
            f"tip_offset must have 3 values, got shape {arr.shape}: {fix}",
            option="tip_offset",
            value=offset,
        )
    if not np.isfinite(arr).all() or np.abs(arr).max() > MAX_LENGTH:
        raise OptionError(
            f"tip_offset {arr.tolist()} is not finite or beyond {MAX_LENGTH:g} m: {fix}",
            option="tip_offset",
            value=offset,
        )
    return _three(arr)


def _three(values: Iterable[float]) -> tuple[float, float, float]:
    """Three numbers as three floats."""
    x, y, z = (float(v) for v in values)
    return x, y, z


def check_package_dirs(dirs: object) -> tuple[str, ...]:
    """``package_dirs`` as a tuple of existing folders; raises ``OptionError`` otherwise."""
    if dirs is None:
        return ()
    if isinstance(dirs, (str, Path)):
        dirs = [dirs]
    try:
        items = list(dirs)  # type: ignore[call-overload]
    except TypeError:
        raise OptionError(
            f"package_dirs must be a list of folders, got {dirs!r}",
            option="package_dirs",
            value=dirs,
        ) from None
    out = []
    for d in items:
        if not isinstance(d, (str, Path)) or not Path(d).is_dir():
            raise OptionError(
                f"package_dirs: {d!r} is not an existing folder; give the folders that hold "
                "the packages package:// paths name",
                option="package_dirs",
                value=d,
            )
        out.append(str(Path(d).resolve()))
    return tuple(out)


def check_limits(
    limits: object, joint_index: Callable[[str], int]
) -> dict[str, tuple[float, float]]:
    """``with_limits``' mapping (joint name -> (lower, upper), rad or m) checked:
    ``JointError`` naming the joint for an unknown one (``joint_index`` raises it), a
    value that is not a pair of limits, or lower > upper."""
    if not isinstance(limits, Mapping):
        raise JointError(
            f"limits must map joint names to (lower, upper), got {limits!r}",
            joint=str(limits),
        )
    checked = {}
    for jname, pair in limits.items():
        if not isinstance(jname, str):
            raise JointError(f"joint names must be str, got {jname!r}", joint=str(jname))
        joint_index(jname)
        if isinstance(pair, (str, bytes)) or not hasattr(pair, "__len__") or len(pair) != 2:
            raise JointError(
                f"limits for {jname!r} must be a pair (lower, upper) in rad or m, got {pair!r}",
                joint=jname,
            )
        lo, hi = (check_limit_value(jname, v) + 0.0 for v in pair)  # -0.0 -> 0.0
        if not lo <= hi:
            raise JointError(
                f"limits for {jname!r} must satisfy lower <= upper, got ({lo}, {hi})",
                joint=jname,
            )
        checked[jname] = (lo, hi)
    return checked


def check_limit_value(jname: str, value: object) -> float:
    """A joint limit given to ``with_limits`` as a float (rad or m; +-inf: no limit on
    that side); raises ``JointError`` naming the joint otherwise."""
    try:
        if isinstance(value, NOT_NUMBERS) or np.iscomplexobj(value):  # type: ignore[arg-type]
            raise TypeError
        out = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        out = math.nan
    if math.isnan(out) or (math.isfinite(out) and abs(out) > MAX_LIMIT):
        raise JointError(
            f"limits for {jname!r} must be numbers (rad or m) within "
            f"+-{MAX_LIMIT:g}, or "
            f"-inf/inf for no limit on that side; got {value!r}",
            joint=jname,
        )
    return out


def set_joint(model: pin.Model, q: np.ndarray, jid: int, value: float) -> None:
    joint = model.joints[jid]
    if joint.nq == 1:
        q[joint.idx_q] = value
    elif joint.nq == 2 and joint.nv == 1:
        q[joint.idx_q : joint.idx_q + 2] = (math.cos(value), math.sin(value))
    else:
        raise JointError(
            f"joint {model.names[jid]!r} has {joint.nq} coordinates; it can only "
            "be locked at its neutral value",
            joint=model.names[jid],
        )


def reduce_model(full: pin.Model, to_lock: list[int], q_ref: np.ndarray, geom=None):
    """``pin.buildReducedModel`` that survives frames sharing a name (a link and a joint
    both called "quill", a link called "universe"): Pinocchio looks frames up by name there
    and raises "Several frames match the filter". For the call, later duplicates, the
    locked joints (whose frames it re-creates under the joint's name) and joints named
    "universe" (it would take the root frame, of that name, for the joint's: a wrong
    placement, not an error) get unique names; the frames get their names back afterwards.
    With ``geom`` (a ``pin.GeometryModel`` on ``full``), returns (model, reduced geometry)."""
    work = full.copy()
    renamed: dict[str, str] = {}
    joint_tmp: dict[int, str] = {}
    universe = [j for j in range(1, full.njoints) if full.names[j] == "universe"]
    for j in [*to_lock, *universe]:  # a joint and its JOINT frame keep one (temporary) name
        joint_tmp[j] = f"{full.names[j]}\x00armik-joint{j}"
        renamed[joint_tmp[j]] = full.names[j]
        work.names[j] = joint_tmp[j]
    seen: set[str] = set()
    for i, frame in enumerate(work.frames):
        tmp = None
        if frame.type == pin.JOINT and frame.parentJoint in joint_tmp:
            tmp = joint_tmp[frame.parentJoint]
        elif frame.name in seen:
            tmp = f"{frame.name}\x00armik{i}"
            renamed[tmp] = frame.name
        if tmp is not None:
            frame.name = tmp
            work.frames[i] = frame
        seen.add(frame.name)
    if geom is None:
        model = pin.buildReducedModel(work, to_lock, q_ref)
    else:
        model, (geom,) = pin.buildReducedModel(work, [geom], to_lock, q_ref)
    for i, frame in enumerate(model.frames):
        if frame.name in renamed:
            frame.name = renamed[frame.name]
            model.frames[i] = frame
    for j in range(model.njoints):
        if model.names[j] in renamed:
            model.names[j] = renamed[model.names[j]]
    return model if geom is None else (model, geom)
