"""A servo over chains that share joints (a torso, a lift): one step over their union.

``Arms.servo`` on tips whose chains share a joint ticks this instead of one ``Servo`` per
chain: every tip's task is stacked over the union's joints (Pinocchio's FK and frame
Jacobians of ``armik.model.union``), and one damped least-squares step goes toward all of
them at once, within the velocity box of ``armik.servo.box`` on every joint (position,
velocity, acceleration and braking limits), by the box QP of ``kernel.step.active_set``.
What a chain's own servo does the same way: the damping grows near a singularity (the
smallest singular value of the stacked Jacobian) and with the error, the joints that the
tasks leave free are pulled toward ``q0``, and the step corrects ``gain`` of the error a
tick. A tip's target is a pose or a position; a region, an axis or a look-at (which a
chain's own servo takes) is refused by name, as are obstacles and ``self_collision``.

In Python over Pinocchio, not one compiled call a tick: ``benchmarks/servo_shared.py``
measures it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import pinocchio as pin

from armik.errors import OptionError, TargetError
from armik.frozen import frozen
from armik.kernel.step import active_set
from armik.model.union import Union
from armik.problem.tasks import Pose, Position
from armik.servo.box import ACCELERATION, BRAKING, POSITION, VELOCITY, velocity_boxes
from armik.servo.limits import DEFAULT_ACCELERATION, per_joint, time_step, urdf_velocities
from armik.servo.result import ServoStatus, ServoStep
from armik.targets.pose import Target, parse_target

SINGULAR = 0.05  # as ``armik.servo.servo``: below this smallest singular value ...
DAMPING = 0.005  # ... the damping grows up to this at 0
DAMPING_ERROR = 0.1  # and by this times the squared error
LAMBDA_MIN = 1e-9
PULL = 2.0  # 1/s toward q0 where the tasks leave joints free
ON_TARGET = 1e-6  # m and rad
REACH_SLACK = 1e-3  # m beyond a chain's reach bound before its target is out of reach
BRAKED = 1e-3  # m: slowing to stop on a target farther than this is reported
_LIMITED = {
    POSITION: ServoStatus.JOINT_LIMIT,
    BRAKING: ServoStatus.JOINT_LIMIT,
    VELOCITY: ServoStatus.VELOCITY_LIMIT,
    ACCELERATION: ServoStatus.ACCELERATION_LIMIT,
}
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
        q = np.asarray(q0, dtype=float) if q0 is not None else union.middle.copy()
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
        g = float(gain) if isinstance(gain, (int, float)) else math.nan
        if not 0.0 < g <= 1.0:
            raise OptionError(
                f"gain must be in (0, 1] (the fraction of the error corrected a tick), got "
                f"{gain!r}",
                option="gain",
                value=gain,
            )
        self._gain, self._tol = g, (float(tol_position), float(tol_orientation))
        self._q, self._v, self._a, self._rest = q.copy(), np.zeros(n), np.zeros(n), q.copy()
        self._frames = {tip: union.model.getFrameId(tip) for tip in self.tips}
        self._last: dict[str, Target] | None = None  # the last tick's targets
        R = union.T_base_world.rotation
        self._to_base = np.kron(np.eye(2), R)  # a twist's two halves into the base axes
        self._scratch = (
            *(np.zeros(n, dtype=np.int64) for _ in range(3)),
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
        union, n, dt = self.union, self.union.dof, self.dt
        last = self._last if self._last is not None and _alike(self._last, goals) else goals
        E, A, E_last = self._tasks(self._q, goals, last)
        sigma = _smallest_singular(A)
        lam = LAMBDA_MIN + DAMPING_ERROR * float(E @ E)
        if sigma < SINGULAR:
            lam += DAMPING * (1.0 - (sigma / SINGULAR) ** 2)
        H = A.T @ A + lam * np.eye(n)
        G = np.linalg.inv(H)
        # the last tick's remaining correction, slowed so that every joint can stop on it at
        # its acceleration limit, and the targets' own motion since, followed at once
        fix = G @ (A.T @ E_last)
        want = np.abs(self._gain * fix / dt)
        can = np.sqrt(2.0 * self._amax * np.abs(fix))
        moving = want > 0.0
        slowed = float(np.min(can[moving] / want[moving], initial=1.0))
        v_fix = min(1.0, slowed) * self._gain * fix / dt
        v_ff = G @ (A.T @ (E - E_last)) / dt
        # toward q0 in what the tasks leave free (the damped pseudo-inverse's null space)
        v_pull = lam * (G @ (PULL * (self._rest - self._q)))
        free = v_ff + v_fix + v_pull
        lb, ub, lk, uk, conflict = velocity_boxes(
            self._q, self._v, union.lower, union.upper, self._vmax, self._amax, dt
        )
        side, held, sub, Hh, gap, mult, Lm, x = self._scratch
        if not active_set(G, free, lb, ub, free, side, held, sub, Hh, gap, mult, Lm, x):
            x[:] = free
        v = np.minimum(np.maximum(x, lb), ub)  # exactly within the box, whatever rounding
        q = np.minimum(np.maximum(self._q + v * dt, union.lower), union.upper)
        v = (q - self._q) / dt
        a = (v - self._v) / dt
        self._q, self._v, self._a, self._last = q, v, a, goals
        pos, ori = self._distances(q, goals)
        status, joint = self._status(free, v, lb, ub, lk, uk, sigma, goals, pos, ori)
        if status is ServoStatus.TRACKING and slowed < 1.0 and max(pos.values()) > BRAKED:
            status = ServoStatus.ACCELERATION_LIMIT  # slowing to stop on a far target
        command = np.stack([q, v, a])
        command.flags.writeable = False
        return frozen(
            ServoStep,
            q=command[0],
            dq=command[1],
            ddq=command[2],
            status=status,
            joint=joint,
            position_error=max(pos.values()),
            orientation_error=max((o for o in ori.values() if o is not None), default=None),
            sigma=sigma,
            conflict=bool(conflict),
            tips=None,
        )

    def _tasks(self, q: np.ndarray, goals: dict, last: dict):
        """(E, A, E_last): the stacked error toward ``goals`` (base axes: each tip's
        position, then its rotation where its goal has one), its Jacobian at q, and the
        error toward ``last`` (the last tick's goals, of the same kinds)."""
        union = self.union
        model, data = union.model, union.data
        pin.computeJointJacobians(model, data, union.to_pin(q))
        rows, rows_last, cols = [], [], []
        for tip, goal in goals.items():
            fid = self._frames[tip]
            T = union.T_base_world * pin.updateFramePlacement(model, data, fid)
            J = self._to_base @ pin.getFrameJacobian(model, data, fid, pin.LOCAL_WORLD_ALIGNED)
            before = last[tip]
            rows.append(goal.position - T.translation)
            rows_last.append(before.position - T.translation)
            if goal.rotation is None:
                cols.append(J[:3])
            else:
                rows.append(pin.log3(goal.rotation @ T.rotation.T))
                rows_last.append(pin.log3(before.rotation @ T.rotation.T))
                cols.append(J)
        return np.concatenate(rows), np.vstack(cols), np.concatenate(rows_last)

    def _distances(self, q: np.ndarray, goals: dict) -> tuple[dict, dict]:
        """Each tip's true distances to its goal at q (m; rad, None for a position)."""
        union = self.union
        model, data = union.model, union.data
        pin.forwardKinematics(model, data, union.to_pin(q))
        pos, ori = {}, {}
        for tip, goal in goals.items():
            T = union.T_base_world * pin.updateFramePlacement(model, data, self._frames[tip])
            pos[tip] = float(np.linalg.norm(goal.position - T.translation))
            ori[tip] = (
                None
                if goal.rotation is None
                else float(np.linalg.norm(pin.log3(goal.rotation @ T.rotation.T)))
            )
        return pos, ori

    def _status(self, free, v, lb, ub, lk, uk, sigma, goals, pos, ori):
        """What limited the tick (``ServoStatus``) and the joint held back, if one was."""
        for tip, goal in goals.items():
            chain = self._chains[tip]
            far = math.dist(goal.position.tolist(), chain.first_joint_origin.tolist())
            if far > chain.reach + REACH_SLACK:
                return ServoStatus.OUT_OF_REACH, None
        tol_p, tol_r = self._tol
        if all(p <= tol_p for p in pos.values()) and all(
            o is None or o <= tol_r for o in ori.values()
        ):
            return ServoStatus.ON_TARGET, None
        held_up = (v >= ub - 1e-12) & (free > ub)
        held_down = (v <= lb + 1e-12) & (free < lb)
        over = np.where(held_up, free - ub, 0.0) + np.where(held_down, lb - free, 0.0)
        if over.max() > 0.0:
            j = int(np.argmax(over))
            kind = uk[j] if held_up[j] else lk[j]
            return _LIMITED[int(kind)], self.joint_names[j]
        if sigma < SINGULAR:
            return ServoStatus.SINGULARITY, None
        return ServoStatus.TRACKING, None


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


def _smallest_singular(A: np.ndarray) -> float:
    """The smallest of A's min(rows, n) largest singular values."""
    return float(np.linalg.svd(A, compute_uv=False)[-1])
