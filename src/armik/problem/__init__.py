"""What to solve, as data: tasks now; constraints, scores and the problem that holds them
next (docs/problem-model.md)."""

from armik.problem.scores import Posture, Score
from armik.problem.tasks import Axis, LookAt, Pose, Position, Relative, Task, TaskError

__all__ = [
    "Axis",
    "LookAt",
    "Pose",
    "Position",
    "Posture",
    "Relative",
    "Score",
    "Task",
    "TaskError",
]
