"""Several tips' kinematics in ``Arm``'s words (``armik.arms.Arms`` has them): a
configuration over every joint split into each chain's, the placement and Jacobian of every
tip or of one frame, tip poses of many configurations, the joint limits, random
configurations, the names and frames; a copy with limits replaced or joints locked on every
chain that holds them. Each answer is its chain's own (``armik.model.frames``, the chain's
model), the joints of the other chains zero in a Jacobian. Beside them, ``Arm``'s
``min_distance`` and ``in_collision`` over every chain's links (``armik.arms_collision``)
and ``intervals`` of one chain's self-motion (``armik.solve.intervals``).
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping
from typing import Any, cast

import numpy as np
import pinocchio as pin

from armik import arms_collision, checked
from armik.arms_options import chain_constraints
from armik.arms_tasks import placing
from armik.constraints.base import own
from armik.constraints.srdf import Pair
from armik.errors import FrameError, JointError, OptionError, TargetError, warn
from armik.model import frames
from armik.model.arm_model import ArmModel
from armik.model.limit_units import degrees_note
from armik.model.reduce import check_limits
from armik.model.union import Union
from armik.solve.intervals import Intervals, intervals
from armik.tolerances import LIMIT_TOL

MOST_SAMPLES = 10**8  # random_q's n, as Arm.random_q takes it


class ArmsKinematics:
    """What ``Arms`` answers about its joints and frames, without solving."""

    tips: tuple[str, ...]
    joint_names: tuple[str, ...]
    dof: int
    lower: np.ndarray
    upper: np.ndarray
    shared: tuple[str, ...]  # the joints more than one chain holds
    _facades: dict[str, Any]  # tip -> its ``Arm``
    _chains: dict[str, ArmModel]
    _columns: dict[str, np.ndarray]
    _union: Union | None  # the chains in one model where they share joints
    _coupled: Union | None  # else, built for the first task that couples them
    _permutation: np.ndarray | None  # ``joint_names``' columns in ``_coupled``
    # tip -> its chain's model within the robot, the links another chain moves left out
    # of its collision geometry (``armik.arms_apart.chains``): None until a solve on chains
    # that share no joint first checks collisions, then kept; a new robot (``with_limits``,
    # ``with_locked``, a backend's copy) starts without it
    _apart: dict[str, ArmModel] | None
    # (obstacles, self_collision) -> the checker of the robot's links against them
    # (``armik.arms_collision``), the last ``MOST_CHECKERS`` kept; a new robot starts empty
    _checkers: dict[tuple[tuple, bool], arms_collision.ArmsChecker]

    def chain(self, tip: str):
        """The ``Arm`` from the base to ``tip``."""
        return self._facades[self._known(tip)]

    @property
    def base(self) -> str:
        """The frame every chain starts from (``Arm.base``)."""
        return next(iter(self._chains.values())).base

    @property
    def tip_offsets(self) -> dict[str, tuple[float, float, float]]:
        """Each tip's tool point offset (``Arm.tip_offset``, m in the tip's frame), for the
        tips that have one."""
        chains = self._chains.items()
        return {tip: arm.tip_offset for tip, arm in chains if arm.tip_offset is not None}

    @property
    def neutral(self) -> np.ndarray:
        """Each joint's neutral value (``Arm.neutral``), in the order of ``joint_names``."""
        return self._by_joint(lambda arm: arm.neutral)

    @property
    def joint_types(self) -> list[str]:
        """Each joint's URDF type (``Arm.joint_types``), in the order of ``joint_names``."""
        return [str(t) for t in self._by_joint(lambda arm: arm.joint_types)]

    def _by_joint(self, read) -> np.ndarray:
        """``read(chain)`` (one value per joint of that chain) over ``joint_names``."""
        each: dict[str, Any] = {}
        for arm in self._facades.values():
            each.update(zip(arm.joint_names, read(arm)))
        return np.array([each[n] for n in self.joint_names])

    def frames(self) -> list[str]:
        """The frames of every chain's model, each once (``Arm.frames``): what ``fk`` and
        ``jacobian`` take as ``frame``."""
        names = [f for arm in self._chains.values() for f in arm.frames()]
        return list(dict.fromkeys(names))

    def with_limits(self, limits: Mapping[str, tuple[float, float]]):
        """A copy of this robot with some joint limits replaced (name -> (lower, upper), rad
        or m), on every chain that holds the joint (``Arm.with_limits``)."""
        given = check_limits(limits, self._joint_index)
        chains = {}
        for tip, arm in self._facades.items():
            on = {n: v for n, v in given.items() if n in arm.joint_names}
            # the others' kept too: a lock of one on this chain is checked against them
            off = {n: v for n, v in given.items() if n not in on}
            chains[tip] = type(arm)(arm.kinematics.with_limits(on, others=off))
        return self._rebuilt(chains)

    def with_locked(self, locked: Mapping[str, float]):
        """A new robot with the joints of ``locked`` (name -> rad or m) locked at those
        values on every chain (``Arm.with_locked``: on or off a chain, its errors)."""
        return self._rebuilt({tip: arm.with_locked(locked) for tip, arm in self._facades.items()})

    def _one_start(self, options: dict, q0: object) -> None:
        """An ``OptionError`` for a user's constraint resolved from the start (its own
        ``at``) on a chain whose joints a batch's q0 sets differently row to row, as
        ``Arm.solve_batch`` refuses it (``constraints.base.at_start``): chains solved apart
        refused it in their own batch, chains solved together resolved it from each row's
        q0. A q0 that is no rows of configurations is left to the batch's own words."""
        given = chain_constraints(options, self.tips)
        if not given or q0 is None or isinstance(q0, (str, bytes)):
            return
        if np.iscomplexobj(q0):  # type: ignore[arg-type]
            return
        try:
            Q = np.asarray(q0, dtype=float)
        except (TypeError, ValueError, OverflowError):
            return
        if Q.ndim != 2 or len(Q) < 2 or Q.shape[1] != self.dof:
            return
        for tip, items in given.items():
            resolved = [c for c in items if own(c)]
            rows = Q[:, self._columns[tip]]
            if resolved and not np.array_equal(rows, rows[[0] * len(rows)], equal_nan=True):
                raise OptionError(
                    f"constraint {type(resolved[0]).__name__} (constraints[{tip!r}]) is "
                    "resolved from the start (its at(arm, seed)), and this batch gives a "
                    "different q0 per row on that chain's joints: give one q0 for every row, "
                    "or solve the rows one by one",
                    option="constraints",
                    value=resolved[0],
                )

    def _rebuilt(self, chains: dict[str, Any]) -> Any:
        """A robot of this type over ``chains`` (tip -> ``Arm``), as ``armik.load`` builds."""
        make: Any = type(self)
        return make(chains)

    def _joint_index(self, name: str) -> int:
        """Index of joint ``name`` in ``joint_names``; ``JointError`` listing them."""
        if name not in self.joint_names:
            raise JointError(
                f"unknown joint {name!r}; this robot's joints: {list(self.joint_names)}",
                joint=name,
                candidates=self.joint_names,
            )
        return self.joint_names.index(name)

    def _joint(self) -> Union:
        """Every chain in one model: the union where they share joints, else built for the
        first task (or servo) that couples them."""
        if self._union is not None:
            return self._union
        if self._coupled is None:
            self._coupled = Union(list(self._chains.values()))
            names = self._coupled.joint_names
            self._permutation = np.array([names.index(n) for n in self.joint_names])
        return self._coupled

    def _known(self, tip: str) -> str:
        """``tip``, or ``FrameError`` naming the robot's tips."""
        if not isinstance(tip, str) or tip not in self._chains:
            raise FrameError(
                f"unknown tip {tip!r}; this robot's tips: {list(self.tips)}",
                frame=tip,
                candidates=self.tips,
            )
        return tip

    def _seed(self, q0: object, row: int | None = None) -> np.ndarray:
        """``q0`` (one value per joint of ``joint_names``) checked, and clipped into the
        limits with an ``ArmikWarning`` where it lies outside them, as ``Arm``'s seed is: a
        tip left out keeps these values, so the robot's answer stays within its limits
        (``row``: the row of a batch's q0 it is)."""
        q = checked.configuration("q0", q0, self.joint_names)
        if bool(np.all(q >= self.lower - LIMIT_TOL) and np.all(q <= self.upper + LIMIT_TOL)):
            return q
        said = dict.fromkeys(
            text
            for tip, arm in self._chains.items()
            for text in arm.limit_violations(q[self._columns[tip]])
        )
        where = "q0" if row is None else f"q0's row {row}"
        said_all = "; ".join(said) + degrees_note(q, self)
        warn(f"{where} outside the joint limits was clipped into them: {said_all}")
        return np.clip(q, self.lower, self.upper)

    def split(self, q: object) -> dict[str, np.ndarray]:
        """``q`` (one value per joint of ``joint_names``) as each chain's joint values."""
        try:
            if isinstance(q, (str, bytes)) or np.iscomplexobj(q):  # type: ignore[arg-type]
                raise TypeError
            arr = np.asarray(q, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            arr = None
        if arr is None or arr.shape != (self.dof,):
            got = f"{arr.size} values" if arr is not None else repr(q)
            raise OptionError(
                f"q must hold {self.dof} values, one per joint of {list(self.joint_names)}, "
                f"got {got}",
                option="q",
                value=q,
            )
        return {tip: arr[cols] for tip, cols in self._columns.items()}

    def fk(self, q: object, frame: str | None = None) -> dict[str, pin.SE3] | pin.SE3:
        """``T_base_frame`` at ``q`` of ``frame`` (a tip or any frame of a chain); without
        ``frame``, every tip's: {tip: ``T_base_tip``} in the order of ``tips``."""
        if frame is None:
            each = self.split(q)
            return {tip: frames.placement(self._chains[tip], each[tip]) for tip in self.tips}
        tip = self._chain_of(frame)
        return frames.placement(self._chains[tip], self.split(q)[tip], frame)

    def jacobian(
        self, q: object, frame: str | None = None, reference: str | None = None
    ) -> dict[str, np.ndarray] | np.ndarray:
        """The 6 x dof Jacobian over every joint of ``frame`` (a tip or any frame of a
        chain), in its own axes (``reference="local"``) or the base's (``"base"``); zero
        for the joints not on its chain (``armik.model.frames``). Without ``frame``, every
        tip's: {tip: J} in the order of ``tips``."""
        model = self._chains[self.tips[0]].model  # each chain's holds every frame
        frame, reference = frames.frame_and_reference(frame, reference, model)
        each = self.split(q)
        out = {}
        for tip in self.tips if frame is None else (self._chain_of(frame),):
            J = np.zeros((6, self.dof))
            J[:, self._columns[tip]] = frames.jacobian(
                self._chains[tip], each[tip], frame, reference
            )
            out[tip] = J
        return out if frame is None else out[tip]

    def fk_batch(self, Q: object) -> dict[str, np.ndarray]:
        """Every tip's poses ``T_base_tip`` (N, 4, 4) of joint values Q (N, dof), rad or m,
        by its chain's compiled FK (``Arm.fk_batch``): {tip: poses} in the order of ``tips``."""
        try:
            if isinstance(Q, (str, bytes)) or np.iscomplexobj(Q):  # type: ignore[arg-type]
                raise TypeError
            arr = np.array(Q, dtype=float, ndmin=2)
        except (TypeError, ValueError):
            raise OptionError(
                f"Q must be an (N, {self.dof}) array of joint values, got {Q!r}",
                option="Q",
                value=Q,
            ) from None
        if arr.ndim != 2 or arr.shape[1] != self.dof:
            raise OptionError(
                f"Q must have shape (N, {self.dof}), one row per configuration (joints "
                f"{list(self.joint_names)}), got {arr.shape}",
                option="Q",
                value=Q,
            )
        if not np.isfinite(arr).all():  # the robot's row and joint, not a chain's part of it
            i, j = np.argwhere(~np.isfinite(arr))[0]
            raise OptionError(
                f"row {i} of Q is not finite at {self.joint_names[j]!r}: {arr[i].tolist()}",
                option="Q",
                value=Q,
            )
        return {tip: self._chains[tip].fk_batch(arr[:, self._columns[tip]]) for tip in self.tips}

    def within_limits(self, q: object, tol: float = LIMIT_TOL) -> bool:
        """Whether every joint of ``q`` (one configuration, ``dof`` values; a NaN is
        outside) lies within its limits (``tol`` rad or m beyond); ``OptionError`` naming
        ``q`` when it is not one configuration of this robot."""
        arr = checked.configuration("q", q, self.joint_names, finite=False)
        tol = checked.number("tol", tol)
        return bool(np.all(arr >= self.lower - tol) and np.all(arr <= self.upper + tol))

    def _chain_of(self, frame: str) -> str:
        """The tip whose chain has ``frame``; ``FrameError`` naming the closest frames."""
        tip = placing(self._chains, frame) if isinstance(frame, str) else None
        if tip in self._chains:
            return cast(str, tip)
        names = self.frames()
        close = difflib.get_close_matches(str(frame), names, n=3)
        raise FrameError(
            f"frame {frame!r} is on no chain of tips {list(self.tips)}; closest: "
            f"{', '.join(map(repr, close)) or 'none'}; robot.frames() lists every frame",
            frame=str(frame),
            candidates=close or names,
        )

    def _random(self, rng: np.random.Generator) -> np.ndarray:
        """A random configuration within the limits, in ``joint_names``'s order."""
        if self._union is not None:
            return self._union.random_q(rng)
        return np.concatenate([a.random_q(rng) for a in self._chains.values()])

    def random_q(
        self, rng: np.random.Generator | int | None = None, n: int | None = None
    ) -> np.ndarray:
        """Uniform joint values within the limits, unlimited joints in [-pi, pi]: one
        configuration (dof,), or ``n`` of them (n, dof). ``rng``: a generator or a seed."""
        gen = checked.generator("rng", rng)
        if n is None:
            return self._random(gen)
        rows = checked.integer("n", n, 0, MOST_SAMPLES)
        out = np.empty((rows, self.dof))
        for i in range(rows):
            out[i] = self._random(gen)
        return out

    def min_distance(
        self, q: object, obstacles: object = (), self_collision: bool = False
    ) -> tuple[float, Pair | None]:
        """(distance m, (name_a, name_b)): the closest pair at joint values ``q`` (rad, m,
        one per joint of ``joint_names``) among every chain's links and ``obstacles``
        (shapes in the base frame) and, with ``self_collision``, the robot's own links, of
        one chain and between chains (``armik.arms_collision``); negative when they
        overlap. Raises ``CollisionError`` when the URDF has no collision geometry."""
        return arms_collision.min_distance(self, q, obstacles, self_collision)

    def in_collision(
        self, q: object, obstacles: object = (), self_collision: bool = False, margin: float = 0.0
    ) -> bool:
        """Whether some pair ``min_distance`` checks is closer than ``margin`` (m) at ``q``."""
        return arms_collision.in_collision(self, q, obstacles, self_collision, margin)

    def intervals(self, target: object, over: str, *, q0: object = None) -> Intervals:
        """Each branch's intervals of ``over`` within the limits (``Arm.intervals``) on the
        chain it parametrises: ``over`` a joint (the chain that holds it), or an option
        ("swivel") of the one tip ``target`` names; ``target`` as ``solve``'s, {tip:
        target} (other tips' targets unread), ``q0`` over every joint."""
        if not isinstance(target, Mapping) or not target:
            raise OptionError(
                f"target must map a tip of {list(self.tips)} to its target, {{tip: target}}, "
                f"got {target!r:.80}",
                option="target",
                value=target,
            )
        given = [self._known(t) for t in target]
        if not isinstance(over, str):
            raise OptionError(
                f'over must name a joint or an option ("swivel"), got {over!r:.80}',
                option="over",
                value=over,
            )
        holding = [t for t in self.tips if over in self._chains[t].joint_names]
        if len(holding) > 1:
            raise OptionError(
                f"joint {over!r} is on the chains of tips {holding}: its value moves each of "
                "them, where intervals are one chain's self-motion; give a joint of one chain",
                option="over",
                value=over,
            )
        if not holding and len(given) > 1:
            raise OptionError(
                f"over={over!r} is a parameter of one chain, and target names tips {given}: "
                "give one tip's target, {tip: target}",
                option="over",
                value=over,
            )
        tip = holding[0] if holding else given[0]
        if tip not in target:
            raise TargetError(
                f"joint {over!r} is on the chain to {tip!r}: give that tip's target, "
                f"{{{tip!r}: target}}"
            )
        seed = None
        if q0 is not None:
            seed = checked.configuration("q0", q0, self.joint_names)[self._columns[tip]]
        return intervals(self._chains[tip], target[tip], over, seed)
