"""The viewer's servo mode: a dragged target followed by the servo (``Arm.servo``), as the
robot would follow a teleoperated target, rather than jumped to by a solve.

A ``Follower`` holds the servo and each tip's latest target; ``frame()`` runs one frame's
ticks toward them (``FRAME`` s of servo time: ``FRAME / dt`` steps) and returns the last
step, every joint within its position, velocity and acceleration limits at every tick. The
viewer calls it ``1 / FRAME`` times a second from a thread of its own and draws the robot
at the step's q; drags only move the targets. The ticks are counted, not timed: a frame
runs the same steps however late its thread wakes, so what the servo commands does not
depend on the machine's load (the robot moves slower on the screen, never jumps).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping

import numpy as np

from armik.arms_servo import ArmsServo
from armik.servo.result import ServoStatus, ServoStep

FRAME = 1.0 / 30.0  # s of servo time a drawn frame (30 frames a second)
STILL = 1e-9  # rad/s (m/s): slower than this on target, the motion has ended

# still there, no tick moves it: on target, or as near as it gets (stalled, or stretched
# toward a target beyond its reach)
_AT_REST = (ServoStatus.ON_TARGET, ServoStatus.STALLED, ServoStatus.OUT_OF_REACH)


class Follower:
    """The servo of ``arm`` (an ``Arm``, or an ``Arms``: its chains side by side or their
    union) from ``q0`` (clipped into the joint limits: the viewer may show a configuration
    outside them, a servo never leaves them), with ``Arm.servo``'s options (``dt``,
    ``velocity_limits``, ``acceleration_limits``, ``obstacles``, ...). ``aim({tip:
    target})`` sets targets, ``frame()`` steps toward them. ``tips``: the tips in order
    (one arm: its one tip)."""

    def __init__(self, arm: object, q0: np.ndarray, tips: tuple[str, ...], **options: object):
        self.arm, self.tips, self.options = arm, tips, options
        self._lock = threading.Lock()  # a frame's ticks, or a restart, at a time
        q0 = np.clip(q0, arm.lower, arm.upper)  # type: ignore[attr-defined]
        self.servo = arm.servo(q0, **options)  # type: ignore[attr-defined]
        self.steps_a_frame = max(1, round(FRAME / self.servo.dt))
        self.targets: dict[str, object] = {}
        self.last: ServoStep | None = None
        self.moving = False

    def aim(self, targets: Mapping[str, object]) -> None:
        """Follow ``targets`` (tip -> target) from the next frame on. On several tips, a
        tip given no target holds its pose where the servo has it now (the viewer aims only
        the tips dragged so far; the servo takes one target per tip)."""
        self.targets = dict(targets)
        self.moving = bool(self.targets)
        if self.moving and isinstance(self.servo, ArmsServo):
            q = self.servo.q
            for tip in self.tips:
                if tip not in self.targets:
                    self.targets[tip] = self.arm.fk(q, tip)  # type: ignore[attr-defined]

    def restart(self, q: np.ndarray) -> None:
        """The robot was put at ``q`` by other means (``show``, the sliders, a solve): the
        servo starts again from there (clipped into the joint limits, which a servo never
        leaves), at rest, its options kept, and waits for the next ``aim``; a frame begun
        before returns a step that is no longer ``last``."""
        arm = self.arm
        q = np.clip(q, arm.lower, arm.upper)  # type: ignore[attr-defined]
        with self._lock:
            self.servo = arm.servo(q, **self.options)  # type: ignore[attr-defined]
            self.moving, self.last = False, None

    def frame(self) -> ServoStep | None:
        """One frame's ticks toward the targets: the last step, or None with no target or
        once a step came to rest on target, or as near as it gets (stalled, out of reach),
        until ``aim`` moves a target."""
        with self._lock:
            if not self.moving:
                return None
            by_tip = isinstance(self.servo, ArmsServo)  # several tips: one target each
            target = self.targets if by_tip else self.targets[self.tips[0]]
            for _ in range(self.steps_a_frame):
                step = self.servo.step(target)
                if step.status in _AT_REST and np.abs(step.dq).max() < STILL:
                    self.moving = False
                    break
            self.last = step
            return step


def run(follower: Follower, draw: Callable[[ServoStep], None], stop: threading.Event) -> None:
    """Until ``stop`` is set: a frame of ``follower`` every ``FRAME`` s while it moves,
    each drawn by ``draw``."""
    while not stop.wait(FRAME):
        step = follower.frame()
        if step is not None:
            draw(step)
