"""A servo at 500 Hz: a target that moves every tick, a joint command safe at every tick.

``arm.servo(q0, dt=0.002)`` starts at rest at ``q0``; each ``servo.step(target)`` returns
the next command (``q``, ``dq``, ``ddq``) within the joint, velocity and acceleration
limits, and says what limited it (``status``, ``reason``).

1. A 10 cm circle at 0.5 Hz, the orientation held: the tracking error.
2. A target that jumps 25 cm: the velocity and acceleration limits shape the move, and
   it settles on the target.
3. A target 3 m away for 1 s, then back: out of reach, no NaN, and it recovers.
4. The commanded sequence checked against every limit by finite differences.
"""

import numpy as np
from _common import out_dir

import armik
from armik.servo.streams import JUMP, START, circle, moved, violations

out_dir(__doc__, figures=False)

dt = 0.002
arm = armik.load("panda")
q0 = START["panda"]
servo = arm.servo(q0, dt=dt, acceleration_limits=20.0)
T0 = arm.fk(q0)

rec = servo.track(circle(T0, 1000, dt))
error = rec.position_error[50:]  # after the first 0.1 s, the arm starting at rest
print(f"circle: RMS error {np.sqrt(np.mean(error**2)):.1e} m, largest {error.max():.1e} m")

jump = servo.track([moved(rec_end := arm.fk(servo.q), JUMP)] * 750)
settled = int(np.flatnonzero(jump.position_error > 1e-5)[-1]) + 1
print(f"jump: {sorted(set(jump.status[:settled].tolist()))} on the way")
print(f"jump: settled within 1e-5 m after {settled * dt:.3f} s: {jump.status[-1]}")

far = moved(rec_end, np.array([3.0, 0.0, 0.0]))
back = servo.track([far] * 500 + [rec_end] * 1000)
print(f"3 m away: {back.status[0]}, NaN: {bool(np.isnan(back.q).any())}")
print(f"back: {back.position_error[-1]:.1e} m, {back.status[-1]}")

Q = np.vstack([rec.q, jump.q, back.q])
over = violations(q0, Q, arm.lower, arm.upper, servo.velocity_limits, servo.acceleration_limits, dt)
print(f"{len(Q)} ticks, largest excess over each limit: {over}")
