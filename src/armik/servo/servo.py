"""``Servo``: streaming differential IK, one compiled tick a target, every limit on the
commanded sequence itself (``Arm.servo`` starts one; docs/servo.md)."""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from armik.errors import OptionError, TargetError
from armik.frozen import frozen
from armik.model.arm_model import ArmModel, model_of
from armik.model.union import Union
from armik.servo import layout as k
from armik.servo import table as _table
from armik.servo.collisions import CollisionRows, ahead, margin_given, rows_for
from armik.servo.fixed import never_moved, structural_ranks
from armik.servo.limits import (
    DEFAULT_ACCELERATION,
    gain_of,
    mimic_own,
    per_joint,
    through_mimics,
    time_step,
    tolerance_of,
    urdf_velocities,
)
from armik.servo.result import STATUSES, ServoRecord, ServoStep, record
from armik.servo.tick import tick

if TYPE_CHECKING:
    from armik.servo.union_collisions import UnionCollisions

SINGULAR = 0.05  # below this smallest singular value (m/rad or 1) the damping grows ...
DAMPING = 0.005  # ... up to this (added to A^T A) at a singular value of 0
DAMPING_ERROR = 0.1  # and by this times the squared error (m^2, rad^2): far, the gradient's way
LAMBDA_MIN = 1e-9  # always: keeps a redundant arm's normal matrix invertible
REACH_SLACK = 1e-3  # m beyond the reach bound before a target is called out of reach
PULL = 2.0  # 1/s: the pull toward q0 where the task leaves joints free or is damped
ON_TARGET = 1e-6  # m and rad: within these of every task's region a tick is on target


class Commanded:
    """What a servo has commanded and within which limits, read from its state array
    (``armik.servo.layout``): a chain's ``Servo`` and the union's ``UnionServo`` alike."""

    _state: np.ndarray
    _cfg: np.ndarray
    _collisions: CollisionRows | UnionCollisions | None
    _no_rows: np.ndarray

    def _rows(self) -> np.ndarray:
        """This tick's collision rows (none without obstacles and self-collision), as far
        out as the joints' velocities need to stop (``collisions.ahead``), the pairs that
        must brake first."""
        if self._collisions is None:
            return self._no_rows
        state = self._state
        reach = ahead(state, self._cfg[k.CURVE])
        return self._collisions.at(state[k.Q], reach, state[k.V], state[k.AMAX], levers=True)

    @property
    def velocity_limits(self) -> np.ndarray:
        """rad/s (m/s) per joint."""
        return self._state[k.VMAX].copy()

    @property
    def acceleration_limits(self) -> np.ndarray:
        """rad/s^2 (m/s^2) per joint."""
        return self._state[k.AMAX].copy()

    @property
    def q(self) -> np.ndarray:
        """The last commanded joint values (rad, m), one per joint."""
        return self._state[k.Q].copy()

    @property
    def dq(self) -> np.ndarray:
        """The last commanded velocity (rad/s, m/s)."""
        return self._state[k.V].copy()


def at_rest(
    state: np.ndarray,
    cfg: np.ndarray,
    arm: ArmModel | Union,
    q: np.ndarray,
    dt: float,
    velocity_limits: object,
    acceleration_limits: object,
    gain: object,
    tol_position: object,
    tol_orientation: object,
) -> None:
    """A servo's state and settings at rest at ``q``, its limits and settings checked
    (``armik.servo.limits``): what a chain's servo and the union's both start from."""
    n = q.shape[0]
    vmax = per_joint(velocity_limits, arm, "velocity_limits", urdf_velocities(arm))
    amax = per_joint(
        acceleration_limits, arm, "acceleration_limits", np.full(n, DEFAULT_ACCELERATION)
    )
    # a mimic joint's limits bind its driver, as its position limits do (``model.mimic``)
    vmax = through_mimics(vmax, mimic_own(arm, velocity_limits, True, math.inf))
    amax = through_mimics(amax, mimic_own(arm, acceleration_limits, False, DEFAULT_ACCELERATION))
    if isinstance(arm, ArmModel):  # (a union's, per tip: ``UnionServo``)
        cfg[k.FIXED : k.FIXED + 18] = never_moved(arm).ravel()
        cfg[k.RANKS : k.RANKS + 3] = structural_ranks(arm)
    state[k.Q], state[k.REST] = q, q
    state[k.VMAX], state[k.AMAX] = vmax, amax
    state[k.LO], state[k.HI] = arm.lower, arm.upper
    cfg[k.DT], cfg[k.GAIN], cfg[k.REACH_SLACK] = dt, gain_of(gain), REACH_SLACK
    cfg[k.TOL_P] = tolerance_of("tol_position", tol_position)
    cfg[k.TOL_R] = tolerance_of("tol_orientation", tol_orientation)
    cfg[k.PULL], cfg[k.LAM_ERR] = PULL, DAMPING_ERROR
    cfg[k.SIGMA_EPS], cfg[k.LAM_MAX], cfg[k.LAM_MIN] = SINGULAR, DAMPING, LAMBDA_MIN


def curvature(arms: list) -> float:
    """A length (m) that bounds how fast the tips' rows turn as the joints move: the
    error's second derivatives are at most about this times the error (a lever arm from a
    joint to the tip, the longest chain's reach; 1 for a rotation row). The step's damping
    grows with it times the error the step cannot remove (``armik.servo.step``): the
    Gauss-Newton step leaves those terms out, and where they outweigh the ones it keeps (a
    target the limits keep out of reach, the arm stretched toward it) it overshoots and
    the arm never settles."""
    reach = max(float(model_of(arm).reach) for arm in arms)
    return max(reach, 1.0) if math.isfinite(reach) else 1.0


class Servo(Commanded):
    """Streaming IK for one arm from joint values ``q0`` at rest: ``step(target)`` gives the
    next command one tick of ``dt`` s later, within the joint limits, the velocity limits
    and the acceleration limits, braking in time for every position limit (see
    ``armik.servo.box``). Built by ``Arm.servo`` (``start``)."""

    def __init__(
        self,
        arm: ArmModel,
        q0: object,
        *,
        dt: object = 0.002,
        velocity_limits: object = None,
        acceleration_limits: object = None,
        gain: object = 1.0,
        obstacles: object = None,
        self_collision: object = False,
        margin: object = 0.01,
        tol_position: float = ON_TARGET,
        tol_orientation: float = ON_TARGET,
    ) -> None:
        self.arm = arm
        self.dt = time_step(dt)
        n = arm.dof
        q = arm.check_q(q0, "q0")
        if not arm.within_limits(q, 0.0):
            raise OptionError(
                "q0 must lie within the joint limits (a servo never commands a position "
                "outside them): " + "; ".join(arm.limit_violations(q, 0.0)),
                option="q0",
                value=q0,
            )
        self._mem, self._imem = k.allocate(arm.kernel_chain.flat)
        self._state, self._cfg, self._out = k.python_views(self._mem, n)
        at_rest(
            self._state, self._cfg, arm, q, self.dt, velocity_limits, acceleration_limits,
            gain, tol_position, tol_orientation,
        )  # fmt: skip
        self._cfg[k.CURVE] = curvature([arm])
        self._names = arm.joint_names
        self._collisions = rows_for(arm, obstacles, self_collision, margin, self.dt)
        self._no_rows = np.zeros((0, 2 * n + 1))

    def step(self, target: object) -> ServoStep:
        """The command one tick later, toward ``target`` (anything ``Arm.solve`` takes for
        the tip: a pose, a position, ``armik.Pose(..., bounds=)``, ``Axis``, ``LookAt``, a
        list of them). Never raises for a target it can read, never returns NaN: a target
        it cannot reach within the limits is approached as far as they allow. Raises
        ``TargetError`` for a target it cannot read."""
        mem, imem = self._mem, self._imem
        near = self._rows()
        # a pose's table is written by the compiled tick itself, where it is a plain one
        if isinstance(target, pin.SE3):
            done = tick(target.homogeneous, mem, imem, near)
        elif isinstance(target, np.ndarray) and target.shape == (4, 4) and _plain(target):
            done = tick(target, mem, imem, near)
        else:
            done = False
        if not done:
            tick(_table.table(target, self.arm), mem, imem, near)
        return self._command()

    def _tick(self, target: object, rows: np.ndarray | None) -> ServoStep:
        """One tick toward ``target`` already read (``table.read``: its ``rows``, None for
        a pose the compiled tick writes itself)."""
        near = self._rows()
        tick(_table.plain_matrix(target) if rows is None else rows, self._mem, self._imem, near)
        return self._command()

    def _command(self) -> ServoStep:
        """The last tick's command and what limited it."""
        out, state = self._out, self._state
        command = state[: k.ACC + 1].copy()  # q, dq, ddq: one read-only copy
        command.flags.writeable = False
        pos, ori, code, j, sigma, conflict = out.tolist()
        status = STATUSES[int(code)]
        return frozen(
            ServoStep,
            q=command[k.Q],
            dq=command[k.V],
            ddq=command[k.ACC],
            status=status,
            joint=self._names[int(j)] if j >= 0 else None,
            position_error=None if pos != pos else pos,  # NaN: not measured
            orientation_error=None if ori != ori else ori,
            sigma=sigma,
            conflict=conflict != 0.0,
        )

    def track(self, targets: Iterable[object]) -> ServoRecord:
        """``step`` through ``targets`` in order, one tick each; the ticks' fields as arrays
        of one row a tick. Every target is read before the first tick: raises
        ``TargetError`` naming the first it cannot read (no tick run), ``OptionError`` for
        one target given alone (``step`` takes one) or none."""
        items = _table.sequence(targets)
        tables = []
        for i, target in enumerate(items):
            try:
                tables.append(_table.read(target, self.arm))
            except TargetError as error:
                raise _table.at_tick(i, error) from None
        return record([self._tick(target, rows) for target, rows in zip(items, tables)])


def _plain(M: np.ndarray) -> bool:
    """Whether the 4x4 M is of the one array type ``tick`` is compiled for (no subclass,
    float64, C order, writable: a read-only array would compile the tick again)."""
    return (
        type(M) is np.ndarray
        and M.dtype == np.float64
        and M.flags.c_contiguous
        and M.flags.writeable
    )


# solve's options the servo reads from each tick's target instead: the way to say them
_AS_TASKS = (
    ": say it with each tick's target, as a task: step(armik.Pose(T, bounds=...)), "
    "step(armik.Pose(T, weights=...)), step(armik.Position(p)), or "
    "step([armik.Position(p), armik.Axis(...)]) and armik.LookAt (docs/servo.md)"
)
_OF_THE_TARGET = {
    **dict.fromkeys(("bounds", "weights", "position_only", "cone", "look_at", "toward"), _AS_TASKS),
    "hold": ": the servo holds no joint (each moves within its velocity box); solve with "
    "hold= for a configuration",
}


def refuse_unknown(options: dict) -> None:
    """Raises ``OptionError`` for an option no servo takes, saying how to ask for it where
    the servo reads it from the target (bounds, weights, a position, an axis)."""
    for name in options:
        if name not in KEYWORDS:
            raise OptionError(
                f"the servo takes no option {name!r}; its options: {', '.join(KEYWORDS)}"
                + _OF_THE_TARGET.get(name, ""),
                option=name,
                value=options[name],
            )


def start(arm: object, q0: object, **options: object) -> Servo:
    """``Arm.servo(q0, dt=0.002, velocity_limits=None, acceleration_limits=None, gain=1.0)``:
    a ``Servo`` for ``arm`` (an ``Arm`` or its model) at rest at ``q0`` (rad, m; within the
    limits), ticking every ``dt`` s, within ``velocity_limits`` (rad/s per joint, a number
    or a mapping joint -> limit; default the URDF's) and ``acceleration_limits`` (rad/s^2;
    default ``DEFAULT_ACCELERATION``), correcting ``gain`` of the error a tick, keeping the
    arm ``margin`` m from ``obstacles`` (shapes in the base frame) and, with
    ``self_collision``, from itself (``armik.servo.collisions``). Raises ``OptionError``
    (``CollisionError``) naming a bad value. See docs/servo.md."""
    refuse_unknown(options)
    margin_given(options)
    return Servo(model_of(arm), q0, **options)  # type: ignore[arg-type]


KEYWORDS: tuple[str, ...] = ("dt", "velocity_limits", "acceleration_limits", "gain")
KEYWORDS += ("tol_position", "tol_orientation", "obstacles", "self_collision", "margin")
