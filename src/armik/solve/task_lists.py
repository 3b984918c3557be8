"""A batch's rows read as task lists (``task_problems``), and lowered together to the
compiled batch's targets and options where every row lowers alike (``lower_all``), or why
a global plan refuses them where they do not (``not_lowered_globally``)."""

from __future__ import annotations

from armik.errors import TargetError
from armik.problem.problem import Problem, as_problem, check_said_twice, lower, refuse_beside_tasks
from armik.problem.tasks import Task


def task_problems(targets: object) -> list[Problem] | None:
    """The problems of a batch of tasks or task lists; None for the other batch spellings."""
    if type(targets) not in (list, tuple) or not targets:
        return None
    first = targets[0]  # type: ignore[index]
    if not isinstance(first, Task) and not (
        type(first) in (list, tuple) and any(isinstance(t, Task) for t in first)
    ):
        return None
    problems = []
    for i, row in enumerate(targets):  # type: ignore[arg-type,var-annotated]
        try:
            problem = as_problem(row)
        except TargetError as error:  # a row that is no task list: said with its number
            raise TargetError(f"target {i}: {error}") from None
        if problem is None:
            raise TargetError(
                f"target {i} is {row!r}: a batch of tasks holds a task or a list of tasks in "
                "every row"
            )
        problems.append(problem)
    return problems


def lower_all(
    problems: list[Problem], options: dict, tip: str | None = None
) -> tuple[list, dict] | None:
    """(targets, options) of the compiled batch when every problem lowers to the same
    options, aim and axis (``problem.lower``; a batch shares them: ``TargetBatch.aim``,
    ``along``), else None."""
    targets, said = [], None  # the options, aim and axis every problem lowers to
    weights = options.get("weights")
    for lowered in (lower(problem, tip, weights) for problem in problems):
        target = None if lowered is None else lowered[0]
        each = None if lowered is None else (lowered[1], *_carried(target))
        if each is None or (said is not None and each != said):
            return None
        targets.append(lowered[0])  # type: ignore[index]
        said = each
    check_said_twice(options, said[0] if said else {})
    if "position_only" in options or "bounds" in options:
        for problem in problems:
            refuse_beside_tasks(problem, options)
    return targets, {**options, **(said[0] if said else {})}


def not_lowered_globally() -> TargetError:
    """Why ``plan='global'`` refuses task lists that do not lower together."""
    return TargetError(
        "plan='global' plans over every solution at each waypoint, and the task lists given "
        "have no compiled form (the task solver gives one answer each): give plan='follow', "
        "or tasks the compiled path has a form for (a pose with bounds or weights, a "
        "position, a tip axis along a direction or within a cone of it, a look-at at one "
        "point, the same in every row)"
    )


def _carried(target: object) -> tuple:
    """(aim, along) of a lowered target (``Target``'s; None for a pose or a position)."""
    return (getattr(target, "aim", None), getattr(target, "along", None))
