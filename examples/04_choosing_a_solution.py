"""Choosing between the two elbow solutions: joint limits first, then nearness to q0."""

import math

from _common import out_dir

import armik

out_dir(__doc__, figures=False)  # takes --out like every example; writes no figure

arm = armik.load("planar_2link")
target = [1.2, 0.5]
for q0 in ([0.0, 1.0], [1.0, -1.0]):
    r = arm.solve(target, q0=q0)
    print(f"q0 = {q0}: picks {r.branch}, q = {[round(float(v), 4) for v in r.q]}")

limited = arm.with_limits({"joint2": (0.0, math.pi)})  # the elbow may only bend one way
r = limited.solve(target, q0=[1.0, 0.0])
print(
    f"joint2 limited to [0, pi], q0 = [1, 0]: picks {r.branch}, q = "
    f"{[round(float(v), 4) for v in r.q]}"
)
for res in limited.solve_all(target):
    print(f"  {res.branch:<10} success={res.success} status={res.status}")
