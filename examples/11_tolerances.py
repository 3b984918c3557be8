"""Tolerances: a region around the target instead of one exact pose (``bounds=``).

``bounds=(bx, by, bz, brx, bry, brz)`` keeps each component of the error twist of the
reached tip pose relative to the target, in the target frame, within +- its bound (m, rad),
as TRAC-IK reads its bounds; ``math.inf`` frees an axis.

1. The 5-joint SO-101 cannot take a full 6-D pose, but it can put its tool point at a
   point with the tool pointing a given way: position and z axis fixed, the spin about z
   free.
2. A UR5 target within +-5 mm and +-0.05 rad: q0 already inside the box needs no step.
3. A region out of reach is a failure with its reason, never an exception.
4. Tasks: a suction cup at a point, pointing down within 3 degrees (``armik.Position`` and
   ``armik.Axis``), on the SO-101 and the UR5: the compiled step follows the cone.
"""

import math

import numpy as np
import pinocchio as pin
from _common import out_dir

import armik

out_dir(__doc__, figures=False)


def pointing(point, direction) -> pin.SE3:
    """A pose at ``point`` whose z axis is ``direction`` (its spin about z arbitrary)."""
    z = np.asarray(direction, float) / np.linalg.norm(direction)
    x = np.cross([0.0, 1.0, 0.0], z) if abs(z[1]) < 0.9 else np.cross(z, [1.0, 0.0, 0.0])
    x /= np.linalg.norm(x)
    return pin.SE3(np.column_stack([x, np.cross(z, x), z]), np.asarray(point, float))


# 1. the SO-101: this point, pointing down within 0.01 rad (its URDF's axes are a few
# microradians off parallel: exactly down is out of reach by ~4e-6 rad, more than 1e-6)
so101 = armik.load("so101")
print(f"{so101.name}: {so101.dof} joints to {so101.tip}")
T = pointing([0.2, 0.05, 0.05], [0.0, 0.0, -1.0])
exact = so101.solve(T, timeout=0.01)
print(f"the exact pose: {exact.status} (5 joints cannot take a 6-D pose)")
r = so101.solve(T, bounds=(0.0, 0.0, 0.0, 0.01, 0.01, math.inf))
tool_z = so101.fk(r.q).rotation[:, 2]
print(f"point and direction: {r.status}, tool z = {np.round(tool_z, 6).tolist()}")
SPIN_FREE = (0.0, 0.0, 0.0, 0.0, 0.0, math.inf)
rng = np.random.default_rng(0)
targets = [pointing(so101.fk(q).translation, so101.fk(q).rotation[:, 2])
           for q in so101.random_q(rng, n=200)]  # fmt: skip
batch = so101.solve_batch(np.array([t.homogeneous for t in targets]), bounds=SPIN_FREE)
print(f"200 reachable points and directions: {int(batch.success.sum())}/200 solved")

# 2. a UR5 target with a small box around it
ur5 = armik.load("ur5")
BOX = (0.005, 0.005, 0.005, 0.05, 0.05, 0.05)
q0 = ur5.random_q(1)
T = ur5.fk(q0) * pin.SE3(pin.exp3(np.array([0.0, 0.03, 0.0])), np.array([0.004, 0.0, 0.0]))
r = ur5.solve(T, q0=q0, bounds=BOX)
print(f"q0 inside the box: {r.status} in {r.iterations} iterations ({r.solver})")
r = ur5.solve(T, q0=ur5.middle, bounds=BOX)
print(f"from mid-limits: {r.status} after {r.iterations} iterations")

# 3. out of reach
r = ur5.solve(pin.SE3(np.eye(3), np.array([2.0, 0.0, 0.5])), bounds=BOX)
print(f"a region 2 m away: {r.status}: {r.reason}")

# 4. a point, the tool's z within 3 degrees of straight down
WITHIN = math.radians(3.0)
for a, p in ((so101, (0.2, 0.05, 0.05)), (ur5, (0.4, 0.2, 0.3))):
    r = a.solve([armik.Position(p), armik.Axis((0, 0, 1), (0, 0, -1), WITHIN)])
    if r.success:
        z = a.fk(r.q).rotation[:, 2]
        tilt = math.degrees(math.acos(min(1.0, -float(z[2]))))
        print(f"{a.name}: {r.status} by {r.solver}, tool {tilt:.2f} degrees from straight down")
    else:
        print(f"{a.name}: {r.status}: {r.reason}")
