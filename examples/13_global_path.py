"""A path that keeps its branch: the global plan over every solution (``plan="global"``).

A UR5 turns a part one and a half turns about the tool axis (a screwing motion). Followed
greedily from the middle of the limits, wrist 3 runs into its +2 pi limit two thirds of the
way and the path is reported ``discontinuous`` there. The global plan looks at every
branch and every 2 pi turn of every joint at every waypoint, and starts wrist 3 where the
whole motion fits: every waypoint reached, no joint moving more than ``max_joint_step``.

A waypoint where every path must jump is still reported, at that waypoint, with the joint
and the size of the smallest jump: never a silent one.
"""

import math

import numpy as np
import pinocchio as pin
from _common import out_dir

import armik

out_dir(__doc__, figures=False)

ur5 = armik.load("ur5")
q = ur5.middle.copy()
q[4] = 1.0
T0 = ur5.fk(q)
n = 150
poses = [
    T0 * pin.SE3(pin.exp3(np.array([0.0, 0.0, 3.0 * math.pi * k / (n - 1)])), np.zeros(3))
    for k in range(n)
]
follow = ur5.solve_path(poses, q, max_joint_step=0.3)
bad = np.flatnonzero(~follow.success)
print(f"follow: {follow.success.sum()}/{n} waypoints; at {bad[0]}: {follow.status[bad[0]]}")
planned = ur5.solve_path(poses, None, max_joint_step=0.3, plan="global")
steps = np.abs(np.diff(planned.q, axis=0)).max()
print(f"global: {planned.success.sum()}/{n} waypoints, largest joint step {steps:.3f} rad")
wrist = planned.q[:, 5]
print(f"wrist 3 runs from {wrist[0]:.2f} to {wrist[-1]:.2f} rad (limits +-{ur5.upper[5]:.2f})")

# a quarter turn of the tool between two waypoints: every path breaks there
flip = pin.SE3(pin.exp3(np.array([math.pi / 2, 0.0, 0.0])), np.zeros(3))
jumpy = [T0 if k < 10 else T0 * flip for k in range(20)]
p = ur5.solve_path(jumpy, q, max_joint_step=0.3, plan="global")
k = int(np.flatnonzero(~p.success)[0])
print(f"a forced jump at waypoint {k}: {p.status[k]}: {p[k].reason.split('; ')[0]}")
