"""Streaming differential IK: a servo that follows a moving target one tick at a time, every
joint, velocity and acceleration limit kept on the commanded sequence (docs/servo.md).

``servo.py`` the ``Servo`` (``Arm.servo`` starts one), ``tick.py`` its compiled tick on
the memory of ``layout.py``, ``box.py`` the per-joint velocity box of every limit,
``singular.py`` the smallest singular value the damping reads, ``table.py`` a target as the
tick's rows, ``limits.py`` the limits checked, ``result.py`` what a tick and a run of ticks
return.
"""

import armik.kernel  # noqa: F401  (first: numba's cache rule, the compile notice)
from armik.servo.result import ServoRecord, ServoStatus, ServoStep
from armik.servo.servo import Servo, start

__all__ = ["Servo", "ServoRecord", "ServoStatus", "ServoStep", "start"]
