"""Many targets at once: a batch, a path without branch flips, and a reachability map.

1. ``solve_batch``: 500 Panda poses, every answer verified, on every core.
2. ``solve_path``: the UR5's tool spun through 360 degrees: the last joint turns on past
   pi instead of snapping back, and a spin past its limit is reported, not hidden.
3. ``reachability``: the fraction of tool orientations the Panda reaches per voxel
   (coarse here to stay fast; ``armik reach panda`` makes a finer one). Writes
   reach_panda.png into --out.
"""

import numpy as np
from _common import out_dir, pyplot

import armik
from armik.solve.reach import reachability

out = out_dir(__doc__)
plt = pyplot()  # the map's figure only: without matplotlib, its summary alone

panda = armik.load("panda")
rng = np.random.default_rng(0)
T = np.array([panda.fk(panda.random_q(rng)).homogeneous for _ in range(500)])  # (N, 4, 4)
batch = panda.solve_batch(T, timeout=0.005, progress=False)
print("batch:", batch.summary())
print(f"  target 0: {batch[0].status}, q = {np.round(batch.q[0], 3).tolist()}")

ur5 = armik.load("ur5")
q0 = np.array([0.3, -1.2, 1.2, -1.5, -1.2, 0.0])


def spin(turns: float, n: int) -> list:
    """The tool turned about the last joint's axis."""
    poses = []
    for angle in np.linspace(0.0, 2 * np.pi * turns, n):
        q = q0.copy()
        q[-1] += angle
        poses.append(ur5.fk(q))
    return poses


one = ur5.solve_path(spin(1.0, 73), q0, max_joint_step=0.5)
print(f"path: 360 degree spin: {one.summary()}")
print(f"  wrist_3 goes from {one.q[0, -1]:.3f} to {one.q[-1, -1]:.3f} rad, no snap back")
two = ur5.solve_path(spin(2.0, 145), q0, max_joint_step=0.5)
flagged = np.flatnonzero(two.status == "discontinuous")
print(f"path: 720 degree spin: {two.counts()}; waypoint {flagged[0]}: {two.reason(flagged[0])}")

reach = reachability(panda, resolution=0.3, orientations=4, timeout=0.002, progress=False)
print("reach:", reach.summary())
if plt is not None:
    print(f"wrote {reach.plot(out / 'reach_panda.png')}")
