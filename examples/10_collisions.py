"""Collisions: a UR5 over a table, with a box on the table beside it.

1. ``min_distance``: the closest link and obstacle at a configuration.
2. ``solve`` with ``obstacles``: the closed form returns the nearest branch that keeps
   clear of the table and the box (a branch through them is refused, not returned).
3. A target inside the box: reachable only in collision, so the status is ``collision``
   and the reason names the pair.
4. ``solve_batch`` with obstacles and self-collision: every success is collision-free.
5. The same as constraint objects (``armik.Collisions``, ``armik.Hold``), which a list of
   tasks takes too: the camera on the wrist looks at a point on the table from anywhere,
   clear of the box, with the last joint held.
"""

import numpy as np
from _common import out_dir

import armik

out_dir(__doc__, figures=False)

ur5 = armik.load("ur5")
table = armik.HalfSpace((0, 0, 1), 0.0)  # the solid is z <= 0: the table top at z = 0
box = armik.Box((0.2, 0.2, 0.3), (0.45, -0.3, 0.15))  # full sides, centre in the base frame
scene = [table, box]

q = np.array([0.0, -1.2, 1.5, -1.9, -1.57, 0.0])
d, pair = ur5.min_distance(q, obstacles=scene)
print(f"at q: closest {pair[0]} and {pair[1]}, {d:.3f} m apart")

# 2. a reachable target: the nearest collision-free branch
rng = np.random.default_rng(3)
shown = 0
for _ in range(200):
    q_goal = ur5.random_q(rng)
    if ur5.in_collision(q_goal, scene, self_collision=True, margin=0.01):
        continue  # targets from collision-free configurations only
    T = ur5.fk(q_goal)
    plain = ur5.solve(T, q0=ur5.middle)
    safe = ur5.solve(T, q0=ur5.middle, obstacles=scene, self_collision=True, margin=0.01)
    if ur5.in_collision(plain.q, scene, self_collision=True, margin=0.01) and safe.success:
        print(f"without obstacles: branch {plain.branch}, in collision")
        a, b = safe.extra["closest_pair"]
        print(f"with obstacles:    branch {safe.branch}, {safe.status}")
        print(f"  closest: {a} and {b}, {safe.extra['min_distance']:.3f} m apart")
        shown += 1
        break

# 3. a target inside the box
inside = ur5.fk(q)
inside.translation = np.array([0.45, -0.3, 0.15])
r = ur5.solve(inside, q0=q, obstacles=scene)
print(f"tool inside the box: {r.status}: {r.reason}")

# 4. many targets at once
Q = ur5.random_q(0, n=300)
keep = [not ur5.in_collision(x, scene, self_collision=True, margin=0.01) for x in Q]
targets = ur5.fk_batch(Q[keep])
res = ur5.solve_batch(targets, obstacles=scene, self_collision=True, progress=False)
print("batch:", res.summary())
ok = all(not ur5.in_collision(x, scene, self_collision=True) for x in res.q[res.success])
print(f"every success collision-free: {ok}")

# 5. constraints as objects: a look-at from anywhere, clear of the scene, wrist 3 held
clear = armik.Collisions(obstacles=scene, self_collision=True, margin=0.01)
look = armik.LookAt((0.45, 0.2, 0.0), axis=(0, 0, 1), within=0.02)
r = ur5.solve([look], q0=q, constraints=[clear, armik.Hold("wrist_3_joint", 0.0)])
T = ur5.fk(r.q)
sight = np.array([0.45, 0.2, 0.0]) - T.translation
angle = np.arccos(np.clip(T.rotation[:, 2] @ sight / np.linalg.norm(sight), -1.0, 1.0))
print(f"look-at with constraints: {r.status} by {r.solver}, {angle:.4f} rad off the point,")
print(f"  wrist_3 at {r.q[5]:.3f}, collision-free: {not ur5.in_collision(r.q, scene, True, 0.01)}")
