"""What a servo tick returns (``ServoStep``), what a run of ticks returns (``ServoRecord``:
the same field names, one row a tick) and the words for what limited a tick."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from enum import Enum

import numpy as np


class ServoStatus(str, Enum):
    """What limited a tick, in the order of ``armik.servo.tick``'s codes."""

    ON_TARGET = "on_target"  # every task holds (within the tolerances)
    TRACKING = "tracking"  # moving toward the target, nothing held it back
    JOINT_LIMIT = "joint_limit"  # a joint at, or braking for, a position limit
    VELOCITY_LIMIT = "velocity_limit"
    ACCELERATION_LIMIT = "acceleration_limit"  # speeding up, or slowing to stop on the target
    SINGULARITY = "singularity"  # damped: a direction the arm has (almost) lost
    OUT_OF_REACH = "out_of_reach"  # the target lies beyond the arm's reach
    OBSTACLE = "obstacle"  # a collision row (an obstacle, or the arm itself) held it back
    STALLED = "stalled"  # no motion brings it nearer: a target the arm cannot take from here

    def __str__(self) -> str:
        return self.value


STATUSES: tuple[ServoStatus, ...] = tuple(ServoStatus)


def reason(status: ServoStatus, joint: str | None, sigma: float, conflict: bool) -> str:
    """The words of a tick's status."""
    if status is ServoStatus.ON_TARGET:
        text = "on target: every task within the tolerances"
    elif status is ServoStatus.TRACKING:
        text = "tracking: no limit held the step back"
    elif status is ServoStatus.OUT_OF_REACH:
        text = "out of reach: the target lies beyond the arm's reach; moving toward it"
    elif status is ServoStatus.STALLED:
        text = (
            "stalled: no motion of the joints brings the tip nearer the target; the nearest "
            "it gets from here (a target this arm cannot take, or a local minimum)"
        )
    elif status is ServoStatus.OBSTACLE:
        text = (
            "obstacle: a pair near its margin, or nearer it than the joints moving it could "
            "stop in, held the step back"
        )
    elif status is ServoStatus.SINGULARITY:
        text = f"near a singularity (smallest singular value {sigma:.3g}): the step is damped"
    elif joint is None:
        text = f"{status.value.replace('_', ' ')}: slowing to stop on the target"
    else:
        text = f"{status.value.replace('_', ' ')} of joint {joint!r} held the step back"
    if conflict:
        text += "; the acceleration limit gave way to braking for a position limit"
    return text


@dataclass(frozen=True, kw_only=True, eq=False)
class ServoStep:
    """One tick's command: joint values ``q`` (rad, m), velocity ``dq`` (rad/s, m/s) and
    acceleration ``ddq`` (rad/s^2, m/s^2), each the finite difference of the commanded
    values; what limited it (``status``, ``reason``, ``joint``: the joint held back, if
    one was); the true distances to the target after the tick, ``position_error`` (m) and
    ``orientation_error`` (rad), as ``solve`` reports them: to the target's position and
    rotation whatever its bounds and weights (an aim's: its axis' angle to its direction),
    None where the target has no such part (a position's orientation); and ``sigma``, the
    smallest singular value of the task Jacobian (inf where no row is active)."""

    # (``reason`` is a property: the words of status and joint, written when read)

    q: np.ndarray
    dq: np.ndarray
    ddq: np.ndarray
    status: ServoStatus
    joint: str | None
    position_error: float | None
    orientation_error: float | None
    sigma: float
    conflict: bool = False  # the acceleration limit gave way to braking (rounding only)
    tips: Mapping[str, ServoStep] | None = None  # on several tips: each chain's own step

    @property
    def reason(self) -> str:
        """What limited the tick, in words (written when read)."""
        return reason(self.status, self.joint, self.sigma, self.conflict)


@dataclass(frozen=True, kw_only=True, eq=False)
class ServoRecord:
    """``Servo.track``'s ticks: ``ServoStep``'s fields, one row a tick (N rows; errors NaN
    where not measured, ``joint`` "" where none)."""

    q: np.ndarray  # (N, dof)
    dq: np.ndarray
    ddq: np.ndarray
    status: np.ndarray  # (N,) of str
    reason: list[str]
    joint: np.ndarray  # (N,) of str
    position_error: np.ndarray  # (N,)
    orientation_error: np.ndarray
    sigma: np.ndarray

    def __len__(self) -> int:
        return int(self.q.shape[0])


def record(steps: Sequence[ServoStep]) -> ServoRecord:
    """The ``ServoRecord`` of ``steps`` in order (at least one)."""

    def column(name: str) -> np.ndarray:
        return np.array([getattr(s, name) for s in steps])

    def errors(name: str) -> np.ndarray:
        values = [getattr(s, name) for s in steps]
        return np.array([math.nan if v is None else v for v in values], dtype=float)

    return ServoRecord(
        q=column("q"),
        dq=column("dq"),
        ddq=column("ddq"),
        status=np.array([s.status.value for s in steps]),
        reason=[s.reason for s in steps],
        joint=np.array([s.joint or "" for s in steps]),
        position_error=errors("position_error"),
        orientation_error=errors("orientation_error"),
        sigma=column("sigma"),
    )
