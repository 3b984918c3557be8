"""A servo over chains that share joints (a torso, a lift): one step over their union.

``Arms.servo`` on tips whose chains share a joint ticks this instead of one ``Servo`` per
chain: every tip's task is stacked over the union's joints (``armik.model.union``'s, in
its base frame), and one damped least-squares step goes toward all of
them at once, within the velocity box of ``armik.servo.box`` on every joint (position,
velocity, acceleration and braking limits), by the box QP of ``kernel.step.active_set``.
What a chain's own servo does the same way: the damping grows near a singularity (the
smallest singular value of the stacked Jacobian) and with the error, the joints that the
tasks leave free are pulled toward ``q0``, and the step corrects ``gain`` of the error a
tick. A tip's target is a pose or a position; a region, an axis or a look-at (which a
chain's own servo takes) is refused by name, as are obstacles and ``self_collision``.

The rows and the step are compiled (``armik.servo.union_tick``: each chain's kernel FK, its
columns scattered into the union's); the targets are read and the result built in Python.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from armik.errors import OptionError, TargetError
from armik.frozen import frozen
from armik.model.union import Union
from armik.problem.tasks import Pose, Position
from armik.servo.limits import (
    DEFAULT_ACCELERATION,
    gain_of,
    per_joint,
    time_step,
    urdf_velocities,
)
from armik.servo.result import STATUSES, ServoStatus, ServoStep
from armik.servo.union_tick import damped_step, task_rows
from armik.targets.pose import Target, parse_target

SINGULAR = 0.05  # as ``armik.servo.servo``: below this smallest singular value ...
DAMPING = 0.005  # ... the damping grows up to this at 0
DAMPING_ERROR = 0.1  # and by this times the squared error
LAMBDA_MIN = 1e-9
PULL = 2.0  # 1/s toward q0 where the tasks leave joints free
ON_TARGET = 1e-6  # m and rad
REACH_SLACK = 1e-3  # m beyond a chain's reach bound before its target is out of reach
BRAKED = 1e-3  # m: slowing to stop on a target farther than this is reported
KEYWORDS: tuple[str, ...] = ("dt", "velocity_limits", "acceleration_limits", "gain")
KEYWORDS += ("tol_position", "tol_orientation")


class UnionServo:
    """One servo over the union of ``chains`` (tip -> its ``ArmModel``) held in ``union``,
    at rest at ``q0`` (one value per joint of ``union.joint_names``)."""

    def __init__(
        self,
        union: Union,
        chains: Mapping[str, object],
        q0: object,
        *,
        dt: object = 0.002,
        velocity_limits: object = None,
        acceleration_limits: object = None,
        gain: object = 1.0,
        tol_position: float = ON_TARGET,
        tol_orientation: float = ON_TARGET,
    ) -> None:
        self.union, self.tips = union, tuple(chains)
        self._chains = dict(chains)
        self.joint_names = union.joint_names
        n = union.dof
        self.dt = time_step(dt)
        try:
            q = np.asarray(q0, dtype=float) if q0 is not None else union.middle.copy()
        except (TypeError, ValueError):
            q = np.full(1, np.nan)  # refused below, by name
        if q.shape != (n,) or not np.all(np.isfinite(q)):
            raise OptionError(
                f"q0 must hold {n} finite joint values ({', '.join(self.joint_names)}), got {q0!r}",
                option="q0",
                value=q0,
            )
        if not union.within_limits(q, 0.0):
            raise OptionError(
                "q0 must lie within the joint limits (a servo never commands a position "
                "outside them)",
                option="q0",
                value=q0,
            )
        self._vmax = per_joint(velocity_limits, union, "velocity_limits", urdf_velocities(union))
        self._amax = per_joint(
            acceleration_limits, union, "acceleration_limits", np.full(n, DEFAULT_ACCELERATION)
        )
        g = gain_of(gain)
        self._gain, self._tol = g, (float(tol_position), float(tol_orientation))
        self._q, self._v, self._rest = q.copy(), np.zeros(n), q.copy()
        self._last: dict[str, Target] | None = None  # the last tick's targets
        # the chains' kernel arrays one after the other, and their joints' union columns
        flats = [chains[tip].kernel_chain.flat for tip in self.tips]  # type: ignore[attr-defined]
        self._packed = np.concatenate([f.packed for f in flats])
        self._kinds = np.concatenate([f.kind for f in flats])
        self._pack_at = np.cumsum([0] + [f.packed.shape[0] for f in flats]).astype(np.int64)
        self._kind_at = np.cumsum([0] + [f.kind.shape[0] for f in flats]).astype(np.int64)
        cols = [[self.joint_names.index(j) for j in chains[t].joint_names] for t in self.tips]  # type: ignore[attr-defined]
        self._maps = np.array([c for part in cols for c in part], dtype=np.int64)
        self._map_at = np.cumsum([0] + [len(c) for c in cols]).astype(np.int64)
        most = max(len(c) for c in cols)
        tips = len(self.tips)
        # the kernel FK's scratch: R, p, each joint's origin and axis, a chain's q, a log,
        # R_goal R^T, and an empty restart table cut to each chain's joints
        self._fk = (
            np.empty((3, 3)),
            np.empty(3),
            np.empty((most, 3)),
            np.empty((most, 3)),
            np.empty(most),
            np.empty(3),
            np.empty((3, 3)),
            np.empty((0, most)),
        )
        self._goal_R, self._goal_p = np.empty((tips, 3, 3)), np.empty((tips, 3))
        self._last_R, self._last_p = np.empty((tips, 3, 3)), np.empty((tips, 3))
        self._rotated = np.zeros(tips, dtype=np.bool_)
        self._E, self._E_last = np.empty(6 * tips), np.empty(6 * tips)
        self._A = np.empty((6 * tips, n))
        self._settings = np.array([SINGULAR, DAMPING, DAMPING_ERROR, LAMBDA_MIN, PULL])
        self._scratch = (
            np.empty(n),
            np.empty(n),
            np.empty(n),
            np.zeros((5, n), dtype=np.int64),
            np.zeros((n, n)),
            np.zeros(n),
            np.zeros(n),
            np.zeros((n, n)),
            np.zeros(n),
        )

    @property
    def q(self) -> np.ndarray:
        """The last commanded joint values (rad, m), in the order of ``joint_names``."""
        return self._q.copy()

    @property
    def dq(self) -> np.ndarray:
        return self._v.copy()

    @property
    def velocity_limits(self) -> np.ndarray:
        return self._vmax.copy()

    @property
    def acceleration_limits(self) -> np.ndarray:
        return self._amax.copy()

    def step(self, targets: Mapping[str, object]) -> ServoStep:
        """One tick toward every tip's target (a pose or a position each)."""
        goals = {tip: _goal(tip, targets[tip]) for tip in self.tips}
        last = self._last if self._last is not None and _alike(self._last, goals) else goals
        gR, gp, lR, lp, rotated = (
            self._goal_R,
            self._goal_p,
            self._last_R,
            self._last_p,
            self._rotated,
        )
        for t, tip in enumerate(self.tips):
            goal, before = goals[tip], last[tip]
            gp[t], lp[t] = goal.position, before.position
            rotated[t] = goal.rotation is not None
            if rotated[t]:
                gR[t], lR[t] = goal.rotation, before.rotation
        union, dt = self.union, self.dt
        E, E_last, A = self._E, self._E_last, self._A
        m = self._rows(self._q, gR, gp, lR, lp, True)
        lb, ub, v, ints, Hh, gap, mult, Lm, x = self._scratch
        sigma, slowed, code, j, conflict = damped_step(
            A[:m], E[:m], E_last[:m], self._q, self._v, self._rest, union.lower, union.upper,
            self._vmax, self._amax, dt, self._gain, self._settings,
            lb, ub, v, ints, Hh, gap, mult, Lm, x,
        )  # fmt: skip
        q = np.minimum(np.maximum(self._q + v * dt, union.lower), union.upper)
        v = (q - self._q) / dt
        a = (v - self._v) / dt
        self._q, self._v, self._last = q, v, goals
        self._rows(q, gR, gp, gR, gp, False)
        pos, ori = _distances(E[:m], rotated)
        status = self._status(code, sigma, goals, pos, ori)
        if status is ServoStatus.TRACKING and slowed < 1.0 and pos > BRAKED:
            status = ServoStatus.ACCELERATION_LIMIT  # slowing to stop on a far target
        command = np.stack([q, v, a])
        command.flags.writeable = False
        return frozen(
            ServoStep,
            q=command[0],
            dq=command[1],
            ddq=command[2],
            status=status,
            joint=self.joint_names[j] if j >= 0 and status is STATUSES[code] else None,
            position_error=pos,
            orientation_error=ori,
            sigma=sigma,
            conflict=bool(conflict),
            tips=None,
        )

    def _rows(self, q, goal_R, goal_p, last_R, last_p, jac: bool) -> int:
        """``task_rows`` at q: ``_E`` toward the goals, ``_E_last`` toward the last ones
        (and ``_A`` with ``jac``); the rows written."""
        fk_R, fk_p, origins, axes, qc, w, M, flat0 = self._fk
        return int(
            task_rows(
                self._packed, self._pack_at, self._kinds, self._kind_at, self._maps,
                self._map_at, q, goal_R, goal_p, last_R, last_p, self._rotated, self._E,
                self._E_last, self._A, jac, fk_R, fk_p, origins, axes, qc, w, M, flat0,
            )
        )  # fmt: skip

    def _status(self, code: int, sigma: float, goals: dict, pos: float, ori) -> ServoStatus:
        """What limited the tick: a target out of reach, on target, a box (``code``), a
        singularity, else tracking."""
        for tip, goal in goals.items():
            chain = self._chains[tip]
            far = math.dist(goal.position.tolist(), chain.first_joint_origin.tolist())  # type: ignore[attr-defined]
            if far > chain.reach + REACH_SLACK:  # type: ignore[attr-defined]
                return ServoStatus.OUT_OF_REACH
        tol_p, tol_r = self._tol
        if pos <= tol_p and (ori is None or ori <= tol_r):
            return ServoStatus.ON_TARGET
        if STATUSES[code] is not ServoStatus.TRACKING:
            return STATUSES[code]
        if sigma < SINGULAR:
            return ServoStatus.SINGULARITY
        return ServoStatus.TRACKING


def _distances(E: np.ndarray, rotated: np.ndarray) -> tuple[float, float | None]:
    """The largest position error and the largest orientation error (None: no tip has a
    rotation) of the stacked rows E."""
    pos, ori, m = 0.0, None, 0
    for turned in rotated.tolist():
        pos = max(pos, math.sqrt(E[m] ** 2 + E[m + 1] ** 2 + E[m + 2] ** 2))
        if turned:
            o = math.sqrt(E[m + 3] ** 2 + E[m + 4] ** 2 + E[m + 5] ** 2)
            ori = o if ori is None else max(ori, o)
        m += 6 if turned else 3
    return pos, ori


def _goal(tip: str, target: object) -> Target:
    """A tip's target as a pose or a position (a ``Target``); ``TargetError`` for any other
    form, naming the way round."""
    if isinstance(target, Pose):
        if target.frame is None and not target.bounds.any() and (target.weights == 1.0).all():
            return parse_target(target.T)
    elif isinstance(target, Position):
        if target.frame is None and not target.bounds.any():
            return parse_target(target.p)
    else:
        try:
            return parse_target(target)
        except TargetError as error:
            raise TargetError(f"the target of tip {tip!r}: {error}") from None
    raise TargetError(
        f"a servo over chains that share joints follows a pose or a position per tip; the "
        f"target of tip {tip!r} is {type(target).__name__} with bounds, weights or a frame: "
        "give a plain pose or position, or servo a chain of its own (arms.chain(tip).servo)"
    )


def _alike(last: dict[str, Target], goals: dict[str, Target]) -> bool:
    """Whether each tip's goal is of the kind it was last tick (a pose, a position)."""
    return all((goals[t].rotation is None) == (last[t].rotation is None) for t in goals)
