"""What every task shares: its measure, the dead zone that makes a region a residual, and
the checks of its inputs.

A task asks one frame of the arm for something: a pose, a position, an axis's direction.
It gives the numeric step a residual that is zero exactly where it holds and the
residual's Jacobian, and it measures itself on a placement computed by Pinocchio, so that
the verdict asks every task whether it holds. Lengths are in m, angles in rad, placements
``T_base_frame`` in the arm's base frame, Jacobians in Pinocchio's LOCAL convention (the
frame's own axes: ``v = R^T dp/dt``, ``w`` with ``dR/dt = R [w]x``).
"""

from __future__ import annotations

import copy
import functools
import math
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from types import FunctionType
from typing import Any, NamedTuple

import numpy as np
import pinocchio as pin

from armik.errors import ArmikError, TargetError
from armik.kernel.problem import NO_CONE, NO_LOOK
from armik.reasons import Cone
from armik.tolerances import MAX_LENGTH

#: A frame's placement ``T_base_frame`` and its LOCAL Jacobian (None where only measured).
Placed = tuple[pin.SE3, np.ndarray | None]


class KernelRow(NamedTuple):
    """A task as the compiled step's six rows on its frame (``kernel.region``'s): the twist
    of the frame relative to ``(R_t, p_t)`` in the target's axes, each component within
    +- its bound (inf: free) and weighted; with ``cone >= 0`` the rotation rows are the
    frame's ``axis`` within ``cone`` rad of the target's image of it, or, with ``look``
    (``kernel.problem.LOOK_POINT``, ``LOOK_TOWARD``), of the line to the point ``sight`` or
    the direction ``sight``. What its true distance has (``Task.centre``'s measure, a
    servo tick's errors): the ``parts`` (position, rotation: a position has no rotation to
    report, an axis no position), each whole whatever its bounds and weights."""

    R_t: np.ndarray
    p_t: np.ndarray
    bounds: np.ndarray
    weights: np.ndarray
    cone: float = NO_CONE
    axis: tuple[float, float, float] | np.ndarray = (0.0, 0.0, 1.0)
    look: int = NO_LOOK
    sight: tuple[float, float, float] | np.ndarray = (0.0, 0.0, 0.0)
    parts: tuple[bool, bool] = (True, True)


def cone_row(axis: np.ndarray, within: float, look: int, sight: np.ndarray) -> KernelRow:
    """The ``KernelRow`` of a frame's axis within a cone of a direction or of the line to
    a point (``Axis``, ``LookAt``): the position free, and no part of its distance."""
    return KernelRow(_EYE, _ZERO, _FREE, _ONES, within, axis, look, sight, parts=(False, True))


_EYE, _ZERO, _ONES, _FREE = np.eye(3), np.zeros(3), np.ones(6), np.full(6, math.inf)


@dataclass(frozen=True)
class TaskError:
    """A task measured on one placement: how far it is from holding (m and rad, 0 inside
    its region; None where it does not measure that part) and whether it holds."""

    position: float | None
    orientation: float | None
    within: bool


class Task(ABC):
    """One thing asked of one frame (``frame``: None for the arm's tip)."""

    frame: str | None = None

    def __init_subclass__(cls, **kwargs: object) -> None:
        """A class of the user's own: its ``residual``, ``jacobian`` and ``measure`` read
        through ``_read`` (an error they raise, a result of another shape: a ``TargetError``
        naming the class); armik's own tasks are read as they are, no call added."""
        super().__init_subclass__(**kwargs)
        if cls.__module__.startswith("armik."):
            return
        for name in ("residual", "jacobian", "measure"):
            own = cls.__dict__.get(name)
            if isinstance(own, FunctionType) and not getattr(own, "_armik_checked", False):
                setattr(cls, name, _read(name, own))

    @property
    def frames(self) -> tuple[str | None, ...]:
        """The frames whose placements the task reads, in the order ``placement`` takes."""
        return (self.frame,)

    def placement(self, placed: list[Placed]) -> Placed:
        """The (placement, LOCAL Jacobian or None) the task measures, from its frames'
        (``placed``, in the order of ``frames``): its one frame's, as they are."""
        return placed[0]

    @property
    @abstractmethod
    def rows(self) -> int:
        """The number of residual rows."""

    @abstractmethod
    def residual(self, T: pin.SE3) -> np.ndarray:
        """(rows,): zero where the task holds, growing with the distance from its region."""

    @abstractmethod
    def jacobian(self, T: pin.SE3, J: np.ndarray) -> np.ndarray:
        """(rows, nv): the residual's derivative, from the frame's LOCAL Jacobian ``J``
        (6, nv) at the same configuration."""

    @abstractmethod
    def measure(self, T: pin.SE3, tol_position: float, tol_orientation: float) -> TaskError:
        """The task on ``T``, within the tolerances (m, rad) added to its region."""

    def kernel_row(self) -> KernelRow | None:
        """The task's rows for the compiled step on its frame, or None where the compiled
        step has no form for it (the Python descent's residual then)."""
        return None

    def shrunk(self, factor: float) -> Task:
        """The task with its region scaled by ``factor`` about its centre (a task without
        a region, or one the factor leaves as it is: itself). A descent aimed inside the
        region ends inside it, not on the region's edge where the residual has a kink and
        the steps chatter. A task the descent's factor leaves as itself has no region: it
        is itself at every factor (the task solver then measures no centre)."""
        return self

    def centre(self) -> Task:
        """The task measuring its frame's true distance to its target: its region shrunk to
        its centre (``shrunk(0)``); what a result's ``position_error`` and
        ``orientation_error`` report, beside the verdict's measure (``measured``). Itself
        where the two are one."""
        return self.shrunk(0.0)

    def free(self) -> tuple[bool, bool]:
        """(position, rotation): whether this task leaves every component of each free (an
        infinite bound or a weight of 0), its error 0 there whatever the answer: words
        leave that 0 out. A task with no bounds (a user's own) frees nothing; a direction
        alone (``Axis``, ``LookAt``) says its own."""
        bounds = getattr(self, "bounds", None)
        if bounds is None:
            return (False, False)
        free = np.isinf(np.asarray(bounds, dtype=float))
        weights = getattr(self, "weights", None)
        if weights is not None:
            free = free | (np.asarray(weights, dtype=float) == 0.0)
        return (bool(free[:3].all()), len(free) == 6 and bool(free[3:].all()))

    def cone_words(self) -> Cone | None:
        """The aim this task's words name its frame's axis by (``reasons.Cone``: an axis
        within a cone of a direction or of the line to a point), or None: no aim."""
        return None

    def rim(self, count: int) -> list[Task]:
        """Exact tasks at ``count`` points spread around the rim of the region, just inside
        it (each answer of one answers this task): where the region's centre is out of
        reach, its rim may not be, and a compiled form may solve it. Default: none."""
        return []


def _read(name: str, own: Callable[..., Any]) -> Callable[..., Any]:
    """A user's task member ``name`` checked on each call: ``residual`` (rows,) numbers,
    ``jacobian`` (rows, nv) from the (6, nv) ``J`` it was given, ``measure`` a
    ``TaskError``; otherwise, or where it raises, a ``TargetError`` naming the class."""

    @functools.wraps(own)
    def read(self: Task, T: pin.SE3, *more: Any) -> Any:
        task = type(self).__name__
        try:
            got = own(self, T, *more)
        except ArmikError:
            raise
        except Exception as exc:
            raise TargetError(
                f"task {task}: its {name} raised {type(exc).__name__}: {exc}"
            ) from exc
        if name == "measure":
            if not isinstance(got, TaskError):
                raise TargetError(
                    f"task {task}: its measure must return a TaskError(position, orientation, "
                    f"within) (armik.problem.tasks.base), got {got!r}"
                )
            return got
        rows = self.rows
        shape = (rows,) if name == "residual" else (rows, np.shape(more[0])[1])
        if type(got) is np.ndarray and got.shape == shape and got.dtype == np.float64:
            return got
        try:
            out = np.asarray(got, dtype=float)
        except (TypeError, ValueError, OverflowError):  # 10**400: no float
            out = None
        if out is None or out.shape != shape:
            given = f"shape {np.shape(got)}" if out is not None else repr(got)
            raise TargetError(
                f"task {task}: its {name} must be an array of shape {shape} (rows = {rows}: "
                f"its rows property), got {given}"
            )
        return out

    read._armik_checked = True  # type: ignore[attr-defined]
    return read


def scaled(bounds: np.ndarray, factor: float) -> np.ndarray:
    """``bounds * factor`` with a free (infinite) bound kept free, ``factor`` 0 included."""
    return np.where(np.isinf(bounds), math.inf, np.where(np.isinf(bounds), 0.0, bounds) * factor)


def replaced(task: Task, **fields: object) -> Task:
    """A copy of ``task`` with ``fields`` replaced (``Task.shrunk``, a task put on a frame)."""
    twin = copy.copy(task)
    twin.__dict__.update(fields)
    return twin


def dead_zone(e: np.ndarray, bounds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(residual, active): each component of ``e`` shrunk towards 0 by its bound, 0 inside
    it (``inf`` frees the component); ``active`` marks the rows with a derivative."""
    active = np.abs(e) > bounds
    residual = np.where(active, e - np.copysign(np.where(np.isinf(bounds), 0.0, bounds), e), 0.0)
    return residual, active


def check_bounds(bounds: object, n: int, what: str) -> np.ndarray:
    """``bounds`` as n non-negative numbers (``math.inf`` frees an axis); ``TargetError``
    naming the value otherwise."""
    try:
        arr = np.array(bounds, dtype=float).reshape(-1)
    except (TypeError, ValueError, OverflowError):  # 10**400: no float
        raise TargetError(f"{what} must be {n} numbers (m or rad), got {bounds!r}") from None
    if arr.shape != (n,):
        raise TargetError(f"{what} must be {n} numbers (m or rad), got {bounds!r}")
    if np.isnan(arr).any() or (arr < 0).any():
        raise TargetError(
            f"{what} must be >= 0 (a tolerance on each side; math.inf frees an axis), got "
            f"{arr.tolist()}"
        )
    # a finite bound beyond any reach is a free axis said as a number (the bounds= option's
    # rule): its square overflows, and the compiled path refused it in the option's words
    if (np.isfinite(arr) & (arr > MAX_LENGTH)).any():
        raise TargetError(
            f"{what} must be at most 1e6 (m or rad) where finite: math.inf frees an axis; "
            f"got {arr.tolist()}"
        )
    return arr


def check_weights(weights: object, n: int, what: str) -> np.ndarray:
    """``weights`` as n finite numbers >= 0, not all 0; ``TargetError`` otherwise."""
    try:
        arr = np.array(weights, dtype=float).reshape(-1)
    except (TypeError, ValueError, OverflowError):  # 10**400: no float
        raise TargetError(f"{what} must be {n} numbers >= 0, got {weights!r}") from None
    if arr.shape != (n,) or not np.isfinite(arr).all() or (arr < 0).any() or not arr.any():
        raise TargetError(
            f"{what} must be {n} finite numbers >= 0, not all 0 (0 frees an axis), got {weights!r}"
        )
    return arr


def unit(vector: object, what: str) -> np.ndarray:
    """``vector`` as a unit 3-vector; ``TargetError`` for a zero-length or non-finite one."""
    try:
        arr = np.array(vector, dtype=float).reshape(-1)
    except (TypeError, ValueError, OverflowError):  # 10**400: no float
        raise TargetError(f"{what} must be 3 numbers, got {vector!r}") from None
    if arr.shape != (3,) or not np.isfinite(arr).all():
        raise TargetError(f"{what} must be 3 finite numbers, got {vector!r}")
    big = float(np.abs(arr).max())
    if big > 1e150:  # the sum of squares of (1e308, 1e308, 0) overflows: the vector scaled
        arr = arr / big  # first (its length inf made it zero, which any axis held)
    norm = float(np.linalg.norm(arr))
    if norm < 1e-9:
        raise TargetError(f"{what} must have a length, got {arr.tolist()} (zero length)")
    return arr / norm


def check_angle(within: object, what: str) -> float:
    """``within`` as an angle in [0, pi] rad; ``TargetError`` otherwise."""
    try:
        angle = float(within)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):  # 10**400: no float
        raise TargetError(f"{what} must be an angle in rad, got {within!r}") from None
    if not 0.0 <= angle <= math.pi:
        raise TargetError(f"{what} must lie in [0, pi] rad, got {within!r}")
    return angle


def check_frame(frame: object) -> str | None:
    if frame is not None and not isinstance(frame, str):
        raise TargetError(f"frame must be a frame's name (a str) or None, got {frame!r}")
    return frame
