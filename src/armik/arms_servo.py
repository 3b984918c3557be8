"""A servo on several tips of one robot (``Arms.servo``): one target per tip a tick.

Chains that share no moving joint (two arms on one base) each get a ``Servo`` of their own
(``armik.servo``), ticked side by side: every limit holds on each chain's joints, so on the
robot's. The joined ``ServoStep`` holds the robot's ``q``, ``dq``, ``ddq`` (the chains'
joints side by side, in the order of ``tips``, as ``Arms.joint_names``), the status of the
tip most held back (``PRECEDENCE``), the largest errors and the smallest singular value
over the tips, and each tip's own step in ``tips``. ``velocity_limits`` and
``acceleration_limits`` are the robot's, as over shared joints: a number, one per joint of
``Arms.joint_names`` or a mapping by its joint names, each chain given its joints' part.

Chains that share joints (a torso, a lift) take one step over their union instead
(``armik.servo.union``): every tip's target at once (anything a chain's own servo takes),
every limit on every joint, obstacles and self-collision (between the chains too) as rows
of that step (``armik.servo.union_collisions``). Not supported, and refused by name:
``self_collision`` on chains that share no joint (each chain would check only itself,
never the other arm).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING

import numpy as np

from armik.arms_apart import facade
from armik.arms_tasks import by_tip
from armik.checked import configuration
from armik.errors import JointError, OptionError, TargetError
from armik.frozen import frozen
from armik.model.arm_model import ArmModel
from armik.problem.tasks.base import replaced
from armik.servo.collisions import margin_given
from armik.servo.result import ServoRecord, ServoStatus, ServoStep, record
from armik.servo.servo import Servo, refuse_unknown, start
from armik.servo.table import at_tick, read, sequence
from armik.servo.union import KEYWORDS as UNION_KEYWORDS
from armik.servo.union import UnionServo

if TYPE_CHECKING:
    from armik.arms_kinematics import ArmsKinematics

# the joined step's status: the first of these that some tip's step has
PRECEDENCE = (
    ServoStatus.OUT_OF_REACH,
    ServoStatus.OBSTACLE,
    ServoStatus.JOINT_LIMIT,
    ServoStatus.VELOCITY_LIMIT,
    ServoStatus.ACCELERATION_LIMIT,
    ServoStatus.SINGULARITY,
    ServoStatus.STALLED,
    ServoStatus.TRACKING,
    ServoStatus.ON_TARGET,
)


LIMITS = ("velocity_limits", "acceleration_limits")  # per joint of the robot, split by chain


def split_limits(arms: ArmsKinematics, name: str, value: object) -> dict[str, object]:
    """``value`` (a number, one per joint of ``arms.joint_names``, or a mapping from those
    joints' names) as each tip's chain's: the number itself, its joints' values, its joints'
    part of the mapping. Raises ``OptionError`` for another length, ``JointError`` for a
    name no chain has; each chain's servo checks the values."""
    names = list(arms.joint_names)
    if isinstance(value, Mapping):
        unknown = [joint for joint in value if joint not in names]
        if unknown:
            raise JointError(
                f"{name} names {unknown}, not joints of this robot; its joints: {names}",
                joint=str(unknown[0]),
                candidates=names,
            )
        return {
            tip: {j: v for j, v in value.items() if j in arms.chain(tip).joint_names}
            for tip in arms.tips
        }
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        arr = None
    if arr is None or arr.ndim > 1 or (arr.ndim == 1 and arr.shape != (arms.dof,)):
        got = f"shape {arr.shape}" if arr is not None else repr(value)
        raise OptionError(
            f"{name} must be a number, one per joint of the robot ({arms.dof}: "
            f"{', '.join(names)}) or a mapping by those names, got {got}",
            option=name,
            value=value,
        )
    if arr.ndim == 0:
        return {tip: value for tip in arms.tips}
    return {tip: arr[cols] for tip, cols in arms._columns.items()}


class ArmsServo:
    """One ``Servo`` per chain of an ``Arms`` whose chains share no joint, at rest at
    ``q0`` (one value per joint of ``Arms.joint_names``), the options each chain's
    (``Arm.servo``'s); one ``UnionServo`` over chains that share joints. Raises
    ``OptionError`` for ``self_collision`` on chains that share no joint, and for an
    option the union's servo does not take."""

    def __init__(self, arms: ArmsKinematics, q0: object, **options: object) -> None:
        if options.get("self_collision") and not arms.shared:
            raise OptionError(
                "self_collision is not supported by a servo on several tips whose chains "
                "share no joint: each chain would check itself only, never the other; give "
                "obstacles=, or servo one chain (arms.chain(tip).servo(..., "
                "self_collision=True))",
                option="self_collision",
                value=options["self_collision"],
            )
        refuse_unknown(options)  # what no servo takes, with the way to say it
        margin_given(options)
        self.tips = arms.tips
        self._tip_set = set(arms.tips)
        self.joint_names = arms.joint_names
        self._servos: dict[str, Servo] = {}
        self._union: UnionServo | None = None
        if arms.shared:  # one step over the union of the chains
            for name, value in options.items():
                if name not in UNION_KEYWORDS:
                    raise OptionError(
                        f"{name}= is not supported by a servo over chains that share joints "
                        f"({list(arms.shared)}); its options: {', '.join(UNION_KEYWORDS)}. "
                        "Servo a chain of its own (arms.chain(tip).servo(...)) for it",
                        option=name,
                        value=value,
                    )
            chains = {tip: arms.chain(tip).kinematics for tip in arms.tips}
            self._union = UnionServo(arms._joint(), chains, q0, **options)  # type: ignore[arg-type]
            self.dt = self._union.dt
            return
        parts = arms.split(configuration("q0", q0, self.joint_names))
        each = {tip: dict(options) for tip in arms.tips}
        for name in LIMITS:
            if options.get(name) is not None:
                for tip, value in split_limits(arms, name, options[name]).items():
                    each[tip][name] = value
        # each chain's scene leaves out the links another chain moves (that chain's servo
        # keeps them clear): held where it was cut, they are no obstacle of its own
        self._servos = {
            tip: start(facade(arms, tip, each[tip]), parts[tip], **each[tip]) for tip in arms.tips
        }
        self.dt = next(iter(self._servos.values())).dt

    def servo(self, tip: str) -> Servo:
        """The ``Servo`` of ``tip``'s chain (chains that share no joint)."""
        if tip not in self.tips:
            raise TargetError(f"unknown tip {tip!r}; this robot's tips: {list(self.tips)}")
        if self._union is not None:
            raise OptionError(
                f"the chains of {list(self.tips)} share joints: one servo steps their union, "
                "no chain has a servo of its own here",
                option="tip",
                value=tip,
            )
        return self._servos[tip]

    def _joined(self, name: str) -> np.ndarray:
        if self._union is not None:
            return getattr(self._union, name)  # type: ignore[no-any-return]
        return np.concatenate([getattr(s, name) for s in self._servos.values()])

    @property
    def q(self) -> np.ndarray:
        """The last commanded joint values (rad, m), in the order of ``joint_names``."""
        return self._joined("q")

    @property
    def dq(self) -> np.ndarray:
        return self._joined("dq")

    @property
    def velocity_limits(self) -> np.ndarray:
        return self._joined("velocity_limits")

    @property
    def acceleration_limits(self) -> np.ndarray:
        return self._joined("acceleration_limits")

    def step(self, targets: Mapping[str, object]) -> ServoStep:
        """One tick of every chain toward its tip's target (``targets``: tip -> anything
        ``Arm.servo``'s ``step`` takes); the joined step (module docstring). Raises
        ``TargetError`` unless every tip has a target and no other is named, and naming
        the tip whose target it cannot read; every target is read before any chain ticks,
        so that a refused step moves none. A flat list of tasks, each naming its frame, is
        read as that mapping (``Arms.solve``'s)."""
        if type(targets) is list or type(targets) is tuple:
            targets = _by_tip(self._arms(), targets)
        if type(targets) is not dict or targets.keys() != self._tip_set:
            self._check(targets)  # (a dict over the tips, the common case, needs none)
        if self._union is not None:
            return self._union.step(targets)
        tables = {tip: _read(tip, targets[tip], s.arm) for tip, s in self._servos.items()}
        steps = {tip: s._tick(targets[tip], tables[tip]) for tip, s in self._servos.items()}
        first = min(steps.values(), key=lambda s: PRECEDENCE.index(s.status))
        command = np.concatenate([np.stack([s.q, s.dq, s.ddq]) for s in steps.values()], axis=1)
        command.flags.writeable = False

        def largest(name: str) -> float | None:
            values = [getattr(s, name) for s in steps.values() if getattr(s, name) is not None]
            return max(values) if values else None

        return frozen(
            ServoStep,
            q=command[0],
            dq=command[1],
            ddq=command[2],
            status=first.status,
            joint=first.joint,
            position_error=largest("position_error"),
            orientation_error=largest("orientation_error"),
            sigma=min(s.sigma for s in steps.values()),
            conflict=any(s.conflict for s in steps.values()),
            tips=steps,
        )

    def _check(self, targets: object) -> None:
        """Raises ``TargetError`` unless ``targets`` maps every tip and no other."""
        if not isinstance(targets, Mapping):
            raise TargetError(
                f"a servo on several tips takes one target per tip, a mapping "
                f"{{tip: target}} over {list(self.tips)} or a list of tasks each naming its "
                f"frame (armik.Pose(T, frame=tip)), got {type(targets).__name__}"
            )
        unknown = [t for t in targets if t not in self.tips]
        missing = [t for t in self.tips if t not in targets]
        if unknown or missing:
            raise TargetError(
                f"one target per tip of {list(self.tips)}: "
                + "; ".join(
                    part
                    for part in (
                        f"unknown tips {unknown}" if unknown else "",
                        f"no target for {missing}" if missing else "",
                    )
                    if part
                )
            )

    def track(self, targets: Iterable[Mapping[str, object]]) -> ServoRecord:
        """``step`` through ``targets`` (one mapping tip -> target a tick), in order. Every
        target is read before the first tick: raises ``TargetError`` naming the first tick
        and tip it cannot read (no tick run), ``OptionError`` for one mapping given alone
        (``step`` takes one) or none."""
        items = sequence(targets, mapping=True)
        arms = self._arms()
        for i, mapping in enumerate(items):
            try:
                if isinstance(mapping, (list, tuple)):  # a flat list of tasks
                    items[i] = mapping = _by_tip(arms, mapping)
                self._check(mapping)
                for tip in self.tips:
                    _read(tip, mapping[tip], arms[tip])
            except TargetError as error:
                raise at_tick(i, error) from None
        return record([self.step(t) for t in items])

    def _arms(self) -> dict[str, ArmModel]:
        """Each tip's chain, whose targets it reads."""
        if self._union is not None:
            return dict(self._union._chains)  # type: ignore[arg-type]
        return {tip: s.arm for tip, s in self._servos.items()}


def _by_tip(chains: Mapping[str, ArmModel], tasks: list | tuple) -> object:
    """A flat list of tasks as the mapping tip -> its tasks (``arms_tasks.by_tip``), each
    task on its tip said without its frame, as a chain's servo takes it."""
    out = by_tip(chains, tasks)
    if type(out) is not dict:
        return out  # not tasks: ``_check`` names what is wrong
    return {
        tip: [replaced(t, frame=None) if t.frame == tip else t for t in each]
        for tip, each in out.items()
    }


def _read(tip: str, target: object, arm: ArmModel) -> np.ndarray | None:
    """``table.read`` of ``tip``'s target; its ``TargetError`` naming the tip."""
    try:
        return read(target, arm)
    except TargetError as error:
        raise TargetError(f"the target of tip {tip!r}: {error}") from None
