"""Scores: which of several verified answers is best (lower is better).

A score ranks answers that already hold every task; it never makes an answer a success.
``prefer=`` names one: ``"nearest"`` (closest to q0), ``"manipulability"`` (Yoshikawa's
``sqrt(det(J J^T))`` of the tip Jacobian, larger is better), ``"limits"`` (the largest
smallest normalised distance to a joint limit), ``Posture(q_ref, weights)``, or any
callable ``cost(q) -> float``.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import pinocchio as pin

from armik.errors import OptionError, warn
from armik.model.arm_model import ArmModel  # a score reads the arm (its Jacobian, limits)
from armik.model.limit_units import degrees_note


class Score(ABC):
    """A cost of one configuration of an arm (lower is better). ``per_joint`` tells how a
    turn of 2 pi on one joint changes it: ``None`` when the cost does not split by joints
    (every combination of turns is scored), else the joint's own term, so that each
    joint's best turn is chosen alone. ``turns_matter`` False: a turn never changes it."""

    name: str = "score"
    turns_matter: bool = True

    def per_joint(self, arm: ArmModel, i: int, qi: float, q0: np.ndarray) -> float | None:
        return None

    def gradient(self, arm: ArmModel, q: np.ndarray, q0: np.ndarray) -> np.ndarray | None:
        """The cost's gradient in q where it has a closed form; None: finite differences."""
        return None

    def words(self, value: float) -> str:
        """A reason's words for the cost ``value``: what the score measures, in its sense."""
        return f"cost {value:.6g}"

    @abstractmethod
    def __call__(self, arm: ArmModel, q: np.ndarray, q0: np.ndarray) -> float:
        """The cost of ``q`` on ``arm``; ``q0`` is the call's seed."""

    def many(self, arm: ArmModel, Q: np.ndarray, q0: np.ndarray) -> np.ndarray:
        """The cost of each row of ``Q`` (a path's rungs): one call per row unless the
        score has an array form."""
        return np.array([self(arm, q, q0) for q in Q], dtype=float).reshape(len(Q))


class Nearest(Score):
    """The distance from q0: the Euclidean norm of q - q0 (rad and m), as TRAC-IK's
    Distance mode."""

    name = "nearest"

    def __call__(self, arm: ArmModel, q: np.ndarray, q0: np.ndarray) -> float:
        return float(np.linalg.norm(q - q0))

    def many(self, arm: ArmModel, Q: np.ndarray, q0: np.ndarray) -> np.ndarray:
        out: np.ndarray = np.linalg.norm(Q - q0, axis=1)
        return out

    def per_joint(self, arm: ArmModel, i: int, qi: float, q0: np.ndarray) -> float | None:
        return abs(qi - float(q0[i]))

    def words(self, value: float) -> str:
        return f"distance {value:.6g} from q0"

    def gradient(self, arm: ArmModel, q: np.ndarray, q0: np.ndarray) -> np.ndarray | None:
        d = q - q0
        n = float(np.linalg.norm(d))
        return d / n if n > 0.0 else np.zeros_like(d)


def manipulability(J: np.ndarray) -> float:
    """Yoshikawa's measure ``sqrt(det(J J^T))`` of a 6 x n Jacobian (``J^T J`` when n < 6)."""
    M = J @ J.T if J.shape[1] >= J.shape[0] else J.T @ J
    return math.sqrt(max(float(np.linalg.det(M)), 0.0))


_FLOAT = np.dtype(float)
_frame_jacobian, _LOCAL = pin.computeFrameJacobian, pin.LOCAL


class Manipulability(Score):
    """Minus the tip Jacobian's manipulability: the best-conditioned answer first."""

    name = "manipulability"
    turns_matter = False  # the Jacobian depends on the angles' sines and cosines only

    def __call__(self, arm: ArmModel, q: np.ndarray, q0: np.ndarray) -> float:
        # ``arm.jacobian(q)`` without checking q again: the answers scored are verified
        # (a ranking scores each one many times, once per 2 pi variant and swept value)
        direct = type(q) is np.ndarray and q.dtype == _FLOAT and arm.model.nq == arm.dof
        qp = q if direct else arm.to_pin(q)
        J = _frame_jacobian(arm.model, arm.data, qp, arm.tip_frame_id, _LOCAL).reshape(6, arm.dof)
        return -manipulability(J)

    def many(self, arm: ArmModel, Q: np.ndarray, q0: np.ndarray) -> np.ndarray:
        """Each row's cost as ``__call__`` gives it (a swept self-motion's branches)."""
        model, data, frame, dof = arm.model, arm.data, arm.tip_frame_id, arm.dof
        rows = Q if Q.dtype == _FLOAT and model.nq == dof else map(arm.to_pin, Q)
        out = np.empty(len(Q))
        for i, qp in enumerate(rows):
            J = _frame_jacobian(model, data, qp, frame, _LOCAL).reshape(6, dof)
            out[i] = -manipulability(J)
        return out

    def words(self, value: float) -> str:
        return f"manipulability {-value:.6g}"  # the measure, not its negated cost


def limit_margin(arm: ArmModel, q: np.ndarray) -> float:
    """The smallest distance to a joint limit over the joints, each as a fraction of its
    range (0.5 at the middle); joints without finite limits are not counted (1.0 when
    none has)."""
    lo, hi = np.asarray(arm.lower), np.asarray(arm.upper)
    bounded = np.isfinite(lo) & np.isfinite(hi) & (hi > lo)
    if not bounded.any():
        return 1.0
    span = hi[bounded] - lo[bounded]
    x = np.asarray(q)[bounded]
    return float(np.min(np.minimum(x - lo[bounded], hi[bounded] - x) / span))


class Limits(Score):
    """Minus ``limit_margin``: the answer farthest from its nearest limit first."""

    name = "limits"

    def __call__(self, arm: ArmModel, q: np.ndarray, q0: np.ndarray) -> float:
        return -limit_margin(arm, q)

    def words(self, value: float) -> str:
        return f"joint-limit margin {-value:.6g} of a joint's range"

    def many(self, arm: ArmModel, Q: np.ndarray, q0: np.ndarray) -> np.ndarray:
        lo, hi = np.asarray(arm.lower), np.asarray(arm.upper)
        bounded = np.isfinite(lo) & np.isfinite(hi) & (hi > lo)
        if not bounded.any():
            return np.full(len(Q), -1.0)
        span = hi[bounded] - lo[bounded]
        X = Q[:, bounded]
        out: np.ndarray = -np.min(np.minimum(X - lo[bounded], hi[bounded] - X) / span, axis=1)
        return out

    def per_joint(self, arm: ArmModel, i: int, qi: float, q0: np.ndarray) -> float | None:
        lo, hi = float(arm.lower[i]), float(arm.upper[i])  # the minimum is largest when
        return -min(qi - lo, hi - qi)  # each joint is as far inside as it can be


def _numbers(value: object, what: str, n: int | None = None) -> np.ndarray:
    """``value`` as a flat float array; ``OptionError`` naming ``what`` when it is no
    numbers (a string, a complex value, a ragged list)."""
    try:
        if isinstance(value, (str, bytes)) or np.iscomplexobj(value):  # type: ignore[arg-type]
            raise TypeError
        return np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        many = "one number per joint" if n is None else f"{n} numbers >= 0"
        raise OptionError(
            f"Posture {what} must be {many}, got {value!r}", option="prefer", value=value
        ) from None


class Posture(Score):
    """``sum(weights * (q - q_ref)^2)``: the answer nearest a reference posture."""

    name = "posture"

    def __init__(self, q_ref: object, weights: object = None) -> None:
        self.q_ref = _numbers(q_ref, "q_ref")
        if self.q_ref.size == 0 or not np.isfinite(self.q_ref).all():
            raise OptionError(
                f"Posture q_ref must be one finite number per joint, got {q_ref!r}", option="prefer"
            )
        n = self.q_ref.size
        self.weights = np.ones(n) if weights is None else _numbers(weights, "weights", n)
        if (
            self.weights.shape != (n,)
            or not np.isfinite(self.weights).all()
            or (self.weights < 0).any()
        ):
            raise OptionError(
                f"Posture weights must be {n} finite numbers >= 0, got {weights!r}",
                option="prefer",
            )

    def said(self) -> dict[str, object]:
        """The posture as a secondary task (``secondary=[...]``): the option ``posture``,
        the compiled step's null-space pull toward ``q_ref``, each joint's by its weight."""
        return {"posture": (tuple(self.q_ref.tolist()), tuple(self.weights.tolist()))}

    def _fits(self, arm) -> None:
        fit_posture(self.q_ref.size, arm.joint_names)

    def __call__(self, arm: ArmModel, q: np.ndarray, q0: np.ndarray) -> float:
        self._fits(arm)
        return float(self.weights @ (q - self.q_ref) ** 2)

    def many(self, arm: ArmModel, Q: np.ndarray, q0: np.ndarray) -> np.ndarray:
        self._fits(arm)
        out: np.ndarray = ((Q - self.q_ref) ** 2) @ self.weights
        return out

    def per_joint(self, arm: ArmModel, i: int, qi: float, q0: np.ndarray) -> float | None:
        self._fits(arm)
        return float(self.weights[i] * (qi - self.q_ref[i]) ** 2)

    def gradient(self, arm: ArmModel, q: np.ndarray, q0: np.ndarray) -> np.ndarray | None:
        self._fits(arm)
        return 2.0 * self.weights * (q - self.q_ref)


def said_in_degrees(q_ref: object, arm: Any, option: str) -> None:
    """An ``ArmikWarning`` where a posture's reference for ``arm`` (one value per joint)
    reads as degrees (``limit_units.degrees_note``): the joints named, in radians."""
    values = np.asarray(q_ref, dtype=float).tolist()
    note = degrees_note(values, arm)
    if note:
        shown = ", ".join(f"{v:g}" for v in values)
        warn(f"{option}=Posture(q_ref): q_ref [{shown}]{note}")


def fit_reference(q_ref: Sequence[float], arm: ArmModel, option: str) -> None:
    """``fit_posture`` of a posture's reference to ``arm``'s joints, then said where it
    reads as degrees (``said_in_degrees``)."""
    fit_posture(len(q_ref), arm.joint_names, option=option)
    said_in_degrees(q_ref, arm, option)


def fit_posture(
    count: int, joints: Sequence[str] | int, whose: str = "the arm", option: str = "prefer"
) -> None:
    """An ``OptionError`` where a posture of ``count`` values is not one per joint
    (``joints``: their names, or how many where the names are not at hand; ``whose``: the
    arm's or the robot's; ``option``: how the posture was given)."""
    n = joints if isinstance(joints, int) else len(joints)
    if count != n:
        names = "" if isinstance(joints, int) else f" of {list(joints)}"
        raise OptionError(
            f"Posture q_ref has {count} values, {whose} {n} joints: give one per joint{names}",
            option=option,
        )


class Cost(Score):
    """A user's ``cost(q) -> float``; an exception or a non-finite value is an armik error
    naming the callable."""

    def __init__(self, fn: Callable[[np.ndarray], float]) -> None:
        self.fn = fn
        self.name = getattr(fn, "__name__", repr(fn))

    def __call__(self, arm: ArmModel, q: np.ndarray, q0: np.ndarray) -> float:
        try:
            value = float(self.fn(np.array(q)))
        except Exception as exc:
            raise OptionError(
                f"prefer={self.name} raised {type(exc).__name__}: {exc} (at q = "
                f"{np.round(q, 6).tolist()}); a cost takes q (rad, m) and returns a number",
                option="prefer",
            ) from exc
        if not math.isfinite(value):
            raise OptionError(
                f"prefer={self.name} returned {value} at q = {np.round(q, 6).tolist()}: a "
                "cost must be a finite number (lower is better)",
                option="prefer",
            )
        return value


_NAMED: dict[str, Callable[[], Score]] = {
    "nearest": Nearest,
    "manipulability": Manipulability,
    "limits": Limits,
}


def parse_score(value: object, arm: object = None) -> Score | None:
    """``prefer=``'s value as a ``Score``; None for None. ``OptionError`` otherwise. A
    ``Posture`` for ``arm`` (an arm's model or a robot) whose reference reads as degrees
    is said (``said_in_degrees``)."""
    if value is None or isinstance(value, Score):
        if arm is not None and isinstance(value, Posture):
            said_in_degrees(value.q_ref, arm, "prefer")
        return value
    if isinstance(value, str):
        if value in _NAMED:
            return _NAMED[value]()
        raise OptionError(
            f"prefer must be None, one of {sorted(_NAMED)}, armik.Posture(q_ref) or a "
            f"callable cost(q), got {value!r}",
            option="prefer",
            value=value,
        )
    if callable(value):
        return Cost(value)
    raise OptionError(
        f"prefer must be None, one of {sorted(_NAMED)}, armik.Posture(q_ref) or a callable "
        f"cost(q), got {value!r}",
        option="prefer",
        value=value,
    )
