"""The tasks: one thing asked of one frame each (see ``base``)."""

from armik.problem.tasks.axis import Axis
from armik.problem.tasks.base import Task, TaskError
from armik.problem.tasks.look_at import LookAt
from armik.problem.tasks.pose import Pose
from armik.problem.tasks.position import Position
from armik.problem.tasks.relative import Relative

__all__ = ["Axis", "LookAt", "Pose", "Position", "Relative", "Task", "TaskError"]
