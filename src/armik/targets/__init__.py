"""Targets: one pose (``pose``: ``Target``, ``parse_target``) and many poses (``batch``:
``TargetBatch``, ``parse_targets``), read from every form a user gives, in the base frame;
a class of the user's own read by the function registered for it (``register_spelling``)."""

from armik.targets.batch import TargetBatch, parse_targets
from armik.targets.pose import Target, parse_target, register_spelling, unregister_spelling

__all__ = [
    "Target",
    "TargetBatch",
    "parse_target",
    "parse_targets",
    "register_spelling",
    "unregister_spelling",
]
