"""Options a route refuses by name, and the way round: what a task list (the task solver)
or several tips solved together cannot take yet."""

from __future__ import annotations

from armik.errors import OptionError
from armik.options import Options
from armik.solve.tasks import SOLVER

_DEFAULT = Options()


# options of the compiled path a task list says in its tasks instead
_SAID_BY_TASKS = ("position_only", "weights", "bounds")
_CONSTRAINTS = ("obstacles", "self_collision")  # not yet for several tips


def check_options(
    opts: Options, solver: str, several_tips: bool = False, held: bool = False
) -> None:
    """Refuse what a task list cannot take (yet, for ``several_tips``), naming the option
    and the way round; ``held``: the list is a plain target's, for its held joints."""
    if solver not in ("auto", SOLVER):
        what = (
            "these held joints are held by the task solver (a closed form holds one joint of "
            "a 7-joint arm)"
            if held
            else "a list of tasks is solved by the task solver"
        )
        raise OptionError(
            f"{what}: give solver='auto', got {solver!r}",
            option="solver",
            value=solver,
        )
    defaults = _DEFAULT
    refused = _SAID_BY_TASKS + (_CONSTRAINTS if several_tips else ())
    for name in refused:
        if getattr(opts, name) != getattr(defaults, name):
            raise OptionError(_not_taken(name, several_tips), option=name, value=None)
    if opts.swivel is not None:  # the self-motion of one SRS arm's closed form
        where, fix = (
            ("several tips at once (chains that share joints, or a task relating them)",
             "solve that chain alone, robot.chain(tip).solve(T, swivel=...)")
            if several_tips
            else ("these held joints", "hold one joint, or leave swivel= out")
            if held
            else ("a list of tasks", "give the pose, arm.solve(T, swivel=...)")
        )  # fmt: skip
        raise OptionError(
            f"swivel={opts.swivel!r} is not taken by the task solver, which solves {where}: "
            f"the swivel fixes an SRS arm's elbow in its closed form; {fix}",
            option="swivel",
            value=opts.swivel,
        )


def _not_taken(name: str, several_tips: bool) -> str:
    """Why option ``name`` is refused, and the way round: by a task list, or where several
    tips are solved together (one descent over every joint, by the task solver)."""
    if not several_tips:
        return (
            f"{name} does not apply to a list of tasks: say it in the tasks "
            "(armik.Pose(T, bounds=..., weights=...), armik.Position)"
        )
    if name in _SAID_BY_TASKS:
        return (
            f"{name} is not taken where several tips are solved together (chains that share "
            "joints, or a task relating them: one task per tip): say it in each tip's target, "
            "{tip: armik.Pose(T, bounds=..., weights=...)} or armik.Position"
        )
    return (
        f"{name} is not taken where several tips are solved together (chains that share "
        "joints, or a task relating them: the task solver, which checks no collision yet): "
        "solve each chain alone, robot.chain(tip).solve(..., obstacles=...)"
    )
