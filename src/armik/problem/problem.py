"""A problem: the tasks a user asks for, parsed once (docs/problem-model.md).

A problem is its primary tasks, its constraints (``armik.constraints``: the joint limits
always, a held joint, collisions) and its budget (``armik.problem.budget``). ``lower``
gives a problem the solve path already has a compiled form for (one pose of the tip, with
weights or bounds; one position of the tip; a position with an axis in a cone; an axis in
a cone alone) back as the target and options of that path, so the old route keeps its
speed; every other problem goes to ``armik.solve.tasks``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import pinocchio as pin

from armik.constraints.base import Constraint
from armik.constraints.limits import JointLimits
from armik.errors import OptionError, TargetError
from armik.problem.budget import DEFAULT as DEFAULT_BUDGET
from armik.problem.budget import Budget
from armik.problem.tasks import Axis, LookAt, Pose, Position, Relative, Task
from armik.problem.tasks.cone import cross
from armik.problem.tasks.look_at import SIGHT
from armik.targets.aim import Aim
from armik.targets.pose import Target


@dataclass(frozen=True)
class Problem:
    """Primary tasks, each of which must hold, measured on Pinocchio's FK, and constraints,
    each of which every answer must satisfy, for a success."""

    tasks: tuple[Task, ...]
    constraints: tuple[Constraint, ...] = (JointLimits(),)
    budget: Budget = DEFAULT_BUDGET  # filled: what the solve spends (its accounts)


def as_problem(target: object) -> Problem | None:
    """The problem ``target`` asks for when it is a task or a list of tasks; None for the
    other target spellings (a pose, a position: ``armik.targets.pose``)."""
    if isinstance(target, Task):
        return Problem((target,))
    if not isinstance(target, (list, tuple)) or not target:
        return None
    if not any(isinstance(t, Task) for t in target):
        return None
    looks = False
    for i, t in enumerate(target):
        if not isinstance(t, Task):
            raise TargetError(
                f"a list of tasks holds only tasks (armik.Pose, armik.Position, armik.Axis, "
                f"armik.LookAt), but item {i} is {t!r}"
            )
        looks = looks or type(t) is LookAt
    if looks:
        _refuse_looking_at_itself(target)
    return Problem(tuple(target))


def _refuse_looking_at_itself(tasks) -> None:
    """A ``TargetError`` for a ``LookAt`` whose point is where a task of its frame holds
    that frame, exactly or within a box that keeps it within ``LOOK_FROM`` of the point: no
    line of sight is left to aim along, and every axis would pass."""
    for look in (t for t in tasks if type(t) is LookAt):
        for t in tasks:
            if t.frame != look.frame:
                continue
            if type(t) is Position:
                at, box = t.p, t.bounds
            elif type(t) is Pose and t.weights[:3].all():
                at, box = t.T.translation, t.bounds[:3]
            else:
                continue
            # the farthest the box lets the frame stand from the point (at most)
            if float(np.linalg.norm(look.point - at) + np.linalg.norm(box)) <= LOOK_FROM:
                within = f" (its box {box.tolist()} m)" if box.any() else ""
                raise TargetError(
                    f"LookAt point {look.point.tolist()} is where {type(t).__name__} puts the "
                    f"frame itself{within}: no direction is left to aim along; look at "
                    f"another point, or give the frame's position a box (bounds=) to stand "
                    f"back in, wider than {LOOK_FROM:g} m"
                )


def refuse_looking_from_target(positions: object, aim: Aim, opts) -> None:
    """The keyword spelling's ``_refuse_looking_at_itself``: a ``TargetError`` where the
    aim's point (``aim.point``: ``look_at=``) is one a target's position (``positions``:
    one, or N of a batch or a path, m) holds the tip on, exactly or within a box no wider
    than ``LOOK_FROM``, its position not freed (an infinite bound, a weight of 0; ``opts``:
    validated options): ``solve(p, look_at=p, cone=...)`` asks what ``[Position(p),
    LookAt(p)]`` asks."""
    look = aim.point
    if look is None:
        return
    bounds, weights = opts.bounds, opts.weights
    if weights is not None and not all(weights[:3]):
        return
    # the farthest a box lets the tip stand from the point (at most): a box within
    # LOOK_FROM of it leaves no line of sight either
    box = 0.0 if bounds is None else float(np.linalg.norm(bounds[:3]))
    if not box <= LOOK_FROM:
        return
    at = np.asarray(positions, dtype=float).reshape(-1, 3)
    near = np.flatnonzero(np.linalg.norm(at - np.asarray(look), axis=1) + box <= LOOK_FROM)
    if len(near):
        which = "the target's position" if len(at) == 1 else f"target {int(near[0])}'s position"
        raise TargetError(
            f"look_at point {list(look)} is {which}, where the tip itself is put: no "
            "direction is left to aim along; look at another point, or give the tip's "
            f"position a box (bounds=) to stand back in, wider than {LOOK_FROM:g} m"
        )


def relative_tasks(target: object) -> list[Relative]:
    """The ``Relative`` tasks of a target (none for a pose or a position)."""
    problem = as_problem(target)
    return [t for t in problem.tasks if isinstance(t, Relative)] if problem else []


def tightened(problem: Problem) -> Problem:
    """The problem with every region shrunk to its centre (``Task.shrunk(0)``): each of its
    answers answers ``problem`` too, and it may have a compiled form ``problem`` has not."""
    return replace(problem, tasks=tuple(t.shrunk(0.0) for t in problem.tasks))


LOOK_FROM = SIGHT  # m: a point nearer the position than this is no direction to aim at


def rims(problem: Problem, count: int) -> list[Problem]:
    """Problems each of whose answers answers ``problem``: every task at its centre but one,
    exactly on a point of that one's rim (``Task.rim``), for each task with a rim."""
    centres = [t.shrunk(0.0) for t in problem.tasks]
    return [
        replace(problem, tasks=tuple(edge if j == i else c for j, c in enumerate(centres)))
        for i, task in enumerate(problem.tasks)
        for edge in task.rim(count)
    ]


def lower(
    problem: Problem, tip: str | None = None, weights: object = None
) -> tuple[object, dict] | None:
    """(target, options) of the compiled path for a problem it has a form for, else None;
    a task on frame ``tip`` is on the arm's tip, as one on no frame. ``weights``: the
    option given beside it (a position weight of 0 beside a ``Position`` and an ``Axis``
    is read in the base frame, as the keyword spelling ``toward=`` reads it)."""
    if any(t.frame is not None and t.frame != tip for t in problem.tasks):
        return None
    if len(problem.tasks) == 2:
        based = weights is not None and _frees_position(weights)
        return _point_and_axis(*problem.tasks, based) or _point_and_look(*problem.tasks)
    if len(problem.tasks) != 1:
        return None
    (task,) = problem.tasks
    if type(task) is LookAt:  # the position free, the axis within its cone of the sight
        free = (math.inf,) * 3 + (0.0,) * 3
        aim = _look(task)._replace(point=tuple(task.point.tolist()))
        return Target(task.point.copy(), np.eye(3), aim=aim), {"bounds": free}
    if type(task) is Pose:
        options: dict = {}
        # with bounds the option's weights act in the target frame, as the task's do
        if task.bounds.any() or (task.weights != 1.0).any():
            options["bounds"] = tuple(task.bounds.tolist())
        if (task.weights != 1.0).any():
            options["weights"] = tuple(task.weights.tolist())
        return pin.SE3(task.T), options
    if type(task) is Position and not task.bounds.any():
        return np.array(task.p), {}
    if type(task) is Axis:  # a direction alone: the position free, the axis in its cone
        free = (math.inf,) * 3 + (0.0,) * 3
        R = _onto(task.axis, task.direction)
        aim = _cone(task)
        return Target(np.zeros(3), R, aim=aim, along=aim.axis), {"bounds": free}
    return None


def as_target(lowered: object) -> Target | None:
    """The target ``lower`` gives as a ``Target``, its values as the task read them when it
    was built (not parsed again): a ``Pose``'s pose, a ``Position``'s point; a ``Target``
    itself (an aim); None for anything else."""
    if type(lowered) is Target:
        return lowered
    if isinstance(lowered, pin.SE3):
        H = lowered.homogeneous  # C-ordered, as the parser's: Pinocchio's rotation is not
        return Target(H[:3, 3].copy(), H[:3, :3].copy())
    if type(lowered) is np.ndarray and lowered.shape == (3,):
        return Target(np.array(lowered, dtype=float))
    return None


def refuse_beside_tasks(problem: Problem, options: dict) -> None:
    """An ``OptionError`` for an option beside a task list the compiled path solves
    (``lower``) that it would read against the tasks: ``position_only=True`` beside a
    ``Pose`` (it dropped the pose's rotation unseen: an answer whatever its rotation was a
    success with no orientation error), and ``bounds`` beside a ``Position`` with an
    ``Axis`` in a cone (read in the frame of a rotation the lowering chose, which no one
    named: a box free along x let the tip off along y and z). A list the task solver takes
    refuses these options; weights and bounds given beside a ``Pose`` are its own
    (``check_said_twice``)."""
    if options.get("position_only") and any(type(t) is Pose for t in problem.tasks):
        raise OptionError(
            "position_only=True drops the rotation a Pose task holds: say what is held in "
            "the tasks, armik.Position(p) for the position alone, or armik.Pose(T, "
            "bounds=(0, 0, 0, inf, inf, inf)) for the pose's position",
            option="position_only",
            value=True,
        )
    bounds = options.get("bounds")
    if bounds is None or {type(t) for t in problem.tasks} != {Position, Axis}:
        return
    try:
        widens = bool(np.any(np.asarray(bounds, dtype=float) != 0.0))
    except (TypeError, ValueError):
        return  # the options' check names it
    if widens:
        raise OptionError(
            f"bounds={bounds!r} beside a Position and an Axis have no frame of their own to be "
            "read in: give the position's box in the task, armik.Position(p, bounds=(bx, by, "
            "bz)) (base frame), the Axis's cone as its within",
            option="bounds",
            value=bounds,
        )


def refuse_tip_frame_weights(said: dict) -> None:
    """An ``OptionError`` for ``weights`` without ``bounds`` (``said``: the options a pose's
    task would take) that free a position axis and a rotation, on a pose the task solver
    takes for its held joints: ``weights=`` weigh the error in the tip frame, the task's
    (``armik.Pose(T, weights=...)``) in the target's, and with a rotation free a position
    axis of one frame is not the other's; the task's verdict would call a success a pose
    the option's rule refuses (other weights free the same poses in either frame)."""
    if said.get("weights") is None or said.get("bounds") is not None:
        return
    try:
        w = np.asarray(said["weights"], dtype=float).reshape(-1)
    except (TypeError, ValueError):
        return  # the options' check names it
    if w.shape != (6,) or w[:3].all() or w[3:].all():
        return
    raise OptionError(
        f"weights={said['weights']!r} weigh the tip frame's error, and the joints held here "
        "are held by the task solver, which weighs a pose's error in the target frame: with "
        "a rotation free, a position axis freed in one frame is not the other's; say it in "
        "the target frame, armik.Pose(T, weights=...), or lock the joints: "
        "arm.with_locked({name: value})",
        option="weights",
        value=said["weights"],
    )


def _frees_position(weights: object) -> bool:
    """Whether ``weights`` (the option, unchecked) give a position axis a weight of 0."""
    try:
        w = np.asarray(weights, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        return False  # the options' check names it
    return w.shape == (6,) and not w[:3].all()


def _point_and_axis(a: Task, b: Task, based: bool = False) -> tuple[object, dict] | None:
    """A position with an axis within a cone of a direction: a pose whose rotation takes
    the axis onto the direction. Exactly along it and the axis one of the tip's own (a
    5-joint arm's "this point, pointing that way"): bounds that free the rotation about
    that axis, exactly (every rotation taking the axis onto the direction is the target's
    turned about the axis, whose log3 lies along it), so that a closed form's sweep
    applies; else the cone (the target's ``aim``), which the compiled step and the verdict
    measure as ``Axis`` does. A position within a box (base frame) with an axis, or with
    ``based`` (weights that free a position axis, which the pose's rotation, the
    lowering's choice, would turn): the target's rotation the identity and the cone around
    the direction itself (``toward``), the box and the weights in the base frame."""
    if type(a) is Axis:
        a, b = b, a
    if type(a) is not Position or type(b) is not Axis:
        return None
    if a.bounds.any() or based:  # in the base frame: the cone around the direction itself
        aim = _cone(b)._replace(toward=tuple(b.direction.tolist()))
        said = {"bounds": (*a.bounds.tolist(), 0.0, 0.0, 0.0)} if a.bounds.any() else {}
        return Target(a.p.copy(), np.eye(3), aim=aim), said
    R = _onto(b.axis, b.direction)
    aim = _cone(b)  # the rotation the lowering's choice: its distance the axis' (``along``)
    along = [k for k, x in enumerate(b.axis.tolist()) if abs(x) == 1.0]
    if b.within == 0.0 and len(along) == 1:
        bounds = [0.0] * 6
        bounds[3 + along[0]] = math.inf
        return Target(a.p.copy(), R, along=aim.axis), {"bounds": tuple(bounds)}
    return Target(a.p.copy(), R, aim=aim, along=aim.axis), {}


def _point_and_look(a: Task, b: Task) -> tuple[object, dict] | None:
    """A position (exact, or within its bounds in the base frame) with an axis looking at a
    point: the cone around the line of sight (the target's ``aim`` with its point), which the
    compiled step and the verdict measure as ``LookAt`` does; None where the point is the
    position itself (any axis holds there, the task solver's)."""
    if type(a) is LookAt:
        a, b = b, a
    if type(a) is not Position or type(b) is not LookAt:
        return None
    sight = b.point - a.p
    if not float(sight @ sight) > LOOK_FROM * LOOK_FROM:
        return None
    # the target's rotation is not read: the cone's direction is the line of sight, and the
    # position's box is in the base frame
    aim = _look(b)._replace(point=tuple(b.point.tolist()))
    said: dict = {}
    if a.bounds.any():
        said["bounds"] = (*a.bounds.tolist(), 0.0, 0.0, 0.0)
    return Target(a.p.copy(), np.eye(3), aim=aim), said


def _look(task: LookAt) -> Aim:
    """The aim of a ``LookAt``: its axis and angle (its point: ``Aim.point``)."""
    x, y, z = task.axis.tolist()
    return _new(Aim, ((x, y, z), float(task.within), None, None))


def _cone(task: Axis) -> Aim:
    """The aim of an ``Axis``: its axis (unit, tip frame) and angle."""
    x, y, z = task.axis.tolist()
    return _new(Aim, ((x, y, z), float(task.within), None, None))  # every solve: no __new__


_new = tuple.__new__


def _onto(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A rotation taking the unit vector ``u`` onto the unit vector ``v``."""
    axis = cross(u, v)
    s, c = math.sqrt(float(axis @ axis)), float(u @ v)
    if s < 1e-12:
        if c > 0.0:
            return np.eye(3)
        other = np.eye(3)[int(np.argmin(np.abs(u)))]  # half a turn about an axis across u
        axis = cross(u, other)
        return pin.exp3(math.pi * axis / np.linalg.norm(axis))
    return pin.exp3(math.atan2(s, c) * axis / s)


def check_said_twice(options: dict, said: dict) -> None:
    """A task that says its bounds or weights, given the same option too: which one? (An
    option that frees the orientation an ``Axis`` or a ``LookAt`` measures is refused with
    the aim they lower to, as a keyword cone's: ``targets.aim.refuse_freed``.)"""
    for name in said:
        if name in options:
            box = ", armik.Position(p, bounds=...)); an armik.Axis or armik.LookAt says the "
            box += "bounds of what it frees itself (the position, the spin about the axis"
            box = box if name == "bounds" else ""
            raise OptionError(
                f"{name} is given both by the task and as an option: give it in the task "
                f"(armik.Pose(T, {name}=...){box})",
                option=name,
                value=options[name],
            )
