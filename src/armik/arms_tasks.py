"""A flat list of tasks for several tips, each naming its frame (Pink's and mink's habit:
``robot.solve([armik.Pose(T_l, frame=left), armik.Relative(right, left, T)])``), read as
the mapping ``Arms.solve`` takes: each task under the tip whose chain holds its frame."""

from __future__ import annotations

from collections.abc import Mapping

from armik.errors import TargetError
from armik.model.arm_model import ArmModel
from armik.model.frames import owner
from armik.problem.tasks import Task


def by_tip(chains: Mapping[str, ArmModel], targets: object) -> object:
    """``targets`` as tip -> its tasks where it is a list of tasks, else as given; a
    ``TargetError`` for a task that names no frame or a frame on no chain."""
    if not isinstance(targets, (list, tuple)) or not targets:
        return targets
    if not all(isinstance(t, Task) for t in targets):
        return targets  # the mapping check names what is wrong
    out: dict[str, list[Task]] = {}
    for task in targets:
        if task.frame is None:
            raise TargetError(
                f"{type(task).__name__} in a list of tasks for several tips names no frame: "
                f"give frame= (one of the tips {list(chains)}, or a frame of their chains)"
            )
        tip = owner(chains, task.frame)
        if tip not in chains:
            raise TargetError(
                f"{type(task).__name__} names frame {task.frame!r}, which no chain of tips "
                f"{list(chains)} has"
            )
        out.setdefault(tip, []).append(task)
    return out
