"""Several tips of one robot at once: TALOS's two hands over its shared torso.

``armik.load(urdf, tips=[...])`` loads one chain per tip from one base; joints shared by
several chains (TALOS's two torso joints) appear once. A target per tip (a pose, a
position, a task list, or ``armik.Relative``: one tip's pose in another's), one answer
over every joint, each tip verified by Pinocchio's FK.

1. Both hands' poses, from FK of a random configuration.
2. A box in both hands, lifted: the left hand's pose, the right hand's in the left's.
3. Twenty targets per hand in one ``solve_batch``.
4. A right-hand target 2 m away: a failure that names the tip and why, and the left hand,
   solved without it, with its error.

TALOS comes from the example-robot-data package (a dependency of armik).
"""

from importlib import metadata
from pathlib import Path

import numpy as np
import pinocchio as pin
from _common import out_dir

import armik

out_dir(__doc__, figures=False)

share = metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share")
urdf = Path(str(share)) / "example-robot-data/robots/talos_data/robots/talos_reduced.urdf"
left, right = "gripper_left_base_link", "gripper_right_base_link"
robot = armik.load(urdf, tips=[left, right])
print(f"{robot}: shared joints {list(robot.shared)}")

rng = np.random.default_rng(14)
q = robot.random_q(rng)
targets = {tip: robot.fk(q, frame=tip) for tip in robot.tips}
r = robot.solve(targets)
errors = {tip: f"{pos:.1e} m" for tip, (pos, _) in r.extra["errors"].items()}
print(f"both poses: {r.status.value}, position errors {errors}")

# a box in both hands, lifted 5 cm: the left hand's pose moved up, the right hand held
# where it was in the left hand's frame
grip = targets[left].actInv(targets[right])
lifted = pin.SE3(targets[left].rotation, targets[left].translation + [0.0, 0.0, 0.05])
box = {left: lifted, right: armik.Relative(right, left, grip)}
r = robot.solve(box)
held = robot.fk(r.q, frame=left).actInv(robot.fk(r.q, frame=right))
gap = np.abs(pin.log6(grip.actInv(held)).vector).max()
print(f"a box in both hands, lifted: {r.status.value}, the grip kept within {gap:.1e}")

qs = [robot.random_q(rng) for _ in range(20)]
batch = robot.solve_batch({tip: [robot.fk(x, frame=tip) for x in qs] for tip in robot.tips})
print(f"batch: {int(batch.success.sum())}/{len(qs)} solved")

far = {left: targets[left], right: pin.SE3(np.eye(3), np.array([2.0, -1.0, 1.0]))}
r = robot.solve(far, timeout=0.05)
why = r.reason.split("; ")[0]  # the failing tip's words; the other tips' follow
print(f"a right hand 2 m away: {r.status.value}: {why}")
print(f"  the left hand, solved without it: position error {r.errors[left][0]:.1e} m")
