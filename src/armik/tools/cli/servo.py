"""``armik servo``: a demo stream through ``Arm.servo`` (a circle about the tip, then an
optional jump), printing the tracking error, what limited the ticks, the time a tick took
and the commanded sequence's largest excess over each limit (finite differences)."""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
import pinocchio as pin

from armik.errors import OptionError
from armik.servo.streams import START, circle, moved, violations
from armik.tools.cli.arms import load_arm

MAX_TICKS = 1_000_000  # the circle's targets are made before the first tick
STARTS = 64  # seeded configurations the default start is chosen among, besides the middle


def cmd_servo(args: argparse.Namespace) -> int:
    arm = load_arm(args)
    if args.q0 is not None:
        q0 = np.array(args.q0, dtype=float)
    elif arm.name in START and arm.kinematics.dof == len(START[arm.name]):
        q0 = START[arm.name]
    else:
        q0 = _start_with_room(arm)
    for flag, value in (("--seconds", args.seconds), ("--hz", args.hz)):
        if not 0.0 < value < math.inf:
            raise OptionError(
                f"{flag} must be a positive finite number, got {value!r}", option=flag, value=value
            )
    if not 0.0 <= args.circle < math.inf:
        raise OptionError(
            f"--circle must be a finite radius >= 0 m, got {args.circle!r}",
            option="--circle",
            value=args.circle,
        )
    if args.jump is not None and not np.isfinite(args.jump).all():
        raise OptionError(
            f"--jump must be 3 finite numbers (m, base frame), got {args.jump}",
            option="--jump",
            value=args.jump,
        )
    servo = arm.servo(
        q0,
        dt=args.dt,
        acceleration_limits=args.acceleration_limit,
        velocity_limits=args.velocity_limit,
    )
    dt = servo.dt
    ticks = max(1, round(args.seconds / dt)) if args.seconds / dt <= MAX_TICKS else None
    if ticks is None:
        raise OptionError(
            f"--seconds {args.seconds:g} at --dt {dt:g} s is {args.seconds / dt:.3g} ticks, "
            f"more than this demo streams ({MAX_TICKS:,}): give a shorter --seconds or a "
            "longer --dt",
            option="--seconds",
            value=args.seconds,
        )
    T0 = arm.fk(q0)
    plane = arm.kinematics.plane
    if plane is not None and abs(plane.normal[0]) > 1.0 - 1e-9 and arm.kinematics.dof >= 3:
        plane = None  # in the base's y-z plane, with a joint for the tool's turn: the circle
    if plane is None:
        stream: list = circle(T0, ticks, dt, args.circle, args.hz)
    else:  # off a planar arm's plane: in it instead, as positions (the tool's turn follows)
        stream = _in_plane(plane, T0.translation, ticks, dt, args.circle, args.hz)
    if plane is None and arm.kinematics.dof < 6:  # no full pose along the circle: positions
        stream = [T.translation for T in stream]
    legs = [("circle", stream)]
    if args.jump is not None:
        last = stream[-1]
        end = moved(last, np.array(args.jump)) if isinstance(last, pin.SE3) else last + args.jump
        legs.append(("jump", [end] * max(1, round(1.5 / dt))))
    print(
        f"{arm.name}: {arm.kinematics.dof} joints, dt {dt * 1e3:g} ms; q0 "
        + " ".join(f"{v:.4g}" for v in q0)
    )
    Q: list[np.ndarray] = []
    took: list[float] = []
    for label, targets in legs:
        steps = []
        for target in targets:
            t = time.perf_counter()
            steps.append(servo.step(target))
            took.append(time.perf_counter() - t)
        Q.extend(s.q for s in steps)
        _report(label, steps, dt)
    over = violations(
        q0, np.array(Q), arm.lower, arm.upper, servo.velocity_limits, servo.acceleration_limits, dt
    )
    us = np.array(took) * 1e6
    print(
        f"tick: median {np.median(us):.0f} us, p99 {np.percentile(us, 99):.0f} us "
        f"({len(us)} ticks; the first compiles or loads the tick)"
    )
    print(
        "largest excess over the limits (finite differences): "
        + ", ".join(f"{k} {v:.1e}" for k, v in over.items())
    )
    return 0


def _start_with_room(arm) -> np.ndarray:
    """The best-conditioned of the middle of the limits and ``STARTS`` seeded configurations
    within the middle half of each joint's range (a turn about the middle where it has no
    limits): the largest smallest singular value of the tip's Jacobian, its position rows
    on an arm of fewer than 6 joints. The middle is often stretched or folded (an iiwa's
    zeros, a SCARA's straight elbow), where a circle cannot start."""
    lo, hi = arm.lower.copy(), arm.upper.copy()
    free = ~(np.isfinite(lo) & np.isfinite(hi))
    lo[free], hi[free] = arm.middle[free] - math.pi, arm.middle[free] + math.pi
    quarter = 0.25 * (hi - lo)
    rng = np.random.default_rng(0)
    starts = [arm.middle, *(lo + quarter + 2.0 * quarter * rng.random((STARTS, len(lo))))]
    rows = slice(0, 6) if arm.kinematics.dof >= 6 else slice(0, 3)

    def room(q: np.ndarray) -> float:
        return float(np.linalg.svd(arm.jacobian(q)[rows], compute_uv=False)[-1])

    return max(starts, key=room)


def _in_plane(plane, tip: np.ndarray, ticks: int, dt: float, radius: float, hz: float) -> list:
    """A circle of ``radius`` m in a planar arm's plane through the tip, at ``hz`` turns a
    second, as positions: its centre ``radius`` from the tip toward the first joint's axis,
    so that it stays within the reach of an arm that starts stretched."""
    inward = plane.to_3d(plane.joint_origins[0]) - tip
    inward -= (inward @ plane.normal) * plane.normal
    size = float(np.linalg.norm(inward))
    inward = inward / size if size > 1e-9 else plane.y
    along = np.cross(plane.normal, inward)
    out = []
    for k in range(1, ticks + 1):
        a = 2.0 * math.pi * hz * k * dt
        out.append(tip + radius * (math.sin(a) * along + (1.0 - math.cos(a)) * inward))
    return out


def _report(label: str, steps: list, dt: float) -> None:
    errors = np.array([s.position_error for s in steps], dtype=float)
    rms = float(np.sqrt(np.mean(errors**2)))
    counts: dict[str, int] = {}
    for s in steps:
        counts[s.status.value] = counts.get(s.status.value, 0) + 1
    said = ", ".join(f"{k} {v}" for k, v in sorted(counts.items(), key=lambda kv: -kv[1]))
    turn = steps[-1].orientation_error
    turned = "orientation free" if turn is None else f"orientation error last {turn:.2e} rad"
    print(
        f"{label}: {len(steps)} ticks ({len(steps) * dt:g} s); position error RMS {rms:.2e} m, "
        f"largest {errors.max():.2e} m, last {errors[-1]:.2e} m, {turned}"
        f"\n  ticks by status: {said}"
    )
